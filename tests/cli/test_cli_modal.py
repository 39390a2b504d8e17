"""`rotorsfd modal CONFIG -o DIR` writes the three files with the agreed columns."""

import csv
import os
import subprocess
import sys
from pathlib import Path

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"


def test_modal_writes_its_three_files_and_run_json(tmp_path):
    out = tmp_path / "modal"
    proc = subprocess.run(
        [sys.executable, "-m", "rotorsfd", "modal", str(PAPER), "-o", str(out),
         "--set", "analysis.modal.speed_range.n=11"],
        capture_output=True, text=True, timeout=600,
        env={**os.environ, "OPENBLAS_NUM_THREADS": "1"})
    assert proc.returncode == 0, proc.stderr
    assert "critical speed 1 (forward)" in proc.stdout
    assert sorted(p.name for p in out.iterdir()) == [
        "campbell.csv", "campbell.png", "critical_speeds.csv",
        "run.json"]                                  # provenance; no temporary files left

    with (out / "critical_speeds.csv").open() as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["mode", "whirl", "speed_rad_s"]
    speeds = [float(r[2]) for r in rows[1:]]
    assert len(speeds) == 2 and speeds == sorted(speeds) and speeds[0] > 0
    assert all(r[1] == "forward" for r in rows[1:])

    with (out / "campbell.csv").open() as fh:
        camp = list(csv.DictReader(fh))
    assert {"speed_rad_s", "mode", "whirl", "frequency_rad_s"} <= set(camp[0])
    assert len({r["speed_rad_s"] for r in camp}) == 11
    assert (out / "campbell.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_run_modal_api_quiet(tmp_path):
    """The same through the Python API; a constant base rate enters the modal system."""
    from rotorsfd import api

    cfg = api.load_config(PAPER, ["analysis.modal.speeds=[0, 500, 1000]",
                                  "analysis.modal.n_critical=1"])
    fixed = api.run_modal(cfg)
    assert fixed.campbell.speeds.tolist() == [0, 500, 1000]
    rolling = api.run_modal(api.with_values(cfg, {"base.rolling.law": "constant",
                                                  "base.rolling.value": "50 rad/s"}))
    assert rolling.critical_speeds[0].speed_rad_s != fixed.critical_speeds[0].speed_rad_s
    paths = fixed.write(tmp_path)
    assert sorted(paths) == ["campbell.csv", "campbell.png", "critical_speeds.csv"]
