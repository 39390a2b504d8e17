"""``rotorsfd response --switch-at bp:N``: the second branch at the N-th branch point
(issue 21 item 2), and the ``--switch-at`` values (``pd:N``, ``bp:N``, plain ``N``).

The CLI cannot express the pumped Mathieu oscillator of tests/stability/test_branch_points
(no config describes a PeriodicProblem of one's own), so the case is a rotor:
tests/data/issue21_branch_point.toml (the issue-14 anisotropic rotor, no gravity, so its
response keeps x(t + T/2) = -x(t)). Its HB equations at H = 13 and N_f = 32 (fixed in the
file) have two pairs of symmetry-breaking pitchforks near Omega~ = 0.307-0.312, each pair
joined by a loop of symmetry-broken orbits (no Floquet multiplier crosses +1 there: they
are the truncated, coarsely sampled equations' branch points; with the default adaptive
H and N_f the branch has none). Checks:

- the CLI's branch_bp1.nc = the Python ``switch_branch_point`` at the located point, with
  the same keywords, leg by leg (1e-9; the CLI stops each leg where it closes on itself,
  the Python call is cut at the same count of points);
- independent of both: the two legs are mirror images under the broken symmetry (their
  odd harmonics equal, their even ones opposite: X_k -> (-1)^(k+1) X_k, 1e-9 C) while the
  main branch has no even harmonics; each leg closes where it started;
- bad values: one line naming --switch-at, the value and what is allowed, exit 2; before
  the work where that can be known (prefix, N < 1, stability off), after the main branch
  is written where it needs the branch (no branch point, N too large, an untyped one).
"""

from __future__ import annotations

from pathlib import Path
from types import SimpleNamespace

import numpy as np
import pytest

from rotorsfd import api, cli
from rotorsfd.analyses.response_branch_switch import (
    check_branch_switch,
    second_branch_problem,
    switch_kwargs,
)
from rotorsfd.cli.response import switch_point
from rotorsfd.errors import ConfigError
from rotorsfd.stability.branch_points import switch_branch_point

ROOT = Path(__file__).parents[2]
CASE = ROOT / "tests" / "data" / "issue21_branch_point.toml"
PAPER = ROOT / "examples" / "paper_rotor.toml"


def one_error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    lines = [line for line in err.strip().splitlines() if line.startswith("rotorsfd: error")]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


@pytest.fixture(scope="module")
def cli_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("bp") / "o"
    status = cli.main(["response", str(CASE), "-o", str(out), "-q", "--switch-at", "bp:1"])
    return status, out


@pytest.fixture(scope="module")
def second(cli_run):
    import xarray as xr

    from rotorsfd.io.branch_files import coefficients

    _, out = cli_run
    with xr.open_dataset(out / "branch_bp1.nc") as ds:
        X, leg = coefficients(ds), ds["leg"].values
        lam, attrs = ds["parameter"].values, dict(ds.attrs)
    with xr.open_dataset(out / "branch.nc") as ds:
        main = coefficients(ds)
    return {"X": X, "leg": leg, "lam": lam, "attrs": attrs, "main": main}


def test_cli_second_branch_is_the_python_switch(cli_run, second):
    status, out = cli_run
    assert status == 0
    for name in ("branch_bp1.nc", "branch_bp1.csv", "branch.csv", "response_deflection.png"):
        assert (out / name).exists()
    assert second["attrs"]["branch_point_kind"] == "symmetry-breaking pitchfork"
    cfg = api.load_config(str(CASE))
    r = api.run_response(cfg, progress=False)
    bif = next(b for b in r.info["stability"].bifurcations if "branch_point" in b.info)
    point = bif.info["branch_point"]
    assert second["attrs"]["branch_point_parameter"] == pytest.approx(point.lam, rel=1e-12)
    counts = np.bincount(second["leg"])
    assert len(counts) == 2 and counts.min() > 10
    lam = r.branch.lam
    sw = switch_branch_point(second_branch_problem(r), point,
                             (float(lam.min()), float(lam.max())),
                             **switch_kwargs(r, max_points=int(counts.max())))
    C = r.clearance
    for k, leg in enumerate(sw.legs):
        mine = second["leg"] == k
        assert leg.n_points == counts[k]
        assert np.max(np.abs(leg.lam - second["lam"][mine])) <= 1e-9 * abs(point.lam)
        h = leg.X.shape[1]
        assert np.max(np.abs(leg.X - second["X"][mine][:, :h])) / C < 1e-9


def test_pitchfork_legs_are_mirror_images_off_the_symmetric_branch(cli_run, second):
    X, leg, lam = second["X"], second["leg"], second["lam"]
    C = 0.127e-3
    a, b = X[leg == 0], X[leg == 1]
    assert np.max(np.abs(lam[leg == 0] - lam[leg == 1])) < 1e-9 * lam.max()
    k = np.arange(X.shape[1])
    sign = np.where(k % 2 == 1, 1.0, -1.0)[None, :, None]      # X_k -> (-1)^(k+1) X_k
    assert np.max(np.abs(a - sign * b)) / C < 1e-9
    # the symmetry-broken part: even harmonics (mean, 2X, ...) on the second branch only
    even = np.abs(a[:, 0::2]).max(axis=(1, 2)) / C
    assert even[1:-1].min() > 1e-4
    assert np.abs(second["main"][:, 0::2]).max() / C < 1e-10
    # each leg goes round the loop and stops back at its first point (the closure stop)
    for x, w in ((a, lam[leg == 0]), (b, lam[leg == 1])):
        far = np.abs(x - x[0]).max(axis=(1, 2)) / C
        assert far.max() > 10 * np.abs(x[-1] - x[0]).max() / C
        assert abs(w[-1] - w[0]) < 1e-3 * w[0]


def test_switch_at_values_parse_as_pd_or_bp():
    assert switch_point("3")[:2] == ("pd", 3) == switch_point("pd:3")[:2]
    assert switch_point("bp:2")[:2] == ("bp", 2)
    assert switch_point("BP:1").text == "BP:1"


@pytest.mark.parametrize("value, words", [("xx:1", "expected pd:N"), ("bp:0", "must be >= 1"),
                                          ("bp:", "expected pd:N"), ("0", "must be >= 1")])
def test_bad_switch_values_stop_before_the_work(tmp_path, capsys, monkeypatch, value, words):
    def reached(*a, **k):
        raise AssertionError("the response started")

    monkeypatch.setattr("rotorsfd.api.run_response", reached)
    status = cli.main(["response", str(CASE), "-o", str(tmp_path / "o"),
                       "--switch-at", value])
    line = one_error_line(capsys)
    assert status == 2 and "--switch-at" in line and words in line and value in line
    assert "bp:N" in line and "pd:N" in line


def test_bp_without_stability_stops_before_the_work(tmp_path, capsys, monkeypatch):
    def reached(*a, **k):
        raise AssertionError("the response started")

    monkeypatch.setattr("rotorsfd.api.run_response", reached)
    status = cli.main(["response", str(CASE), "-o", str(tmp_path / "o"), "--switch-at",
                       "bp:1", "--set", "analysis.stability.enabled=false"])
    line = one_error_line(capsys)
    assert status == 2 and "'bp:1'" in line and "analysis.stability.enabled" in line
    assert "branch points" in line


def test_bp_on_a_branch_without_branch_points(tmp_path, capsys):
    out = tmp_path / "o"
    status = cli.main(["response", str(PAPER), "-o", str(out), "-q", "--switch-at", "bp:1",
                       "--set", "analysis.response.speed_range={start_ratio=0.5, "
                       "stop_ratio=0.56}"])
    line = one_error_line(capsys)
    assert status == 2
    assert "--switch-at" in line and "'bp:1'" in line and "no branch point" in line
    assert (out / "branch.csv").exists() and not (out / "branch_bp1.csv").exists()


def fake_result(types: list[str], located: list[bool]) -> SimpleNamespace:
    """The parts of a ResponseResult the check reads: bifurcation rows and the located
    bifurcations (a branch point's ``info['branch_point']`` when it is typed)."""
    rows = [{"type": t, "speed_ratio": 0.3 + 0.01 * i} for i, t in enumerate(types)]
    bifs = [SimpleNamespace(info={"branch_point": object()} if ok else {})
            for ok in located]
    return SimpleNamespace(bifurcations=rows, info={"stability": SimpleNamespace(
        bifurcations=bifs)}, is_speed=True)


def test_bp_number_out_of_range_and_untyped_branch_points():
    r = fake_result(["saddle-node", "pitchfork", "period-doubling", "branch-point"],
                    [False, True, False, False])
    assert check_branch_switch(r, 1) == 1
    with pytest.raises(ConfigError) as exc:
        check_branch_switch(r, 3, "bp:3")
    text = str(exc.value)
    assert text.startswith("--switch-at: got 'bp:3'") and "bp:1..bp:2" in text
    assert "1: pitchfork at Omega~ = 0.31" in text and "2: branch-point at" in text
    with pytest.raises(ConfigError, match="untyped branch-point"):
        check_branch_switch(r, 2)


def test_bp_number_too_large_after_the_main_branch(cli_run, tmp_path, capsys):
    out = tmp_path / "o"
    status = cli.main(["response", str(CASE), "-o", str(out), "-q", "--switch-at", "bp:5"])
    line = one_error_line(capsys)
    assert status == 2 and "'bp:5'" in line and "bp:1..bp:4" in line
    assert (out / "branch.csv").exists() and not (out / "branch_bp5.csv").exists()
