"""``rotorsfd simulate --speed-law`` and ``[analysis.simulate] speed_law``: the files of a
run-up (orbit against time and speed, eccentricity, the law) and one line for bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.cli import main
from rotorsfd.timedomain.speed_law_config import parse_speed_law_text, speed_law_from_config

RAMP = "ramp,start=500 rad/s,stop=900 rad/s,duration=0.04 s"


@pytest.fixture(scope="module")
def run(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("runup_cli")
    cfg = small_rotor_toml(tmp / "r.toml")
    status = main(["simulate", str(cfg), "--speed-law", RAMP, "-o", str(tmp / "out"), "-q"])
    return status, tmp / "out"


def test_files(run):
    status, out = run
    assert status == 0
    ds = xr.open_dataset(out / "timeseries.nc")
    speed = ds["speed"].values
    assert speed[0] == pytest.approx(500.0) and speed[-1] == pytest.approx(900.0)
    assert np.all(np.diff(speed) >= 0.0)
    np.testing.assert_allclose(ds["speed"].values[ds["time"].values <= 0.04],
                               500.0 + 1e4 * ds["time"].values[ds["time"].values <= 0.04],
                               rtol=1e-12)
    assert "ramp 500 -> 900" in ds.attrs["speed_law"]
    r = ds["radius"].sel(node=1).values
    np.testing.assert_allclose(r, np.hypot(*ds["displacement"].sel(node=1).values.T),
                               rtol=1e-12)
    ecc = ds["eccentricity"].sel(node=1).values
    np.testing.assert_allclose(ecc, r / 0.127e-3, rtol=1e-12)
    for v in ds.data_vars.values():
        assert np.all(np.isfinite(v.values))
    summary = json.loads((out / "summary.json").read_text())
    peak = summary["peaks"]["1"]
    i = int(np.argmax(r))
    assert peak["radius_max_m"] == pytest.approx(r[i], rel=1e-12)
    assert peak["speed_rad_s"] == pytest.approx(speed[i], rel=1e-12)
    assert summary["max_eccentricity_run"] == pytest.approx(ecc.max(), rel=1e-9)


def test_config_field_and_table_law(tmp_path):
    (tmp_path / "speeds.csv").write_text("time_s,speed_rad_s\n0,500\n0.02,700\n0.04,900\n")
    cfg = api.load_config(small_rotor_toml(
        tmp_path / "r.toml", extra='[analysis.simulate]\nspeed_law = { law = "table", '
        'file = "speeds.csv" }\nsteps_per_period = 100\n'))
    res = api.run_simulation(cfg, search_path=tmp_path, progress=False)
    assert res.settings["speed_max_rad_s"] == pytest.approx(900.0)
    assert res.settings["steps_per_period"] == 100
    np.testing.assert_allclose(res.run.omega[res.run.t <= 0.04],
                               500.0 + 1e4 * res.run.t[res.run.t <= 0.04], rtol=1e-9)


def test_rate_gives_the_duration():
    law = speed_law_from_config(parse_speed_law_text(
        "ramp,start=500 rad/s,stop=1200 rad/s,rate=350 rad/s^2"))
    assert law.duration == pytest.approx(2.0)
    law = speed_law_from_config({"law": "ramp", "start": "8000 rpm", "stop": "6000 rpm",
                                 "rate": "-1000 rpm/s"})
    assert law.duration == pytest.approx(2.0)


@pytest.mark.parametrize("argv, needle", [
    (["--speed-law", "ramp,start=500 rad/s,stop=900 rad/s"], "speed_law.duration"),
    (["--speed-law", "ramp,start=500 m,stop=900 rad/s,duration=1 s"], "speed_law.start"),
    (["--speed-law", "spin,start=1"], "speed_law.law"),
    (["--speed-law", "ramp,start=5 rad/s,stop=9 rad/s,rate=-1 rad/s^2"], "speed_law.rate"),
    (["--speed-law", "missing.csv"], "speed_law.file"),
    (["--speed-law", RAMP, "--speed", "500"], "--speed-law"),
    (["--speed-law", "ramp,start"], "--speed-law"),
])
def test_bad_speed_law_exit_2_one_line(tmp_path, capsys, argv, needle):
    cfg = small_rotor_toml(tmp_path / "r.toml")
    status = main(["simulate", str(cfg), "-o", str(tmp_path / "out"), "-q", *argv])
    err = capsys.readouterr().err.strip()
    assert status == 2
    assert needle in err and len(err.splitlines()) == 1, err
    assert not (tmp_path / "out").exists()


def test_bad_config_field_exit_2(tmp_path, capsys):
    cfg = small_rotor_toml(tmp_path / "r.toml", extra='[analysis.simulate]\nspeed_law = '
                           '{ law = "ramp", start = "5 rad/s", stop = "9 rad/s", '
                           'duration = "1 s", spin = 3 }\n')
    status = main(["simulate", str(cfg), "-o", str(tmp_path / "out"), "-q"])
    err = capsys.readouterr().err.strip()
    assert status == 2 and "speed_law.spin" in err and len(err.splitlines()) == 1, err


def test_overlay_of_a_branch(tmp_path, capsys):
    """--overlay draws a response's branch over the run-up (recorded in summary.json and
    the figure written); without a speed law, or with a missing file: one line, exit 2,
    before any work."""
    cfg = small_rotor_toml(tmp_path / "r.toml")
    assert main(["response", str(cfg), "-o", str(tmp_path / "b"), "-q"]) == 0
    branch = tmp_path / "b" / "branch.nc"
    assert main(["simulate", str(cfg), "--speed-law", RAMP, "--overlay", str(branch),
                 "-o", str(tmp_path / "s"), "-q"]) == 0
    summary = json.loads((tmp_path / "s" / "summary.json").read_text())
    assert summary["overlay"] == str(branch)
    assert (tmp_path / "s" / "envelope.png").stat().st_size > 10_000
    capsys.readouterr()
    for argv, field in [(["--overlay", str(branch)], "needs a speed law"),
                        (["--speed-law", RAMP, "--overlay", str(tmp_path / "no.nc")],
                         "an existing branch.nc")]:
        assert main(["simulate", str(cfg), *argv, "-o", str(tmp_path / "x"), "-q"]) == 2
        err = capsys.readouterr().err.strip().splitlines()
        assert len(err) == 1 and field in err[0] and "--overlay" in err[0]
        assert not (tmp_path / "x").exists()
