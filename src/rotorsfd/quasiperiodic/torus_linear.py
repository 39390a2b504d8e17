"""The torus problem and its coupled linear operator, condensed exactly onto the nonlinear DOFs.

The linear part has coefficients periodic in ``theta2 = w_b t`` (the moving-base terms of
a harmonic base law):

    M q'' + D(theta2) q' + K(theta2) q = f(theta) + S^T F_nl(q_n, q_n'),
    D(theta2) = sum_{|j| <= b} D_j e^{i j theta2},   K(theta2) = sum_{|j| <= b} K_j e^{i j theta2}

(``D_{-j} = conj(D_j)``; b = 2 for the built-in laws, whose coefficients hold w_b(t),
w_b(t)^2 and dw_b/dt). Balancing ``exp(i (k1 theta1 + k2 theta2))`` gives, for harmonic
``(k1, k2)`` with ``omega_k = k1 Omega + k2 w_b``,

    sum_{|j| <= b} Z_{k, j} X_{(k1, k2 - j)} = F_k + S^T G_k,
    Z_{k, j} = K_j + i omega_{(k1, k2-j)} D_j - delta_{j0} omega_k^2 M.

The operator couples k2 to k2 +- 1, +- 2 but never two values of k1 (the base terms do
not depend on theta1): it is block diagonal over k1, one complex block of
``n (2 h(k1) + 1)`` unknowns per k1 (the k1 = 0 block on the two-sided ``c_{0,k2}``,
:func:`~rotorsfd.quasiperiodic.torus_fourier.block_vectors`). Harmonics with k2 beyond the
truncation are dropped from the coupling (the truncation).

**Condensation.** As in :mod:`rotorsfd.harmonic.condensation`, a fixed fictitious
spring/damper ``Delta_k = K_r + i omega_k^* C_r`` on the nonlinear DOFs (omega^* the
frequencies when it was set) is added to both sides, and with ``Zt = Z + S^T Delta S`` per
block (one complex LU of the whole k1 block: exact, since the harmonics of one block
couple)

    X = u + C (G + Delta Xs),   u = Zt^{-1} F,   C = Zt^{-1} S^T,
    R(Xs, lam) = Xs - Pt - Ht (G(Xs) + Delta Xs) = 0,   Ht = S C,  Pt = S u,

so the receptance ``Ht`` couples the k2 harmonics of one k1 at the nonlinear DOFs: the
condensed unknowns are those of the nonlinear DOFs only, as in the periodic case, at the
price of a solve of size ``n (2h + 1)`` per block instead of n per harmonic (banded when
the rotor's matrices are: :class:`ColumnSolver`). Exact
derivatives: ``dHt = -S Zt^{-1} dZ C``, ``dPt = S Zt^{-1} (dF - dZ u)``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import get_lapack_funcs, lu_factor, lu_solve

from rotorsfd.harmonic.fourier import to_complex
from rotorsfd.harmonic.residual import real_blocks
from rotorsfd.quasiperiodic.torus_fourier import (
    TorusLattice,
    block_real_indices,
    block_real_maps,
    block_vectors,
    from_blocks,
)

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass
class TorusProblem:
    """A second-order system with theta2-periodic linear terms and a local nonlinearity.

    ``coefficients(lam) -> (D, K)``, each (b+1, n, n) complex: D_j, K_j for j = 0..b
    (module docstring); ``dcoefficients(lam)`` their lam-derivatives. ``forcing(lam,
    lattice) -> (nk, n)`` one-sided coefficients F_k of f on the half lattice,
    ``dforcing`` their derivative. ``frequencies(lam) -> (Omega, w_b)``,
    ``dfrequencies(lam)``. ``elements``: the nonlinear force (an
    :class:`~rotorsfd.elements.ElementSet`: ``force``, ``force_and_jacobian`` over sample
    axes, ``limit``) on ``nl_dofs``; ``scaling`` (n,) the per-DOF length scales.
    """

    n_dof: int
    nl_dofs: NDArray[np.int64]
    M: FloatArray
    coefficients: Callable[[float], tuple[ComplexArray, ComplexArray]]
    dcoefficients: Callable[[float], tuple[ComplexArray, ComplexArray]]
    forcing: Callable[[float, TorusLattice], ComplexArray]
    dforcing: Callable[[float, TorusLattice], ComplexArray]
    frequencies: Callable[[float], tuple[float, float]]
    dfrequencies: Callable[[float], tuple[float, float]]
    elements: Any = None
    scaling: FloatArray | float = 1.0
    name: str = "torus problem"
    info: dict = field(default_factory=dict)

    def __post_init__(self) -> None:
        self.nl_dofs = np.atleast_1d(np.asarray(self.nl_dofs, dtype=np.int64))

    @property
    def m(self) -> int:
        return int(self.nl_dofs.size)

    @property
    def dof_scale(self) -> FloatArray:
        return np.broadcast_to(np.asarray(self.scaling, dtype=float), (self.n_dof,)).copy()

    def limit(self, q_nl: FloatArray) -> float:
        """The elements' validity measure of samples (0 without elements)."""
        if self.elements is None or not self.m:
            return 0.0
        return float(self.elements.limit(q_nl))


def column_operator(problem: TorusProblem, lattice: TorusLattice, k1: int, lam: float,
                    deriv: bool = False) -> tuple[ComplexArray, ComplexArray | None]:
    """The block Z of column k1 (p n, p n), p = 2h+1, rows and columns ordered (k2 from
    -h, DOF), and its lam-derivative (module docstring)."""
    n, h = problem.n_dof, lattice.h(k1)
    p = 2 * h + 1
    D, K = problem.coefficients(lam)
    b = D.shape[0] - 1
    om, wb = problem.frequencies(lam)
    w = k1 * om + np.arange(-h, h + 1) * wb
    Z = np.zeros((p, n, p, n), dtype=complex)
    if deriv:
        dD, dK = problem.dcoefficients(lam)
        dom, dwb = problem.dfrequencies(lam)
        dw = k1 * dom + np.arange(-h, h + 1) * dwb
        dZ = np.zeros_like(Z)
    for j in range(-min(b, p - 1), min(b, p - 1) + 1):   # Z[r, :, r - j, :]
        rr = np.arange(max(0, j), min(p, p + j))
        cc = rr - j
        Dj = D[j] if j >= 0 else np.conj(D[-j])
        Kj = K[j] if j >= 0 else np.conj(K[-j])
        Z[rr, :, cc, :] = Kj[None] + 1j * w[cc, None, None] * Dj[None]
        if deriv:
            dDj = dD[j] if j >= 0 else np.conj(dD[-j])
            dKj = dK[j] if j >= 0 else np.conj(dK[-j])
            dZ[rr, :, cc, :] = dKj[None] + 1j * (dw[cc, None, None] * Dj[None]
                                                 + w[cc, None, None] * dDj[None])
    diag = np.arange(p)
    Z[diag, :, diag, :] -= (w**2)[:, None, None] * problem.M[None]
    if deriv:
        dZ[diag, :, diag, :] -= (2 * w * dw)[:, None, None] * problem.M[None]
    shape = (p * n, p * n)
    return Z.reshape(shape), (dZ.reshape(shape) if deriv else None)


def complex_to_real(lattice: TorusLattice, k1: int, A: ComplexArray, width: int
                    ) -> tuple[NDArray[np.int64], FloatArray]:
    """A complex column operator A (p w, p w) as a real matrix on the real layout:
    ``(global indices g, Re((U x I) A (T x I)))`` with g into the flattened (n_real, w)
    layout (:func:`~rotorsfd.quasiperiodic.torus_fourier.block_real_maps`)."""
    T, U = block_real_maps(lattice, k1)
    eye = np.eye(width)
    R = (np.kron(U, eye) @ A @ np.kron(T, eye)).real
    idx = block_real_indices(lattice, k1)
    g = (idx[:, None] * width + np.arange(width)[None, :]).ravel()
    return g, R


class ColumnSolver:
    """LU of a column block Z (p n, p n), rows ordered (k2, DOF). Reordered DOF-major
    (index d p + r) the block is banded when the rotor's matrices are: with ``dof_band``
    the half bandwidth of M, D_j, K_j (FE: a few DOFs), that of the reordered block is
    ``dof_band p + p - 1``; then LAPACK's banded LU (gbtrf/gbtrs), else a dense LU."""

    def __init__(self, Z: ComplexArray, p: int, n: int, dof_band: int) -> None:
        self.perm = (np.arange(n)[:, None] + n * np.arange(p)[None, :]).ravel()
        N = p * n
        A = Z.reshape(p, n, p, n).transpose(1, 0, 3, 2).reshape(N, N)   # = Z[perm][:, perm]
        # entries (d, r), (e, c) with |d - e| <= dof_band: |i - j| <= dof_band p + p - 1
        kl = ku = min(dof_band * p + p - 1, N - 1)
        self.banded = kl + ku < N // 4
        if not self.banded:
            self.lu = lu_factor(Z, check_finite=False)
            return
        gbtrf, self._gbtrs = get_lapack_funcs(("gbtrf", "gbtrs"), (A,))
        ab = np.zeros((2 * kl + ku + 1, N), dtype=complex)
        for d in range(-ku, kl + 1):              # ab[kl + ku + i - j, j] = A[i, j]
            diag = np.diagonal(A, -d)
            if d >= 0:
                ab[kl + ku + d, : N - d] = diag
            else:
                ab[kl + ku + d, -d:] = diag
        self.lu, self.piv, info = gbtrf(ab, kl, ku)
        if info > 0:
            raise np.linalg.LinAlgError("singular torus column operator")
        self.kl, self.ku = kl, ku
        self.inverse = np.argsort(self.perm)

    def solve(self, b: ComplexArray) -> ComplexArray:
        """Z^-1 b for b (p n, c)."""
        if not self.banded:
            return lu_solve(self.lu, b, check_finite=False)
        x, _ = self._gbtrs(self.lu, self.kl, self.ku, b[self.perm], self.piv)
        return x[self.inverse]


@dataclass
class TorusCondensed:
    """Condensed operators at one lam, in the real layout of the nonlinear DOFs:
    ``Ht`` (n_real m, n_real m), ``Pt`` (n_real, m), their lam-derivatives (None when not
    asked), and per k1 ``u`` (p n,) and ``C`` (p n, p m) for the recovery."""

    lam: float
    Ht: FloatArray
    Pt: FloatArray
    u: list[ComplexArray]
    C: list[ComplexArray]
    dHt: FloatArray | None = None
    dPt: FloatArray | None = None


class TorusCondenser:
    """Exact condensation of the torus equations onto the nonlinear DOFs (module doc)."""

    def __init__(self, problem: TorusProblem, lattice: TorusLattice) -> None:
        self.problem, self.lattice = problem, lattice
        m = problem.m
        self.Kr = np.zeros((m, m))
        self.Cr = np.zeros((m, m))
        self.freq_shift = (0.0, 0.0)
        self._cache: TorusCondensed | None = None

    def set_shift(self, Kr: FloatArray, Cr: FloatArray, lam: float) -> None:
        """Delta_k = Kr + i omega_k(lam) Cr, held fixed (also when lam changes)."""
        self.Kr, self.Cr = np.asarray(Kr, float), np.asarray(Cr, float)
        om, wb = self.problem.frequencies(lam)
        self.freq_shift = (float(om), float(wb))
        self._cache = None

    def delta(self, k1: int) -> ComplexArray:
        """(p, m, m) shift of column k1, k2 = -h..h."""
        om_s, wb_s = self.freq_shift
        h = self.lattice.h(k1)
        w = k1 * om_s + np.arange(-h, h + 1) * wb_s
        return self.Kr[None] + 1j * w[:, None, None] * self.Cr[None]

    def delta_real(self) -> FloatArray:
        """Delta on the real layout (n_real m, n_real m), per half-lattice harmonic."""
        w = self.lattice.frequencies(*self.freq_shift)
        stack = self.Kr[None] + 1j * w[:, None, None] * self.Cr[None]
        return real_blocks(stack)

    def condense(self, lam: float, deriv: bool = True) -> TorusCondensed:
        """Receptance, particular response and (deriv) their lam-derivatives at lam."""
        c = self._cache
        if c is not None and c.lam == lam and (c.dHt is not None or not deriv):
            return c
        p_, lat = self.problem, self.lattice
        n, m, s = p_.n_dof, p_.m, p_.nl_dofs
        nr = lat.n_real
        F = block_vectors(lat, p_.forcing(lam, lat))
        dF = block_vectors(lat, p_.dforcing(lam, lat)) if deriv else None
        Ht = np.zeros((nr * m, nr * m))
        Pt = np.zeros((nr, m))
        dHt = np.zeros_like(Ht) if deriv else None
        dPt = np.zeros_like(Pt) if deriv else None
        us, Cs = [], []
        D, K = p_.coefficients(lam)
        pattern = np.abs(p_.M) + np.abs(D).sum(axis=0) + np.abs(K).sum(axis=0)
        r_, c_ = np.nonzero(pattern)
        band = int(np.abs(r_ - c_).max(initial=0))      # the shift is diagonal
        for k1 in range(lat.H1 + 1):
            Z, dZ = column_operator(p_, lat, k1, lam, deriv)
            p = 2 * lat.h(k1) + 1
            rows = (np.arange(p)[:, None] * n + s[None, :]).ravel()   # S in the column
            if m:
                dl = self.delta(k1)
                for r in range(p):
                    Z[np.ix_(r * n + s, r * n + s)] += dl[r]
            lu = ColumnSolver(Z, p, n, band)
            rhs = np.zeros((p * n, p * m + 1), dtype=complex)
            rhs[rows, np.arange(p * m)] = 1.0
            rhs[:, -1] = F[k1].ravel()
            sol = lu.solve(rhs)
            C, u = sol[:, :-1], sol[:, -1]
            us.append(u)
            Cs.append(C)
            idx = block_real_indices(lat, k1)
            _, U = block_real_maps(lat, k1)
            Pt[idx] = (U @ u[rows].reshape(p, m)).real
            if m:
                g, R = complex_to_real(lat, k1, C[rows], m)
                Ht[np.ix_(g, g)] = R
            if not deriv:
                continue
            rhs2 = np.concatenate([dZ @ C, (dF[k1].ravel() - dZ @ u)[:, None]], axis=1)
            sol2 = lu.solve(rhs2)[rows]
            dPt[idx] = (U @ sol2[:, -1].reshape(p, m)).real
            if m:
                g, R = complex_to_real(lat, k1, -sol2[:, :-1], m)
                dHt[np.ix_(g, g)] = R
        out = TorusCondensed(lam, Ht, Pt, us, Cs, dHt, dPt)
        self._cache = out
        return out

    def recover(self, cond: TorusCondensed, xs: FloatArray, G: FloatArray) -> ComplexArray:
        """All-DOF one-sided coefficients (nk, n): ``X = u + C (G + Delta Xs)`` per k1."""
        lat, n, m = self.lattice, self.problem.n_dof, self.problem.m
        cols = []
        if m:
            rhs = (G.reshape(-1) + self.delta_real() @ xs.reshape(-1)).reshape(-1, m)
            rb = block_vectors(lat, to_complex(rhs))
        for k1 in range(lat.H1 + 1):
            p = 2 * lat.h(k1) + 1
            X = cond.u[k1].copy()
            if m:
                X = X + cond.C[k1] @ rb[k1].ravel()
            cols.append(X.reshape(p, n))
        return from_blocks(lat, cols)
