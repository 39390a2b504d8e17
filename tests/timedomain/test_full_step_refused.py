"""``analysis.simulate.reduction = "none"`` (the full step: a dense n x 2n step operator,
O(n^3) to prepare, O(n^2) a step) is refused above DENSE_MAX_DOF with one ConfigError
naming the field, the value, the limit and the model's size, before any dense matrix is
formed; at and below the limit it still runs (tests/timedomain/test_td_reduced.py runs it
on the paper rotor)."""

from __future__ import annotations

import numpy as np
import pytest

from rotors import forbid_dense_rotor_matrices, uniform_sfd_rotor_raw
from rotorsfd.analyses.runup_simulation import run_speed_law_simulation
from rotorsfd.analyses.simulate import run_simulation
from rotorsfd.analyses.td_integration import time_domain_inputs, with_reduction
from rotorsfd.errors import ConfigError
from rotorsfd.io.config import config_from_dict
from rotorsfd.model.build import build_system
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.timedomain.speed_law import RampSpeed

MESSAGE = (r'analysis\.simulate\.reduction: got \'none\'; the full step \(a dense n x 2n '
           r'step operator\) is allowed up to 400 DOFs and this model has 420: use "auto"')


@pytest.fixture(scope="module")
def config():
    return config_from_dict(uniform_sfd_rotor_raw(104))      # 420 DOFs


def test_with_reduction_refuses_the_full_step_of_a_large_model(config, monkeypatch):
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        inputs = time_domain_inputs(build_system(config), 300.0)
        assert inputs.n_dof == 420 > DENSE_MAX_DOF
        with pytest.raises(ConfigError, match=MESSAGE) as err:
            with_reduction(inputs, "none")
        assert err.value.field == "analysis.simulate.reduction" and err.value.value == "none"
        assert with_reduction(inputs, "auto").reduction is not None   # the allowed one


def test_simulate_and_runup_refuse_it_before_forming_a_dense_matrix(monkeypatch):
    raw = uniform_sfd_rotor_raw(104)
    raw["analysis"] = {"simulate": {"reduction": "none"}}
    config = config_from_dict(raw)
    system = build_system(config)
    sim = config.analysis.simulate
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        with pytest.raises(ConfigError, match=MESSAGE):
            run_simulation(system, 300.0, settings=sim, progress=False)
        with pytest.raises(ConfigError, match=MESSAGE):
            run_speed_law_simulation(system, RampSpeed(250.0, 450.0, 0.03), sim=sim,
                                     nodes=[1, 53], steps_per_period=80)


def test_the_full_step_of_a_model_at_the_limit_still_runs():
    """A 400-DOF model (99 elements): "none" steps the full model."""
    system = build_system(config_from_dict(uniform_sfd_rotor_raw(99)))
    assert system.n_dof == DENSE_MAX_DOF
    inputs = with_reduction(time_domain_inputs(system, 300.0), "none")
    assert inputs.reduction is None and inputs.n_dof == DENSE_MAX_DOF
    assert np.all(np.isfinite(inputs.K.diagonal()))


def test_auto_without_a_craig_bampton_model_is_refused_on_a_large_model(monkeypatch):
    """Supported only by the SFD at node 1: with the SFD's DOFs fixed the shaft pivots
    about node 1 (a free interior, no Craig-Bampton model), so "auto" would fall back to
    the dense full step: refused above the limit, one line; the 84-DOF analogue falls back
    as before."""
    raw = uniform_sfd_rotor_raw(104)
    raw["rotor"]["supports"] = []
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        inputs = time_domain_inputs(build_system(config_from_dict(raw)), 300.0)
        with pytest.raises(ConfigError, match=r"analysis\.simulate\.reduction: got 'auto'; "
                           r"no Craig-Bampton model of this 420-DOF model \(.*\), and the "
                           r"full step is allowed up to 400 DOFs"):
            with_reduction(inputs, "auto")
    small = uniform_sfd_rotor_raw(20)
    small["rotor"]["supports"] = []
    inputs = time_domain_inputs(build_system(config_from_dict(small)), 300.0)
    assert inputs.n_dof == 84 and with_reduction(inputs, "auto").reduction is None
