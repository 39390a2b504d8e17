"""Initial states of ``simulate``: the HB orbit shifted by a fraction of the period, and the
final state of a previous run (``timeseries.nc``), by the API and the CLI."""

from __future__ import annotations

import numpy as np
import pytest
import xarray as xr

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.simulate import (
    hb_state,
    load_state,
    run_simulation,
    shift_phase,
    system_from_config,
)
from rotorsfd.cli import main
from rotorsfd.errors import ConfigError
from rotorsfd.harmonic.periodic import solve_periodic

C = 0.127e-3
REF = 800.0
SHORT = dict(steps_per_period=200, poincare_periods=20, record_periods=2,
             lyapunov_periods=0, progress=False, nodes=[1, 3])


@pytest.fixture(scope="module")
def config(tmp_path_factory):
    path = small_rotor_toml(tmp_path_factory.mktemp("state") / "small.toml",
                            unbalance="100 g*mm", reference=f"{REF} rad/s")
    return api.load_config(path)


def test_shift_phase_is_the_orbit_later() -> None:
    """X_k exp(i k 2 pi p) evaluated at t = 0 is the orbit at t = p T (independent check:
    the series summed at that time)."""
    rng = np.random.default_rng(1)
    X = rng.normal(size=(5, 3)) + 1j * rng.normal(size=(5, 3))
    w, p = 3.0, 0.3
    t = p * 2 * np.pi / w
    k = np.arange(5)[:, None]
    direct = (X * np.exp(1j * k * w * t)).sum(axis=0).real
    q0, v0 = hb_state(shift_phase(X, p), w)
    assert np.allclose(q0, direct, rtol=0, atol=1e-13)
    assert np.allclose(v0, (1j * k * w * X * np.exp(1j * k * w * t)).sum(axis=0).real,
                       rtol=0, atol=1e-12)


def test_hb_phase_half_reaches_the_same_orbit_with_one_attractor(config) -> None:
    """Omega~ = 0.9 (below the folds of this rotor: one attractor): from the HB orbit (H=8)
    and from it shifted by T/2 the integration ends on the same orbit: the last two
    periods at the same times agree to 1e-4 C at the journal and the disk, while the two
    starts differ by more than 0.1 C."""
    system = system_from_config(config)
    speed = 0.9 * REF
    sol = solve_periodic(system.periodic_problem(), speed, 8)
    q_a, _ = hb_state(sol.X, speed)
    q_b, _ = hb_state(shift_phase(sol.X, 0.5), speed)
    assert np.max(np.abs(q_a[:2] - q_b[:2])) > 0.1 * C
    runs = [run_simulation(config, speed, periods=400, from_hb=True, hb_phase=p,
                           harmonics=8, **SHORT) for p in (0.0, 0.5)]
    assert "shifted by 0.5" in runs[1].settings["initial_state"]
    assert np.array_equal(runs[0].t, runs[1].t)
    assert np.max(np.abs(runs[0].q - runs[1].q)) < 1e-4 * C
    assert runs[0].motion_name == runs[1].motion_name == "period-1"


def test_continuing_from_a_saved_state_equals_one_longer_run(config, tmp_path) -> None:
    """150 periods, written; 100 more from its timeseries.nc (same speed: starts at the
    saved time) = one run of 250 periods: final state and the recorded last two periods
    equal to round-off (1e-9 of the amplitude)."""
    speed = 1.05 * REF
    first = run_simulation(config, speed, periods=150, **SHORT)
    first.write(tmp_path / "a", plots=False)
    saved = load_state(tmp_path / "a")
    assert saved.t == pytest.approx(150 * 2 * np.pi / speed, rel=1e-12)
    assert np.array_equal(saved.q, first.q_final) and np.array_equal(saved.v, first.v_final)
    second = run_simulation(config, speed, periods=100, initial_state=tmp_path / "a",
                            **SHORT)
    whole = run_simulation(config, speed, periods=250, **SHORT)
    amp = np.max(np.abs(whole.q))
    assert np.allclose(second.t, whole.t, rtol=1e-12, atol=0)
    assert np.max(np.abs(second.q - whole.q)) < 1e-9 * amp
    assert np.max(np.abs(second.q_final - whole.q_final)) < 1e-9 * amp
    assert second.t_final == pytest.approx(whole.t_final, rel=1e-12)


def test_saved_state_at_another_speed_keeps_the_rotor_phase(config, tmp_path) -> None:
    """From a state saved at 1.05 a run at 1.06 starts where Omega_new t = the saved
    phase (mod 2 pi), so the unbalance force is continuous."""
    speed = 1.05 * REF
    run_simulation(config, speed, periods=30, **SHORT).write(tmp_path / "a", plots=False)
    saved = load_state(tmp_path / "a" / "timeseries.nc")
    new = 1.06 * REF
    r = run_simulation(config, new, periods=30, initial_state=saved, **SHORT)
    t0 = r.settings["start_time_s"]
    assert np.cos(new * t0) == pytest.approx(np.cos(speed * saved.t), abs=1e-9)
    assert np.sin(new * t0) == pytest.approx(np.sin(speed * saved.t), abs=1e-9)
    assert 0 <= t0 < 2 * np.pi / new


def test_state_errors(config, tmp_path) -> None:
    with pytest.raises(ConfigError, match="no such file"):
        load_state(tmp_path / "missing")
    with pytest.raises(ConfigError, match="one of"):
        run_simulation(config, 800.0, periods=30, from_hb=True,
                       initial_state=tmp_path / "x", **SHORT)
    xr.Dataset({"displacement": ("t", [0.0])}).to_netcdf(tmp_path / "old.nc")
    with pytest.raises(ConfigError, match="no final state"):
        load_state(tmp_path / "old.nc")


def test_cli_initial_state_and_hb_phase(tmp_path, capsys) -> None:
    cfg = small_rotor_toml(tmp_path / "small.toml", unbalance="100 g*mm",
                           reference=f"{REF} rad/s")
    short = ["--set", "analysis.simulate.periods=40", "--set",
             "analysis.simulate.poincare_periods=10", "--set",
             "analysis.simulate.steps_per_period=100", "-q", "--lyapunov-periods", "0"]
    assert main(["simulate", str(cfg), "--speed-ratio", "0.9", "--from-hb", "--hb-phase",
                 "0.5", "-o", str(tmp_path / "a"), *short]) == 0
    with xr.open_dataset(tmp_path / "a" / "timeseries.nc") as ds:
        assert "shifted by 0.5" in ds.attrs["initial_state"]
        assert ds["final_displacement"].size == ds["final_velocity"].size > 8
    assert main(["simulate", str(cfg), "--speed-ratio", "0.9", "--initial-state",
                 str(tmp_path / "a"), "-o", str(tmp_path / "b"), *short]) == 0
    with xr.open_dataset(tmp_path / "b" / "timeseries.nc") as ds:
        assert ds.attrs["t_final_s"] == pytest.approx(80 * 2 * np.pi / 720.0, rel=1e-12)
    assert main(["simulate", str(cfg), "--speed-ratio", "0.9", "--hb-phase", "0.5",
                 "-o", str(tmp_path / "c"), *short]) == 2
    assert "needs --from-hb" in capsys.readouterr().err
