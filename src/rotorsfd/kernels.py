"""The compiled nonlinear-force kernel contract shared by the solvers (docs/INTERFACES.md).

Every force law has the signature ``kernel(q, v, params, F, dFdq, dFdv) -> int`` (0, or 1
on contact). The harmonic-balance loops (:mod:`rotorsfd.harmonic.aft_kernels`) and the
time-stepping loops (:mod:`rotorsfd.timedomain`) call it as a first-class function, so one
compiled loop serves every force law; :func:`as_cfunc` compiles a kernel to that type once.
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
