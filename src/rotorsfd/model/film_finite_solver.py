"""Compiled discrete Reynolds operator of the finite-length squeeze film and its solver.

Grid: ``n`` nodes in theta (periodic, ``theta_i = 2 pi i / n``), ``m`` intervals in zeta
on the half land (nodes ``zeta_j = j/m``). Second-order central differences in
conservative form (``H^3`` at the half nodes ``theta_{i+1/2}``), mirror ghost at mid-land
(``dPi/dzeta = 0``), the Robin end ``H^3 dPi/dzeta + beta Pi = 0`` by a ghost node
(open end ``beta = inf``: ``Pi = 0`` at ``j = m``, not an unknown)::

    a_{i-1/2} (Pi_{i-1,j} - Pi_ij) + a_{i+1/2} (Pi_{i+1,j} - Pi_ij)
        + c_i (Pi_{i,j-1} - 2 Pi_ij + Pi_{i,j+1}) = m_k(theta_i)
    a_{i+1/2} = lam H^3(theta_{i+1/2}) / dtheta^2,   c_i = H^3(theta_i) / dzeta^2

The system is periodic block tridiagonal in theta with the axial nodes as blocks (the
theta coupling is ``a I``): block elimination along the chain ``0..n-2`` with the last
block as the border (its Schur complement), without pivoting (the blocks are diagonally
dominant). Cost ``O(n nb^3)`` to factor, ``O(n nb^2)`` per right-hand side.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit


@njit(cache=True)
def film_coefficients(eps: float, lam: float, n: int, m: int
                      ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """``(a, c, da, dc)``: the theta coupling ``a_i = lam H^3(theta_{i+1/2}) / dtheta^2``,
    the axial ``c_i = H^3(theta_i) / dzeta^2`` and their eps-derivatives."""
    dth = 2.0 * math.pi / n
    a = np.empty(n)
    c = np.empty(n)
    da = np.empty(n)
    dc = np.empty(n)
    for i in range(n):
        th = (i + 0.5) * dth
        ch = math.cos(th)
        hh = 1.0 + eps * ch
        a[i] = lam * hh * hh * hh / (dth * dth)
        da[i] = 3.0 * lam * hh * hh * ch / (dth * dth)
        cn = math.cos(i * dth)
        hn = 1.0 + eps * cn
        c[i] = hn * hn * hn * m * m
        dc[i] = 3.0 * hn * hn * cn * m * m
    return a, c, da, dc


@njit(cache=True, inline="always")
def _diag_block(D: np.ndarray, ci: float, am: float, ap: float, m: int, nb: int,
                beta: float) -> None:
    """The axial block of theta node i (``nb = m`` open, ``m + 1`` with a Robin end)."""
    for r in range(nb):
        for s in range(nb):
            D[r, s] = 0.0
    for j in range(nb):
        D[j, j] = -(am + ap) - 2.0 * ci
        if j == 0:
            if nb > 1:
                D[0, 1] = 2.0 * ci
        elif j == m:  # Robin end: ghost Pi_{m+1} = Pi_{m-1} - 2 dzeta beta Pi_m / H^3
            D[j, j - 1] = 2.0 * ci
            D[j, j] -= 2.0 * beta * m
        else:
            D[j, j - 1] = ci
            if j + 1 < nb:
                D[j, j + 1] = ci


@njit(cache=True)
def _invert(A: np.ndarray, out: np.ndarray, work: np.ndarray) -> None:
    """``out = A^-1`` by Gauss-Jordan without pivoting (diagonally dominant A)."""
    k = A.shape[0]
    for r in range(k):
        for s in range(k):
            work[r, s] = A[r, s]
            out[r, s] = 1.0 if r == s else 0.0
    for p in range(k):
        inv = 1.0 / work[p, p]
        for s in range(k):
            work[p, s] *= inv
            out[p, s] *= inv
        for r in range(k):
            if r != p:
                f = work[r, p]
                if f != 0.0:
                    for s in range(k):
                        work[r, s] -= f * work[p, s]
                        out[r, s] -= f * out[p, s]


@njit(cache=True)
def factor(a: np.ndarray, c: np.ndarray, m: int, nb: int, beta: float
           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Block elimination of the periodic system: ``(Dinv, Bt, Sinv)`` with ``Dinv_i`` the
    inverse pivots of the chain ``0..n-2``, ``Bt_i`` the back-substituted coupling of block
    ``i`` to the border ``x_B = x_{n-1}`` (``x_i = alpha_i - Bt_i x_B``) and ``Sinv`` the
    inverse Schur complement of the border."""
    n = a.shape[0]
    Dinv = np.empty((n, nb, nb))
    S = np.zeros((n, nb, nb))
    D = np.empty((nb, nb))
    work = np.empty((nb, nb))
    for i in range(n - 1):
        am = a[i - 1]  # a_{i-1/2}; a[-1] = a_{n-1/2}
        ap = a[i]
        _diag_block(D, c[i], am, ap, m, nb, beta)
        if i > 0:
            f = am * am
            for r in range(nb):
                for s in range(nb):
                    D[r, s] -= f * Dinv[i - 1, r, s]
        _invert(D, Dinv[i], work)
        # S_i = Dinv_i (B_i - a_{i-1/2} S_{i-1}), B_0 = a_{-1/2} I, B_{n-2} = a_{n-3/2} I
        for r in range(nb):
            for s in range(nb):
                work[r, s] = -am * S[i - 1, r, s] if i > 0 else 0.0
        if i == 0:
            for r in range(nb):
                work[r, r] += am
        if i == n - 2:
            for r in range(nb):
                work[r, r] += ap
        for r in range(nb):
            for s in range(nb):
                acc = 0.0
                for t in range(nb):
                    acc += Dinv[i, r, t] * work[t, s]
                S[i, r, s] = acc
    # back substitution of the coupling: Bt_i = S_i - a_{i+1/2} Dinv_i Bt_{i+1}
    Bt = S
    for i in range(n - 3, -1, -1):
        ap = a[i]
        for r in range(nb):
            for s in range(nb):
                acc = 0.0
                for t in range(nb):
                    acc += Dinv[i, r, t] * Bt[i + 1, t, s]
                work[r, s] = acc
        for r in range(nb):
            for s in range(nb):
                Bt[i, r, s] -= ap * work[r, s]
    # Schur complement of the border row n-1
    _diag_block(D, c[n - 1], a[n - 2], a[n - 1], m, nb, beta)
    for r in range(nb):
        for s in range(nb):
            D[r, s] -= a[n - 2] * Bt[n - 2, r, s] + a[n - 1] * Bt[0, r, s]
    Sinv = np.empty((nb, nb))
    _invert(D, Sinv, work)
    return Dinv, Bt, Sinv


@njit(cache=True)
def solve(a: np.ndarray, Dinv: np.ndarray, Bt: np.ndarray, Sinv: np.ndarray,
          b: np.ndarray) -> None:
    """Solve in place for the right-hand sides ``b (n, nb, k)``."""
    n, nb, k = b.shape
    g = np.empty((n, nb, k))
    tmp = np.empty((nb, k))
    for i in range(n - 1):  # g_i = Dinv_i (b_i - a_{i-1/2} g_{i-1})
        for r in range(nb):
            for q in range(k):
                tmp[r, q] = b[i, r, q] - (a[i - 1] * g[i - 1, r, q] if i > 0 else 0.0)
        for r in range(nb):
            for q in range(k):
                acc = 0.0
                for t in range(nb):
                    acc += Dinv[i, r, t] * tmp[t, q]
                g[i, r, q] = acc
    for i in range(n - 3, -1, -1):  # alpha_i = g_i - a_{i+1/2} Dinv_i alpha_{i+1}
        for r in range(nb):
            for q in range(k):
                acc = 0.0
                for t in range(nb):
                    acc += Dinv[i, r, t] * g[i + 1, t, q]
                tmp[r, q] = acc
        for r in range(nb):
            for q in range(k):
                g[i, r, q] -= a[i] * tmp[r, q]
    for r in range(nb):
        for q in range(k):
            tmp[r, q] = b[n - 1, r, q] - a[n - 2] * g[n - 2, r, q] - a[n - 1] * g[0, r, q]
    for r in range(nb):
        for q in range(k):
            acc = 0.0
            for t in range(nb):
                acc += Sinv[r, t] * tmp[t, q]
            b[n - 1, r, q] = acc
    for i in range(n - 1):
        for r in range(nb):
            for q in range(k):
                acc = 0.0
                for t in range(nb):
                    acc += Bt[i, r, t] * b[n - 1, t, q]
                b[i, r, q] = g[i, r, q] - acc


@njit(cache=True)
def apply_operator(a: np.ndarray, c: np.ndarray, m: int, nb: int, beta: float,
                   x: np.ndarray, out: np.ndarray) -> None:
    """``out = A x`` for fields ``x (n, nb, k)`` with the coefficients ``a, c`` (used with
    their eps-derivatives, and ``beta = 0``, for ``A' x``)."""
    n, _, k = x.shape
    for i in range(n):
        am = a[i - 1]
        ap = a[i]
        ci = c[i]
        im = i - 1 if i > 0 else n - 1
        ip = i + 1 if i < n - 1 else 0
        for j in range(nb):
            for q in range(k):
                v = am * x[im, j, q] + ap * x[ip, j, q] - (am + ap) * x[i, j, q]
                v -= 2.0 * ci * x[i, j, q]
                if j == 0:
                    if nb > 1:
                        v += 2.0 * ci * x[i, 1, q]
                elif j == m:
                    v += 2.0 * ci * x[i, j - 1, q] - 2.0 * beta * m * x[i, j, q]
                else:
                    v += ci * x[i, j - 1, q]
                    if j + 1 < nb:
                        v += ci * x[i, j + 1, q]
                out[i, j, q] = v
