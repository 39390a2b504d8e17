"""Compiled short-bearing squeeze-film kernels: force and exact Jacobian of one sample.

Derivation in ``docs/sfd.md``. Summary, with ``n = (cos phi, sin phi)`` the outward normal
of the journal at the absolute angle ``phi`` and ``q = (y, z)``, ``v = (vy, vz)``::

    h = C - q.n,   dh/dt = -v.n,   p = 6 mu (dh/dt) / h^3 (x^2 - L^2/4)   (short bearing)
    F = -R int_film int_x p n dx dphi = -mu R L^3 int_film n n^T v / h^3 dphi

In the frame of the line of centres (``theta`` as in the paper: ``h = C (1 + eps cos
theta)``, ``phi = psi + pi + theta``, ``m = (cos theta, sin theta)``, ``Rot`` the rotation
by ``psi``)::

    F     = -K Rot B Rot^T v,         B = int m m^T / (1 + eps cos theta)^3 dtheta
    dF/dv = -K Rot B Rot^T
    dF/dq = 3 K / C Rot T Rot^T (+ pi-film edge term),
            T = int (m.w) m m^T / (1 + eps cos theta)^4 dtheta,  w = Rot^T v = (v_r, v_t)

with ``K = mu R L^3 / C^3``. The substitution of Sommerfeld,
``1 + eps cos theta = (1 - eps^2) / (1 - eps cos chi)``, turns every integrand above into
a trigonometric polynomial in ``chi`` times a power of ``s = sqrt(1 - eps^2)``, so all
integrals are closed forms over any arc, with no division by ``eps``.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

#: Cavitation model codes used in the kernel parameter vector.
CAVITATION_CODES: dict[str, int] = {"pi": 0, "none": 1, "guembel": 2}
PI_FILM, FULL_FILM, GUEMBEL = 0, 1, 2

#: Layout of ``kernel_params``: indices into the float64 parameter vector.
P_VISCOSITY, P_RADIUS, P_LENGTH, P_CLEARANCE, P_EPS_MAX, P_CODE = range(6)
N_PARAMS = 6


@njit(cache=True, inline="always")
def _chi_of_theta(theta: float, eps: float, s: float) -> float:
    """Sommerfeld angle: ``cos chi = (cos theta + eps)/(1 + eps cos theta)``,
    ``sin chi = s sin theta/(1 + eps cos theta)``, continuous in theta (``chi = theta``
    at multiples of pi)."""
    ct = math.cos(theta)
    st = math.sin(theta)
    s_minus_1 = -eps * eps / (1.0 + s)
    return theta + math.atan2(st * (s_minus_1 * ct - eps), ct * ct + eps * ct + s * st * st)


@njit(cache=True, inline="always")
def _arc_integrals(chi1: float, chi2: float, eps: float, s: float
                   ) -> tuple[float, float, float, float, float, float, float]:
    """Closed forms over the film arc ``[theta1, theta2]`` (mapped to ``[chi1, chi2]``).

    Returns ``(I2, I1, I3, T30, T21, T12, T03)`` with
    ``I2 = int cos^2/(1+eps cos)^3``, ``I1 = int sin cos/(...)^3``, ``I3 = int sin^2/(...)^3``
    and ``Tjk = int cos^j sin^k/(1+eps cos)^4`` (``j + k = 3``), using
    ``int cos^j sin^k/(1+eps cos)^n dtheta = s^(k-2n+1) int (cos chi - eps)^j sin^k chi dchi``
    when ``j + k = n - 1``.
    """
    dchi = chi2 - chi1
    c1, c2 = math.cos(chi1), math.cos(chi2)
    s1, s2 = math.sin(chi1), math.sin(chi2)
    d_s = s2 - s1
    d_c = c2 - c1
    d_sc = s2 * c2 - s1 * c1  # sin 2chi / 2
    d_ss = s2 * s2 - s1 * s1
    d_s3 = s2 * s2 * s2 - s1 * s1 * s1
    d_c3 = c2 * c2 * c2 - c1 * c1 * c1
    # n = 3, j + k = 2
    p20 = (0.5 + eps * eps) * dchi + 0.5 * d_sc - 2.0 * eps * d_s
    p11 = 0.5 * d_ss + eps * d_c
    p02 = 0.5 * dchi - 0.5 * d_sc
    # n = 4, j + k = 3
    q30 = (d_s - d_s3 / 3.0) - 1.5 * eps * (dchi + d_sc) + 3.0 * eps * eps * d_s \
        - eps * eps * eps * dchi
    a1, a2 = c1 - eps, c2 - eps
    q21 = -(a2 * a2 * a2 - a1 * a1 * a1) / 3.0
    q12 = d_s3 / 3.0 - 0.5 * eps * (dchi - d_sc)
    q03 = -d_c + d_c3 / 3.0
    s3 = s * s * s
    s4 = s3 * s
    s5 = s4 * s
    return (p20 / s5, p11 / s4, p02 / s3, q30 / (s5 * s * s), q21 / (s5 * s), q12 / s5,
            q03 / s4)


@njit(cache=True)
def sfd_sample(y: float, z: float, vy: float, vz: float, params: np.ndarray,
               F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """Force and Jacobian of one sample; returns 0, or 1 if ``eps >= eps_max`` or the
    state is not finite (outputs then untouched)."""
    mu = params[P_VISCOSITY]
    rad = params[P_RADIUS]
    length = params[P_LENGTH]
    clr = params[P_CLEARANCE]
    eps_max = params[P_EPS_MAX]
    code = int(params[P_CODE])
    e = math.hypot(y, z)
    eps = e / clr
    if not (eps < eps_max) or not (math.isfinite(vy) and math.isfinite(vz)):
        return 1
    K = mu * rad * length * length * length / (clr * clr * clr)
    if e > 0.0:
        cp, sp = y / e, z / e
    else:
        cp, sp = 1.0, 0.0
    vr = cp * vy + sp * vz
    vt = -sp * vy + cp * vz
    s2 = (1.0 - eps) * (1.0 + eps)
    s = math.sqrt(s2)
    mean_film = False  # Guembel at v = 0: mean of the limiting Jacobians
    if code == PI_FILM:
        chi1, chi2 = math.pi, 2.0 * math.pi
    elif code == FULL_FILM:
        chi1, chi2 = 0.0, 2.0 * math.pi
    elif vr == 0.0 and vt == 0.0:
        mean_film = True
        chi1, chi2 = 0.0, math.pi  # I2, I3 are half the full film's; I1 set to 0 below
    else:
        th1 = math.atan2(vt, vr) + 0.5 * math.pi
        chi1 = _chi_of_theta(th1, eps, s)
        chi2 = _chi_of_theta(th1 + math.pi, eps, s)
    i2, i1, i3, t30, t21, t12, t03 = _arc_integrals(chi1, chi2, eps, s)
    if mean_film:
        i1 = 0.0
    # G = Rot B Rot^T, B = [[I2, I1], [I1, I3]]
    g00 = cp * cp * i2 - 2.0 * cp * sp * i1 + sp * sp * i3
    g11 = sp * sp * i2 + 2.0 * cp * sp * i1 + cp * cp * i3
    g01 = cp * sp * (i2 - i3) + (cp * cp - sp * sp) * i1
    dFdv[0, 0] = -K * g00
    dFdv[0, 1] = -K * g01
    dFdv[1, 0] = -K * g01
    dFdv[1, 1] = -K * g11
    F[0] = dFdv[0, 0] * vy + dFdv[0, 1] * vz
    F[1] = dFdv[1, 0] * vy + dFdv[1, 1] * vz
    if mean_film or (code == PI_FILM and e == 0.0):
        # Guembel at v = 0: dF/dq is linear in v, so 0. Pi film at the centre: not
        # differentiable; the mean over psi of the limiting dF/dq, which is 0.
        dFdq[0, 0] = 0.0
        dFdq[0, 1] = 0.0
        dFdq[1, 0] = 0.0
        dFdq[1, 1] = 0.0
        return 0
    # T = vr [[T30, T21], [T21, T12]] + vt [[T21, T12], [T12, T03]]
    a00 = vr * t30 + vt * t21
    a01 = vr * t21 + vt * t12
    a11 = vr * t12 + vt * t03
    b00 = cp * cp * a00 - 2.0 * cp * sp * a01 + sp * sp * a11
    b11 = sp * sp * a00 + 2.0 * cp * sp * a01 + cp * cp * a11
    b01 = cp * sp * (a00 - a11) + (cp * cp - sp * sp) * a01
    k3 = 3.0 * K / clr
    dFdq[0, 0] = k3 * b00
    dFdq[0, 1] = k3 * b01
    dFdq[1, 0] = k3 * b01
    dFdq[1, 1] = k3 * b11
    if code == PI_FILM:
        # the film ends (theta = pi, 2 pi) turn with psi: grad psi = e_t / e, and
        # [1/(1-eps)^3 - 1/(1+eps)^3] / eps = (6 + 2 eps^2) / (1 - eps^2)^3
        edge = K / clr * (6.0 + 2.0 * eps * eps) / (s2 * s2 * s2) * vr
        dFdq[0, 0] += edge * cp * (-sp)
        dFdq[0, 1] += edge * cp * cp
        dFdq[1, 0] += edge * sp * (-sp)
        dFdq[1, 1] += edge * sp * cp
    return 0


@njit(cache=True)
def sfd_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
               dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """Compiled-kernel signature of ``docs/INTERFACES.md``: ``q = (y, z)``, ``v = (vy, vz)``;
    writes ``F`` (2,), ``dFdq``, ``dFdv`` (2, 2); returns 0, or 1 on journal contact."""
    return sfd_sample(q[0], q[1], v[0], v[1], params, F, dFdq, dFdv)


@njit(cache=True)
def sfd_batch(y: np.ndarray, z: np.ndarray, vy: np.ndarray, vz: np.ndarray,
              params: np.ndarray, F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray,
              want_jac: bool) -> int:
    """Loop of :func:`sfd_sample` over flat arrays. Returns -1 if all samples are fine,
    else the index of the first contact sample (the outputs after it are undefined)."""
    f = np.empty(2)
    jq = np.empty((2, 2))
    jv = np.empty((2, 2))
    for i in range(y.shape[0]):
        if sfd_sample(y[i], z[i], vy[i], vz[i], params, f, jq, jv) != 0:
            return i
        F[i, 0] = f[0]
        F[i, 1] = f[1]
        if want_jac:
            for a in range(2):
                for b in range(2):
                    dFdq[i, a, b] = jq[a, b]
                    dFdv[i, a, b] = jv[a, b]
    return -1
