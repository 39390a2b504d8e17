"""Compiled finite-length squeeze film: the discrete Reynolds solver of one sample and its
exact derivative (the equations are in :mod:`rotorsfd.model.film_finite`).

Frame of the line of centres: ``theta`` from the thickest film, ``H = 1 + eps cos theta``,
``zeta = 2 x / L`` in ``[0, 1]`` (the half land; the film is symmetric about mid-land).
The pressure is ``p = (3 mu L^2 / C^3) (w_r Pi_r + w_t Pi_t)`` with ``Pi_k`` the two basis
solutions of the dimensionless Reynolds equation (``lam = (L/D)^2``)::

    lam d/dtheta (H^3 dPi/dtheta) + d/dzeta (H^3 dPi/dzeta) = m_k(theta)
    m_r = cos theta, m_t = sin theta
    dPi/dzeta = 0 at zeta = 0,    H^3 dPi/dzeta + beta Pi = 0 at zeta = 1

The discrete operator and its solver: :mod:`rotorsfd.model.film_finite_solver`. Here:
the two basis solutions and their eps-derivative, the quadrature of the force, the force
and Jacobian of one sample and the kernel of the contract of :mod:`rotorsfd.kernels`.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

from rotorsfd.model.film_finite_solver import (
    apply_operator,
    factor,
    film_coefficients,
    solve,
)
from rotorsfd.model.film_finite_table import hermite_fields, hermite_matrices

#: Cavitation model codes (the short film's): pi film (arc theta in [pi, 2 pi]), 2 pi film,
#: Guembel clamp (p = max(p_full, 0) node by node).
CAVITATION_CODES: dict[str, int] = {"pi": 0, "none": 1, "guembel": 2}
PI_FILM, FULL_FILM, GUEMBEL = 0, 1, 2

#: Layout of the parameter vector (the element appends nothing: the housing offset is here).
#: ``P_TABLE_N``: nodes of the eps table of :mod:`rotorsfd.model.film_finite_table` (0:
#: none, solve at every sample); the table follows from ``N_PARAMS`` on.
(P_VISCOSITY, P_RADIUS, P_LENGTH, P_CLEARANCE, P_EPS_MAX, P_CODE, P_N_THETA, P_N_AXIAL,
 P_END_FLOW, P_OFFSET_Y, P_OFFSET_Z, P_TABLE_N) = range(12)
N_PARAMS = 12

#: A sealed end (beta = 0) is solved with this end-flow coefficient: the constant pressure
#: mode is then fixed by the zero net end flow; the force changes by O(beta) relative.
BETA_SEALED = 1e-7


@njit(cache=True)
def quadrature_weights(n: int, m: int, nb: int, code: int) -> tuple[np.ndarray, np.ndarray]:
    """``(w_theta (n,), w_zeta (nb,))``: Simpson in zeta on ``[0, 1]`` (m even; exact for
    the short film's parabola), periodic trapezoid in theta, Simpson on the pi film's arc
    ``[pi, 2 pi]`` (n divisible by 4)."""
    dth = 2.0 * math.pi / n
    wt = np.zeros(n)
    if code == PI_FILM:
        half = n // 2
        for k in range(half + 1):  # node i = half + k, theta = pi + k dth
            w = 1.0 if (k == 0 or k == half) else (4.0 if k % 2 == 1 else 2.0)
            wt[(half + k) % n] += w * dth / 3.0
    else:
        for i in range(n):
            wt[i] = dth
    wz = np.zeros(nb)
    dz = 1.0 / m
    for j in range(min(nb, m + 1)):
        w = 1.0 if (j == 0 or j == m) else (4.0 if j % 2 == 1 else 2.0)
        wz[j] = w * dz / 3.0
    return wt, wz


@njit(cache=True)
def basis_fields(eps: float, lam: float, n: int, m: int, beta: float, want_derivative: bool
                 ) -> tuple[np.ndarray, np.ndarray]:
    """``(Pi, dPi/deps)``, each ``(n, nb, 2)``: the basis solutions for ``m_r = cos theta``
    (index 0) and ``m_t = sin theta`` (index 1); ``dPi/deps = -A^-1 A' Pi`` (zeros if not
    ``want_derivative``)."""
    open_end = math.isinf(beta)
    nb = m if open_end else m + 1
    b = beta if beta > BETA_SEALED else BETA_SEALED
    a, c, da, dc = film_coefficients(eps, lam, n, m)
    Dinv, Bt, Sinv = factor(a, c, m, nb, 0.0 if open_end else b)
    pi_ = np.empty((n, nb, 2))
    dth = 2.0 * math.pi / n
    for i in range(n):
        ct = math.cos(i * dth)
        st = math.sin(i * dth)
        for j in range(nb):
            pi_[i, j, 0] = ct
            pi_[i, j, 1] = st
    solve(a, Dinv, Bt, Sinv, pi_)
    dpi = np.zeros((n, nb, 2))
    if want_derivative:
        apply_operator(da, dc, m, nb, 0.0, pi_, dpi)
        for i in range(n):
            for j in range(nb):
                dpi[i, j, 0] = -dpi[i, j, 0]
                dpi[i, j, 1] = -dpi[i, j, 1]
        solve(a, Dinv, Bt, Sinv, dpi)
    return pi_, dpi


@njit(cache=True)
def guembel_sums(pi_: np.ndarray, dpi: np.ndarray, wr: float, wt: float, wz: np.ndarray
                 ) -> tuple[float, float, float, float, float, float, float, float]:
    """The Guembel film's sums ``(G, M, dG/deps)`` (without ``kappa``): in theta, on every
    cell the exact integral of ``p_lin m_hat`` over the cell's part where ``p_lin > 0``
    (``p_lin`` the linear interpolant of ``p``, ``m_hat`` the linear weight that makes the
    integral over a whole cell the trapezoid). The integrand vanishes at a crossing, so
    moving it adds nothing to the derivatives, and a node changing sign changes neither
    the sums nor their derivatives: the force is C1 in the state (Newton on the HB
    residual converges; a node-wise clamp would make it jump), with a clamp error
    O(dtheta^2) and the trapezoid's accuracy where the film is whole."""
    n, nb, _ = pi_.shape
    dth = 2.0 * math.pi / n
    out = np.zeros(8)  # g0, g1, m00, m01, m10, m11, d0, d1
    for i in range(n):
        i1 = i + 1 if i < n - 1 else 0
        # the weight m_hat = (2 m0 - m1)(1 - t) + (2 m1 - m0) t: int_0^1 p_lin m_hat is the
        # trapezoid (p0 m0 + p1 m1) / 2 on a cell where p > 0 throughout
        a0, b0 = math.cos(i * dth), math.sin(i * dth)
        a1, b1 = math.cos((i + 1) * dth), math.sin((i + 1) * dth)
        c0, c1 = 2.0 * a0 - a1, 2.0 * a1 - a0
        s0, s1 = 2.0 * b0 - b1, 2.0 * b1 - b0
        for j in range(nb):
            if wz[j] == 0.0:
                continue
            p0 = wr * pi_[i, j, 0] + wt * pi_[i, j, 1]
            p1 = wr * pi_[i1, j, 0] + wt * pi_[i1, j, 1]
            if p0 > 0.0 and p1 > 0.0:  # int_0^1 of p_lin m_hat: the trapezoid
                k00, k01, k10, k11 = 1.0 / 3.0, 1.0 / 6.0, 1.0 / 6.0, 1.0 / 3.0
            elif p0 > 0.0 or p1 > 0.0:
                # int over the positive part of (x0 (1-t) + x1 t)(y0 (1-t) + y1 t) dt
                t = p0 / (p0 - p1)
                j00 = (1.0 - (1.0 - t) ** 3) / 3.0
                j01 = 0.5 * t * t - t * t * t / 3.0
                j11 = t * t * t / 3.0
                if p1 > 0.0:  # positive on [t, 1]
                    j00, j01, j11 = 1.0 / 3.0 - j00, 1.0 / 6.0 - j01, 1.0 / 3.0 - j11
                k00, k01, k10, k11 = j00, j01, j01, j11
            else:
                continue
            w = wz[j] * dth
            # sum over a (node of p) and b (node of m) of k_ab x_a m_b
            ca, cb = k00 * c0 + k01 * c1, k10 * c0 + k11 * c1
            sa, sb = k00 * s0 + k01 * s1, k10 * s0 + k11 * s1
            for q in range(2):
                x0 = pi_[i, j, q]
                x1 = pi_[i1, j, q]
                out[2 + q] += w * (x0 * ca + x1 * cb)
                out[4 + q] += w * (x0 * sa + x1 * sb)
            x0 = wr * dpi[i, j, 0] + wt * dpi[i, j, 1]
            x1 = wr * dpi[i1, j, 0] + wt * dpi[i1, j, 1]
            out[6] += w * (x0 * ca + x1 * cb)
            out[7] += w * (x0 * sa + x1 * sb)
            out[0] += w * (p0 * ca + p1 * cb)
            out[1] += w * (p0 * sa + p1 * sb)
    return out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7]


@njit(cache=True)
def film_sums(eps: float, wr: float, wt: float, params: np.ndarray
              ) -> tuple[float, float, float, float, float, float, float, float]:
    """``(G, M, dG/deps)`` of the discrete film in the frame of the line of centres:
    ``G = kappa sum W chi p m`` (2,), ``M = dG/dw`` (2, 2, row-major), ``dG/deps`` (2,)."""
    mu = params[P_VISCOSITY]
    rad = params[P_RADIUS]
    length = params[P_LENGTH]
    clr = params[P_CLEARANCE]
    code = int(params[P_CODE])
    n = int(params[P_N_THETA])
    m = int(params[P_N_AXIAL])
    lam = (0.5 * length / rad) ** 2
    pi_, dpi = basis_fields(eps, lam, n, m, params[P_END_FLOW], True)
    nb = pi_.shape[1]
    wth, wz = quadrature_weights(n, m, nb, code)
    kappa = 3.0 * mu * rad * length ** 3 / clr ** 3
    dth = 2.0 * math.pi / n
    if code == GUEMBEL:
        g0, g1, m00, m01, m10, m11, d0, d1 = guembel_sums(pi_, dpi, wr, wt, wz)
    else:
        g0 = g1 = 0.0
        m00 = m01 = m10 = m11 = 0.0
        d0 = d1 = 0.0
        for i in range(n):
            if wth[i] == 0.0:
                continue
            ct = math.cos(i * dth)
            st = math.sin(i * dth)
            for j in range(nb):
                w = wth[i] * wz[j]
                if w == 0.0:
                    continue
                p = wr * pi_[i, j, 0] + wt * pi_[i, j, 1]
                g0 += w * p * ct
                g1 += w * p * st
                m00 += w * pi_[i, j, 0] * ct
                m01 += w * pi_[i, j, 1] * ct
                m10 += w * pi_[i, j, 0] * st
                m11 += w * pi_[i, j, 1] * st
                dp = wr * dpi[i, j, 0] + wt * dpi[i, j, 1]
                d0 += w * dp * ct
                d1 += w * dp * st
    return (kappa * g0, kappa * g1, kappa * m00, kappa * m01, kappa * m10, kappa * m11,
            kappa * d0, kappa * d1)


@njit(cache=True)
def rotate_out(cp: float, sp: float, e: float, clr: float, wr: float, wt: float,
               g0: float, g1: float, m00: float, m01: float, m10: float, m11: float,
               d0: float, d1: float, F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray
               ) -> None:
    """``F = Rot G``, ``dF/dv = Rot M Rot^T``, ``dF/dq = Rot dG/deps e_r^T / C + Rot (J G -
    M J w) e_t^T / e`` (the psi term left out at ``e = 0``)."""
    F[0] = cp * g0 - sp * g1
    F[1] = sp * g0 + cp * g1
    r00 = cp * m00 - sp * m10
    r01 = cp * m01 - sp * m11
    r10 = sp * m00 + cp * m10
    r11 = sp * m01 + cp * m11
    dFdv[0, 0] = r00 * cp - r01 * sp
    dFdv[0, 1] = r00 * sp + r01 * cp
    dFdv[1, 0] = r10 * cp - r11 * sp
    dFdv[1, 1] = r10 * sp + r11 * cp
    fr0 = (cp * d0 - sp * d1) / clr
    fr1 = (sp * d0 + cp * d1) / clr
    ft0 = ft1 = 0.0
    if e > 0.0:
        # J G = (-g1, g0); J w = (-wt, wr)
        u0 = -g1 - (m00 * (-wt) + m01 * wr)
        u1 = g0 - (m10 * (-wt) + m11 * wr)
        ft0 = (cp * u0 - sp * u1) / e
        ft1 = (sp * u0 + cp * u1) / e
    dFdq[0, 0] = fr0 * cp - ft0 * sp
    dFdq[0, 1] = fr0 * sp + ft0 * cp
    dFdq[1, 0] = fr1 * cp - ft1 * sp
    dFdq[1, 1] = fr1 * sp + ft1 * cp


@njit(cache=True)
def table_matrices(eps: float, params: np.ndarray
                   ) -> tuple[float, float, float, float, float, float, float, float]:
    """``(M, dM/deps)`` from the eps table stored after ``N_PARAMS``."""
    return hermite_matrices(eps, params[P_EPS_MAX], params, N_PARAMS, int(params[P_TABLE_N]))


@njit(cache=True)
def table_guembel_sums(eps: float, wr: float, wt: float, params: np.ndarray
                       ) -> tuple[float, float, float, float, float, float, float, float]:
    """The Guembel film's ``(G, M, dG/deps)`` on the fields of the eps table."""
    n = int(params[P_N_THETA])
    m = int(params[P_N_AXIAL])
    nb = m if math.isinf(params[P_END_FLOW]) else m + 1
    pi_ = np.empty((n, nb, 2))
    dpi = np.empty((n, nb, 2))
    hermite_fields(eps, params[P_EPS_MAX], params, N_PARAMS, int(params[P_TABLE_N]), pi_,
                   dpi)
    _, wz = quadrature_weights(n, m, nb, GUEMBEL)
    kappa = 3.0 * params[P_VISCOSITY] * params[P_RADIUS] * params[P_LENGTH] ** 3 \
        / params[P_CLEARANCE] ** 3
    g0, g1, m00, m01, m10, m11, d0, d1 = guembel_sums(pi_, dpi, wr, wt, wz)
    return (kappa * g0, kappa * g1, kappa * m00, kappa * m01, kappa * m10, kappa * m11,
            kappa * d0, kappa * d1)


@njit(cache=True)
def finite_sample(y: float, z: float, vy: float, vz: float, params: np.ndarray,
                  F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """Force and exact Jacobian of the discrete film at ``q = (y, z)`` (relative to the
    housing centre), ``v = (vy, vz)``; returns 0, or 1 if ``eps >= eps_max`` or the state
    is not finite (outputs then untouched). With an eps table in the parameters:
    ``M(eps)`` and ``dM/deps`` from it, ``G = M w`` (pi and 2 pi films), or the basis
    fields from it (Guembel)."""
    clr = params[P_CLEARANCE]
    e = math.hypot(y, z)
    eps = e / clr
    if not (eps < params[P_EPS_MAX]) or not (math.isfinite(vy) and math.isfinite(vz)):
        return 1
    cp, sp = (y / e, z / e) if e > 0.0 else (1.0, 0.0)
    wr = cp * vy + sp * vz
    wt = -sp * vy + cp * vz
    if params[P_TABLE_N] > 0.0 and int(params[P_CODE]) == GUEMBEL:
        g0, g1, m00, m01, m10, m11, d0, d1 = table_guembel_sums(eps, wr, wt, params)
    elif params[P_TABLE_N] > 0.0:
        m00, m01, m10, m11, dm00, dm01, dm10, dm11 = table_matrices(eps, params)
        g0 = m00 * wr + m01 * wt
        g1 = m10 * wr + m11 * wt
        d0 = dm00 * wr + dm01 * wt
        d1 = dm10 * wr + dm11 * wt
    else:
        g0, g1, m00, m01, m10, m11, d0, d1 = film_sums(eps, wr, wt, params)
    rotate_out(cp, sp, e, clr, wr, wt, g0, g1, m00, m01, m10, m11, d0, d1, F, dFdq, dFdv)
    return 0


@njit(cache=True)
def finite_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
                  dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """Kernel contract of :mod:`rotorsfd.kernels`: the film at ``q - o`` (housing offset
    ``o`` in the parameter vector); returns 0, or 1 on journal contact."""
    return finite_sample(q[0] - params[P_OFFSET_Y], q[1] - params[P_OFFSET_Z], v[0], v[1],
                         params, F, dFdq, dFdv)


@njit(cache=True)
def finite_batch(y: np.ndarray, z: np.ndarray, vy: np.ndarray, vz: np.ndarray,
                 params: np.ndarray, F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray
                 ) -> int:
    """Loop of :func:`finite_sample` over flat arrays (no offset); -1 if all samples are
    fine, else the index of the first contact sample."""
    for i in range(y.shape[0]):
        if finite_sample(y[i], z[i], vy[i], vz[i], params, F[i], dFdq[i], dFdv[i]) != 0:
            return i
    return -1
