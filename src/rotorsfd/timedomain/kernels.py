"""Nonlinear-force kernels for the compiled stepping loops.

Every kernel has the signature of ``docs/INTERFACES.md``::

    kernel(q, v, params, F, dFdq, dFdv) -> int   # 0, or 1 on contact

The stepping loops call the kernel as a first-class function of type
:data:`KERNEL_TYPE` (an indirect call, a few ns), so one compiled loop serves every
kernel and is cached on disk. :func:`as_cfunc` turns an ``@njit`` kernel into that type.
The generic test kernels here (a cubic spring, no force) are also the Duffing kernels.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rotorsfd.kernels import KERNEL_SIGNATURE, KERNEL_TYPE, as_cfunc

__all__ = ["KERNEL_SIGNATURE", "KERNEL_TYPE", "as_cfunc", "cubic_spring_kernel",
           "null_inertial_kernel", "null_kernel"]


@njit(cache=True)
def null_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
                dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """No nonlinear force: ``F = 0``."""
    for i in range(F.shape[0]):
        F[i] = 0.0
        for j in range(F.shape[0]):
            dFdq[i, j] = 0.0
            dFdv[i, j] = 0.0
    return 0


@njit(cache=True)
def null_inertial_kernel(q: np.ndarray, v: np.ndarray, a: np.ndarray, params: np.ndarray,
                         F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray,
                         dFda: np.ndarray) -> int:
    """No force (the inertial contract): the placeholder the stepping loops get when the
    law has no acceleration dependence (never called then)."""
    for i in range(F.shape[0]):
        F[i] = 0.0
        for j in range(F.shape[0]):
            dFdq[i, j] = 0.0
            dFdv[i, j] = 0.0
            dFda[i, j] = 0.0
    return 0


@njit(cache=True)
def cubic_spring_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
                        dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """Uncoupled cubic springs ``F_i = -k1 q_i - k3 q_i^3`` with ``params = [k1, k3]``
    (Duffing: ``x'' + c x' + k1 x + k3 x^3 = f``); contact if ``|q_i| >= params[2]``
    when a third parameter is given."""
    k1 = params[0]
    k3 = params[1]
    limit = params[2] if params.shape[0] > 2 else np.inf
    for i in range(F.shape[0]):
        x = q[i]
        if not abs(x) < limit:
            return 1
        F[i] = -k1 * x - k3 * x * x * x
        for j in range(F.shape[0]):
            dFdq[i, j] = 0.0
            dFdv[i, j] = 0.0
        dFdq[i, i] = -k1 - 3.0 * k3 * x * x
    return 0
