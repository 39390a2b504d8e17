"""``rotorsfd rerun DIR`` (issue 23 item 3): a result made again from its run.json gives
the same files; a folder without run.json is refused in one line (exit 2)."""

from __future__ import annotations

import json

import pytest
import xarray as xr

from rotors import small_rotor_toml
from rotorsfd import cli
from rotorsfd.io import provenance

#: a short, cheap branch: one harmonic, no stability, a narrow speed range
SMALL = ["--set", "analysis.stability.enabled=false", "--set", "analysis.response.harmonics=1",
         "--set", "analysis.response.speed_range.start_ratio=0.9",
         "--set", "analysis.response.speed_range.stop_ratio=1.1"]


def test_folder_without_run_json_is_one_line_exit_2(tmp_path, capsys):
    assert cli.main(["rerun", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1
    assert err[0].startswith(cli.PREFIX) and "run.json" in err[0] and str(tmp_path) in err[0]


def test_run_json_naming_no_command_is_one_line_exit_2(tmp_path, capsys):
    (tmp_path / provenance.RUN_FILE).write_text(json.dumps({"command": "no-such"}))
    assert cli.main(["rerun", str(tmp_path)]) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "no-such" in err[0]


@pytest.mark.slow
def test_response_rerun_gives_identical_files(tmp_path, monkeypatch):
    """branch.csv has no time stamp (elapsed time and dates are only netCDF attributes),
    so it is compared byte for byte; branch.nc's data variables and coordinates exactly."""
    monkeypatch.chdir(tmp_path)                       # relative paths, as a user types them
    small_rotor_toml(tmp_path / "small.toml")
    assert cli.main(["response", "small.toml", *SMALL, "-o", "first", "-q"]) == 0
    record = json.loads((tmp_path / "first" / "run.json").read_text())
    assert record["command"] == "response"
    assert record["argv"][:2] == ["response", "small.toml"]
    assert "harmonics = 1" in record["config_toml"]   # resolved: --set applied
    (tmp_path / "small.toml").write_text("not toml at all")   # the saved config is used

    elsewhere = tmp_path / "elsewhere"
    elsewhere.mkdir()
    monkeypatch.chdir(elsewhere)                      # the saved working folder is used
    assert cli.main(["rerun", "../first", "-o", "../second", "-q"]) == 0
    first, second = tmp_path / "first", tmp_path / "second"
    assert (second / "branch.csv").read_bytes() == (first / "branch.csv").read_bytes()
    with xr.open_dataset(first / "branch.nc") as a, xr.open_dataset(second / "branch.nc") as b:
        assert set(a.data_vars) == set(b.data_vars) and a.sizes["point"] > 3
        for name in (*a.data_vars, *a.coords):
            xr.testing.assert_identical(a[name], b[name])
        assert a.attrs["config_toml"] == b.attrs["config_toml"]
        assert b.attrs["command_line"] == "rotorsfd rerun ../first -o ../second -q"
    again = json.loads((second / "run.json").read_text())
    assert again["config_toml"] == record["config_toml"] and again["cwd"] == str(tmp_path)
    assert not (second / "INCOMPLETE.txt").exists()


@pytest.mark.parametrize("argv", [["rerun", "--help"]])
def test_rerun_is_a_registered_command(argv, capsys):
    assert cli.main(argv) == 0
    assert "run.json" in capsys.readouterr().out


@pytest.mark.slow
def test_simulate_rerun_keeps_the_analysis_options(tmp_path):
    """--speed-ratio, --record-periods and --lyapunov-periods are parsed again from the
    saved argv: timeseries.nc's variables and poincare.csv (no time stamp) come out the
    same."""
    config = small_rotor_toml(tmp_path / "small.toml")
    argv = ["simulate", str(config), "--set", "analysis.simulate.periods=20",
            "--set", "analysis.simulate.poincare_periods=5",
            "--set", "analysis.simulate.steps_per_period=64", "--speed-ratio", "0.9",
            "--record-periods", "4", "--lyapunov-periods", "0", "-o", str(tmp_path / "a"),
            "-q"]
    assert cli.main(argv) == 0
    assert cli.main(["rerun", str(tmp_path / "a"), "-o", str(tmp_path / "b"), "-q"]) == 0
    a, b = tmp_path / "a", tmp_path / "b"
    assert (a / "poincare.csv").read_bytes() == (b / "poincare.csv").read_bytes()
    with xr.open_dataset(a / "timeseries.nc") as x, xr.open_dataset(b / "timeseries.nc") as y:
        assert x.sizes["time"] == y.sizes["time"] and x.attrs["speed_ratio"] == 0.9
        for name in (*x.data_vars, *x.coords):
            xr.testing.assert_identical(x[name], y[name])
