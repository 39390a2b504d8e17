"""Dense condensation from each harmonic's dynamic stiffness as a matrix polynomial in lam:
one eigendecomposition per harmonic for a whole branch instead of one LU per point.

With the frequency ``w(lam) = w0 + w1 lam`` (the problem's ``frequency_line``) and the
linear part polynomial in lam (``matrices.polynomial()``: M, D_j, K_j, j <= 2),

    Z_k(lam) = K - (k w)^2 M + i k w D = sum_{j <= d} lam^j A_j                   (d <= 3)

    A_0 = K_0 - k^2 w0^2 M + i k w0 D_0,   A_1 = K_1 - 2 k^2 w0 w1 M + i k (w0 D_1 + w1 D_0),
    A_2 = K_2 - k^2 w1^2 M + i k (w0 D_2 + w1 D_1),   A_3 = i k w1 D_2.

In ``mu = lam / tau`` (tau the lam of the first build: eigenvalues of order one), the block
companion matrix Cp (d n) of the monic ``A_d^-1 Z_k`` (``y_j = mu^j x``; last block row
``-A_d^-1 [A_0 .. A_{d-1}]``) has ``(mu - Cp) y = e_d A_d^-1 b`` for ``Z_k x = b``, so with
``Cp = V diag(theta) V^-1``

    Z_k^-1 = P diag(phi) Q,   dZ_k^-1/dlam = -P diag(phi^2) Q / tau,   phi = 1/(mu - theta),

``P = V[:n]`` (n, dn), ``Q = (V^-1)[:, last n] A_d^-1`` (dn, n); a constant Z_k (d = 0) is
``P = I, Q = Z_k^-1, phi = 1``. A point then costs O(d n m) per harmonic, not an O(n^3) LU.
The shift ``Delta_k`` on the nonlinear DOFs S by Woodbury (``H0 = S Z^-1 S^T``, ``C0 = Z^-1
S^T``, ``u0 = Z^-1 F``, ``W = (I + Delta H0)^-1``, ``W_L = (I + H0 Delta)^-1``):

    Ht = H0 W,   C = C0 W,   g = W Delta S u0,   u = u0 - C0 g,   Pt = S u0 - H0 g,
    dHt = W_L dH0 W,   dPt = W_L (S Z^-1 dF + S (dZ^-1) F - dH0 g).

Exact in exact arithmetic; in floating point the error grows with the condition of V, so
each harmonic's decomposition is checked against an LU of ``Z_k`` where it is built
(:data:`PENCIL_RTOL`, the receptance and its lam-derivative): a harmonic that fails keeps
the LU (the static one alone; any other: the whole condensation). Used after
:data:`PENCIL_AFTER` dense condensations of the same linear part (a branch, not a few
points).
"""

from __future__ import annotations

import warnings
import weakref
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.linalg
from numpy.typing import NDArray

from rotorsfd.harmonic.dense_condensation import dense_solves

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Dense condensations of one linear part before its harmonics are decomposed: a branch
#: has hundreds, a problem of a fold curve's Newton a few (at most 13 in the paper run;
#: one decomposition costs about 150 LUs, so a linear part condensed 64 to ~150 times
#: pays more than it saves, one condensed more often saves).
PENCIL_AFTER = 64
#: Largest relative difference (max norm) of the receptance and of its lam-derivative from
#: an LU of Z_k where a harmonic's decomposition is built; above it the harmonic keeps
#: the LU.
PENCIL_RTOL = 1e-8
#: Smallest ratio of the LU pivots of the leading coefficient A_d (below it A_d counts as
#: singular, e.g. the centripetal stiffness of a base rate: eigenvalues at infinity).
LEADING_RCOND = 1e-12


@dataclass(frozen=True)
class Pencil:
    """One harmonic's ``Z_k^-1 = P diag(phi(mu)) Q`` (module docstring); theta None for a
    constant Z_k (phi = 1)."""

    P: ComplexArray       # (n, dn)
    Q: ComplexArray       # (dn, n)
    theta: ComplexArray | None


@dataclass(frozen=True)
class Stack:
    """The pencils of consecutive harmonics stacked (leading axis: the harmonic): P, Q and
    their rows / columns at the nonlinear DOFs Ps = P[:, s], Qs = Q[:, :, s]; theta None
    for constant Z_k; tau the scale of mu = lam / tau."""

    P: ComplexArray       # (h, n, dn)
    Q: ComplexArray       # (h, dn, n)
    Ps: ComplexArray      # (h, m, dn)
    Qs: ComplexArray      # (h, dn, m)
    theta: ComplexArray | None
    tau: float

    def phi(self, lam: float) -> tuple[ComplexArray, ComplexArray]:
        """``phi`` and ``d phi / d lam`` (h, dn) at lam."""
        return _phi(self.theta, lam, self.tau, (self.P.shape[0], self.P.shape[2]))


def _phi(theta: ComplexArray | None, lam: float, tau: float, shape: tuple
         ) -> tuple[ComplexArray, ComplexArray]:
    """``phi = 1 / (lam / tau - theta)`` and ``d phi / d lam = -phi^2 / tau`` (ones and
    zeros of ``shape`` for a constant Z_k, theta None)."""
    if theta is None:
        return np.ones(shape, dtype=complex), np.zeros(shape, dtype=complex)
    f = 1.0 / (lam / tau - theta)
    return f, -f * f / tau


def coefficients(M: FloatArray, D: tuple, K: tuple, w0: float, w1: float, k: int
                 ) -> list[Any]:
    """``[A_0, .., A_d]`` of ``Z_k(lam)`` (module docstring), trailing zero terms dropped;
    a term is an array or 0."""
    z = [0 if a is None else a for a in D]
    s = [0 if a is None else a for a in K]
    kk = float(k * k)
    A = [s[0] - kk * w0 * w0 * M + 1j * k * w0 * z[0],
         s[1] - 2.0 * kk * w0 * w1 * M + 1j * k * (w0 * z[1] + w1 * z[0]),
         s[2] - kk * w1 * w1 * M + 1j * k * (w0 * z[2] + w1 * z[1]),
         1j * k * w1 * z[2]]
    nonzero = [j for j, a in enumerate(A) if not (np.isscalar(a) and a == 0)
               and np.any(a != 0)]
    d = max(nonzero) if nonzero else 0
    return A[: d + 1]


def decompose(A: list[Any], tau: float, n: int) -> Pencil:
    """The pencil of ``sum_j lam^j A_j`` in ``mu = lam / tau``."""
    d = len(A) - 1
    if d == 0:
        return Pencil(np.eye(n, dtype=complex), scipy.linalg.inv(
            np.asarray(A[0], dtype=complex) + np.zeros((n, n))), None)
    B = [np.asarray(a, dtype=complex) * tau**j + np.zeros((n, n)) for j, a in enumerate(A)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
        lu = scipy.linalg.lu_factor(B[d], check_finite=False)
    pivots = np.abs(np.diagonal(lu[0]))
    if not pivots.min() > LEADING_RCOND * pivots.max():
        raise np.linalg.LinAlgError("singular leading coefficient A_d")
    Cp = np.zeros((d * n, d * n), dtype=complex)
    for j in range(d - 1):
        Cp[j * n:(j + 1) * n, (j + 1) * n:(j + 2) * n] = np.eye(n)
    Cp[(d - 1) * n:] = -scipy.linalg.lu_solve(lu, np.hstack(B[:d]), check_finite=False)
    theta, V = scipy.linalg.eig(Cp, overwrite_a=True, check_finite=False)
    E = np.zeros((d * n, n), dtype=complex)
    E[(d - 1) * n:] = np.eye(n)
    X = scipy.linalg.solve(V, E, check_finite=False)           # V^-1 e_d
    Q = scipy.linalg.lu_solve(lu, X.T, trans=1, check_finite=False).T   # .. A_d^-1
    return Pencil(np.ascontiguousarray(V[:n]), np.ascontiguousarray(Q), theta)


class HarmonicPencils:
    """The pencils of one linear part and frequency line, harmonic by harmonic, built on
    demand and checked where built (None: that harmonic keeps the LU)."""

    def __init__(self, polynomial: tuple, line: tuple[float, float], s: NDArray[np.int64]
                 ) -> None:
        self.M, self.D, self.K = polynomial
        self.w0, self.w1 = (float(c) for c in line)
        self.s = s
        self.n = int(self.M.shape[0])
        self.tau: float | None = None
        self.pencils: dict[int, Pencil | None] = {}
        self._stacks: dict[tuple[int, int], Stack | None] = {}

    def pencil(self, k: int, lam: float, Z: ComplexArray, dZ: ComplexArray) -> Pencil | None:
        """Harmonic k's pencil, built at the first call and checked against ``Z_k(lam)``
        and ``dZ_k/dlam`` (dense, formed by the caller)."""
        if k in self.pencils:
            return self.pencils[k]
        if self.tau is None:
            self.tau = abs(lam) if lam != 0.0 else 1.0
        try:
            out: Pencil | None = decompose(
                coefficients(self.M, self.D, self.K, self.w0, self.w1, k), self.tau, self.n)
        except (np.linalg.LinAlgError, ValueError):
            out = None
        if out is not None and not self._agrees(out, lam, Z, dZ):
            out = None
        self.pencils[k] = out
        return out

    def stack(self, ks: range, lam: float, mats: Callable[[], tuple], w: float, dw: float
              ) -> Stack | None:
        """The pencils of harmonics ``ks`` stacked, built where missing (checked against
        ``Z_k(lam)`` from ``mats() = (M, D, K, dM, dD, dK)`` at lam), None if one of them
        does not serve or their sizes differ."""
        key = (ks.start, ks.stop)
        if key in self._stacks:
            return self._stacks[key]
        M, D, K, dM, dD, dK = mats()
        out: list[Pencil] = []
        for k in ks:
            kw = k * w
            Z = K - kw * kw * M + 1j * kw * D
            dZ = dK - kw * kw * dM - (2.0 * k * kw * dw) * M + 1j * k * (dw * D + w * dD)
            pc = self.pencil(k, lam, Z, dZ)
            if pc is None or (out and pc.P.shape != out[0].P.shape):
                self._stacks[key] = None
                return None
            out.append(pc)
        s = self.s
        constant = out[0].theta is None
        st = Stack(np.stack([p.P for p in out]), np.stack([p.Q for p in out]),
                   np.stack([p.P[s] for p in out]), np.stack([p.Q[:, s] for p in out]),
                   None if constant else np.stack([p.theta for p in out]), self.tau)
        self._stacks[key] = st
        return st

    def _agrees(self, pc: Pencil, lam: float, Z: ComplexArray, dZ: ComplexArray) -> bool:
        """The receptance S Z^-1 S^T and its lam-derivative within PENCIL_RTOL of an LU."""
        s = self.s
        f, df = _phi(pc.theta, lam, self.tau, (pc.P.shape[1],))
        if not (np.all(np.isfinite(f)) and np.all(np.isfinite(pc.P))
                and np.all(np.isfinite(pc.Q))):
            return False
        E = np.eye(self.n)[:, s]
        C = np.linalg.solve(Z, E)                      # Z^-1 S^T
        R = np.linalg.solve(Z.T, E)                    # (S Z^-1)^T
        H0, dH0 = C[s], -R.T @ dZ @ C
        h = (pc.P[s] * f) @ pc.Q[:, s]
        dh = (pc.P[s] * df) @ pc.Q[:, s]
        ok = np.max(np.abs(h - H0)) <= PENCIL_RTOL * np.max(np.abs(H0))
        return bool(ok and np.max(np.abs(dh - dH0)) <= PENCIL_RTOL * max(
            np.max(np.abs(dH0)), np.finfo(float).tiny))


#: One :class:`HarmonicPencils` per linear part (weakly keyed: gone with it) and
#: frequency line, with the count of dense condensations seen
_PENCILS: weakref.WeakKeyDictionary = weakref.WeakKeyDictionary()


def pencils_for(problem: Any) -> HarmonicPencils | None:
    """The pencils of ``problem``'s linear part once it has been condensed densely
    :data:`PENCIL_AFTER` times (counted here), None before, or when the problem does not
    state its linear part as a polynomial (``matrices.polynomial``) and its frequency as
    a line (``frequency_line``)."""
    mats, line = problem.matrices, problem.frequency_line
    if line is None or not hasattr(mats, "polynomial"):
        return None
    try:
        seen = _PENCILS.setdefault(mats, {})
    except TypeError:          # not weakly referenceable
        return None
    key = (float(line[0]), float(line[1]), tuple(problem.nl_dofs))
    entry = seen.get(key)
    if entry is None:
        entry = seen[key] = [0, None]
    entry[0] += 1
    if entry[0] <= PENCIL_AFTER:
        return None
    if entry[1] is None:
        entry[1] = HarmonicPencils(mats.polynomial(), line, problem.nl_dofs)
    return entry[1]


def _inverse(A: ComplexArray) -> ComplexArray:
    """The inverse of each small matrix of A (h, m, m); closed form for m = 2."""
    if A.shape[1] != 2:
        return np.linalg.inv(A)
    out = np.empty_like(A)
    out[:, 0, 0], out[:, 1, 1] = A[:, 1, 1], A[:, 0, 0]
    out[:, 0, 1], out[:, 1, 0] = -A[:, 0, 1], -A[:, 1, 0]
    return out / (A[:, 0, 0] * A[:, 1, 1] - A[:, 0, 1] * A[:, 1, 0])[:, None, None]


def _forcing_rows(Q: ComplexArray, F: ComplexArray, dF: ComplexArray, deriv: bool
                  ) -> ComplexArray:
    """``Q_k [F_k, dF_k]`` (h, dn, 2) (without deriv ``Q_k F_k``, (h, dn, 1)), formed only
    for the harmonics that are forced."""
    rhs = np.stack([F, dF], axis=2) if deriv else F[:, :, None]
    out = np.zeros((Q.shape[0], Q.shape[1], rhs.shape[2]), dtype=complex)
    nz = np.flatnonzero(rhs.any(axis=(1, 2)))
    if nz.size:
        out[nz] = Q[nz] @ rhs[nz]
    return out


def evaluate(st: Stack, lam: float, delta: ComplexArray, F: ComplexArray,
             dF: ComplexArray, deriv: bool) -> tuple:
    """``(Ht, Pt, dHt, dPt, recovery)`` of the stacked harmonics (module docstring):
    receptances Ht (h, m, m), particular responses Pt (h, m), their lam-derivatives (None
    without deriv) and ``recovery() -> (u (h, n), C (h, n, m))``."""
    f, df = st.phi(lam)
    A = st.Ps * f[:, None, :]                   # S P diag(phi)
    H0 = A @ st.Qs
    QR = _forcing_rows(st.Q, F, dF, deriv)
    AR = A @ QR                                 # S Z^-1 [F, dF]
    u0s = AR[:, :, :1]
    eye = np.eye(H0.shape[1])
    W = _inverse(eye + delta @ H0)
    Ht = H0 @ W
    g = W @ (delta @ u0s)
    Pt = (u0s - H0 @ g)[:, :, 0]
    dHt = dPt = None
    if deriv:
        dA = st.Ps * df[:, None, :]
        dH0 = dA @ st.Qs
        WL = _inverse(eye + H0 @ delta)
        dHt = WL @ dH0 @ W
        dPt = (WL @ (AR[:, :, 1:] + dA @ QR[:, :, :1] - dH0 @ g))[:, :, 0]

    def recovery() -> tuple[ComplexArray, ComplexArray]:
        Pf = st.P * f[:, None, :]
        C0 = Pf @ st.Qs
        return (Pf @ QR[:, :, :1] - C0 @ g)[:, :, 0], C0 @ W

    return Ht, Pt, dHt, dPt, recovery


def condense_pencils(problem: Any, lam: float, H: int, delta: ComplexArray, w: float,
                     dw: float, F: ComplexArray, dF: ComplexArray, deriv: bool
                     ) -> tuple | None:
    """``(Ht, Pt, dHt, dPt, recovery)`` of harmonics 0..H at lam from the pencils of the
    problem's linear part (the static harmonic by an LU if its pencil does not serve), or
    None where the pencils do not serve (not yet :data:`PENCIL_AFTER` condensations, no
    polynomial form, a harmonic k >= 1 that failed its check): the caller's LU then."""
    pens = pencils_for(problem) if H >= 1 else None
    if pens is None:
        return None
    def mats() -> tuple:
        return (*problem.matrices(lam), *problem.dmatrices(lam))

    hi = pens.stack(range(1, H + 1), lam, mats, w, dw)
    if hi is None:
        return None
    lo = pens.stack(range(0, 1), lam, mats, w, dw)
    Ht1, Pt1, dHt1, dPt1, rec1 = evaluate(hi, lam, delta[1:], F[1:], dF[1:], deriv)
    if lo is not None:
        Ht0, Pt0, dHt0, dPt0, rec0 = evaluate(lo, lam, delta[:1], F[:1], dF[:1], deriv)
    else:
        m, n = problem.m, problem.n_dof
        sol = np.empty((1, n, m + 1), dtype=complex)
        dsol = np.empty((1, m, m + 1), dtype=complex)
        dense_solves(problem, 0, delta[:1], *mats(), w, dw, F[:1], dF[:1], deriv, sol, dsol)
        s = problem.nl_dofs
        Ht0, Pt0 = sol[:, s, :m], sol[:, s, m]
        dHt0, dPt0 = dsol[:, :, :m], dsol[:, :, m]

        def rec0() -> tuple[ComplexArray, ComplexArray]:
            return sol[:, :, m], sol[:, :, :m]

    def recovery() -> tuple[ComplexArray, ComplexArray]:
        (u0, C0), (u1, C1) = rec0(), rec1()
        return np.concatenate([u0, u1]), np.concatenate([C0, C1])

    out = [np.concatenate([a, b]) if b is not None else None
           for a, b in ((Ht0, Ht1), (Pt0, Pt1), (dHt0, dHt1), (dPt0, dPt1))]
    if not all(a is None or np.all(np.isfinite(a)) for a in out):
        raise FloatingPointError(f"singular dynamic stiffness at lam={lam:.6g}")
    return (*out, recovery)
