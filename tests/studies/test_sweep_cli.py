"""``rotorsfd sweep``: SIGKILL halfway and --resume gives the uninterrupted files without
recomputing finished points; progress bar and --quiet; --scheduler on a LocalCluster."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import time
from pathlib import Path

import pytest
import xarray as xr
from sweep_helpers import sweep_toml

from rotorsfd.cli import main

AXES = ["--axis", "elements.sfd.clearance_ratio=0.4 %,0.5 %,0.6 %",
        "--axis", "unbalance[0].magnitude=40 g*mm,45 g*mm,50 g*mm,55 g*mm"]
FILES = ("sweep.nc", "summary.csv", "sweep.json")


def _cli(*args: str) -> list[str]:
    return [sys.executable, "-m", "rotorsfd", "sweep", *args]


#: attributes that say how a run was invoked (provenance): a resumed sweep's differ
INVOCATION = ("command_line",)


def _bytes(directory: Path) -> dict[str, object]:
    """The result files byte for byte; sweep.nc as its data and attributes without the
    invocation's (the command line of a resumed or dask run is another one)."""
    out: dict[str, object] = {f: (directory / f).read_bytes() for f in FILES
                              if f != "sweep.nc"}
    with xr.open_dataset(directory / "sweep.nc") as ds:
        d = ds.load().to_dict()
    for name in INVOCATION:
        d["attrs"].pop(name, None)
    out["sweep.nc"] = repr(d)
    return out


def _env() -> dict[str, str]:
    return {**os.environ, "OPENBLAS_NUM_THREADS": "1"}


def test_sigkill_then_resume_equals_uninterrupted(tmp_path):
    cfg = sweep_toml(tmp_path / "rotor.toml")
    full, part = tmp_path / "full", tmp_path / "part"
    assert main(["sweep", str(cfg), "-o", str(full), "--task", "synthetic:fail_above=0.0055",
                 "--workers", "1", "--quiet", *AXES]) == 0
    log1, log2 = tmp_path / "run1.log", tmp_path / "run2.log"
    proc = subprocess.Popen(
        _cli(str(cfg), "-o", str(part), "--task",
             f"synthetic:fail_above=0.0055,delay=0.4,log={log1}", "--workers", "2",
             "--quiet", *AXES), env=_env(), start_new_session=True,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    points = part / "points"
    deadline = time.monotonic() + 60
    while time.monotonic() < deadline:
        if len(list(points.glob("0*.json"))) >= 4:
            break
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.02)
    os.killpg(proc.pid, signal.SIGKILL)                    # the CLI and its workers
    proc.wait()
    finished = {p.stem for p in points.glob("0*.json")}
    assert 4 <= len(finished) < 12, finished
    assert not (part / "sweep.nc").exists()                # killed: nothing combined
    run = subprocess.run(
        _cli(str(cfg), "-o", str(part), "--task",
             f"synthetic:fail_above=0.0055,log={log2}", "--workers", "2", "--resume",
             "--quiet", *AXES), env=_env(), capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    rerun = log2.read_text().splitlines()
    assert len(rerun) == 12 - len(finished)                # none of the finished points
    values = {f"{i * 4 + j:06d}": (c, u) for i, c in enumerate((0.004, 0.005, 0.006))
              for j, u in enumerate((4e-5, 4.5e-5, 5e-5, 5.5e-5))}
    recomputed = {pid for pid, v in values.items()
                  if any(line == repr(v) for line in rerun)}
    assert recomputed == set(values) - finished
    assert _bytes(part) == _bytes(full)


def _default_sigint() -> None:
    """The CLI starts as a terminal's foreground job does, with SIGINT at its default and
    not blocked (a child inherits an ignored SIGINT and the signal mask across exec: an
    ignored SIGINT stays ignored in Python, a blocked one is never delivered). In
    two fresh-clone parallel suites the sweep ran on after the SIGINT and exited 0, while
    the test alone passed; the cause is not found yet: the failure message prints this
    process's SIGINT handler."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    signal.pthread_sigmask(signal.SIG_UNBLOCK, {signal.SIGINT})


def test_ctrl_c_leaves_valid_partial_result(tmp_path):
    cfg = sweep_toml(tmp_path / "rotor.toml")
    out = tmp_path / "out"
    proc = subprocess.Popen(
        _cli(str(cfg), "-o", str(out), "--task", "synthetic:delay=4.0", "--workers", "2",
             "--quiet", *AXES), env=_env(), start_new_session=True,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True, preexec_fn=_default_sigint)
    deadline = time.monotonic() + 60
    while len(list((out / "points").glob("0*.json"))) < 2 and time.monotonic() < deadline:
        time.sleep(0.02)
    # 4 s a point: 24 s for the sweep and the SIGINT after the first two points, so under
    # a loaded parallel suite it still lands mid-sweep (at 1 s and at 2 s a point, after
    # three points, fresh-clone runs twice saw the sweep finish first: a starved parent
    # saves the points of several finished futures at once)
    assert proc.poll() is None, "the sweep ended before the SIGINT was sent"
    assert len(list((out / "points").glob("0*.json"))) < 12
    os.killpg(proc.pid, signal.SIGINT)                     # Ctrl-C at the terminal
    _, err = proc.communicate(timeout=30)
    assert proc.returncode == 130, (err, "SIGINT in the test process:",
                                    signal.getsignal(signal.SIGINT), "blocked:",
                                    signal.SIGINT in signal.pthread_sigmask(
                                        signal.SIG_BLOCK, set()))
    assert "--resume" in err
    manifest = json.loads((out / "sweep.json").read_text())
    done = len(list((out / "points").glob("0*.json")))
    assert manifest["complete"] is False and manifest["counts"]["ok"] == done < 12
    with xr.open_dataset(out / "sweep.nc") as ds:
        assert ds.attrs["complete"] == 0 and int((ds["status"] == 3).sum()) == 12 - done
    lines = (out / "summary.csv").read_text().splitlines()
    assert len(lines) == 13 and sum(",pending," in row for row in lines) == 12 - done


def test_progress_bar_and_quiet(tmp_path, capsys):
    cfg = sweep_toml(tmp_path / "rotor.toml")
    assert main(["sweep", str(cfg), "-o", str(tmp_path / "a"), "--task", "synthetic",
                 "--workers", "1", *AXES]) == 0
    out, err = capsys.readouterr()
    assert "sweep" in err and "12/12" in err and "pt/s" in err    # tqdm with rate / ETA
    assert "12 points (3 x 4): 12 ok" in out and "sweep.nc" in out
    assert main(["sweep", str(cfg), "-o", str(tmp_path / "b"), "--task", "synthetic",
                 "--workers", "1", "--quiet", *AXES]) == 0
    assert capsys.readouterr() == ("", "")


def test_existing_folder_needs_resume_and_bad_task(tmp_path, capsys):
    cfg = sweep_toml(tmp_path / "rotor.toml")
    args = ["sweep", str(cfg), "-o", str(tmp_path / "a"), "--workers", "1", "--quiet", *AXES]
    assert main([*args, "--task", "synthetic"]) == 0
    assert main([*args, "--task", "synthetic"]) == 2
    assert "--resume" in capsys.readouterr().err
    assert main([*args, "--task", "synthetic", "--resume"]) == 0
    assert main(["sweep", str(cfg), "-o", str(tmp_path / "c"), "--task", "nope"]) == 2
    assert "allowed: response, simulate, stability-chart, synthetic" in capsys.readouterr().err


def test_scheduler_option_on_local_cluster(tmp_path):
    distributed = pytest.importorskip("distributed")
    cfg = sweep_toml(tmp_path / "rotor.toml")
    assert main(["sweep", str(cfg), "-o", str(tmp_path / "serial"), "--task",
                 "synthetic:fail_above=0.0055", "--workers", "1", "--quiet", *AXES]) == 0
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=False,
                                  host="127.0.0.1", protocol="tcp",
                                  dashboard_address=None) as cluster:
        run = subprocess.run(
            _cli(str(cfg), "-o", str(tmp_path / "dask"), "--task",
                 "synthetic:fail_above=0.0055", "--scheduler", cluster.scheduler_address,
                 "--quiet", *AXES), env=_env(), capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert _bytes(tmp_path / "dask") == _bytes(tmp_path / "serial")


def _group(pgid: int) -> list[str]:
    """Live processes of the process group ``pgid`` (zombies excluded: init reaps them)."""
    ps = subprocess.run(["ps", "-ww", "-o", "pid=,stat=,args=", "-g", str(pgid)],
                        capture_output=True, text=True)
    return [line for line in ps.stdout.splitlines() if line.split()[1][0] != "Z"]


def test_sigkill_of_the_cli_leaves_no_process(tmp_path):
    """Only the `rotorsfd sweep` process is killed: its workers, the forkserver and the
    resource tracker exit by themselves, quietly; the folder is marked incomplete."""
    cfg = sweep_toml(tmp_path / "rotor.toml")
    out = tmp_path / "out"
    proc = subprocess.Popen(
        _cli(str(cfg), "-o", str(out), "--task", "synthetic:delay=1.0", "--workers", "2",
             "--quiet", *AXES), env=_env(), start_new_session=True,
        stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    deadline = time.monotonic() + 120
    while not list((out / "points").glob("0*.json")) and time.monotonic() < deadline:
        assert proc.poll() is None, proc.communicate()
        time.sleep(0.02)
    before = _group(proc.pid)
    assert any("forkserver" in line for line in before), before
    assert sum("forkserver" in line for line in before) >= 3, before   # server + 2 workers
    assert any("resource_tracker" in line for line in before), before
    os.kill(proc.pid, signal.SIGKILL)                      # the CLI only, not its group
    proc.wait()
    deadline = time.monotonic() + 20
    while _group(proc.pid) and time.monotonic() < deadline:
        time.sleep(0.1)
    assert _group(proc.pid) == []
    _, err = proc.communicate(timeout=10)
    assert "leaked" not in err and "Traceback" not in err, err
    assert "and has not finished" in (out / "INCOMPLETE.txt").read_text()
    run = subprocess.run(_cli(str(cfg), "-o", str(out), "--task", "synthetic", "--workers",
                              "2", "--resume", "--quiet", *AXES),
                         env=_env(), capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert not (out / "INCOMPLETE.txt").exists()
