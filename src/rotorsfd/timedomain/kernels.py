"""Nonlinear-force kernels for the compiled stepping loops.

Every kernel has the signature of ``docs/INTERFACES.md``::

    kernel(q, v, params, F, dFdq, dFdv) -> int   # 0, or 1 on contact

The stepping loops call the kernel as a first-class function of type
:data:`KERNEL_TYPE` (an indirect call, a few ns), so one compiled loop serves every
kernel and is cached on disk. :func:`as_cfunc` turns an ``@njit`` kernel into that type.
The generic test kernels here (a cubic spring, no force) are also the Duffing kernels.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import cfunc, njit, types
from numba.core.ccallback import CFunc
from numba.core.registry import CPUDispatcher

#: ``int64(float64[::1] q, v, params, F, float64[:, ::1] dFdq, dFdv)``
KERNEL_SIGNATURE = types.int64(
    types.float64[::1], types.float64[::1], types.float64[::1], types.float64[::1],
    types.float64[:, ::1], types.float64[:, ::1],
)
KERNEL_TYPE = types.FunctionType(KERNEL_SIGNATURE)

_CFUNCS: dict[Any, CFunc] = {}


def as_cfunc(kernel: Any) -> CFunc:
    """Compiled first-class version of ``kernel`` (an ``@njit`` dispatcher, a plain
    function with the kernel signature, or already a ``cfunc``); memoised per kernel."""
    if isinstance(kernel, CFunc):
        return kernel
    cached = _CFUNCS.get(kernel)
    if cached is not None:
        return cached
    py_func = kernel.py_func if isinstance(kernel, CPUDispatcher) else kernel
    if not callable(py_func):
        raise TypeError(f"kernel must be an @njit function or a cfunc, got {kernel!r}")
    try:
        compiled = cfunc(KERNEL_SIGNATURE, cache=True)(py_func)
    except Exception:  # source not cacheable (closure, interactive): compile in memory
        compiled = cfunc(KERNEL_SIGNATURE)(py_func)
    _CFUNCS[kernel] = compiled
    return compiled


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
