"""FloquetEvaluator with modal damping of a few modes on a banded model above
DENSE_MAX_DOF: the Craig-Bampton basis projects the damping from its factors
(``Psi^T D_b Psi + W^T diag(c) W``, ``W = U^T Psi``), never forming the full matrix; the
reduced damping and the multipliers equal those from the same damping formed as one
(full) CSR matrix, 1e-10."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from rotors import uniform_sfd_rotor_raw
from rotorsfd.model.lowrank import BandedLowRank
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.stability.branch_options import StabilityOptions
from rotorsfd.stability.floquet_evaluator import FloquetEvaluator

N_EL = 104


def _config() -> dict:
    return uniform_sfd_rotor_raw(N_EL, modal_ratio=0.01)


def test_lowrank_basis_equals_full_damping() -> None:
    from rotorsfd import api
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.io.config import config_from_dict

    system = api.build_system(config_from_dict(_config()))
    problem = system.periodic_problem()
    assert problem.n_dof > DENSE_MAX_DOF and problem.matrices.lowrank is not None
    speed = 300.0
    X = solve_periodic(problem, speed, H=3).X
    o = StabilityOptions()
    split = FloquetEvaluator(problem, o)
    M, D, K = split.linear_part(speed)
    assert isinstance(D, BandedLowRank) and sp.issparse(M) and sp.issparse(K)
    a = split(speed, X)
    full = FloquetEvaluator(problem, o)
    full.linear_part = lambda lam: problem.matrices.sparse(lam)   # D formed: full CSR
    assert full.linear_part(speed)[1].nnz > 0.9 * problem.n_dof ** 2
    b = full(speed, X)
    red = split.reduced(speed, 2 * np.pi / speed)
    psi = red.basis
    Dfull = problem.matrices.sparse(speed)[1]
    ref = psi.T @ (Dfull @ psi)
    np.testing.assert_allclose(red.D, ref, rtol=0, atol=1e-12 * np.abs(ref).max())
    lowrank_part = ref - psi.T @ (D.band @ psi)      # the modal term is in the model
    assert np.abs(lowrank_part).max() > 1e-3 * np.abs(ref).max()
    # multipliers (moduli: invariant under the bases' rotation within degenerate pairs)
    assert a.info["n_modes"] == b.info["n_modes"] >= 2
    ma, mb = (np.sort(np.abs(r.multipliers))[::-1][:8] for r in (a, b))
    np.testing.assert_allclose(ma, mb, rtol=1e-10)
    # the modes above the cut-off: Ritz values on two Lanczos bases of the extension
    # (1e-12 apart here, on a multiplier of 0.012: absolute, as |mu| is read against 1)
    assert a.info["max_multiplier_outside"] == pytest.approx(
        b.info["max_multiplier_outside"], abs=1e-10)
