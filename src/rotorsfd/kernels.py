"""The compiled nonlinear-force kernel contract shared by the solvers (docs/INTERFACES.md).

Every force law has the signature ``kernel(q, v, params, F, dFdq, dFdv) -> int`` (0, or 1
on contact). The harmonic-balance loops (:mod:`rotorsfd.harmonic.aft_kernels`) and the
time-stepping loops (:mod:`rotorsfd.timedomain`) call it as a first-class function, so one
compiled loop serves every force law; :func:`as_cfunc` compiles a kernel to that type once.

A law that depends on the acceleration too (the fluid inertia of a film) has in addition
an *inertial* kernel ``kernel_a(q, v, a, params, F, dFdq, dFdv, dFda) -> int`` with the
whole force ``F(q, v, a)`` and its three Jacobians (:data:`INERTIAL_SIGNATURE`,
:func:`as_inertial_cfunc`). A law without one (``inertial_kernel`` None) costs the loops
nothing: they call the plain kernel and add no mass term.
"""

from __future__ import annotations

from typing import Any

from numba import cfunc, types
from numba.core.ccallback import CFunc
from numba.core.registry import CPUDispatcher

#: ``int64(float64[::1] q, v, params, F, float64[:, ::1] dFdq, dFdv)``
KERNEL_SIGNATURE = types.int64(
    types.float64[::1], types.float64[::1], types.float64[::1], types.float64[::1],
    types.float64[:, ::1], types.float64[:, ::1],
)
KERNEL_TYPE = types.FunctionType(KERNEL_SIGNATURE)

#: ``int64(q, v, a, params, F, float64[:, ::1] dFdq, dFdv, dFda)``
INERTIAL_SIGNATURE = types.int64(
    types.float64[::1], types.float64[::1], types.float64[::1], types.float64[::1],
    types.float64[::1], types.float64[:, ::1], types.float64[:, ::1], types.float64[:, ::1],
)
INERTIAL_TYPE = types.FunctionType(INERTIAL_SIGNATURE)

_CFUNCS: dict[Any, CFunc] = {}


def as_cfunc(kernel: Any, signature: Any = KERNEL_SIGNATURE) -> CFunc:
    """Compiled first-class version of ``kernel`` (an ``@njit`` dispatcher, a plain
    function with the kernel signature, or already a ``cfunc``); memoised per kernel."""
    if isinstance(kernel, CFunc):
        return kernel
    cached = _CFUNCS.get((kernel, signature))
    if cached is not None:
        return cached
    py_func = kernel.py_func if isinstance(kernel, CPUDispatcher) else kernel
    if not callable(py_func):
        raise TypeError(f"kernel must be an @njit function or a cfunc, got {kernel!r}")
    try:
        compiled = cfunc(signature, cache=True)(py_func)
    except Exception:  # source not cacheable (closure, interactive): compile in memory
        compiled = cfunc(signature)(py_func)
    _CFUNCS[(kernel, signature)] = compiled
    return compiled


def as_inertial_cfunc(kernel: Any) -> CFunc:
    """:func:`as_cfunc` of an inertial kernel (:data:`INERTIAL_SIGNATURE`)."""
    return as_cfunc(kernel, INERTIAL_SIGNATURE)
