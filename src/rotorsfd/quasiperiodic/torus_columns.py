"""The k1 column blocks of the linear torus operator written straight into band storage,
their LU and the solves of the condensation, in one compiled pass per column.

Column k1 couples the harmonics (k1, k2), k2 = -h..h (p = 2h + 1 of them;
:mod:`~rotorsfd.quasiperiodic.torus_linear`), through

    Z[(r, d), (c, e)] = K_j[d, e] + i w_c D_j[d, e] - delta_j0 w_c^2 M[d, e],
    j = r - c (|j| <= b),   w_c = k1 Omega + (c - h) w_b,

(``D_{-j} = conj(D_j)``). Ordered DOF-major (row ``d p + r``) and with M, D_j, K_j of half
bandwidth beta (a finite-element rotor: a few DOFs), the block has the half bandwidth
``kl = beta p + min(b, p - 1)``. Its entries are written from the band entries of M, D_j,
K_j alone (``n (2 beta + 1)`` each) into band storage: O(n beta p b) work per column
instead of building and reordering the dense (p n)^2 block; one banded LU with partial
pivoting (:func:`rotorsfd.harmonic.banded.band_lu`, LAPACK ``zgbtf2``'s algorithm) serves
both solves of the column, all in one numba call. Above a quarter-full band (small
models) the block is written dense (DOF-major as well) and factorised by ``getrf``.

The lam-derivative ``dZ`` (same pattern; ``dw`` the frequencies' derivatives)

    dZ[(r, d), (c, e)] = dK_j + i (dw_c D_j + w_c dD_j) - delta_j0 (2 w_c dw_c M)

is applied to the receptance and the particular response entry by entry (a compiled
loop over the pattern). The fictitious shift of the condensation (on the
nonlinear DOFs, per harmonic) is added to the band in place.
"""

from __future__ import annotations

from dataclasses import dataclass
from functools import cached_property, lru_cache

import numpy as np
from numba import njit
from numpy.typing import NDArray
from scipy.linalg import lu_factor, lu_solve

from rotorsfd.harmonic.banded import band_lu, band_solve
from rotorsfd.quasiperiodic.torus_bands import band_entries, two_sided

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]


def half_bandwidth(*mats: ComplexArray) -> int:
    """Largest ``|i - j|`` of a nonzero entry over matrices (..., n, n)."""
    pattern = sum(np.abs(a).reshape(-1, *a.shape[-2:]).sum(axis=0) for a in mats)
    r, c = np.nonzero(pattern)
    return int(np.abs(r - c).max(initial=0))


@dataclass(frozen=True)
class ColumnPattern:
    """Index structure of one column block: ``n`` DOFs, ``p`` harmonics, base coupling
    degree ``b``, DOF half bandwidth ``beta`` (module docstring)."""

    n: int
    p: int
    b: int
    beta: int

    @property
    def N(self) -> int:
        return self.n * self.p

    @property
    def kl(self) -> int:
        """Half bandwidth of the DOF-major block (lower = upper)."""
        return min(self.beta * self.p + min(self.b, self.p - 1), self.N - 1)

    @property
    def banded(self) -> bool:
        """True when the band is less than a quarter of the block."""
        return 2 * self.kl < self.N // 4

    @cached_property
    def band_entries(self) -> tuple[IntArray, IntArray]:
        """(I, J) of the n x n entries with |I - J| <= beta, row-major."""
        return band_entries(self.n, self.beta)


@lru_cache(maxsize=64)
def column_pattern(n: int, p: int, b: int, beta: int) -> ColumnPattern:
    """The (cached) pattern of a column block."""
    return ColumnPattern(n, p, b, beta)


def two_sided_band(A: ComplexArray, I: IntArray, J: IntArray) -> ComplexArray:
    """(2b + 1, ne): band entries of A_j for j = -b..b from A (b + 1, n, n), j >= 0
    (``A_{-j} = conj(A_j)``)."""
    return two_sided(A[:, I, J])


class BandedColumn:
    """One column block from its pattern and band entries: LU and the solves of the
    condensation (module docstring); DOF-major right-hand sides.

    ``Dv, Kv`` (2b + 1, ne), ``Mv`` (ne,): the band entries (:func:`two_sided_band`);
    ``w`` (p,) the column's frequencies; ``shift`` (p, m, m) added on the DOFs ``s``
    (None: none). :meth:`condense` returns ``Zt^-1 rhs`` and, with the derivatives
    (``dDv, dKv, dw``), ``Zt^-1 (e_last dF - dZ Zt^-1 rhs)``."""

    def __init__(self, pattern: ColumnPattern, Dv: ComplexArray, Kv: ComplexArray,
                 Mv: FloatArray, w: FloatArray, s: IntArray | None = None,
                 shift: ComplexArray | None = None) -> None:
        self.pattern = pt = pattern
        self.Dv, self.Kv, self.Mv, self.w = Dv, Kv, Mv, np.asarray(w, dtype=float)
        p = pt.p
        if s is not None and shift is not None and s.size:
            r_, a_, b_ = np.nonzero(shift)
            self.srow, self.scol = s[a_] * p + r_, s[b_] * p + r_
            self.sval = shift[r_, a_, b_].astype(complex)
            if np.abs(self.srow - self.scol).max(initial=0) > pt.kl:
                raise ValueError("the shift couples DOFs beyond the band of the column")
        else:
            self.srow = self.scol = np.zeros(0, dtype=np.int64)
            self.sval = np.zeros(0, dtype=complex)

    def condense(self, rhs: ComplexArray, dDv: ComplexArray | None = None,
                 dKv: ComplexArray | None = None, dw: FloatArray | None = None,
                 dF: ComplexArray | None = None
                 ) -> tuple[ComplexArray, ComplexArray | None]:
        """``(Zt^-1 rhs, Zt^-1 ([0 .. 0, dF] - dZ Zt^-1 rhs))`` (the second None without
        derivatives); LinAlgError if Zt is singular."""
        pt = self.pattern
        I, J = pt.band_entries
        deriv = dDv is not None
        z = np.zeros((1, 1), dtype=complex)
        args = (self.Dv, self.Kv, self.Mv, self.w, dDv if deriv else z,
                dKv if deriv else z, dw if deriv else np.zeros(1),
                np.zeros(0, complex) if dF is None else np.asarray(dF, dtype=complex),
                I, J, pt.p, pt.b, pt.kl, self.srow, self.scol, self.sval,
                np.ascontiguousarray(rhs, dtype=complex), deriv)
        if pt.banded:
            sol, sol2, info, ab, ipiv = condense_band_column(*args)
            self.factors = (ab, ipiv)
        else:
            sol, sol2, info, lu = dense_column(*args)
            self.factors = lu
        if info:
            raise np.linalg.LinAlgError("singular torus column operator")
        return sol, (sol2 if deriv else None)

    def direction(self, x: ComplexArray, dDv: ComplexArray, dKv: ComplexArray,
                  dw: FloatArray, dF: ComplexArray) -> ComplexArray:
        """``Zt^-1 (dF - dZ x)`` for one DOF-major vector x (N,), with the factors of the
        last :meth:`condense`: the lam-derivative of ``Zt^-1 (F + S^T g)`` at fixed g
        when ``x = Zt^-1 (F + S^T g)`` (the whole derivative of the condensed response in
        one solve)."""
        pt = self.pattern
        I, J = pt.band_entries
        x = np.ascontiguousarray(x, dtype=complex).reshape(-1, 1)
        dF = np.ascontiguousarray(dF, dtype=complex).reshape(-1, 1)
        if pt.banded:
            ab, ipiv = self.factors
            return band_direction(ab, ipiv, pt.kl, self.Dv, self.Mv, self.w, dDv, dKv, dw,
                                  I, J, pt.p, pt.b, x, dF)[:, 0]
        N = x.shape[0]
        A, dA = np.zeros((N, N), dtype=complex), np.zeros((N, N), dtype=complex)
        fill_column(A, dA, self.Dv, self.Kv, self.Mv, self.w, dDv, dKv, dw, I, J, pt.p,
                    pt.b, True)
        return lu_solve(self.factors, dF - dA @ x, check_finite=False)[:, 0]


def dense_column(Dv, Kv, Mv, w, dDv, dKv, dw, dF, I, J, p, b, kl, srow, scol, sval,
                 rhs, deriv):
    """:func:`condense_band_column` for a block stored dense (numpy, LAPACK getrf)."""
    N = rhs.shape[0]
    A = np.zeros((N, N), dtype=complex)
    dA = np.zeros((N, N) if deriv else (1, 1), dtype=complex)
    fill_column(A, dA, Dv, Kv, Mv, w, dDv, dKv, dw, I, J, p, b, deriv)
    np.add.at(A, (srow, scol), sval)
    try:
        lu = lu_factor(A, check_finite=False)
    except (ValueError, np.linalg.LinAlgError):
        return rhs, rhs, 1, None
    if not np.all(np.isfinite(lu[0])) or np.any(np.diag(lu[0]) == 0):
        return rhs, rhs, 1, None
    sol = lu_solve(lu, rhs, check_finite=False)
    if not deriv:
        return sol, sol, 0, lu
    y = -(dA @ sol)
    y[:, -1] += dF
    return sol, lu_solve(lu, y, check_finite=False), 0, lu


@njit(cache=True)
def _subtract_dz(y, x, Dv, Mv, w, dDv, dKv, dw, I, J, p, b):
    """``y -= dZ x`` (y, x (N, c)) with dZ's entries formed on the fly."""
    nc = x.shape[1]
    bb = min(b, p - 1)
    for j in range(-bb, bb + 1):
        jj = j + b
        for c in range(max(0, -j), min(p, p - j)):
            wc = w[c]
            dwc = dw[c]
            for e in range(I.size):
                dv = dKv[jj, e] + 1j * (dwc * Dv[jj, e] + wc * dDv[jj, e])
                if j == 0:
                    dv -= 2.0 * wc * dwc * Mv[e]
                if dv != 0.0:
                    row = I[e] * p + c + j
                    col = J[e] * p + c
                    for k in range(nc):
                        y[row, k] -= dv * x[col, k]


@njit(cache=True)
def fill_column(A, dA, Dv, Kv, Mv, w, dDv, dKv, dw, I, J, p, b, deriv):
    """Write the entries of Z (and dZ) into dense DOF-major arrays A (dA)."""
    bb = min(b, p - 1)
    for j in range(-bb, bb + 1):
        jj = j + b
        for c in range(max(0, -j), min(p, p - j)):
            wc = w[c]
            for e in range(I.size):
                row = I[e] * p + c + j
                col = J[e] * p + c
                v = Kv[jj, e] + 1j * wc * Dv[jj, e]
                if j == 0:
                    v -= wc * wc * Mv[e]
                A[row, col] = v
                if deriv:
                    dv = dKv[jj, e] + 1j * (dw[c] * Dv[jj, e] + wc * dDv[jj, e])
                    if j == 0:
                        dv -= 2.0 * wc * dw[c] * Mv[e]
                    dA[row, col] = dv


@njit(cache=True)
def condense_band_column(Dv, Kv, Mv, w, dDv, dKv, dw, dF, I, J, p, b, kl, srow, scol,
                         sval, rhs, deriv):
    """The banded column in one compiled pass: Z written into band storage
    (``ab[col, 2 kl + row - col]``, :func:`rotorsfd.harmonic.banded.band_lu`'s layout),
    plus the shift, LU, ``sol = Zt^-1 rhs``, and with ``deriv``
    ``sol2 = Zt^-1 ([0 .. 0, dF] - dZ sol)`` with dZ's entries formed on the fly.
    Returns (sol, sol2, info, ab, ipiv), info > 0 if Zt is singular; ab, ipiv the
    factors (for :func:`band_direction`)."""
    N = rhs.shape[0]
    nc = rhs.shape[1]
    ab = np.zeros((N, 3 * kl + 1), dtype=np.complex128)
    bb = min(b, p - 1)
    kv = 2 * kl
    for j in range(-bb, bb + 1):
        jj = j + b
        for c in range(max(0, -j), min(p, p - j)):
            wc = w[c]
            for e in range(I.size):
                row = I[e] * p + c + j
                col = J[e] * p + c
                v = Kv[jj, e] + 1j * wc * Dv[jj, e]
                if j == 0:
                    v -= wc * wc * Mv[e]
                ab[col, kv + row - col] = v
    for t in range(sval.size):
        ab[scol[t], kv + srow[t] - scol[t]] += sval[t]
    ipiv = np.zeros(N, dtype=np.int64)
    sol = rhs.copy()
    info = band_lu(ab, kl, kl, ipiv)
    if info:
        return sol, sol, info, ab, ipiv
    band_solve(ab, kl, kl, ipiv, sol)
    if not deriv:
        return sol, sol, 0, ab, ipiv
    y = np.zeros_like(sol)
    _subtract_dz(y, sol, Dv, Mv, w, dDv, dKv, dw, I, J, p, b)
    for i in range(N):
        y[i, nc - 1] += dF[i]
    band_solve(ab, kl, kl, ipiv, y)
    return sol, y, 0, ab, ipiv


@njit(cache=True)
def band_direction(ab, ipiv, kl, Dv, Mv, w, dDv, dKv, dw, I, J, p, b, x, dF):
    """``Zt^-1 (dF - dZ x)`` (x, dF (N, c)) with the band factors of
    :func:`condense_band_column`, dZ's entries formed on the fly."""
    y = dF.copy()
    _subtract_dz(y, x, Dv, Mv, w, dDv, dKv, dw, I, J, p, b)
    band_solve(ab, kl, kl, ipiv, y)
    return y


def dof_major(x: ComplexArray, p: int, n: int) -> ComplexArray:
    """Rows (r, d) -> (d, r): harmonic-major (p n, ...) to DOF-major."""
    return x.reshape(p, n, *x.shape[1:]).swapaxes(0, 1).reshape(p * n, *x.shape[1:])


def harmonic_major(x: ComplexArray, p: int, n: int) -> ComplexArray:
    """Rows (d, r) -> (r, d): DOF-major (p n, ...) to harmonic-major."""
    return x.reshape(n, p, *x.shape[1:]).swapaxes(0, 1).reshape(p * n, *x.shape[1:])
