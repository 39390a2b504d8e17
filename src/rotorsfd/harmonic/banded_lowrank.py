"""Condensation of a banded dynamic stiffness plus a low-rank damping term (numba).

Modal damping of the lowest r modes, ``C_s = U diag(c) U^T`` (``U = M Phi`` n x r,
:class:`rotorsfd.model.damping.ModalDamping` with ``modes``), adds to the banded
``Zb_k = K - (kw)^2 M + i kw D_band + S^T Delta_k S`` the rank-r term
``i kw U diag(c) U^T``. With the banded LU of Zb_k (:mod:`rotorsfd.harmonic.banded`) and
``Y_k = Zb_k^-1 U``, the Woodbury identity gives the inverse of the whole Zt_k::

    Zt_k^-1 B = Zb_k^-1 B - Y_k Cap_k^-1 U^T Zb_k^-1 B,
    Cap_k = diag(1 / (i kw c)) + U^T Y_k            (r x r),

so ``C_k = Zt_k^-1 S^T``, ``u_k = Zt_k^-1 F_k`` and their lam-derivatives (``dZ_k`` gains
``i k w' U diag(c) U^T``: the term is constant in lam) cost r more right-hand sides and an
r x r solve per harmonic instead of a dense n x n LU. Harmonic 0 has no damping term. The
solution is refined against the whole Zt_k (the residual's ``K x`` in doubled precision,
:func:`rotorsfd.harmonic.banded.band_residual`, minus the low-rank term) with the same
Woodbury solve, as :func:`rotorsfd.harmonic.banded.condense_bands` refines.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rotorsfd.harmonic.banded import (
    band_residual,
    band_solve,
    derivative_rhs,
    harmonic_band_lu,
    real_harmonic0,
    split_outputs,
    static_harmonic,
    unit_rhs,
)


@njit(cache=True)
def _transpose_times(U: np.ndarray, x: np.ndarray) -> np.ndarray:
    """``U^T x`` (r, nc) for x (n, nc) complex, skipping U's zeros."""
    n, nc = x.shape
    r = U.shape[1]
    p = np.zeros((r, nc), dtype=np.complex128)
    for i in range(n):
        for q in range(r):
            u = U[i, q]
            if u != 0.0:
                for c in range(nc):
                    p[q, c] += u * x[i, c]
    return p


@njit(cache=True)
def _woodbury(ab: np.ndarray, kl: int, ku: int, ipiv: np.ndarray, U: np.ndarray,
              Y: np.ndarray, cap: np.ndarray, b: np.ndarray) -> None:
    """``b <- Zt^-1 b`` in place: ``Zb^-1 b - Y Cap^-1 (U^T Zb^-1 b)`` (module
    docstring; ``cap`` the r x r capacitance matrix, Y = Zb^-1 U)."""
    band_solve(ab, kl, ku, ipiv, b)
    n, nc = b.shape
    r = U.shape[1]
    if r == 0:
        return
    p = _transpose_times(U, b)
    z = np.linalg.solve(cap, p)
    for i in range(n):
        for q in range(r):
            y = Y[i, q]
            for c in range(nc):
                b[i, c] -= y * z[q, c]


@njit(cache=True)
def _lowrank_times(U: np.ndarray, coef: np.ndarray, x: np.ndarray, out: np.ndarray,
                   scale: complex) -> None:
    """``out -= scale U diag(coef) U^T x`` for x (n, nc)."""
    n, nc = x.shape
    r = U.shape[1]
    p = _transpose_times(U, x)
    for q in range(r):
        for c in range(nc):
            p[q, c] *= scale * coef[q]
    for i in range(n):
        for q in range(r):
            u = U[i, q]
            if u != 0.0:
                for c in range(nc):
                    out[i, c] -= u * p[q, c]


@njit(cache=True)
def condense_bands_lowrank(Mb: np.ndarray, Db: np.ndarray, Kb: np.ndarray,
                           dMb: np.ndarray, dDb: np.ndarray, dKb: np.ndarray,
                           U: np.ndarray, coef: np.ndarray, w: float, dw: float, kl: int,
                           ku: int, s: np.ndarray, delta: np.ndarray, F: np.ndarray,
                           dF: np.ndarray, deriv: bool, sol: np.ndarray, dsol: np.ndarray,
                           Ht: np.ndarray, Pt: np.ndarray, dHt: np.ndarray,
                           dPt: np.ndarray, refine: int | None, k_first: int = 0) -> int:
    """:func:`rotorsfd.harmonic.banded.condense_bands` (the same inputs, outputs and
    return codes) with the damping ``D = D_band + U diag(coef) U^T``: Mb, Db, Kb and the
    derivatives in band storage (Db without the low-rank term), U (n, r), coef (r,);
    ``k_first`` as there (harmonics below it already in sol, dsol)."""
    n = Kb.shape[0]
    m = s.shape[0]
    nh = F.shape[0]
    r = U.shape[1]
    ab = np.zeros((n, 2 * kl + ku + 1), dtype=np.complex128)
    ipiv = np.empty(n, dtype=np.int64)
    rhs = np.empty((n, m + 1), dtype=np.complex128)
    Y = np.empty((n, r), dtype=np.complex128)
    cap = np.empty((r, r), dtype=np.complex128)
    k0 = k_first
    if k0 == 0 and real_harmonic0(delta, F, dF, deriv):
        status = static_harmonic(Mb, Kb, dKb, kl, ku, s, delta, F, dF, deriv, sol, dsol)
        if status != 0:
            return status
        k0 = 1
    for k in range(k0, nh):
        kw = k * w
        kw2 = kw * kw
        if harmonic_band_lu(Mb, Db, Kb, kl, ku, kw, s, delta[k], ab, ipiv) != 0:
            return k + 1
        rk = r if k > 0 else 0          # harmonic 0: no damping term
        Yk = Y[:, :rk]
        capk = cap[:rk, :rk]
        if rk:
            for i in range(n):
                for q in range(rk):
                    Yk[i, q] = U[i, q]
            band_solve(ab, kl, ku, ipiv, Yk)
            for a in range(rk):
                for q in range(rk):
                    acc = 0.0j
                    for i in range(n):
                        acc += U[i, a] * Yk[i, q]
                    capk[a, q] = acc
                capk[a, a] += -1j / (kw * coef[a])
        Uk = U[:, :rk]
        out = sol[k]
        unit_rhs(s, F[k], out)
        _woodbury(ab, kl, ku, ipiv, Uk, Yk, capk, out)
        if refine is not None:      # None: compiled without the refinement
            for _ in range(refine):
                band_residual(Mb, Db, Kb, kl, ku, kw, kw2, s, delta[k], F[k], out, rhs)
                if rk:
                    _lowrank_times(Uk, coef, out, rhs, 1j * kw)
                _woodbury(ab, kl, ku, ipiv, Uk, Yk, capk, rhs)
                for i in range(n):
                    for c in range(m + 1):
                        out[i, c] += rhs[i, c]
        if not deriv:
            continue
        # [-dZ_k C_k, dF_k - dZ_k u_k], dZ_k = banded part + i k w' U diag(coef) U^T
        derivative_rhs(Mb, Db, dMb, dDb, dKb, kl, ku, k, w, dw, dF[k], out, rhs)
        if rk and dw != 0.0:
            _lowrank_times(Uk, coef, out, rhs, 1j * k * dw)
        _woodbury(ab, kl, ku, ipiv, Uk, Yk, capk, rhs)
        for a in range(m):
            for c in range(m + 1):
                dsol[k, a, c] = rhs[s[a], c]
    return split_outputs(s, deriv, sol, dsol, Ht, Pt, dHt, dPt)
