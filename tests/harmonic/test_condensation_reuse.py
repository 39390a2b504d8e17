"""Savings on the banded condensation of a large model (issue 17 items 2-3): the fused
doubled-precision residual of the refinement step and the truncation estimate's reuse of
the point's harmonics, each against the previous code path and an independent reference."""

from __future__ import annotations

from fractions import Fraction

import numpy as np
import pytest
from tests.model.test_sparse import rotor

from rotorsfd.elements.sfd import SFDElement
from rotorsfd.harmonic import banded
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.harmonic.truncation import estimate_condenser, truncation_error
from rotorsfd.model.damping import ModalDamping
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance
from rotorsfd.sfd import SFD

LAM = 650.0


def _rel(a, b) -> float:
    a, b = np.asarray(a), np.asarray(b)
    return float(np.abs(a - b).max() / np.abs(b).max())


def _problem(modal: bool, n_elements: int = 120):
    """A 484-DOF banded rotor (above ``REFINE_MIN_DOF``: the refinement step runs)."""
    sfd = SFD(viscosity=0.0051, radius=0.0262, length=0.017, clearance=0.127e-3)
    damping = ModalDamping(0.02, modes=4) if modal else None
    system = RotorSystem(rotor(n_elements, damping), [SFDElement("sfd", 1, sfd)],
                         [Unbalance(n_elements // 2, 2e-5, 0.3)])
    return system.periodic_problem()


def _rowwise_residual(Mb, Db, Kb, kl, ku, kw, s, delta_k, F_k, x):
    """The residual as computed before: one ``_exact_dot_row`` per row, column and part."""
    n, nc = x.shape
    m = nc - 1
    xr = np.empty((n, 2 * nc))
    xr[:, 0::2], xr[:, 1::2] = x.real, x.imag
    r = np.empty_like(x)
    for i in range(n):
        for c in range(nc):
            rhs = F_k[i] if c == m else 0.0j
            re_hi, re_lo = banded._exact_dot_row(Kb, kl, ku, i, xr, 2 * c)
            im_hi, im_lo = banded._exact_dot_row(Kb, kl, ku, i, xr, 2 * c + 1)
            r[i, c] = complex((rhs.real - re_hi) - re_lo, (rhs.imag - im_hi) - im_lo)
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            e = complex(-kw * kw * Mb[j, ku + i - j], kw * Db[j, ku + i - j])
            if e != 0.0:
                r[i] -= e * x[j]
    for a in range(m):
        r[s[a], a] += 1.0
        r[s[a]] -= delta_k[a] * x[s[a]]
    return r


def _band_system(seed: int, n: int = 60, kl: int = 3, ku: int = 4):
    rng = np.random.default_rng(seed)
    Kb, Mb, Db = (rng.normal(size=(n, kl + ku + 1)) * sc for sc in (1e9, 1.0, 1e2))
    s = np.array([5, 40])
    x = rng.normal(size=(n, 3)) + 1j * rng.normal(size=(n, 3))
    F = rng.normal(size=n) + 1j * rng.normal(size=n)
    return Mb, Db, Kb, kl, ku, s, np.array([2e6 + 1j, 3e5 - 2j]), F, x


def test_fused_residual_is_the_rowwise_one_bit_for_bit():
    """The fused pass over a row's band gives the same bits as one Dot2 per column."""
    Mb, Db, Kb, kl, ku, s, dk, F, x = _band_system(3)
    kw = 37.0
    r = np.empty_like(x)
    banded.band_residual(Mb, Db, Kb, kl, ku, kw, kw * kw, s, dk, F, x, r)
    assert np.array_equal(r, _rowwise_residual(Mb, Db, Kb, kl, ku, kw, s, dk, F, x))


def test_fused_residual_stiffness_part_is_exact_to_working_precision():
    """``F - K x`` with M = D = Delta = 0 on a cancelling x (K x ~ F to 1e-9): the fused
    residual = the exact rational one rounded, to 2 eps of it (a plain sum would be off by
    eps |K| |x| ~ 1e-7 of it)."""
    Mb, _, Kb, kl, ku, _, _, F, _ = _band_system(4)
    n = Kb.shape[0]
    K = np.zeros((n, n))
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            K[i, j] = Kb[j, ku + i - j]
    rng = np.random.default_rng(5)
    x = np.linalg.solve(K, F)[:, None] * (1 + 1e-9 * rng.normal(size=(n, 1)))
    r = np.empty_like(x)
    zero = np.zeros_like(Mb)
    banded.band_residual(zero, zero, Kb, kl, ku, 1.0, 1.0, np.array([], dtype=np.int64),
                         np.zeros(0, complex), F, x, r)
    for i in range(0, n, 7):
        for part in ("real", "imag"):
            xs = getattr(x[:, 0], part)
            exact = Fraction(getattr(F[i], part)) - sum(
                (Fraction(K[i, j]) * Fraction(xs[j]) for j in range(n) if K[i, j] != 0.0),
                Fraction(0))
            got = getattr(r[i, 0], part)
            assert abs(Fraction(got) - exact) <= 2.3e-16 * abs(exact), (i, part)
            plain = abs(getattr(F[i], part)) + float(sum(abs(K[i]) * abs(xs)))
            assert abs(float(exact)) < 1e-6 * plain    # the case cancels


@pytest.mark.parametrize("modal", [False, True])
def test_reused_harmonics_equal_a_full_condensation(modal):
    """Condensation at H = 3 reusing the H = 1 condenser's harmonics 0, 1 (same shift
    by ``adopt_shift``) = the same condensation computed in full, bit for bit, and = an
    independent dense solve of Zt_k (to the LU's rounding x condition)."""
    p = _problem(modal)
    lo, hi, ref = CondensedHB(p, 1, 16), CondensedHB(p, 3, 32), CondensedHB(p, 3, 32)
    xs = 2e-5 * np.random.default_rng(2).normal(size=(3, p.m))
    lo.set_shift(xs, LAM)
    lo.condense(LAM)
    assert hi.adopt_shift(lo) and ref.adopt_shift(lo)
    assert np.array_equal(hi.delta[:2], lo.delta)
    assert hi._reusable(lo, LAM, True) is not None      # the copy path is taken
    a, b = hi.condense(LAM, reuse=lo), ref.condense(LAM)
    for name in ("Ht", "Pt", "u", "C", "dHt", "dPt"):
        assert np.array_equal(getattr(a, name), getattr(b, name)), name
    M, D, K = (np.asarray(A.toarray() if hasattr(A, "toarray") else A)
               for A in p.matrices(LAM))
    w, s = p.frequency(LAM), p.nl_dofs
    for k in range(4):
        Z = K - (k * w) ** 2 * M + 1j * k * w * D
        Z[np.ix_(s, s)] += hi.delta[k]
        Ht = np.linalg.solve(Z, np.eye(p.n_dof)[:, s])[s]
        assert _rel(a.Ht[k], Ht) <= 1e-15 * np.linalg.cond(Z) + 1e-13, k


def test_truncation_estimate_with_the_point_condenser_is_unchanged():
    """The estimate of a converged H = 1 point with the point's shift and harmonics
    (``point=``) = the estimate with its own shift, to 1e-10 relative, with a tangent."""
    p = _problem(False)
    res = solve_periodic(p, LAM, 1, tol=1e-12, condensed=True)
    xs = to_real(res.X[:, p.nl_dofs])
    pt = CondensedHB(p, 1, 16)
    pt.set_shift(xs, LAM)
    pt.condense(LAM)
    t = np.random.default_rng(7).normal(size=xs.size + 1)
    t /= np.linalg.norm(t)
    own = truncation_error(p, xs, LAM, tangent=t, lam_scale=LAM)
    reuse = truncation_error(p, xs, LAM, tangent=t, lam_scale=LAM,
                             condenser=estimate_condenser(p, 1), point=pt)
    assert own.error > 1e-8                        # a case with a truncation error
    assert abs(reuse.error - own.error) <= 1e-10 * own.error
    assert _rel(reuse.delta, own.delta) <= 1e-10
    assert abs(reuse.delta_lam - own.delta_lam) <= 1e-10 * abs(own.delta_lam) + 1e-300


@pytest.mark.parametrize("modal", [False, True])
def test_point_from_the_linear_guess_keeps_its_condensation(modal, monkeypatch):
    """``solve_periodic`` from the linearised response takes over the guess's condensation
    (shift at rest) instead of condensing again at the guess's shift: one condensation
    per point instead of two, the same solution as the previous path (a fresh shift at the
    guess) to 1e-10, near the resonance where the nonlinearity matters."""
    p = _problem(modal)
    calls = []
    condense = CondensedHB.condense

    def counted(self, lam, deriv=True, reuse=None):
        c = self._cache
        if c is None or c.lam != lam or (deriv and c.dHt is None):
            calls.append(self.H)
        return condense(self, lam, deriv, reuse)

    monkeypatch.setattr(CondensedHB, "condense", counted)
    lam = 1.3 * LAM
    new = solve_periodic(p, lam, 3, tol=1e-12, condensed=True)
    n_new, calls[:] = len(calls), []
    monkeypatch.setattr(CondensedHB, "adopt_condensation", lambda self, other: False)
    old = solve_periodic(p, lam, 3, tol=1e-12, condensed=True)
    assert (n_new, len(calls)) == (1, 2)
    assert new.iterations >= 2                     # a nonlinear case, not one linear step
    assert _rel(new.X, old.X) <= 1e-10
