"""Scope BLAS/LAPACK to one thread around the many small dense factorisations of HB.

Multi-threaded OpenBLAS is slower on 10-1000-sized matrices and collapses when the machine
is loaded (thread wake-ups of milliseconds per call); parallelism belongs to the studies
layer (one process per parameter set). Uses threadpoolctl when installed, else no-op.
"""

from __future__ import annotations

from contextlib import AbstractContextManager, nullcontext

try:
    from threadpoolctl import threadpool_limits
except ImportError:  # pragma: no cover - optional dependency
    threadpool_limits = None


def single_threaded_blas() -> AbstractContextManager:
    """Context manager limiting BLAS to one thread (no-op without threadpoolctl)."""
    if threadpool_limits is None:
        return nullcontext()
    return threadpool_limits(limits=1, user_api="blas")
