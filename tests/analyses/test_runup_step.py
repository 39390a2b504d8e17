"""Step control of transient runs (analyses/runup_step.py): the halving ladder of a
run-up converges at second order, "auto" stops at the tolerance, a fixed step that fails
it warns, and the controlled run equals a plain run at the accepted step."""

from __future__ import annotations

from itertools import pairwise

import numpy as np
import pytest

from rotors import linear_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.runup_simulation import law_of, run_speed_law_simulation


@pytest.fixture(scope="module")
def setup(tmp_path_factory):
    path = linear_rotor_toml(tmp_path_factory.mktemp("step") / "r.toml", unbalance="50 g*mm")
    config = api.load_config(path)
    law = law_of({"law": "ramp", "start": "700 rad/s", "stop": "950 rad/s",
                  "rate": "2000 rad/s^2"})
    return api.build_system(config), config.analysis.simulate, law


def test_auto_halves_until_the_tolerance(setup):
    """From T/200 the change of one halving falls by about 4 (second order) and "auto"
    accepts the finer run of the first pair below the tolerance; that run equals a plain
    run at that step (to the last bit)."""
    system, sim, law = setup
    tol = 3e-4
    res = run_speed_law_simulation(system, law, sim=sim.model_copy(update={
        "step_tolerance": tol}), nodes=(3,), steps_per_period="auto")
    step = res.settings["time_step"]
    d = [h["difference"] for h in step["halvings"]]
    assert len(d) >= 2 and d[-1] <= tol < d[-2]
    assert all(3.0 < a / b < 5.0 for a, b in pairwise(d))
    n = step["steps_per_period"]
    assert n == step["halvings"][-1]["steps_per_period"][1]
    plain = run_speed_law_simulation(system, law, sim=sim.model_copy(update={
        "step_check_periods": 0}), nodes=(3,), steps_per_period=n)
    np.testing.assert_array_equal(plain.run.q, res.run.q)
    assert "warning" not in res.summary()


def test_a_fixed_step_that_fails_warns(setup):
    system, sim, law = setup
    res = run_speed_law_simulation(system, law, sim=sim.model_copy(update={
        "step_tolerance": 1e-6}), nodes=(3,), steps_per_period=64)
    step = res.settings["time_step"]
    assert step["mode"] == "fixed" and step["steps_per_period"] == 64
    assert step["difference"] > 1e-6 and not step["converged"]
    assert 'steps_per_period = "auto"' in step["warning"]
    assert "warning: time step T/64 is too coarse" in res.summary()
