"""FloquetEvaluator on a banded model above DENSE_MAX_DOF (issue 17 item 2): the
Craig-Bampton basis from the CSR matrices (sparse LU + shift-invert Lanczos) gives the
multipliers of the dense basis (every mode by LAPACK) to 1e-8, and the modes above the
cut-off by shift-invert Arnoldi the dense companion form's largest |exp(lambda T)|."""

from __future__ import annotations

import numpy as np
import pytest

from rotors import uniform_sfd_rotor_raw
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.stability.branch_options import StabilityOptions
from rotorsfd.stability.floquet_evaluator import FloquetEvaluator

N_EL = 104
pytestmark = pytest.mark.slow   # ~7 s: the dense companion form of 888 states


def _config() -> dict:
    return uniform_sfd_rotor_raw(N_EL)


@pytest.fixture(scope="module")
def point():
    from rotorsfd import api
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.io.config import config_from_dict

    system = api.build_system(config_from_dict(_config()))
    problem = system.periodic_problem()
    assert problem.n_dof > DENSE_MAX_DOF and hasattr(problem.matrices, "sparse")
    speed = 300.0
    return problem, speed, solve_periodic(problem, speed, H=3).X


def test_sparse_basis_equals_dense(point) -> None:
    import scipy.sparse as sp

    problem, speed, X = point
    o = StabilityOptions()
    sparse = FloquetEvaluator(problem, o)
    a = sparse(speed, X)
    assert sp.issparse(sparse.linear_part(speed)[0]) and sparse._basis.sparse
    dense = FloquetEvaluator(problem, o)
    dense.linear_part = lambda lam: tuple(np.asarray(x, float)
                                          for x in problem.matrices(lam))
    b = dense(speed, X)
    assert not dense._basis.sparse
    assert a.info["n_modes"] == b.info["n_modes"] >= 2
    ma, mb = (np.sort(np.abs(r.multipliers))[::-1][:8] for r in (a, b))
    assert np.abs(ma - mb).max() <= 1e-8
    assert a.max_abs == pytest.approx(b.max_abs, abs=1e-8)
    # above the cut-off: the sparse path's Ritz values of the averaged model on the basis
    # extended to OUTSIDE_FACTOR x the cut-off against the same Ritz values on the dense
    # basis; the dense path's value is the companion form's over every mode
    from rotorsfd.stability.floquet_evaluator import OUTSIDE_FACTOR
    from rotorsfd.stability.orbit import orbit_samples
    from rotorsfd.stability.outside import averaged_eigenvalues, mode_eigenvalues
    from rotorsfd.stability.reduction import FixedInterfaceBasis

    cut = a.info["omega_cut"]
    assert cut == b.info["omega_cut"] == pytest.approx(0.25 * 400 * speed / (2 * np.pi))
    nl = problem.nl_dofs
    T = 2 * np.pi / speed
    Jq, Jv = problem.law(speed).jacobian(*orbit_samples(X[:, nl], speed, 400,
                                                        endpoint=False))
    Jq, Jv = Jq.mean(axis=0), Jv.mean(axis=0)
    M, D, K = (np.array(x, float) for x in problem.matrices(speed))
    ext = FixedInterfaceBasis(M, K, nl).reduce(D, None, OUTSIDE_FACTOR * cut)
    ritz = averaged_eigenvalues(ext.M, ext.D, ext.K, ext.nl_dofs, Jq, Jv, omega_max=cut)
    assert ritz.size >= 2
    assert a.info["max_multiplier_outside"] == pytest.approx(
        np.abs(np.exp(ritz * T)).max(), abs=1e-8)
    K[np.ix_(nl, nl)] -= Jq
    D[np.ix_(nl, nl)] -= Jv
    lam = mode_eigenvalues(M, D, K)
    above = lam[np.abs(lam.imag) > cut]
    assert b.info["max_multiplier_outside"] == pytest.approx(
        np.abs(np.exp(above * T)).max(), abs=1e-9)
