"""A rigid rotor of mass m on one short journal bearing under gravity (the classical oil
whirl problem), as a generic periodic problem whose force law depends on the speed lam.

    m q'' = F_jb(q, q'; lam) + (0, -m g) + U lam^2 (cos lam t, sin lam t)

The bearing geometry is that of the tests (mu = 0.02 Pa s, R = 25 mm, L = 20 mm,
C = 50 um); lam is the journal speed [rad/s].
"""

from __future__ import annotations

import numpy as np

from rotorsfd.elements.journal_bearing import JournalBearingConfig, JournalBearingElement
from rotorsfd.harmonic.problem import NonlinearLaw, PeriodicProblem

MU, RADIUS, LENGTH, CLEARANCE = 0.02, 0.025, 0.02, 50e-6
G = 9.81


def bearing(cavitation: str = "pi") -> JournalBearingElement:
    """The test bearing at node 1, speed unset."""
    return JournalBearingConfig(node=1, viscosity=MU, radius=RADIUS, length=LENGTH,
                                clearance=CLEARANCE, cavitation=cavitation).build("jb")


def ocvirk_load(eps: float, speed: float) -> float:
    """Short-bearing (Ocvirk) load capacity of the pi film,
    ``W = (mu Omega R L^3 / (4 C^2)) eps sqrt(pi^2 (1 - eps^2) + 16 eps^2) / (1 - eps^2)^2``
    (Childs 1993, eq. 3.40; Friswell et al. 2010, eq. 5.68)."""
    return (MU * speed * RADIUS * LENGTH**3 / (4 * CLEARANCE**2) * eps
            * np.sqrt(np.pi**2 * (1 - eps**2) + 16 * eps**2) / (1 - eps**2) ** 2)


def friswell_coefficients(eps: float) -> tuple[np.ndarray, np.ndarray]:
    """Dimensionless short-bearing stiffness ``a`` and damping ``b`` (K = (W/C) a,
    C = (W/(C Omega)) b) of the pi film, Friswell, Penny, Garvey and Lees, Dynamics of
    Rotating Machines (Cambridge 2010), eq. (5.77): coordinates (u, v) = (horizontal,
    vertical up), the load W acting down, the journal turning from u to v."""
    e2 = eps**2
    h0 = 1.0 / (np.pi**2 * (1 - e2) + 16 * e2) ** 1.5
    s = np.sqrt(1 - e2)
    pi2 = np.pi**2
    a = h0 * np.array([
        [4 * (pi2 * (2 - e2) + 16 * e2),
         np.pi * (pi2 * (1 - e2) ** 2 - 16 * e2**2) / (eps * s)],
        [-np.pi * (pi2 * (1 - e2) * (1 + 2 * e2) + 32 * e2 * (1 + e2)) / (eps * s),
         4 * (pi2 * (1 + 2 * e2) + 32 * e2 * (1 + e2) / (1 - e2))]])
    b = h0 * np.array([
        [2 * np.pi * s * (pi2 * (1 + 2 * e2) - 16 * e2) / eps,
         -8 * (pi2 * (1 + 2 * e2) - 16 * e2)],
        [-8 * (pi2 * (1 + 2 * e2) - 16 * e2),
         2 * np.pi * (pi2 * (1 - e2) ** 2 + 48 * e2) / (eps * s)]])
    return a, b


def rigid_rotor_problem(mass: float, unbalance: float = 0.0) -> PeriodicProblem:
    """The rigid rotor on the bearing as a :class:`PeriodicProblem` in the speed."""
    jb = bearing()
    unset = jb.with_parameter("speed", float("nan"))

    def law(lam: float) -> NonlinearLaw:
        e = jb.with_parameter("speed", lam)
        return NonlinearLaw(e.force, lambda q, v: e.force_and_jacobian(q, v)[1:],
                            e.force_and_jacobian, e.kernel_params,
                            lambda q, v: e.dforce(q, v, "speed"))

    zero = np.zeros((2, 2))

    def forcing(lam: float, H: int) -> np.ndarray:
        F = np.zeros((H + 1, 2), dtype=complex)
        F[0, 1] = -mass * G
        if H >= 1:
            F[1] = unbalance * lam**2 * np.array([1.0, -1j])
        return F

    def dforcing(lam: float, H: int) -> np.ndarray:
        dF = np.zeros((H + 1, 2), dtype=complex)
        if H >= 1:
            dF[1] = 2 * unbalance * lam * np.array([1.0, -1j])
        return dF

    return PeriodicProblem(
        n_dof=2, nl_dofs=np.array([0, 1]),
        matrices=lambda lam: (mass * np.eye(2), zero, zero),
        dmatrices=lambda lam: (zero, zero, zero), forcing=forcing, dforcing=dforcing,
        frequency=lambda lam: float(lam), dfrequency=lambda lam: 1.0,
        nl_force=unset.force, nl_jacobian=lambda q, v: unset.force_and_jacobian(q, v)[1:],
        nl_kernel=jb.kernel, nl_kernel_params=unset.kernel_params, scaling=CLEARANCE,
        nl_limit=jb.limit, name="rigid rotor on a journal bearing", nl_at=law)
