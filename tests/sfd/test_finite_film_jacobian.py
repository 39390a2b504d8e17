"""The exact Jacobian of the discrete finite-length film against central differences of its
force, and the compiled kernel (housing offset in its parameters) against the numpy API."""

from __future__ import annotations

import math

import numpy as np
import pytest
from sfd_helpers import CR, MU, C, random_states

from rotorsfd.model.film_finite import FiniteSFD
from rotorsfd.model.film_finite_kernels import P_OFFSET_Y, P_OFFSET_Z


def central_differences(film: FiniteSFD, y: float, z: float, vy: float, vz: float
                        ) -> tuple[np.ndarray, np.ndarray]:
    x = np.array([y, z, vy, vz])
    steps = np.array([1e-6 * C, 1e-6 * C, 1e-6 * max(abs(vy), abs(vz)),
                      1e-6 * max(abs(vy), abs(vz))])
    J = np.empty((2, 4))
    for k in range(4):
        d = np.zeros(4)
        d[k] = steps[k]
        fp = np.array(film.force(*(x + d)))
        fm = np.array(film.force(*(x - d)))
        J[:, k] = (fp - fm) / (2 * steps[k])
    return J[:, :2], J[:, 2:]


@pytest.mark.parametrize("model, table", [("pi", False), ("pi", True), ("none", False),
                                          ("none", True), ("guembel", False),
                                          ("guembel", True)])
@pytest.mark.parametrize("end_flow", [math.inf, 0.5])
def test_jacobian_against_central_differences(model: str, table: bool, end_flow: float
                                              ) -> None:
    """Relative to the Jacobian's size: the differences carry O(h^2) truncation and
    roundoff ~1e-10/h; a Guembel sample whose step crosses a node's sign change would
    show a kink (none in these states: the worst sample is reported on failure). With the
    eps table the Jacobian is the exact derivative of the interpolated force."""
    film = FiniteSFD.from_ratios(MU, C, CR, 0.325, model, end_flow=end_flow, table=table)
    assert film.tabulated == table
    y, z, vy, vz = random_states(12, 7, 0.05, 0.9)
    for i in range(y.size):
        _, jq, jv = film.force_and_jacobian(y[i], z[i], vy[i], vz[i])
        fq, fv = central_differences(film, y[i], z[i], vy[i], vz[i])
        assert np.abs(jq - fq).max() < 1e-6 * np.abs(jq).max(), (i, jq, fq)
        assert np.abs(jv - fv).max() < 1e-6 * np.abs(jv).max(), (i, jv, fv)


def test_jacobian_at_the_centre_is_finite_and_matches_for_the_full_film() -> None:
    """e = 0: the psi term is left out; for the 2 pi film it vanishes there (M isotropic),
    so the Jacobian is still the derivative."""
    film = FiniteSFD.from_ratios(MU, C, CR, 0.325, "none")
    _, jq, jv = film.force_and_jacobian(0.0, 0.0, 0.02, -0.01)
    fq, fv = central_differences(film, 1e-9 * C, 0.0, 0.02, -0.01)
    assert np.abs(jv - fv).max() < 1e-6 * np.abs(jv).max()
    assert np.abs(jq - fq).max() < 1e-5 * film.linear_damping * 0.02 / C
    np.testing.assert_allclose(jv, -film.linear_damping * np.eye(2), rtol=2e-3, atol=1e-9)


@pytest.mark.parametrize("model", ["pi", "guembel"])
def test_kernel_with_offset_equals_the_api(model: str) -> None:
    film = FiniteSFD.from_ratios(MU, C, CR, 0.325, model, end_flow=3.0)
    params = film.kernel_params
    params[P_OFFSET_Y], params[P_OFFSET_Z] = 0.2 * C, -0.1 * C
    y, z, vy, vz = random_states(20, 11, 0.0, 0.9)
    F, dq, dv = film.force_and_jacobian(y, z, vy, vz)
    f, jq, jv = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
    kernel = film.numba_kernel
    for i in range(y.size):
        q = np.array([y[i] + 0.2 * C, z[i] - 0.1 * C])
        assert kernel(q, np.array([vy[i], vz[i]]), params, f, jq, jv) == 0
        np.testing.assert_allclose(f, F[i], rtol=1e-12, atol=1e-12 * np.abs(F[i]).max())
        np.testing.assert_allclose(jq, dq[i], rtol=1e-11, atol=1e-11 * np.abs(dq[i]).max())
        np.testing.assert_allclose(jv, dv[i], rtol=1e-12, atol=1e-12 * np.abs(dv[i]).max())
    f[:] = 7.0
    assert kernel(np.array([0.2 * C + 0.9995 * C, -0.1 * C]), np.zeros(2), params, f, jq,
                  jv) == 1
    assert np.all(f == 7.0)


@pytest.mark.parametrize("model", ["pi", "none", "guembel"])
@pytest.mark.parametrize("end_flow", [math.inf, 0.0])
def test_eps_table_error_bound(model: str, end_flow: float) -> None:
    """The table's error, measured at every interval's midpoint when it is built, is below
    1e-5 (M; Guembel: the fields, 2e-5) and 1e-4 (dM/deps); on random states the
    tabulated force is within 1e-6 of the grid solver, the velocity Jacobian too, and
    dF/dq within 1e-3 (its psi term divides the table's error by e: largest near the
    centre)."""
    tab = FiniteSFD.from_ratios(MU, C, CR, 0.325, model, end_flow=end_flow)
    ref = FiniteSFD.from_ratios(MU, C, CR, 0.325, model, end_flow=end_flow, table=False)
    bound = 2e-5 if model == "guembel" else 1e-5
    assert tab.table_error[0] < bound and tab.table_error[1] < 1e-4
    y, z, vy, vz = random_states(100, 17, 0.0, 0.99)
    F, dq, dv = tab.force_and_jacobian(y, z, vy, vz)
    F0, dq0, dv0 = ref.force_and_jacobian(y, z, vy, vz)
    for a, b, tol in ((F, F0, 1e-6), (dv, dv0, 1e-6), (dq, dq0, 1e-3)):
        scale = np.abs(b).reshape(100, -1).max(axis=1)
        assert np.all(np.abs(a - b).reshape(100, -1).max(axis=1) <= tol * scale)
