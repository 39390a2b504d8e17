"""Stability tests use small matrices: BLAS threads only add overhead (and contention on
a loaded machine), so they run single-threaded when threadpoolctl is available."""

from __future__ import annotations

import pytest


@pytest.fixture(autouse=True)
def _single_blas_thread():
    try:
        from threadpoolctl import threadpool_limits
    except ImportError:  # pragma: no cover
        yield
        return
    with threadpool_limits(limits=1, user_api="blas"):
        yield
