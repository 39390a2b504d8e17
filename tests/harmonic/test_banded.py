"""Compiled paths of the condensed HB: banded LU vs LAPACK, compiled AFT vs callables."""

import dataclasses

import numpy as np
import pytest
import scipy.linalg

from rotorsfd.harmonic import banded
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.examples import beam_rotor, generic_chain, jeffcott_damper
from rotorsfd.harmonic.residual import dynamic_stiffness
from rotorsfd.sfd import SFD

SFD_PAPER = SFD.from_ratios(0.0051, 1.27e-4, 0.00485, 0.325, cavitation="pi")


def _rel(a, b):
    return np.abs(a - b).max() / np.abs(b).max()


def _state(H, m, amp, seed):
    rng = np.random.default_rng(seed)
    return amp * rng.normal(size=(2 * H + 1, m)) / np.arange(1, 2 * H + 2)[:, None]


def test_band_lu_pivots_like_a_dense_solve():
    """A band matrix that needs row interchanges (tiny diagonal): banded LU + solve
    = dense LAPACK solve to 1e-12."""
    rng = np.random.default_rng(1)
    n, kl, ku = 30, 3, 2
    A = np.zeros((n, n), dtype=complex)
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            A[i, j] = rng.normal() + 1j * rng.normal()
        A[i, i] *= 1e-6
    ab = np.zeros((n, 2 * kl + ku + 1), dtype=complex)
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            ab[j, kl + ku + i - j] = A[i, j]
    ipiv = np.empty(n, dtype=np.int64)
    assert banded.band_lu(ab, kl, ku, ipiv) == 0
    assert np.any(ipiv != np.arange(n))
    b = rng.normal(size=(n, 3)) + 1j * rng.normal(size=(n, 3))
    x = b.copy()
    banded.band_solve(ab, kl, ku, ipiv, x)
    assert _rel(x, scipy.linalg.solve(A, b)) <= 1e-12


@pytest.mark.parametrize("H", [3, 8])
def test_banded_condensation_equals_dense_lapack(H):
    """All outputs of the compiled banded path (receptance, particular response, their
    lam-derivatives, recovery columns) = the dense LAPACK path to 1e-12."""
    p = beam_rotor(rayleigh_beta=1e-5)
    a = CondensedHB(p, H, 64)
    xs = _state(H, 2, 0.2 * 1.27e-4, 5)
    a.set_shift(xs, 900.0)
    b = a.with_problem(p)                               # the same shift
    b._band = (-1, -1)                                  # force the dense path
    ca, cb = a.condense(900.0), b.condense(900.0)
    assert a._band[0] > 0 and b._band[0] < 0
    # the two LUs differ by rounding, amplified by the condition number (resonances)
    M, D, K = p.matrices(900.0)
    kappa = 1.0
    for k, Z in enumerate(dynamic_stiffness(M, D, K, 900.0, H)):
        Z[np.ix_(p.nl_dofs, p.nl_dofs)] += a.delta[k]
        kappa = max(kappa, np.linalg.cond(Z))
    for name in ("Ht", "Pt", "u", "C", "dHt", "dPt"):
        assert _rel(getattr(ca, name), getattr(cb, name)) <= max(1e-12, 1e-15 * kappa), name


def test_band_widens_when_a_matrix_leaves_it():
    """A coupling outside the band found at the first lam: the band grows, the result
    equals the dense path."""
    p0 = generic_chain(n=40, nl=(3, 30))
    M, D, K = p0.matrices(0.5)

    def matrices(lam):
        Kl = K.copy()
        if lam > 1.0:
            Kl[0, 20] = Kl[20, 0] = -0.1
        return M, D, Kl

    p = dataclasses.replace(p0, matrices=matrices)
    a, b = CondensedHB(p, 2, 16), CondensedHB(p, 2, 16)
    b._band = (-1, -1)
    a.condense(0.5)
    band0 = a._band
    ca, cb = a.condense(1.2), b.condense(1.2)
    assert a._band[0] > band0[0] or a._band[0] < 0
    for name in ("Ht", "Pt", "dHt", "dPt"):
        assert _rel(getattr(ca, name), getattr(cb, name)) <= 1e-12, name


@pytest.mark.parametrize("make, lam, amp", [
    (lambda sfd: beam_rotor(sfd=sfd), 900.0, 0.3 * 1.27e-4),
    (lambda sfd: jeffcott_damper(sfd=sfd, static=(0.0, -30.0)), 320.0, 0.3 * 1.27e-4),
])
def test_compiled_aft_equals_callables(make, lam, amp):
    """Residual and exact Jacobians with the SFD's compiled kernel = with the vectorised
    callables (the same force law) to 1e-12."""
    pk = make(SFD_PAPER)
    assert pk.nl_kernel is not None
    pc = dataclasses.replace(pk, nl_kernel=None, nl_kernel_params=None)
    H = 4
    xs = _state(H, 2, amp, 7)
    out = []
    for p in (pk, pc):
        hb = CondensedHB(p, H, 64)
        hb.set_shift(xs, lam)
        out.append((*hb.residual(xs, lam), hb.residual(xs, lam, jac=False)[0]))
    for a, b in zip(*out, strict=True):
        assert _rel(a, b) <= 1e-12


def test_compiled_aft_contact_raises_the_force_law_error():
    from rotorsfd.errors import JournalContactError

    p = beam_rotor(sfd=SFD_PAPER)
    hb = CondensedHB(p, 3, 32)
    xs = np.zeros((7, 2))
    xs[1, 0] = 1.5 * SFD_PAPER.clearance
    with pytest.raises(JournalContactError):
        hb.residual(xs, 900.0)


def test_compiled_aliasing_equals_callables():
    """Aliasing estimate (force at 2N samples) by the kernel = by the callables."""
    pk = beam_rotor(sfd=SFD_PAPER)
    pc = dataclasses.replace(pk, nl_kernel=None, nl_kernel_params=None)
    xs = _state(3, 2, 0.3 * 1.27e-4, 9)
    out = []
    for p in (pk, pc):
        hb = CondensedHB(p, 3, 32)
        hb.set_shift(xs, 900.0)
        hb.residual(xs, 900.0)
        out.append(hb.aliasing(xs, 900.0))
    assert out[0] > 0 and abs(out[0] - out[1]) <= 1e-9 * out[1]


def _stiff_chain(n):
    """A fixed-free chain whose springs (1e12 N/m) exceed the stiffness of its lowest mode
    by ~n^2, lightly damped at its end: the conditions of a fine beam mesh near resonance."""
    K = np.zeros((n, n))
    for i in range(n):
        K[i, i] = 2e12 if i < n - 1 else 1e12
        if i:
            K[i, i - 1] = K[i - 1, i] = -1e12
    M = np.eye(n) * (1.0 + 0.01 * np.arange(n))
    D = np.zeros((n, n))
    D[n - 1, n - 1] = 10.0
    w2, _ = scipy.linalg.eigh(K, M)
    return M, D, K, float(np.sqrt(w2[0]))


def test_refinement_solves_the_unrounded_system():
    """Iterative refinement with the stiffness residual in doubled precision
    (``refine=1``) gives the receptance and particular response of the system with the
    double-precision data K, M, D, w unrounded: checked against a 40-digit mpmath solve of
    that system to 1e-12 (4e-13 measured: the rounding of (kw)^2 is left); without
    refinement the rounding of ``K - w^2 M`` costs 9.5e-11 here."""
    mpmath = pytest.importorskip("mpmath")
    n, kl, ku = 60, 1, 1
    M, D, K, w1 = _stiff_chain(n)
    w = 0.9999 * w1
    s = np.array([n - 1])
    delta = np.array([[0.0], [0.0]], dtype=complex)
    F = np.zeros((2, n), dtype=complex)
    F[1, n // 2] = 1.0
    bands = [sp_band(A, kl, ku) for A in (M, D, K)]
    zero = np.zeros_like(bands[0])

    def condensed(refine):
        sol = np.empty((2, n, 2), dtype=complex)
        dsol = np.empty((2, 1, 2), dtype=complex)
        Ht, dHt = np.empty((2, 2, 1, 1), dtype=complex)
        Pt, dPt = np.empty((2, 2, 1), dtype=complex)
        assert banded.condense_bands(*bands, zero, zero, zero, w, 1.0, kl, ku, s, delta,
                                     F, F, False, sol, dsol, Ht, Pt, dHt, dPt, refine) == 0
        return Ht[1, 0, 0], Pt[1, 0]

    mpmath.mp.dps = 40
    mw = mpmath.mpf(w)
    Z = mpmath.matrix(n, n)
    for i in range(n):
        for j in range(max(0, i - 1), min(n, i + 2)):
            Z[i, j] = mpmath.mpf(K[i, j]) - mw**2 * mpmath.mpf(M[i, j]) \
                + 1j * mw * mpmath.mpf(D[i, j])
    ref = []
    for load in (n - 1, n // 2):
        rhs = mpmath.matrix(n, 1)
        rhs[load] = 1
        ref.append(complex(mpmath.lu_solve(Z, rhs)[n - 1]))
    err = {r: [abs(a - b) / abs(b) for a, b in zip(condensed(r), ref, strict=True)]
           for r in (0, 1)}
    assert max(err[1]) <= 1e-12                 # (the rounding of (kw)^2 is left)
    assert min(err[0]) >= 30 * max(err[1])      # the refinement is what makes it exact


def sp_band(A, kl, ku):
    """Band storage ``ab[j, ku + i - j] = A[i, j]`` of a dense A."""
    return banded.dense_to_band(np.ascontiguousarray(A), kl, ku)


def test_sparse_full_hb_equals_the_dense_full_hb(monkeypatch):
    """The full-model HB with a CSR Jacobian (``SparseFullHB``) has the residual,
    Jacobian and lam-derivative of the dense ``FullHB`` (1e-12), and its Newton solve
    (SuperLU on the bordered system) the same solution (1e-10) -- on the 12-element
    beam rotor of tests/model (56 DOF, forced onto the sparse path)."""
    import scipy.sparse as sp
    from tests.model.test_sparse import rotor

    from rotorsfd.elements.sfd import SFDElement
    from rotorsfd.harmonic import full_sparse
    from rotorsfd.harmonic.full_sparse import SparseFullHB
    from rotorsfd.harmonic.hb_system import HBSystem
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.harmonic.residual import FullHB
    from rotorsfd.model.system import RotorSystem
    from rotorsfd.model.unbalance import Unbalance

    sfd = SFD(viscosity=0.0051, radius=0.0262, length=0.017, clearance=0.127e-3)
    system = RotorSystem(rotor(12), [SFDElement("sfd", 1, sfd)], [Unbalance(7, 2e-5, 0.3)])
    p = system.periodic_problem()
    H, lam = 3, 650.0
    x = _state(H, p.n_dof, 2e-5, 3)
    a, b = SparseFullHB(p, H, 32), FullHB(p, H, 32)
    Ra, Ja, dRa = a.residual(x, lam)
    Rb, Jb, dRb = b.residual(x, lam)
    assert sp.issparse(Ja)
    assert _rel(Ra, Rb) <= 1e-12 and _rel(Ja.toarray(), Jb) <= 1e-12
    assert _rel(dRa, dRb) <= 1e-12
    dense = solve_periodic(p, lam, H, tol=1e-12, condensed=False)
    monkeypatch.setattr(full_sparse, "SPARSE_MIN_DOF", 0)        # force the sparse path
    assert isinstance(HBSystem(p, H, 32, False, lam, lam).hb, SparseFullHB)
    sparse = solve_periodic(p, lam, H, tol=1e-12, condensed=False)
    assert sp.issparse(sparse.jacobian) and not sp.issparse(dense.jacobian)
    assert dense.iterations >= 1
    assert np.abs(sparse.X - dense.X).max() <= 1e-10 * np.abs(dense.X).max()
