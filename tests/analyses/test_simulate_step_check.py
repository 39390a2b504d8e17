"""Time-step control of ``run_simulation``: a fixed step checked by one halving, and the
automatic step (``steps_per_period = "auto"``), halved until one halving moves the journal
orbit by less than ``step_tolerance``. Newmark is second order, so the change per halving
shrinks ~4x; the accepted orbit is checked against an independent run at a 4x finer step."""

from __future__ import annotations

import itertools
import json

import numpy as np
import pytest
from pydantic import ValidationError

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.simulate import (
    displaced_state,
    integrate_periods,
    run_simulation,
    system_from_config,
    time_domain_inputs,
)
from rotorsfd.analyses.step_control import compare_windows, run_window, settled_period
from rotorsfd.errors import ConfigError
from rotorsfd.model.dofs import dof_index

REF = 800.0


@pytest.fixture(scope="module")
def configs(tmp_path_factory):
    d = tmp_path_factory.mktemp("step_check")
    return {u: api.load_config(small_rotor_toml(d / f"u{i}.toml", unbalance=u,
                                                reference=f"{REF} rad/s"))
            for i, u in enumerate(("50 g*mm", "100 g*mm"))}


def _run(system, ratio: float, spp, check: int = 10, **kw):
    return run_simulation(system, ratio * REF, steps_per_period=spp, periods=300,
                          poincare_periods=20, lyapunov_periods=0, nodes=[1, 3],
                          progress=False, step_check_periods=check, **kw)


def test_weakly_nonlinear_difference_is_second_order(configs) -> None:
    """U = 50 g mm at 0.9 x 800 rad/s (eps ~ 0.04): T/100 -> 9.3e-5 C, T/200 -> 2.3e-5 C
    (ratio 4.0); no warning; the figure is in the summary and summary.json."""
    system = system_from_config(configs["50 g*mm"])
    a, b = (_run(system, 0.9, spp) for spp in (100, 200))
    ca, cb = a.step_check.last, b.step_check.last
    assert a.step_check.mode == "fixed" and a.step_check.steps_per_period == 100
    assert ca.steps_per_period == (100, 200) and cb.steps_per_period == (200, 400)
    assert ca.periods == 10 and ca.node == 1 and ca.unit == "C"
    assert ca.period == 1 and "period-1 orbit" in ca.compared
    assert 5e-5 < ca.difference < 2e-4
    assert 3.5 < ca.difference / cb.difference < 4.5
    assert not ca.coarse and a.step_check.warning() is None
    assert "warning" not in a.summary()
    assert "step check T/100 vs T/200 (last 10 periods, node 1)" in a.summary()
    d = json.loads(json.dumps(a.summary_dict()))
    assert d["step_check"]["difference"] == pytest.approx(ca.difference, rel=1e-12)
    assert d["step_check"]["too_coarse"] is False and d["step_check"]["mode"] == "fixed"
    assert d["settings"]["step_check_periods"] == 10


def test_coarse_fixed_step_warns_with_the_error_and_what_to_set(configs) -> None:
    """U = 100 g mm at 1.05 (eps ~ 0.65) at T/20: halving the step moves the journal
    orbit by ~0.12 C, far above step_tolerance = 1e-3 C."""
    system = system_from_config(configs["100 g*mm"])
    res = _run(system, 1.05, 20)
    c = res.step_check.last
    assert 0.06 < c.difference < 0.25
    assert c.coarse and not res.step_check.converged
    text = res.summary()
    assert (f"warning: time step T/20 is too coarse here: halving it moves the orbit by "
            f"{c.difference:.3g} C (step_tolerance 0.001 C); set "
            'analysis.simulate.steps_per_period = "auto"') in text
    assert res.summary_dict()["step_check"]["warning"] == res.step_check.warning()


def test_auto_step_converges_to_the_tolerance(configs, tmp_path) -> None:
    """U = 100 g mm at 1.05, "auto" from T/200 with step_tolerance = 1e-4 C: the change
    per halving falls ~4x per halving, the last one below 1e-4 C, the one before above
    it; the recorded orbit is that of the accepted step and lies within the tolerance of
    an independent run at a 4x finer fixed step from the same start."""
    system = system_from_config(configs["100 g*mm"])
    res = run_simulation(system, 1.05 * REF, periods=300, poincare_periods=20,
                         lyapunov_periods=0, nodes=[1, 3], progress=False,
                         step_tolerance=1e-4)
    ctl = res.step_check
    assert ctl.mode == "auto" and ctl.converged and res.motion_name == "period-1"
    diffs = [c.difference for c in ctl.checks]
    assert diffs[-1] < 1e-4 < diffs[-2] and len(diffs) >= 2
    assert all(3.0 < a / b < 5.5 for a, b in itertools.pairwise(diffs))
    spp = ctl.steps_per_period
    assert spp == ctl.checks[-1].steps_per_period[1] == res.settings["steps_per_period"]
    assert res.settings["dt_s"] == pytest.approx(res.period / spp, rel=1e-12)
    assert np.allclose(np.diff(res.t), res.period / spp, rtol=1e-9)
    fine = run_simulation(system, 1.05 * REF, steps_per_period=4 * spp, periods=300,
                          poincare_periods=20, lyapunov_periods=0, nodes=[1, 3],
                          progress=False, step_check_periods=0)
    C = system.length_scale
    gap = np.max(np.hypot(*(res.poincare_q[-5:, 0] - fine.poincare_q[-5:, 0]).T)) / C
    assert gap < 1e-4
    assert gap < 0.6 * diffs[-1]          # the accepted step is ~d/3 from converged
    d = json.loads(json.dumps(res.summary_dict()))["step_check"]
    assert d["mode"] == "auto" and d["converged"] is True
    assert d["difference"] == pytest.approx(diffs[-1], rel=1e-12)
    assert d["estimated_error"] == pytest.approx(diffs[-1] / 3, rel=1e-12)
    assert len(d["halvings"]) == len(diffs)
    assert f"time step (auto): T/{spp}" in res.summary()
    # timeseries.nc keeps at most 400 samples a period (every k-th step), both ends
    import xarray as xr

    res.write(tmp_path, plots=False)
    with xr.open_dataset(tmp_path / "timeseries.nc") as ds:
        n = int(ds.attrs["samples_per_period"])
        assert ds.attrs["steps_per_period"] == spp and n == min(spp, 400)
        assert ds.sizes["time"] == 20 * n + 1
        np.testing.assert_allclose(np.diff(ds["time"].values), res.period / n, rtol=1e-9)
        np.testing.assert_allclose(ds["displacement"].values[-1], res.q[-1], rtol=0,
                                   atol=1e-15)


def test_auto_step_at_its_cap_warns(configs) -> None:
    system = system_from_config(configs["100 g*mm"])
    res = run_simulation(system, 1.05 * REF, periods=120, poincare_periods=20,
                         lyapunov_periods=0, nodes=[1], progress=False,
                         step_tolerance=1e-7, max_steps_per_period=800)
    ctl = res.step_check
    assert ctl.steps_per_period == 800 and not ctl.converged
    assert [c.steps_per_period for c in ctl.checks] == [(200, 400), (400, 800)]
    w = ctl.warning()
    assert w.startswith("the time step did not converge to step_tolerance = 1e-07 C by "
                        "max_steps_per_period = 800")
    assert "raise analysis.simulate.max_steps_per_period" in w
    assert f"warning: {w}" in res.summary()


def test_envelope_compares_motions_that_are_not_periodic(configs) -> None:
    """The first 10 periods from the displaced state (a transient, not periodic): the
    comparison is the orbit envelope, and it shrinks with the step (2.1x here: the
    transient's high modes are not in the asymptotic range of the step)."""
    system = system_from_config(configs["50 g*mm"])
    inputs = time_domain_inputs(system, 0.9 * REF)
    start = (displaced_state(system.n_dof, 1e-5), np.zeros(system.n_dof), 0.0)
    w = {n: run_window(inputs, start, steps_per_period=n, periods=10, node=1)
         for n in (100, 200, 400)}
    C = system.length_scale
    assert settled_period(w[100].pq, 2.5e-4 * C) is None
    a = compare_windows(w[100], w[200], node=1, scale=C, unit="C")
    b = compare_windows(w[200], w[400], node=1, scale=C, unit="C")
    assert "envelope" in a.compared and a.period is None
    assert a.difference == a.envelope_difference
    assert 1e-5 < b.difference < a.difference < 1e-3
    assert 1.5 < a.difference / b.difference < 5.0


def test_snapshot_is_the_state_of_the_shorter_run(configs) -> None:
    """The chunk boundary at ``snapshot_period`` holds exactly the final state of a run of
    that many periods (the step check restarts from it)."""
    system = system_from_config(configs["50 g*mm"])
    inputs = time_domain_inputs(system, 0.9 * REF)
    kw = {"steps_per_period": 50, "record_dofs": [0, 1], "record_periods": 1,
          "poincare_periods": 1, "chunk_periods": 7}
    long = integrate_periods(inputs, 1e-6, 0.0, periods=30, snapshot_period=20, **kw)
    short = integrate_periods(inputs, 1e-6, 0.0, periods=20, **kw)
    q, v, t = long.snapshot
    assert t == pytest.approx(short.t_final, rel=1e-14)
    np.testing.assert_allclose(q, short.q_final, rtol=0, atol=1e-12 * np.abs(q).max())
    np.testing.assert_allclose(v, short.v_final, rtol=0, atol=1e-12 * np.abs(v).max())
    assert integrate_periods(inputs, 1e-6, 0.0, periods=5, **kw).snapshot is None
    assert dof_index(1, "y") == 0


def test_config_fields(configs, tmp_path) -> None:
    sim = configs["50 g*mm"].analysis.simulate
    assert (sim.steps_per_period, sim.step_tolerance, sim.max_steps_per_period,
            sim.step_check_periods) == ("auto", 1e-3, 3200, 20)
    for extra in ("step_check_periods = -1", "steps_per_period = 4",
                  'steps_per_period = "fine"', "step_tolerance = 0"):
        path = small_rotor_toml(tmp_path / "s.toml", extra=f"\n[analysis.simulate]\n{extra}\n")
        with pytest.raises((ValidationError, ConfigError)):
            api.load_config(path)
    system = system_from_config(configs["50 g*mm"])
    with pytest.raises(ConfigError, match="must exceed the recorded periods"):
        run_simulation(system, 0.9 * REF, periods=20, poincare_periods=20, progress=False)
