"""A Jeffcott rotor with one rub element, as a periodic problem and as integrator inputs.

    m q'' + c q' + k q = U Omega^2 (cos Omega t, sin Omega t) + F_rub(q, q'),   lam = Omega
"""

from __future__ import annotations

import numpy as np

from rotorsfd.elements.rub import RubElement
from rotorsfd.harmonic.examples import unbalance_forcing
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.timedomain import Forcing, HarmonicLoad

MASS, STIFFNESS, DAMPING, UNBALANCE = 10.0, 1.0e6, 200.0, 5.0e-4
CLEARANCE = 1.0e-4


def rub(friction: float = 0.1, contact_stiffness: float = 1.0e7,
        smoothing: float = 1.0e-6, offset: tuple[float, float] = (0.0, 0.0)) -> RubElement:
    """The rub of the tests, at node 1 (DOFs 0, 1: the Jeffcott rotor's y, z)."""
    return RubElement("rub", 1, CLEARANCE, contact_stiffness, friction, smoothing, offset)


def matrices(mass: float = MASS, stiffness: float = STIFFNESS, damping: float = DAMPING):
    """``(M, D, K)`` of the Jeffcott rotor."""
    return mass * np.eye(2), damping * np.eye(2), stiffness * np.eye(2)


def problem(element: RubElement, unbalance: float = UNBALANCE, **kw) -> PeriodicProblem:
    """The periodic problem of the rotor with the rub (HB with the element's kernel)."""
    M, D, K = matrices(**kw)
    Z = np.zeros((2, 2))
    forcing, dforcing = unbalance_forcing(np.array([1.0, -1.0j]), unbalance)

    return PeriodicProblem(
        n_dof=2, nl_dofs=np.array([0, 1]), matrices=lambda lam: (M, D, K),
        dmatrices=lambda lam: (Z, Z, Z), forcing=forcing, dforcing=dforcing,
        frequency=lambda lam: lam, dfrequency=lambda lam: 1.0, nl_force=element.force,
        nl_jacobian=lambda q, v: element.force_and_jacobian(q, v)[1:],
        nl_force_jacobian=element.force_and_jacobian, scaling=element.scale,
        name="jeffcott_rub", nl_kernel=element.kernel,
        nl_kernel_params=element.kernel_params)


def forcing(omega: float, unbalance: float = UNBALANCE) -> Forcing:
    """The unbalance load ``U Omega^2 (cos, sin)`` for the time integration."""
    f = unbalance * omega**2
    return Forcing(omega=omega, harmonics=(HarmonicLoad(1.0, np.array([f, 0.0]),
                                                        np.array([0.0, f])),))
