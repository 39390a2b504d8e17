"""Outputs of a transient run: the waterfall against synthetic whirls, the natural
frequencies and the waterfall of a slow linear run-up against its critical speed, the
steady branch overlay against the branch file's own deflection columns, the files and
figures."""

from __future__ import annotations

import json

import numpy as np
import pytest
import xarray as xr

from rotors import linear_rotor_toml, small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.runup_simulation import (
    branch_envelope,
    law_of,
    run_speed_law_simulation,
)
from rotorsfd.linear.critical import critical_speeds
from rotorsfd.timedomain.waterfall import waterfall


def test_waterfall_of_synthetic_whirls():
    """A forward whirl of 20 um at 50 Hz plus a backward one of 5 um at 120 Hz, on bins:
    the two-sided waterfall has them at +50 and -120 Hz with their radii (1e-9); off a
    bin the Hann window loses at most 15.1 % (1.42 dB)."""
    t = np.arange(0.0, 2.0, 1e-3)
    y = 2e-5 * np.cos(2 * np.pi * 50 * t) + 5e-6 * np.cos(2 * np.pi * 120 * t)
    z = 2e-5 * np.sin(2 * np.pi * 50 * t) - 5e-6 * np.sin(2 * np.pi * 120 * t)
    w = waterfall(t, y, z, 0.2)
    for row in w.amplitude:
        assert w.frequency[np.argmax(row)] == pytest.approx(50.0)
        assert row.max() == pytest.approx(2e-5, rel=1e-9)
        back = np.where(w.frequency < 0, row, 0.0)
        assert w.frequency[np.argmax(back)] == pytest.approx(-120.0)
        assert back.max() == pytest.approx(5e-6, rel=1e-9)
    off = waterfall(t, 2e-5 * np.cos(2 * np.pi * 52.5 * t), 2e-5 * np.sin(2 * np.pi * 52.5 * t),
                    0.2)
    assert 0.84 * 2e-5 < off.amplitude.max() < 2e-5
    assert w.time[0] >= 0.1 - 1e-12 and w.time[-1] <= 1.9 + 1e-12   # whole windows only


@pytest.fixture(scope="module")
def linear_runups(tmp_path_factory):
    """Run-ups of the linear small rotor through its first critical at 250 and 50 rad/s^2."""
    tmp = tmp_path_factory.mktemp("transient")
    cfg_path = linear_rotor_toml(tmp / "r.toml", unbalance="50 g*mm")
    config = api.load_config(cfg_path)
    system = api.build_system(config)
    runs = [run_speed_law_simulation(
        system, law_of({"law": "ramp", "start": "600 rad/s", "stop": "1000 rad/s",
                        "rate": f"{rate} rad/s^2"}),
        sim=config.analysis.simulate, nodes=(3,), title="linear", steps_per_period=64)
        for rate in RATES]
    return system, runs


RATES = (250.0, 50.0)


def test_runup_peak_lags_the_critical_speed_as_the_root_of_the_rate(linear_runups):
    """Passage through a resonance (Lewis 1932; Markert and Seidler 2001, Int. J. Mech.
    Sci. 43: the peak's speed lag grows as the square root of the acceleration): the lags
    of the two run-ups are in the ratio sqrt(250 / 50) (5 %), the peak extrapolated to a
    zero rate is the first forward critical speed (0.5 %); the natural frequency in the
    file crosses 1X there (1e-3) and the waterfall's 1X amplitude peaks with the radius
    envelope (1 %)."""
    system, runs = linear_runups
    crit = critical_speeds(system.rotor, n=1, whirl="forward", speed_range=(0.0, 2e4))
    w_c = float(crit[0].speed_rad_s)
    peaks = [float(r.run.omega[np.argmax(r.radius(3))]) for r in runs]
    roots = np.sqrt(RATES)
    slope = (peaks[0] - peaks[1]) / (roots[0] - roots[1])
    assert peaks[1] - slope * roots[1] == pytest.approx(w_c, rel=5e-3)
    assert (peaks[0] - w_c) / (peaks[1] - w_c) == pytest.approx(roots[0] / roots[1], rel=0.05)
    speeds, wn = runs[1].natural
    assert np.interp(w_c, speeds, wn[:, 0]) == pytest.approx(w_c, rel=1e-3)
    fall = runs[1].waterfall(3)
    w_mid = np.interp(fall.time, runs[1].run.t, runs[1].run.omega)
    one_x = np.array([np.interp(w / (2 * np.pi), fall.frequency, row)
                      for w, row in zip(w_mid, fall.amplitude, strict=True)])
    assert w_mid[np.argmax(one_x)] == pytest.approx(peaks[1], rel=0.01)


def test_files_and_figures(linear_runups, tmp_path):
    """timeseries.nc holds the waterfall over (window, frequency, node) and the natural
    frequencies with units; summary.json the peaks; the figures are written."""
    res = linear_runups[1][0]
    paths = res.write(tmp_path)
    assert {"timeseries.nc", "summary.json", "envelope.png", "waterfall_3.png"} <= set(paths)
    with xr.open_dataset(paths["timeseries.nc"]) as ds:
        assert ds["waterfall"].dims == ("window", "frequency", "node")
        assert ds["waterfall"].attrs["units"] == "m"
        assert ds["natural_frequency"].attrs["units"] == "rad/s"
        assert float(ds["waterfall"].max()) == pytest.approx(
            float(res.waterfall(3).amplitude.max()), rel=1e-12)
    summary = json.loads(paths["summary.json"].read_text())
    assert summary["peaks"]["3"]["radius_max_m"] > 0


def test_branch_overlay_equals_the_branch_files_deflection(tmp_path):
    """The steady branch drawn over a run-up: its largest orbit radius at a node, from
    the harmonics, equals the branch file's own defl_<node> * C (1e-3, 128 samples)."""
    cfg_path = small_rotor_toml(tmp_path / "r.toml")
    res = api.run_response(api.load_config(cfg_path))
    res.write(tmp_path / "b")
    env = branch_envelope(tmp_path / "b" / "branch.nc", (1,))
    with xr.open_dataset(tmp_path / "b" / "branch.nc") as ds:
        defl = ds["defl_1"].values * 0.127e-3
    _, radius, stable = env[1]
    assert radius == pytest.approx(defl, rel=1e-3)
    assert set(np.unique(stable)) <= {0.0, 1.0}
