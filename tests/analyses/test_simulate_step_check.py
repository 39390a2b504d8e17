"""The time-step check of ``run_simulation``: the last periods integrated again at half
the step. Newmark is second order, so on a smooth (weakly nonlinear) orbit the reported
difference shrinks ~4x when the base step halves; near-contact orbits at a coarse step
draw the warning."""

from __future__ import annotations

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
    step_check,
    system_from_config,
    time_domain_inputs,
)
from rotorsfd.errors import ConfigError
from rotorsfd.model.dofs import dof_index

REF = 800.0


@pytest.fixture(scope="module")
def configs(tmp_path_factory):
    d = tmp_path_factory.mktemp("step_check")
    return {u: api.load_config(small_rotor_toml(d / f"u{i}.toml", unbalance=u,
                                                reference=f"{REF} rad/s"))
            for i, u in enumerate(("50 g*mm", "100 g*mm"))}


def _run(system, ratio: float, spp: int, check: int = 10, **kw):
    return run_simulation(system, ratio * REF, steps_per_period=spp, periods=300,
                          poincare_periods=20, lyapunov_periods=0, nodes=[1, 3],
                          progress=False, step_check_periods=check, **kw)


def test_weakly_nonlinear_difference_is_second_order(configs) -> None:
    """U = 50 g mm at 0.9 x 800 rad/s (eps ~ 0.04): T/100 -> 9.3e-5 C, T/200 -> 2.3e-5 C
    (ratio 4.0); no warning; the figure is in the summary and summary.json."""
    system = system_from_config(configs["50 g*mm"])
    a, b = (_run(system, 0.9, spp) for spp in (100, 200))
    ca, cb = a.step_check, b.step_check
    assert ca.steps_per_period == (100, 200) and cb.steps_per_period == (200, 400)
    assert ca.periods == 10 and ca.node == 1 and ca.unit == "C"
    assert "final-period orbit" in ca.compared
    assert 5e-5 < ca.difference < 2e-4
    assert 3.5 < ca.difference / cb.difference < 4.5
    assert 3.5 < ca.orbit_difference / cb.orbit_difference < 4.5
    assert not ca.coarse and ca.warning() is None
    assert "warning" not in a.summary()
    assert "step check (T/100 vs T/200, last 10 periods, node 1)" in a.summary()
    d = json.loads(json.dumps(a.summary_dict()))
    assert d["step_check"]["difference"] == pytest.approx(ca.difference, rel=1e-12)
    assert d["step_check"]["too_coarse"] is False
    assert d["settings"]["step_check_periods"] == 10


def test_coarse_step_near_large_orbit_warns(configs) -> None:
    """U = 100 g mm at 1.05 (eps ~ 0.65) at T/20: halving the step moves the journal
    orbit by ~0.12 C (T/40: ~0.03 C, still above 0.01 C)."""
    system = system_from_config(configs["100 g*mm"])
    res = _run(system, 1.05, 20)
    c = res.step_check
    assert 0.06 < c.difference < 0.25
    assert c.coarse
    text = res.summary()
    assert ("warning: time step T/20 may be too coarse here: halving it moves the orbit "
            f"by {c.difference:.3g} C; raise analysis.simulate.steps_per_period") in text
    assert res.summary_dict()["step_check"]["warning"] == c.warning()


def test_non_periodic_comparison_is_the_envelope(configs) -> None:
    """``periodic=False`` compares the max/min radius over the periods, and says so; on a
    period-1 orbit it is of the size of the orbit difference."""
    system = system_from_config(configs["50 g*mm"])
    res = _run(system, 0.9, 100, check=0)
    assert res.step_check is None and "step check" not in res.summary()
    inputs = time_domain_inputs(system, 0.9 * REF)
    q290, v290 = _state_after(system, res.speed, 290)
    c = step_check(inputs, (q290, v290, 290 * res.period), periods=10,
                   steps_per_period=100, node=1, t=res.t, q=res.q[:, 0],
                   poincare_q=res.poincare_q[:, 0], periodic=False,
                   clearance=system.sfd.clearance)
    assert "envelope" in c.compared and "not periodic" in c.compared
    assert c.difference == c.envelope_difference
    assert 5e-5 < c.difference < 2e-4


def _state_after(system, speed: float, periods: int):
    """The full state of ``_run``'s integration (T/100, from the 1 um displaced state)
    after ``periods`` periods."""
    tr = integrate_periods(time_domain_inputs(system, speed),
                           displaced_state(system.n_dof, 1e-6), 0.0, steps_per_period=100,
                           periods=periods, record_dofs=[dof_index(1, "y")],
                           record_periods=1, poincare_periods=1)
    return tr.q_final, tr.v_final


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


def test_config_field(configs, tmp_path) -> None:
    cfg = configs["50 g*mm"]
    assert cfg.analysis.simulate.step_check_periods == 20
    path = small_rotor_toml(tmp_path / "s.toml", extra="\n[analysis.simulate]\n"
                            "step_check_periods = -1\n")
    with pytest.raises((ValidationError, ConfigError)):
        api.load_config(path)
