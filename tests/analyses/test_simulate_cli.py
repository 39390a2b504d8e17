"""``rotorsfd simulate``: the documented files and columns, the summary, the HB start,
contact (one line, exit 1, nothing written), bad arguments (exit 2)."""

from __future__ import annotations

import csv
import json

import numpy as np
import pytest
import xarray as xr

from rotors import small_rotor_toml
from rotorsfd.cli import main

C = 0.127e-3
FILES = ("timeseries.nc", "poincare.csv", "summary.json", "simulation.png", "orbit.png",
         "phase.png", "poincare.png", "spectrum.png")
SHORT = ["--set", "analysis.simulate.periods=120", "--set",
         "analysis.simulate.poincare_periods=20", "--set",
         "analysis.simulate.steps_per_period=100"]


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("simulate")
    cfg = small_rotor_toml(tmp / "small.toml", unbalance="100 g*mm", reference="800 rad/s")
    status = main(["simulate", str(cfg), "--speed-ratio", "1.05", "-o", str(tmp / "out"),
                   "-q", "--lyapunov-periods", "30", "--record-periods", "3", *SHORT])
    return status, tmp / "out", cfg


def test_files_and_columns(run) -> None:
    status, out, _ = run
    assert status == 0
    for name in FILES:
        assert (out / name).stat().st_size > 0, name
    with (out / "poincare.csv").open() as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["node", "period", "y", "z", "vy", "vz"]
    nodes = sorted({int(r[0]) for r in rows[1:]})
    assert nodes == [1, 3]
    periods = sorted({int(r[1]) for r in rows[1:]})
    assert periods == list(range(101, 121))            # the last 20 of 120 periods
    with xr.open_dataset(out / "timeseries.nc") as ds:
        assert set(ds["displacement"].dims) == {"time", "node", "direction"}
        assert list(ds["direction"].values) == ["y", "z"]
        assert list(ds["node"].values) == [1, 3]
        assert ds.sizes["time"] == 3 * 100 + 1         # the last 3 periods, both ends
        q = ds["displacement"].values
        assert np.all(np.isfinite(q)) and np.all(np.isfinite(ds["velocity"].values))
        t_end = float(ds["time"].values[-1])
        assert t_end == pytest.approx(120 * 2 * np.pi / (1.05 * 800))
        # the Poincare rows are the time series at t = k T
        first = next(r for r in rows[1:] if r[0] == "1" and r[1] == "120")
        assert float(first[2]) == pytest.approx(q[-1, 0, 0], rel=1e-12)


def test_summary(run) -> None:
    _, out, _ = run
    s = json.loads((out / "summary.json").read_text())
    assert s["motion"] == "period-1"
    ev = s["evidence"]
    assert ev["n_distinct_poincare"] == 1 and ev["poincare_period"] == 1
    assert ev["spectral_lines"][0]["ratio"] == pytest.approx(1.0, abs=1e-6)
    assert s["lyapunov"]["per_period"] < 0.01
    assert 0.3 < s["max_eccentricity"] <= s["max_eccentricity_whole_run"] < 1.0
    st = s["settings"]
    assert (st["steps_per_period"], st["periods"], st["poincare_periods"],
            st["record_periods"], st["scheme"]) == (100, 120, 20, 3, "newmark")
    assert st["speed_ratio"] == pytest.approx(1.05) and s["elapsed_s"] > 0
    assert "NaN" not in (out / "summary.json").read_text()


def test_from_hb_starts_on_the_orbit(run, tmp_path) -> None:
    """Started on the HB orbit, the first recorded period is already steady: the journal
    Poincare points agree with the displaced start's to 2e-3 C after 120 periods, and
    with each other from the first period on."""
    _, out, cfg = run
    status = main(["simulate", str(cfg), "--speed", "840", "-o", str(tmp_path), "-q",
                   "--from-hb", "--lyapunov-periods", "0", *SHORT,
                   "--set", "analysis.simulate.poincare_periods=120",
                   "--set", "analysis.response.harmonics=6"])
    assert status == 0
    s = json.loads((tmp_path / "summary.json").read_text())
    assert s["settings"]["initial_state"].startswith("HB")
    with (tmp_path / "poincare.csv").open() as fh:
        rows = [r for r in csv.DictReader(fh) if r["node"] == "1"]
    y = np.array([float(r["y"]) for r in rows])
    assert np.ptp(y) < 2e-3 * C                        # no transient to speak of
    with (out / "poincare.csv").open() as fh:
        ref = [r for r in csv.DictReader(fh) if r["node"] == "1"]
    assert abs(float(ref[-1]["y"]) - y[-1]) < 2e-3 * C


def test_contact_ends_the_run_exit_0_with_a_warning(tmp_path, capsys) -> None:
    """Too coarse a step for a large unbalance: the Newton iterates reach the contact
    limit; the run ends there as a result (issue 22 item 3): exit 0, the files written
    with ``ended = "limit"``, one warning line with time, rotor period and eps."""
    cfg = small_rotor_toml(tmp_path / "small.toml", unbalance="5000 g*mm",
                           reference="800 rad/s")
    out = tmp_path / "out"
    status = main(["simulate", str(cfg), "--speed-ratio", "1.0", "-o", str(out), "-q",
                   "--set", "analysis.simulate.steps_per_period=8",
                   "--set", "analysis.simulate.periods=50",
                   "--set", "analysis.simulate.poincare_periods=10"])
    err = [line for line in capsys.readouterr().err.strip().splitlines()
           if line.startswith("rotorsfd:")]
    assert status == 0
    assert len(err) == 1 and err[0].startswith("rotorsfd: warning: ")
    assert "journal contact" in err[0] and "rotor period" in err[0]
    assert "eccentricity ratio eps=" in err[0]
    summary = json.loads((out / "summary.json").read_text())
    assert summary["ended"] == "limit" and summary["motion"] == "contact"
    assert (out / "timeseries.nc").is_file() and not (out / "INCOMPLETE.txt").exists()


@pytest.mark.parametrize("argv", [["--speed", "800", "--speed-ratio", "1"], []])
def test_bad_speed_arguments_exit_2(tmp_path, capsys, argv) -> None:
    cfg = small_rotor_toml(tmp_path / "small.toml", reference="800 rad/s")
    status = main(["simulate", str(cfg), "-o", str(tmp_path / "out"), "-q", *argv])
    assert status == 2
    assert len(capsys.readouterr().err.strip().splitlines()) == 1
