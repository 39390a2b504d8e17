"""The sparse full-model HB without a dense n x n matrix (issue 17 item 2, HB side): the
linear part split once per lam into band + low-rank modal term, the Jacobian as CSR +
low-rank factors solved by Woodbury, the stiffness scale read from band storage, and a
deterministic Lanczos start in the Craig-Bampton basis. References: the dense FullHB
(every matrix formed), dense LAPACK solves, the dense diagonal, a second call."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from tests.model.test_sparse import rotor

from rotorsfd.elements.sfd import SFDElement
from rotorsfd.harmonic import full_sparse
from rotorsfd.harmonic.full_sparse import SparseFullHB
from rotorsfd.harmonic.hb_system import HBSystem, stiffness_diagonal
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.harmonic.residual import FullHB
from rotorsfd.model.damping import ModalDamping
from rotorsfd.model.lowrank import BandedLowRank, SparseLowRank
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance
from rotorsfd.sfd import SFD

H, LAM = 3, 650.0


def _rel(a, b) -> float:
    a, b = np.asarray(a), np.asarray(b)
    return float(np.abs(a - b).max() / np.abs(b).max())


def _problem(modal: bool, n_elements: int = 12):
    sfd = SFD(viscosity=0.0051, radius=0.0262, length=0.017, clearance=0.127e-3)
    damping = ModalDamping(0.02, modes=4) if modal else None
    system = RotorSystem(rotor(n_elements, damping), [SFDElement("sfd", 1, sfd)],
                         [Unbalance(7, 2e-5, 0.3)])
    return system.periodic_problem()


def _state(n: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    x = 2e-5 * rng.standard_normal((2 * H + 1, n))
    return x / (1.0 + np.arange(2 * H + 1))[:, None]


@pytest.mark.parametrize("modal", [False, True])
def test_residual_and_jacobian_equal_the_dense_assembly(modal):
    """R, dR/dx and dR/dlam of SparseFullHB = the dense FullHB (1e-10 relative), with
    modal damping of 4 modes (Jacobian: CSR + rank-2Hr factors) and without (CSR)."""
    p = _problem(modal)
    assert (p.matrices.lowrank is not None) == modal
    x = _state(p.n_dof, 3)
    a, b = SparseFullHB(p, H, 32), FullHB(p, H, 32)
    for lam in (LAM, 1.3 * LAM):
        Ra, Ja, dRa = a.residual(x, lam)
        Rb, Jb, dRb = b.residual(x, lam)
        assert isinstance(Ja, SparseLowRank) if modal else sp.issparse(Ja)
        assert _rel(Ra, Rb) <= 1e-10
        assert _rel(Ja.toarray(), Jb) <= 1e-10
        assert _rel(dRa, dRb) <= 1e-10
        lin = a.linear_terms(lam)
        assert isinstance(lin.D, BandedLowRank) == modal   # the modal term not formed
        assert a.linear_terms(lam) is lin                   # split once per lam
        Rj = a.residual(x, lam, jac=False)[0]
        assert np.array_equal(Rj, Ra)


def test_sparse_lowrank_bordered_solve_equals_lapack():
    """``[S + L R^T, c; a^T] x = b`` by Woodbury from the SuperLU of the sparse part =
    numpy's dense solve (1e-10), and the scaling / column helpers = their dense forms."""
    rng = np.random.default_rng(5)
    n, r = 60, 4
    S = sp.random(n, n, density=0.08, random_state=1, format="csr") + 4 * sp.identity(n)
    A = SparseLowRank(S, 0.3 * rng.standard_normal((n, r)), rng.standard_normal((n, r)))
    col, a, rhs = rng.standard_normal(n), rng.standard_normal(n + 1), rng.standard_normal(n + 1)
    Ac = A.with_column(col)
    dense = np.vstack([np.column_stack([A.toarray(), col]), a])
    assert _rel(Ac.bordered_solve(a, rhs), np.linalg.solve(dense, rhs)) <= 1e-10
    rows, cols = rng.uniform(0.5, 2, n), rng.uniform(0.5, 2, n)
    assert _rel(A.scaled(rows, cols).toarray(), rows[:, None] * A.toarray() * cols) <= 1e-14
    left, last = Ac.without_last_column()
    assert _rel(left.toarray(), A.toarray()) <= 1e-14 and _rel(last, col) <= 1e-14
    assert _rel(Ac @ a, dense[:n] @ a) <= 1e-13
    assert Ac.is_finite()


def test_full_hb_solution_with_modal_damping_equals_the_dense_path(monkeypatch):
    """The Newton solve of the full HB with modal damping on the sparse path (Woodbury
    bordered solves) = the dense FullHB's (1e-9 of the largest coefficient)."""
    p = _problem(True)
    dense = solve_periodic(p, LAM, H, tol=1e-12, condensed=False)
    monkeypatch.setattr(full_sparse, "SPARSE_MIN_DOF", 0)        # force the sparse path
    assert isinstance(HBSystem(p, H, 32, False, LAM, LAM).hb, SparseFullHB)
    sparse = solve_periodic(p, LAM, H, tol=1e-12, condensed=False)
    assert isinstance(sparse.jacobian, SparseLowRank)
    assert dense.iterations >= 1
    assert np.abs(sparse.X - dense.X).max() <= 1e-9 * np.abs(dense.X).max()
    cond = solve_periodic(p, LAM, H, tol=1e-12, condensed=True)   # a second method
    assert np.abs(sparse.X - cond.X).max() <= 1e-6 * np.abs(cond.X).max()


@pytest.mark.parametrize("modal", [False, True])
def test_stiffness_diagonal_equals_the_dense_diagonal(modal):
    """K_ii from band storage = ``np.diag`` of the dense K (exactly: the same entries)."""
    p = _problem(modal)
    for lam in (LAM, 2 * LAM):
        d = stiffness_diagonal(p, lam)
        assert np.array_equal(d, np.diag(p.matrices(lam)[2]))
        assert np.any(d != 0.0)


def test_fixed_interface_modes_are_deterministic():
    """Two sparse Craig-Bampton bases of the same 444-DOF rotor (shift-invert Lanczos,
    above DENSE_MAX_DOF) give bit-identical modes and frequencies; the frequencies equal
    the dense eigh of the interior (1e-9)."""
    import scipy.linalg as sla

    from rotorsfd.stability.reduction import FixedInterfaceBasis

    r = rotor(110)
    nl = np.array([0, 1])
    M, K = sp.csr_matrix(r.M), sp.csr_matrix(r.K)
    bases = [FixedInterfaceBasis(M, K, nl) for _ in range(2)]
    for b in bases:
        b.reduce(sp.csr_matrix(r.C), None, 3e4)
        assert b.sparse
    a, b = bases
    assert a.omegas.size >= 4
    assert np.array_equal(a.omegas, b.omegas) and np.array_equal(a.modes, b.modes)
    i = a.i
    Kd, Md = r.K[np.ix_(i, i)], r.M[np.ix_(i, i)]
    Kd = Kd.toarray() if sp.issparse(Kd) else Kd
    Md = Md.toarray() if sp.issparse(Md) else Md
    w = np.sqrt(sla.eigh(0.5 * (Kd + Kd.T), 0.5 * (Md + Md.T), eigvals_only=True,
                         subset_by_index=[0, a.omegas.size - 1]))
    assert _rel(a.omegas, w) <= 1e-9
