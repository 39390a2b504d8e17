"""The compiled kernel of the rub element (:class:`rotorsfd.elements.rub.RubElement`).

One sample of the smoothed contact law with Coulomb friction (derivation in the docstring
of :mod:`rotorsfd.elements.rub` and in ``docs/elements.md``), ``d = q - o``, ``r = |d|``,
``p = r - delta``, ``A = I + mu J``::

    F = -k_c s(p) A d / r,   dF/dq = -k_c A [(s / r) I + (s' - s / r) e_r e_r^T],   dF/dv = 0

Kept apart from the element and its config model so that loading a config does not load
numba: the element imports this module when its ``kernel`` is first asked for.
"""

from __future__ import annotations

import numpy as np
from numba import njit

__all__ = ["N_PARAMS", "P_CLEARANCE", "P_FRICTION", "P_OFFSET_Y", "P_OFFSET_Z",
           "P_SMOOTHING", "P_STIFFNESS", "rub_kernel"]

#: Parameter vector of :func:`rub_kernel` (``RubElement.kernel_params``).
P_CLEARANCE, P_STIFFNESS, P_FRICTION, P_SMOOTHING, P_OFFSET_Y, P_OFFSET_Z = range(6)
N_PARAMS = 6


@njit(cache=True)
def rub_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
               dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """One sample of the rub law ``F = -k_c s(p) (I + mu J) d / r`` and its Jacobians
    (module doc); always 0 (a contact law has no domain limit)."""
    delta, kc, mu, eps = params[P_CLEARANCE], params[P_STIFFNESS], params[P_FRICTION], \
        params[P_SMOOTHING]
    dy = q[0] - params[P_OFFSET_Y]
    dz = q[1] - params[P_OFFSET_Z]
    for i in range(2):
        for j in range(2):
            dFdv[i, j] = 0.0
    r = np.sqrt(dy * dy + dz * dz)
    p = r - delta
    x = (p + 0.5 * eps) / eps
    if x <= 0.0:
        F[0] = 0.0
        F[1] = 0.0
        for i in range(2):
            for j in range(2):
                dFdq[i, j] = 0.0
        return 0
    if x >= 1.0:
        s = p
        ds = 1.0
    else:
        s = eps * x * x * x * (1.0 - 0.5 * x)
        ds = x * x * (3.0 - 2.0 * x)
    g = kc * s / r
    h = kc * ds - g
    ey = dy / r
    ez = dz / r
    # B = g I + h e_r e_r^T;  F = -A g d,  dF/dq = -A B with A = [[1, -mu], [mu, 1]]
    F[0] = -g * (dy - mu * dz)
    F[1] = -g * (dz + mu * dy)
    b00 = g + h * ey * ey
    b01 = h * ey * ez
    b11 = g + h * ez * ez
    dFdq[0, 0] = -(b00 - mu * b01)
    dFdq[0, 1] = -(b01 - mu * b11)
    dFdq[1, 0] = -(b01 + mu * b00)
    dFdq[1, 1] = -(b11 + mu * b01)
    return 0
