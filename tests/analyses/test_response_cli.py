"""`rotorsfd response CONFIG -o DIR`: files and exit 0; a bad [analysis.response] value
exits 2 with one line; a branch stopped by journal contact exits 1 with one line and
writes the points so far, without NaN."""

from __future__ import annotations

import csv
import os
import subprocess
import sys

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd.cli import main
from rotorsfd.io.branch_files import read_branch


def test_response_command_end_to_end(tmp_path):
    config = small_rotor_toml(tmp_path / "small.toml")
    out = tmp_path / "out"
    proc = subprocess.run(
        [sys.executable, "-m", "rotorsfd", "response", str(config), "-o", str(out),
         "--set", "analysis.response.speed_range.stop_ratio=1.2"],
        capture_output=True, text=True, timeout=600,
        env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    assert proc.returncode == 0, proc.stderr
    assert "ok: reached the end of the range" in proc.stdout
    assert sorted(p.name for p in out.iterdir()) == [
        "bifurcations.csv", "branch.csv", "branch.nc", "multipliers.png",
        "response_deflection.png", "response_node1.png",
        "response_node3.png", "run.json"]  # stability on by default; provenance
    with (out / "branch.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert float(rows[-1]["speed_ratio"]) == pytest.approx(1.2, rel=1e-12)
    assert (out / "response_node1.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_quiet_prints_nothing(tmp_path, capsys):
    config = small_rotor_toml(tmp_path / "small.toml")
    status = main(["response", str(config), "-o", str(tmp_path / "q"), "--quiet",
                   "--set", "analysis.response.speed_range.stop_ratio=0.8"])
    captured = capsys.readouterr()
    assert status == 0 and captured.out == "" and captured.err == ""


@pytest.mark.parametrize("override, field", [
    ("analysis.response.harmonics=0", "analysis.response.harmonics"),
    ("analysis.response.speed_range.stop_ratio=-1", "analysis.response.speed_range"),
    ("analysis.response.directions=['x']", "analysis.response.directions"),
    ("analysis.response.nodes=[9]", "analysis.response.nodes"),
])
def test_bad_response_value_exits_2(tmp_path, capsys, override, field):
    config = small_rotor_toml(tmp_path / "small.toml")
    status = main(["response", str(config), "-o", str(tmp_path / "bad"), "--quiet",
                   "--set", override])
    err = capsys.readouterr().err
    assert status == 2
    assert err.count("\n") == 1 and field in err, err
    assert not (tmp_path / "bad").exists()


def test_unsupported_parameter_exits_2(tmp_path, capsys):
    config = small_rotor_toml(tmp_path / "small.toml")
    status = main(["response", str(config), "-o", str(tmp_path / "bad"), "--quiet",
                   "--set", "analysis.response.parameter=materials.steel.density",
                   "--set", "analysis.response.speed_ratio=1.0",
                   "--set", "analysis.response.parameter_range=['7000 kg/m^3', '8000 kg/m^3']"])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1
    assert "analysis.response.parameter" in err and "base.pitching.value" in err


def test_contact_ends_branch_as_a_result(tmp_path, capsys):
    """A huge unbalance drives the journal to the eccentricity limit: the branch up to
    there is a result (issue 22 item 3): exit 0, one warning line naming where and why
    (the solver's account only with --verbose), ``ended = "limit"`` in branch.nc, the
    points written, no NaN anywhere."""
    config = small_rotor_toml(tmp_path / "small.toml", unbalance="2000 g*mm")
    out = tmp_path / "out"
    status = main(["response", str(config), "-o", str(out), "--quiet"])
    err = capsys.readouterr().err
    assert status == 0
    assert err.count("\n") == 1 and err.startswith("rotorsfd: warning: response branch ended")
    assert "lam=" not in err
    # the element and the field that ended the branch, in the user's terms
    assert "points at Omega~ = " in err and ": SFD 'sfd' at node 1 (pi film, C = 0.000127 m) " \
        "reached eps = 0.95" in err and "analysis.response.max_eccentricity = 0.95" in err
    assert main(["response", str(config), "-o", str(tmp_path / "v"), "-q", "-v"]) == 0
    verbose = capsys.readouterr().err
    assert verbose.startswith(err.strip()) and "[solver: " in verbose and "lam=" in verbose
    text = (out / "branch.csv").read_text()
    assert "nan" not in text.lower() and "inf" not in text.lower()
    rows = list(csv.DictReader(text.splitlines()))
    assert len(rows) >= 5
    assert max(float(r["speed_ratio"]) for r in rows) < 1.4
    assert max(float(r["defl_1"]) for r in rows) < 1.0
    ds = read_branch(out / "branch.nc")
    assert ds.attrs["success"] == 0 and "limit" in ds.attrs["message"]
    assert ds.attrs["ended"] == "limit" and ds.attrs["outcome"] == err.strip().split(
        "warning: ", 1)[1] + verbose.strip()[len(err.strip()):]
    for name, var in {**ds.data_vars, **ds.coords}.items():
        if np.issubdtype(var.dtype, np.number):
            assert np.all(np.isfinite(var.values)), name


def test_messages_in_the_users_terms(tmp_path, capsys):
    """Issue 24 item 1: the outcome names the field to change (max_points) and the
    success line says where the branch ended in Omega~, not in the solver's lam."""
    config = small_rotor_toml(tmp_path / "small.toml")
    sets = ["--set", "analysis.stability.enabled=false"]
    assert main(["response", str(config), "-o", str(tmp_path / "a"), *sets]) == 0
    out = capsys.readouterr().out
    assert "ok: reached the end of the range at Omega~ = 1.4 (" in out and "lam=" not in out
    status = main(["response", str(config), "-o", str(tmp_path / "b"), "--quiet", *sets,
                   "--set", "analysis.response.max_points=5"])
    err = capsys.readouterr().err
    assert status == 1 and "stopped after 5 points at Omega~ = " in err
    assert ": analysis.response.max_points reached (raise it" in err


def test_success_line_keeps_the_continuation_warnings(tmp_path):
    """The user's line replaces the solver's 'lam=' but keeps its '; warning: ...' tail."""
    from rotorsfd import api

    config = api.load_config(small_rotor_toml(tmp_path / "small.toml"),
                             ["analysis.stability.enabled=false"])
    result = api.run_response(config, progress=False)
    result.branch.message += "; warning: HB truncation error above 0.001 at a test point"
    assert result.message.startswith("reached the end of the range at Omega~ = 1.4 (")
    assert result.message.endswith("; warning: HB truncation error above 0.001 at a test "
                                   "point")
