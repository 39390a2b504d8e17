"""Suite-wide setup: the solvers work on small dense matrices, where threaded BLAS only adds
overhead and contention on a 2-core machine, so every test runs with one BLAS thread."""

from __future__ import annotations

import pytest
from threadpoolctl import threadpool_limits


@pytest.fixture(autouse=True)
def _single_blas_thread():
    with threadpool_limits(limits=1, user_api="blas"):
        yield
