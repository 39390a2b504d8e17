"""Time integration of a model above DENSE_MAX_DOF with modal damping of a few modes:
the integrator's inputs keep CSR matrices and the damping as banded + low-rank (no dense
n x n array); the reduced (Craig-Bampton) step projects the damping from its factors and
the full step densifies it. Both equal the same runs on the dense matrices (the damping
formed as one full matrix), 1e-9 of the orbit (measured 7e-12 to 1.5e-10 from run to run:
the two reductions' bases come from separate eigensolves, which agree to round-off only)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
import scipy.sparse as sp

from rotors import uniform_sfd_rotor_raw
from rotorsfd import api
from rotorsfd.analyses.td_integration import (
    integrate_periods,
    time_domain_inputs,
    with_reduction,
)
from rotorsfd.io.config import config_from_dict
from rotorsfd.model.lowrank import BandedLowRank, dense
from rotorsfd.model.sparse import DENSE_MAX_DOF

N_EL = 104


@pytest.fixture(scope="module")
def model():
    cfg = uniform_sfd_rotor_raw(N_EL, modal_ratio=0.02)
    system = api.build_system(config_from_dict(cfg))
    inputs = time_domain_inputs(system, 300.0)
    dense_inputs = dataclasses.replace(inputs, M=dense(inputs.M), D=dense(inputs.D),
                                       K=dense(inputs.K))
    return system, inputs, dense_inputs


def _run(inputs, system, periods: int = 20):
    rd = [0, 1, system.rotor.dof_index(N_EL // 2 + 1, "y")]
    return integrate_periods(inputs, 0.0, 0.0, steps_per_period=100, periods=periods,
                             record_dofs=rd, record_periods=2, poincare_periods=10)


def test_inputs_keep_the_band(model) -> None:
    system, inputs, dense_inputs = model
    assert inputs.n_dof > DENSE_MAX_DOF
    assert sp.issparse(inputs.M) and sp.issparse(inputs.K)
    assert isinstance(inputs.D, BandedLowRank) and inputs.D.U.shape[1] == 6
    assert inputs.D.band.nnz < 20 * inputs.n_dof
    M, D, K = system.matrices(300.0)
    np.testing.assert_allclose(dense_inputs.D, D, rtol=0, atol=1e-13 * np.abs(D).max())
    np.testing.assert_array_equal(dense_inputs.K, K)
    np.testing.assert_array_equal(dense_inputs.M, M)


def test_reduced_step_equals_the_dense_damping(model) -> None:
    system, inputs, dense_inputs = model
    a = with_reduction(inputs, "auto")
    b = with_reduction(dense_inputs, "auto")
    assert a.reduction is not None and a.reduction.n_dof == b.reduction.n_dof
    ra, rb = _run(a, system), _run(b, system)
    scale = np.abs(rb.q).max()
    assert scale > 0
    assert np.abs(ra.q - rb.q).max() <= 1e-9 * scale
    assert np.abs(ra.poincare_q - rb.poincare_q).max() <= 1e-9 * scale
    # the modal damping acts: without it the orbit differs
    no_modal = dataclasses.replace(inputs, D=inputs.D.band)
    rc = _run(with_reduction(no_modal, "auto"), system)
    assert np.abs(rc.q - ra.q).max() > 1e-4 * scale


def test_full_step_equals_the_dense_damping(model) -> None:
    system, inputs, dense_inputs = model
    # the integrator's full step (the config's reduction = "none" is refused at this
    # size: tests/timedomain/test_full_step_refused.py)
    ra = _run(dataclasses.replace(inputs, reduction=None), system, 3)
    rb = _run(dataclasses.replace(dense_inputs, reduction=None), system, 3)
    assert np.abs(ra.q - rb.q).max() <= 1e-12 * np.abs(rb.q).max()
