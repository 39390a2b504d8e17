"""Scope BLAS/LAPACK to one thread around the many small dense factorisations of HB.

Multi-threaded OpenBLAS is slower on 10-1000-sized matrices and collapses when the machine
is loaded (thread wake-ups of milliseconds per call); parallelism belongs to the studies
layer (one process per parameter set). Uses threadpoolctl when installed, else no-op.

The libraries are looked up once (a ``ThreadpoolController`` made at the first call, when
numpy's and scipy's BLAS are loaded: the solvers import both): ``threadpool_limits``
rescans the process's shared libraries at every call, milliseconds that dominated a
single-point solve.
"""

from __future__ import annotations

from contextlib import AbstractContextManager, nullcontext
from typing import Any

try:
    from threadpoolctl import ThreadpoolController
except ImportError:  # pragma: no cover - optional dependency
    ThreadpoolController = None

_controller: list[Any] = []


def single_threaded_blas() -> AbstractContextManager:
    """Context manager limiting BLAS to one thread (no-op without threadpoolctl)."""
    if ThreadpoolController is None:
        return nullcontext()
    if not _controller:
        _controller.append(ThreadpoolController())
    return _controller[0].limit(limits=1, user_api="blas")
