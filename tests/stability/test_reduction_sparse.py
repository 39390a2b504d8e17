"""The sparse Craig-Bampton basis (sparse LU constraint modes, shift-invert Lanczos for
the fixed-interface modes asked for) spans the model of the dense one: the same kept
natural frequencies and the same eigenvalues of the reduced gyroscopic model (1e-8)."""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla

from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.stability.reduction import FixedInterfaceBasis, craig_bampton

STEEL = Material(7810.0, 211e9, 81.783e9)


def state_eigenvalues(M, D, K, count: int) -> np.ndarray:
    """The ``count`` eigenvalues of smallest |Im| (upper half plane) of the pencil."""
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-np.linalg.solve(M, K),
                                                   -np.linalg.solve(M, D)]])
    lam = sla.eigvals(A)
    lam = lam[lam.imag > 0]
    return lam[np.argsort(lam.imag)][:count]


def test_sparse_craig_bampton_equals_dense() -> None:
    n_el = 120
    # anisotropic supports: no repeated frequencies at the cut-off
    rotor = Rotor(uniform_shaft(1.2, n_el, 0.0, 0.03, STEEL),
                  disks=[Disk.from_geometry(61, 7810.0, 0.03, 0.12, 0.04)],
                  supports=[LinearSupport(1, 2e7, 1.5e7, cyy=300.0, czz=200.0),
                            LinearSupport(n_el + 1, 3e7, 1e7, cyy=100.0, czz=400.0)])
    assert rotor.n_dof > DENSE_MAX_DOF
    speed = 800.0
    D = rotor.C_csr + speed * rotor.G_csr
    nl = np.array([0, 1])
    omega_max = 3000.0
    sparse = FixedInterfaceBasis(rotor.M_csr, rotor.K_csr, nl)
    assert sparse.sparse
    a = sparse.reduce(D, None, omega_max)
    b = craig_bampton(rotor.M, D.toarray(), rotor.K, nl, omega_max=omega_max)
    assert a.omegas.size == b.omegas.size >= 4
    assert np.abs(a.omegas - b.omegas).max() <= 1e-8 * b.omegas.max()
    assert sparse.omegas.size < rotor.n_dof // 4     # only the lowest modes computed
    la = state_eigenvalues(a.M, a.D, a.K, 6)
    lb = state_eigenvalues(b.M, b.D, b.K, 6)
    assert np.abs(la - lb).max() <= 1e-8 * np.abs(lb).max()
    # the boundary rows of the basis stay the identity (physical nonlinear DOFs)
    np.testing.assert_array_equal(a.basis[nl, :2], np.eye(2))
    assert sparse.matches(rotor.M_csr, rotor.K_csr)
    assert not sparse.matches(rotor.M_csr, 2.0 * rotor.K_csr)
    # n_modes: the lowest ones, whatever omega_max
    c = sparse.reduce(D, 3, None)
    np.testing.assert_allclose(c.omegas, b.omegas[:3], rtol=1e-8)
