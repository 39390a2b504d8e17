"""The compiled kernel (INTERFACES.md signature) agrees with the vectorised path."""

from __future__ import annotations

import numpy as np
import pytest
from numba import njit
from sfd_helpers import MODELS, C, paper_sfd, random_states


@pytest.mark.parametrize("model", MODELS)
def test_kernel_equals_vectorised_path(model: str) -> None:
    sfd = paper_sfd(model)
    y, z, vy, vz = random_states(200, 41, 0.0, 0.99)
    y[0] = z[0] = 0.0
    vy[1] = vz[1] = 0.0
    F, dq, dv = sfd.force_and_jacobian(y, z, vy, vz)
    kernel, params = sfd.numba_kernel, sfd.kernel_params
    f, jq, jv = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
    for i in range(y.size):
        status = kernel(np.array([y[i], z[i]]), np.array([vy[i], vz[i]]), params, f, jq, jv)
        assert status == 0
        np.testing.assert_allclose(f, F[i], rtol=1e-14, atol=1e-14 * np.abs(F[i]).max())
        np.testing.assert_allclose(jq, dq[i], rtol=1e-14, atol=1e-14 * np.abs(dq[i]).max())
        np.testing.assert_allclose(jv, dv[i], rtol=1e-14, atol=1e-14 * np.abs(dv[i]).max())


def test_kernel_contact_status_and_compiled_caller() -> None:
    """Status 1 at contact or on a non-finite state, outputs untouched; callable from njit."""
    sfd = paper_sfd("pi")
    kernel = sfd.numba_kernel

    @njit
    def caller(q, v, params):
        f, jq, jv = np.full(2, 7.0), np.full((2, 2), 7.0), np.full((2, 2), 7.0)
        return kernel(q, v, params, f, jq, jv), f, jq, jv

    for q, v in (([0.999 * C, 0.0], [0.0, 0.0]), ([0.0, 2 * C], [0.0, 0.0]),
                 ([np.nan, 0.0], [0.0, 0.0]), ([0.0, 0.0], [np.nan, 0.0])):
        status, f, jq, jv = caller(np.array(q), np.array(v), sfd.kernel_params)
        assert status == 1
        assert np.all(f == 7.0) and np.all(jq == 7.0) and np.all(jv == 7.0)
    status, f, _, _ = caller(np.array([0.5 * C, 0.0]), np.array([0.0, 0.01]), sfd.kernel_params)
    assert status == 0
    np.testing.assert_allclose(f, np.array(sfd.force(0.5 * C, 0.0, 0.0, 0.01)), rtol=1e-15)
