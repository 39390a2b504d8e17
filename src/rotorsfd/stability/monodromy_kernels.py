"""Compiled monodromy recursions (Newmark and generalized-alpha) of small dense models.

The loops of :func:`rotorsfd.stability.monodromy.monodromy_newmark` and
:func:`~rotorsfd.stability.monodromy.monodromy_generalized_alpha`, step for step the same
arithmetic (the Woodbury form of the rank-m time dependence, module docstring of
``monodromy``) in one compiled function: the constant operators (``S_0^-1`` products,
``Z = S_0^-1 P``, ``G = P^T Z``) are formed once by the caller, the loop forms per step

    Newmark:   Y = [AB AE] [X; V] + Z r_j,  Y <- Y + Z W_{j+1} (I - G W_{j+1})^-1 P^T Y,
               V <- 2/h (Y - X) - V,  X <- Y
    gen-alpha: Y = -a_m S_M A - S_D v* - S_K x* + Z r_j,  the same Woodbury term, A <- Y

with ``(I - G W)`` (m x m) solved by Gaussian elimination with partial pivoting (as
LAPACK's ``gesv``) and the two rank-m terms applied as one product. The n x 2n product
of the constant operator is one BLAS call (``np.dot`` into a buffer: measured faster
than compiled loops from n = 8 up); the rank-m work is loops; nothing is allocated in
the loop, and no array slices are assigned (they made the first compilation 3x longer).
Compiled once, cached on disk; the loops release the GIL (threaded sweeps run in parallel).
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True)
def _gemm_acc(A: np.ndarray, B: np.ndarray, C: np.ndarray) -> None:
    """``C += A @ B`` (loops; for the thin rank-m products)."""
    n, k = A.shape
    p = B.shape[1]
    for i in range(n):
        for l in range(k):
            a = A[i, l]
            for c in range(p):
                C[i, c] += a * B[l, c]


@njit(cache=True)
def _solve_small(A: np.ndarray, B: np.ndarray) -> None:
    """``B <- A^-1 B`` in place (A overwritten by its LU factors), partial pivoting."""
    m = A.shape[0]
    p = B.shape[1]
    for k in range(m):
        piv = k
        big = abs(A[k, k])
        for i in range(k + 1, m):
            if abs(A[i, k]) > big:
                big = abs(A[i, k])
                piv = i
        if piv != k:
            for c in range(m):
                A[k, c], A[piv, c] = A[piv, c], A[k, c]
            for c in range(p):
                B[k, c], B[piv, c] = B[piv, c], B[k, c]
        d = A[k, k]
        for i in range(k + 1, m):
            f = A[i, k] / d
            if f != 0.0:
                A[i, k] = f
                for c in range(k + 1, m):
                    A[i, c] -= f * A[k, c]
                for c in range(p):
                    B[i, c] -= f * B[k, c]
    for k in range(m - 1, -1, -1):
        for j in range(k + 1, m):
            f = A[k, j]
            for c in range(p):
                B[k, c] -= f * B[j, c]
        d = A[k, k]
        for c in range(p):
            B[k, c] /= d


@njit(cache=True)
def _rank_m_update(Y: np.ndarray, Z: np.ndarray, G: np.ndarray, W: np.ndarray,
                   nl: np.ndarray, rP: np.ndarray, IGW: np.ndarray, u: np.ndarray) -> None:
    """``Y <- Y + Z r + Z W (I - G W)^-1 (Y + Z r)[nl]`` as one product
    ``Y += Z (r + W (I - G W)^-1 (Y[nl] + G r))`` (Woodbury; ``rP`` is r, overwritten)."""
    m = nl.shape[0]
    p = Y.shape[1]
    for a in range(m):
        for b in range(m):
            s = 1.0 if a == b else 0.0
            for c in range(m):
                s -= G[a, c] * W[c, b]
            IGW[a, b] = s
        for c in range(p):
            u[a, c] = Y[nl[a], c]
        for b in range(m):
            f = G[a, b]
            for c in range(p):
                u[a, c] += f * rP[b, c]
    _solve_small(IGW, u)
    _gemm_acc(W, u, rP)
    _gemm_acc(Z, rP, Y)


@njit(cache=True, nogil=True)
def newmark_loop(AB: np.ndarray, AE: np.ndarray, Z: np.ndarray, G: np.ndarray,
                 nl: np.ndarray, Kn: np.ndarray, Cn: np.ndarray, h: float) -> np.ndarray:
    """Monodromy ``[X; V]`` (2n, 2n) of average-acceleration Newmark over N = len(Kn) - 1
    steps from ``X = [I 0]``, ``V = [0 I]`` (``monodromy_newmark``, Woodbury form)."""
    n = AB.shape[0]
    m = nl.shape[0]
    p = 2 * n
    N = Kn.shape[0] - 1
    ABE = np.empty((n, p))  # [AB AE]
    for i in range(n):
        for c in range(n):
            ABE[i, c] = AB[i, c]
            ABE[i, n + c] = AE[i, c]
    S = np.zeros((p, p))  # [X; V]
    for i in range(p):
        S[i, i] = 1.0
    Y = np.empty((n, p))
    rP = np.empty((m, p))
    W = np.empty((m, m))
    IGW = np.empty((m, m))
    u = np.empty((m, p))
    c2 = 2.0 / h
    for j in range(N):
        np.dot(ABE, S, Y)  # AB X + AE V
        if m:
            # r = -(2/h C_{j+1} - K_j) X[nl] - (C_{j+1} - C_j) V[nl]
            rP.fill(0.0)
            for a in range(m):
                for b in range(m):
                    fx = Kn[j, a, b] - c2 * Cn[j + 1, a, b]
                    fv = Cn[j, a, b] - Cn[j + 1, a, b]
                    kx = nl[b]
                    kv = n + kx
                    for c in range(p):
                        rP[a, c] += fx * S[kx, c] + fv * S[kv, c]
            for a in range(m):
                for b in range(m):
                    W[a, b] = c2 * Cn[j + 1, a, b] + Kn[j + 1, a, b]
            _rank_m_update(Y, Z, G, W, nl, rP, IGW, u)
        for i in range(n):
            for c in range(p):
                S[n + i, c] = c2 * (Y[i, c] - S[i, c]) - S[n + i, c]
                S[i, c] = Y[i, c]
    return S


@njit(cache=True, nogil=True)
def generalized_alpha_loop(SM: np.ndarray, SD: np.ndarray, SK: np.ndarray, Z: np.ndarray,
                           G: np.ndarray, nl: np.ndarray, Kn: np.ndarray, Cn: np.ndarray,
                           A0: np.ndarray, h: float, am: float, af: float, g: float,
                           b: float, Mn: np.ndarray, inertial: bool) -> np.ndarray:
    """Monodromy ``[X; V]`` (2n, 2n) of generalized-alpha over N = len(Kn) - 1 steps from
    ``X = [I 0]``, ``V = [0 I]``, ``A = A0`` (``monodromy_generalized_alpha``).

    ``Mn`` (N+1, m, m): the added mass ``dF/da`` of a force of the acceleration on the
    orbit, the mass ``M - P Mn(t) P^T``: ``r += a_m Mn_j A[nl]`` and
    ``W += (1 - a_m) Mn_{j+1}`` in the rank-m update when ``inertial``; otherwise (the
    usual case) ``Mn`` is a placeholder and skipped (one compiled specialisation)."""
    n = SM.shape[0]
    m = nl.shape[0]
    p = 2 * n
    N = Kn.shape[0] - 1
    L = np.empty((n, 3 * n))  # [-a_m S_M, -S_D, -S_K]
    R = np.empty((3 * n, p))  # [A; v*; x*]
    X = np.zeros((n, p))
    V = np.zeros((n, p))
    for i in range(n):
        for c in range(n):
            L[i, c] = -am * SM[i, c]
            L[i, n + c] = -SD[i, c]
            L[i, 2 * n + c] = -SK[i, c]
        for c in range(p):
            R[i, c] = A0[i, c]
        X[i, i] = 1.0
        V[i, n + i] = 1.0
    Xp = np.empty((n, p))
    Vp = np.empty((n, p))
    Y = np.empty((n, p))
    rP = np.empty((m, p))
    W = np.empty((m, m))
    IGW = np.empty((m, m))
    u = np.empty((m, p))
    cx = h * h * (0.5 - b)
    cv = h * (1.0 - g)
    for j in range(N):
        for i in range(n):
            for c in range(p):
                a_ = R[i, c]
                xp = X[i, c] + h * V[i, c] + cx * a_
                vp = V[i, c] + cv * a_
                Xp[i, c] = xp
                Vp[i, c] = vp
                R[2 * n + i, c] = af * X[i, c] + (1.0 - af) * xp
                R[n + i, c] = af * V[i, c] + (1.0 - af) * vp
        np.dot(L, R, Y)  # -a_m S_M A - S_D v* - S_K x*
        if m:
            # r = a_f (C_j V[nl] + K_j X[nl]) + (1 - a_f)(C_{j+1} Vp[nl] + K_{j+1} Xp[nl])
            rP.fill(0.0)
            for a in range(m):
                for e in range(m):
                    k = nl[e]
                    c0 = af * Cn[j, a, e]
                    k0 = af * Kn[j, a, e]
                    c1 = (1.0 - af) * Cn[j + 1, a, e]
                    k1 = (1.0 - af) * Kn[j + 1, a, e]
                    for c in range(p):
                        rP[a, c] += (c0 * V[k, c] + k0 * X[k, c]
                                     + c1 * Vp[k, c] + k1 * Xp[k, c])
            for a in range(m):
                for e in range(m):
                    W[a, e] = (1.0 - af) * (g * h * Cn[j + 1, a, e]
                                            + b * h * h * Kn[j + 1, a, e])
            if inertial:   # the added mass (docstring)
                for a in range(m):
                    for e in range(m):
                        k = nl[e]
                        ma = am * Mn[j, a, e]
                        W[a, e] += (1.0 - am) * Mn[j + 1, a, e]
                        for c in range(p):
                            rP[a, c] += ma * R[k, c]
            _rank_m_update(Y, Z, G, W, nl, rP, IGW, u)
        for i in range(n):
            for c in range(p):
                R[i, c] = Y[i, c]
                X[i, c] = Xp[i, c] + b * h * h * Y[i, c]
                V[i, c] = Vp[i, c] + g * h * Y[i, c]
    out = np.empty((2 * n, p))
    for i in range(n):
        for c in range(p):
            out[i, c] = X[i, c]
            out[n + i, c] = V[i, c]
    return out
