"""Interruptions (issue 24, item 4): Ctrl-C on `response` writes the points computed so
far and says where; a result folder is marked INCOMPLETE.txt while a command runs, the
mark stays when the run is interrupted or killed and goes when it ends."""

from __future__ import annotations

import dataclasses
import os
import re
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest

from rotors import small_rotor_toml
from rotorsfd import cli
from rotorsfd.errors import ConvergenceError
from rotorsfd.io.marker import MARKER

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"


def _with_handler(monkeypatch: pytest.MonkeyPatch, handler) -> None:
    spec = cli.COMMANDS["modal"]
    monkeypatch.setitem(cli.COMMANDS, "modal", dataclasses.replace(spec, handler=handler))


def test_marker_while_running_then_removed(tmp_path, monkeypatch):
    out = tmp_path / "out"
    seen = []

    def handler(args, config):
        seen.append((out / MARKER).read_text())
        (out / "result.csv").write_text("a\n")
        return 0

    _with_handler(monkeypatch, handler)
    assert cli.main(["modal", str(PAPER), "-o", str(out), "-q"]) == 0
    assert seen[0].startswith("rotorsfd modal started writing this folder at ")
    assert "has not finished: if this file is still here, the run was killed" in seen[0]
    assert sorted(p.name for p in out.iterdir()) == ["result.csv", "run.json"]


def test_failure_before_any_result_leaves_no_folder(tmp_path, monkeypatch, capsys):
    def handler(args, config):
        raise ConvergenceError("journal contact at Omega = 900 rad/s")

    _with_handler(monkeypatch, handler)
    assert cli.main(["modal", str(PAPER), "-o", str(tmp_path / "out")]) == 1
    assert not (tmp_path / "out").exists()
    existing = tmp_path / "old"                     # a folder of an earlier run stays as it was
    existing.mkdir()
    (existing / "branch.csv").write_text("x\n")
    assert cli.main(["modal", str(PAPER), "-o", str(existing)]) == 1
    assert [p.name for p in existing.iterdir()] == ["branch.csv"]


def test_interrupt_keeps_the_marker(tmp_path, monkeypatch, capsys):
    def handler(args, config):
        raise KeyboardInterrupt

    _with_handler(monkeypatch, handler)
    out = tmp_path / "out"
    assert cli.main(["modal", str(PAPER), "-o", str(out)]) == 130
    assert capsys.readouterr().err == (f"rotorsfd: interrupted: {out / MARKER} marks the "
                                       "folder incomplete\n")
    text = (out / MARKER).read_text()
    assert text.startswith("rotorsfd modal was interrupted (Ctrl-C) at ")
    assert text.endswith("The other files may be partial or missing.\n")


def test_ctrl_c_on_response_writes_the_points_so_far(tmp_path):
    """A real SIGINT while the branch is being continued (a small step: ~800 points)."""
    cfg = small_rotor_toml(tmp_path / "rotor.toml")
    out = tmp_path / "out"
    proc = subprocess.Popen(
        [sys.executable, "-m", "rotorsfd", "response", str(cfg), "-o", str(out),
         "--set", "analysis.response.step_max=0.01", "--set",
         "analysis.stability.enabled=false"],
        stdout=subprocess.PIPE, stderr=subprocess.PIPE,
        env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    seen, deadline = b"", time.monotonic() + 240
    while time.monotonic() < deadline:               # the progress bar: "N points"
        chunk = proc.stderr.read1(4096)
        assert chunk, (proc.wait(), seen.decode())
        seen += chunk
        counts = re.findall(rb"response: (\d+) points", seen)
        if counts and int(counts[-1]) >= 5:
            break
    proc.send_signal(signal.SIGINT)
    out_text, err = proc.communicate(timeout=240)
    err = (seen + err).decode()
    assert proc.returncode == 130, err
    assert "stopping after the current point and writing what was computed" in err
    m = re.search(r"rotorsfd: interrupted: the (\d+) points computed before Ctrl-C "
                  r"\(Omega~ = 0\.6 \.\. ([\d.]+)\) are written to (\S+); (\S+) marks the "
                  r"folder incomplete", err)
    assert m, err
    n, end = int(m[1]), float(m[2])
    assert m[3] == str(out) and m[4] == str(out / MARKER)
    assert 5 <= n < 300 and 0.6 < end < 1.4
    rows = (out / "branch.csv").read_text().splitlines()
    assert len(rows) == n + 1                        # header + the points
    assert (out / "branch.nc").is_file()
    marker = (out / MARKER).read_text()
    assert f"The {n} points computed before Ctrl-C" in marker
    assert b"wrote " in out_text and f"{n} points".encode() in out_text
    assert b"callback" not in out_text               # solver wording: not for the user


def test_rerun_after_a_kill_removes_half_written_files(tmp_path, monkeypatch):
    """SIGKILL while writing leaves the marker and a temporary file; the next run in the
    folder removes the temporary file and, once it has finished, the marker."""
    out = tmp_path / "out"
    (out / "points").mkdir(parents=True)
    (out / MARKER).write_text("rotorsfd modal started writing this folder ...\n")
    stale = [out / ".branch.nc.k2j3h4.tmp.nc", out / "points" / ".000001.json.ab12.tmp.json"]
    for p in stale:
        p.write_bytes(b"")
    (out / "campbell.csv").write_text("kept\n")
    seen = []
    _with_handler(monkeypatch, lambda args, config: seen.append(
        sorted(p.name for p in out.rglob("*"))) or 0)
    assert cli.main(["modal", str(PAPER), "-o", str(out), "-q"]) == 0
    assert seen == [[MARKER, "campbell.csv", "points"]]
    assert sorted(p.name for p in out.rglob("*")) == ["campbell.csv", "points", "run.json"]
