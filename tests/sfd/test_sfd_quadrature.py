"""Independent check: quadrature of the short-bearing pressure field p(x, theta).

Written in the paper's frame of the line of centres, independently of the code's
absolute-frame closed forms::

    h = C (1 + eps cos theta),  dh/dt = C (eps' cos theta + eps psi' sin theta)
    p(x, theta) = 6 mu (dh/dt) / h^3 (x^2 - L^2/4)        (d/dx(h^3 dp/dx) = 12 mu dh/dt)
    F_r = R int int p cos theta dx dtheta,  F_t = R int int p sin theta dx dtheta
    (the pressure pushes the journal along -outward normal = (cos theta, sin theta) in (e_r, e_t))
    Fy = F_r cos psi - F_t sin psi,  Fz = F_r sin psi + F_t cos psi
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from scipy.integrate import quad
from sfd_helpers import MODELS, C, paper_sfd, random_states

X_GAUSS, W_GAUSS = np.polynomial.legendre.leggauss(4)  # exact for the quadratic in x


def quad_force(sfd, y, z, vy, vz):
    mu, R, L = sfd.viscosity, sfd.radius, sfd.length
    e = math.hypot(y, z)
    psi = math.atan2(z, y)
    eps = e / C
    deps = (math.cos(psi) * vy + math.sin(psi) * vz) / C
    dpsi = (y * vz - z * vy) / e**2
    x = 0.5 * L * X_GAUSS
    w = 0.5 * L * W_GAUSS

    def p_axial(theta):  # int p dx over the land, by Gauss-Legendre in x
        h = C * (1 + eps * math.cos(theta))
        hdot = C * (deps * math.cos(theta) + eps * dpsi * math.sin(theta))
        return float(np.sum(w * 6 * mu * hdot / h**3 * (x**2 - L**2 / 4)))

    if sfd.cavitation == "pi":
        a, b, pts = math.pi, 2 * math.pi, None
    elif sfd.cavitation == "none":
        a, b, pts = 0.0, 2 * math.pi, None
    else:  # positive pressure only; the sign changes of dh/dt as break points
        a, b = 0.0, 2 * math.pi
        t0 = math.atan2(-deps, eps * dpsi) % math.pi
        pts = [t0, t0 + math.pi]
    f = p_axial if pts is None else (lambda t: max(p_axial(t), 0.0))
    tol = 1e-13 * sfd.coefficient * math.hypot(vy, vz) / R  # |F| >= ~ K |v| / 2
    opts = dict(epsabs=tol, epsrel=1e-12, limit=400, points=pts)
    Fr = R * quad(lambda t: f(t) * math.cos(t), a, b, **opts)[0]
    Ft = R * quad(lambda t: f(t) * math.sin(t), a, b, **opts)[0]
    return (Fr * math.cos(psi) - Ft * math.sin(psi), Fr * math.sin(psi) + Ft * math.cos(psi))


@pytest.mark.parametrize("model", MODELS)
def test_closed_forms_match_pressure_quadrature(model: str) -> None:
    sfd = paper_sfd(model)
    y, z, vy, vz = random_states(25, 11, 0.001, 0.95)
    Fy, Fz = sfd.force(y, z, vy, vz)
    for i in range(y.size):
        qy, qz = quad_force(sfd, y[i], z[i], vy[i], vz[i])
        scale = math.hypot(qy, qz)
        assert abs(Fy[i] - qy) <= 1e-8 * scale, (i, Fy[i], qy)
        assert abs(Fz[i] - qz) <= 1e-8 * scale, (i, Fz[i], qz)
