"""Fluid inertia of the short open-ended squeeze film: the force and its exact Jacobians.

Model (San Andres and Vance 1986; San Andres 2012, the short open-ended SFD with temporal
and convective fluid inertia; derived in ``derivations/sfd_inertia.py`` and
``docs/sfd.md``): the axial momentum equation integrated across the film with the
Poiseuille profile ("averaged inertia", bulk flow), with ``q_x = -h' x`` from continuity,
gives at the land of length L (``x`` in ``[-L/2, L/2]``, ``p = 0`` at the open ends)::

    p = (x^2 - L^2/4) [6 mu h'/h^3 + (rho/2) (h''/h - (12/5) h'^2/h^2)]

which is the lubrication pressure plus a term exactly linear in the squeeze Reynolds
number ``Re_s = rho omega C^2 / mu`` (the first-order correction is the whole correction
in this model). With ``h = C - q.n``, ``h' = -v.n``, ``h'' = -a.n`` (``n = (cos phi, sin
phi)``) the inertia force ``F_in = -R int int p n dx dphi`` over the film arc is::

    F_in = -(rho R L^3 / 12) int_film [(n.a)/h + (12/5) (n.v)^2/h^2] n dphi
         = -M_a(q) a - (rho R L^3 / 5) int_film (n.v)^2 n / h^2 dphi

with the added-mass matrix ``M_a = (rho R L^3 / 12) int_film n n^T / h dphi`` (centred:
``pi rho R L^3 / (12 C)`` for the full film, half that for the pi film). Why this form and
not the formal first-order perturbation (Reinhardt and Lund 1975; Hamzehlouia and
Behdinan 2017): the averaged-inertia pressure stays accurate up to ``Re_s`` of order 10,
the range of engine dampers, where the perturbation series degrades, and it is the form
San Andres compares with measurements; the perturbation differs by the velocity profile's
weighting of the temporal term (6/5 instead of 1, derived in the same script).

Film arcs (the viscous film's, ``rotorsfd.model.sfd``; to first order in ``Re_s`` the
inertia does not move a Guembel boundary, where the viscous pressure vanishes): pi film
``phi - psi`` in ``[0, pi]``, 2 pi film the whole circle (two panels split at the thinnest
film), Guembel ``phi`` in ``[beta - pi/2, beta + pi/2]``, ``beta = atan2(vz, vy)``, split
at ``psi`` when the thinnest film lies inside. Each panel is integrated by Gauss-Legendre
with :data:`N_GAUSS` nodes (the integrand's poles are at the thinnest film, a panel end:
relative error below 1e-12 up to ``eps = 0.99``, about 1e-7 at 0.999), and the Jacobians
are the exact derivatives of that discrete sum, moving panel ends included:
``dS/dp = dA/dp sum w (-f + (B - A)(1 - x) f') + dB/dp sum w (f + (B - A) x f')``. Where
an arc is undefined (pi film at ``e = 0``, Guembel at ``v = 0``) the mean over its
direction is used: half the full film, without end terms.
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["CONVECTIVE", "N_GAUSS", "film_inertia_sample"]

#: Gauss-Legendre nodes per panel.
N_GAUSS = 48
_x, _w = np.polynomial.legendre.leggauss(N_GAUSS)
#: nodes and weights on [0, 1]
GL_X = 0.5 * (_x + 1.0)
GL_W = 0.5 * _w
#: coefficient of the convective term: the Poiseuille profile's int u^2 = (6/5) q^2/h,
#: differentiated in x (2 (6/5) = 12/5)
CONVECTIVE = 12.0 / 5.0

PI_FILM, FULL_FILM, GUEMBEL = 0, 1, 2


@njit(cache=True, inline="always")
def _panel(A: float, B: float, y: float, z: float, vy: float, vz: float, ay: float,
           az: float, clr: float, S: np.ndarray, Sq: np.ndarray, Sv: np.ndarray,
           Sa: np.ndarray, gA: np.ndarray, gB: np.ndarray, ends: bool) -> None:
    """Add ``int_A^B f dphi`` (``f = [(n.a)/h + k (n.v)^2/h^2] n``) to ``S`` and its
    fixed-node derivatives to ``Sq, Sv, Sa``; with ``ends`` the end sums ``gA, gB`` of the
    module doc (overwritten)."""
    span = B - A
    k = CONVECTIVE
    if ends:
        gA[0] = 0.0
        gA[1] = 0.0
        gB[0] = 0.0
        gB[1] = 0.0
    for i in range(GL_X.shape[0]):
        xi = GL_X[i]
        wi = GL_W[i]
        phi = A + span * xi
        c = math.cos(phi)
        s = math.sin(phi)
        h = clr - (y * c + z * s)
        ih = 1.0 / h
        ih2 = ih * ih
        na = ay * c + az * s
        nv = vy * c + vz * s
        g = na * ih + k * nv * nv * ih2
        W = wi * span
        S[0] += W * g * c
        S[1] += W * g * s
        gq = W * (na * ih2 + 2.0 * k * nv * nv * ih2 * ih)
        gv = W * 2.0 * k * nv * ih2
        ga = W * ih
        cc = c * c
        cs = c * s
        ss = s * s
        Sq[0, 0] += gq * cc
        Sq[0, 1] += gq * cs
        Sq[1, 0] += gq * cs
        Sq[1, 1] += gq * ss
        Sv[0, 0] += gv * cc
        Sv[0, 1] += gv * cs
        Sv[1, 0] += gv * cs
        Sv[1, 1] += gv * ss
        Sa[0, 0] += ga * cc
        Sa[0, 1] += ga * cs
        Sa[1, 0] += ga * cs
        Sa[1, 1] += ga * ss
        if ends:
            ta = -ay * s + az * c
            tv = -vy * s + vz * c
            qt = -y * s + z * c
            gd = ta * ih + na * qt * ih2 + k * (2.0 * nv * tv * ih2
                                                + 2.0 * nv * nv * qt * ih2 * ih)
            fd0 = gd * c - g * s   # f' = g' n + g t
            fd1 = gd * s + g * c
            f0 = g * c
            f1 = g * s
            gA[0] += wi * (-f0 + span * (1.0 - xi) * fd0)
            gA[1] += wi * (-f1 + span * (1.0 - xi) * fd1)
            gB[0] += wi * (f0 + span * xi * fd0)
            gB[1] += wi * (f1 + span * xi * fd1)


@njit(cache=True, inline="always")
def _end_term(J: np.ndarray, g: np.ndarray, d0: float, d1: float) -> None:
    """``J += g (d0, d1)``: an end sum times the gradient of the panel end."""
    J[0, 0] += g[0] * d0
    J[0, 1] += g[0] * d1
    J[1, 0] += g[1] * d0
    J[1, 1] += g[1] * d1


@njit(cache=True)
def film_inertia_sample(y: float, z: float, vy: float, vz: float, ay: float, az: float,
                        rho: float, rad: float, length: float, clr: float, code: int,
                        F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray,
                        dFda: np.ndarray) -> None:
    """Add the inertia force of one sample (module doc) and its exact Jacobians to
    ``F (2,)``, ``dFdq, dFdv (2, 2)`` and write ``dFda (2, 2)``; ``(y, z)`` from the
    housing centre, ``eps < 1`` (checked by the caller)."""
    S = np.zeros(2)
    Sq = np.zeros((2, 2))
    Sv = np.zeros((2, 2))
    Sa = np.zeros((2, 2))
    gA = np.zeros(2)
    gB = np.zeros(2)
    hA = np.zeros(2)
    hB = np.zeros(2)
    e = math.hypot(y, z)
    if e > 0.0:
        psi = math.atan2(z, y)
        dpsi0, dpsi1 = -z / (e * e), y / (e * e)   # grad psi = e_t / e
    else:
        psi = 0.0
        dpsi0, dpsi1 = 0.0, 0.0
    vmag2 = vy * vy + vz * vz
    scale = 1.0
    if code == PI_FILM and e > 0.0:
        _panel(psi, psi + math.pi, y, z, vy, vz, ay, az, clr, S, Sq, Sv, Sa, gA, gB, True)
        _end_term(Sq, gA, dpsi0, dpsi1)
        _end_term(Sq, gB, dpsi0, dpsi1)
    elif code == GUEMBEL and vmag2 > 0.0:
        beta = math.atan2(vz, vy)
        db0, db1 = -vz / vmag2, vy / vmag2
        A = beta - 0.5 * math.pi
        B = beta + 0.5 * math.pi
        split = psi + 2.0 * math.pi * math.floor((B - psi) / (2.0 * math.pi))
        if e > 0.0 and split > A:   # the thinnest film inside the arc: two panels
            _panel(A, split, y, z, vy, vz, ay, az, clr, S, Sq, Sv, Sa, gA, gB, True)
            _panel(split, B, y, z, vy, vz, ay, az, clr, S, Sq, Sv, Sa, hA, hB, True)
            _end_term(Sv, gA, db0, db1)
            _end_term(Sq, gB, dpsi0, dpsi1)
            _end_term(Sq, hA, dpsi0, dpsi1)
            _end_term(Sv, hB, db0, db1)
        else:
            _panel(A, B, y, z, vy, vz, ay, az, clr, S, Sq, Sv, Sa, gA, gB, True)
            _end_term(Sv, gA, db0, db1)
            _end_term(Sv, gB, db0, db1)
    else:
        # the full circle (2 pi film), or the mean over the arc's direction (pi film at
        # e = 0, Guembel at v = 0): half of it
        if code != FULL_FILM:
            scale = 0.5
        _panel(psi, psi + math.pi, y, z, vy, vz, ay, az, clr, S, Sq, Sv, Sa, gA, gB, True)
        _panel(psi + math.pi, psi + 2.0 * math.pi, y, z, vy, vz, ay, az, clr, S, Sq, Sv,
               Sa, hA, hB, True)
        for r in range(2):
            gA[r] += hB[r]   # both ends of the circle at psi
            gB[r] += hA[r]
        _end_term(Sq, gA, dpsi0, dpsi1)
        _end_term(Sq, gB, dpsi0, dpsi1)
    kin = -scale * rho * rad * length * length * length / 12.0
    for r in range(2):
        F[r] += kin * S[r]
        for c in range(2):
            dFdq[r, c] += kin * Sq[r, c]
            dFdv[r, c] += kin * Sv[r, c]
            dFda[r, c] = kin * Sa[r, c]
