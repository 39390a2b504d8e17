"""Bearing centre (eps = 0, 1e-12), contact (eps >= eps_max), bad input, Guembel at v = 0."""

from __future__ import annotations

import numpy as np
import pytest
from sfd_helpers import MODELS, C, paper_sfd

from rotorsfd.errors import ConfigError, JournalContactError
from rotorsfd.sfd import SFD


@pytest.mark.parametrize("eps", [0.0, 1e-12])
@pytest.mark.parametrize("model", MODELS)
def test_centre_is_a_linear_damper(model: str, eps: float) -> None:
    sfd = paper_sfd(model)
    c = sfd.linear_damping
    rng = np.random.default_rng(31)
    psi = rng.uniform(-np.pi, np.pi, 64)
    vy, vz = rng.normal(size=(2, 64)) * 0.05
    y, z = eps * C * np.cos(psi), eps * C * np.sin(psi)
    F, dq, dv = sfd.force_and_jacobian(y, z, vy, vz)
    assert np.all(np.isfinite(F)) and np.all(np.isfinite(dq)) and np.all(np.isfinite(dv))
    np.testing.assert_allclose(F[:, 0], -c * vy, rtol=1e-10, atol=1e-10 * c * 0.05)
    np.testing.assert_allclose(F[:, 1], -c * vz, rtol=1e-10, atol=1e-10 * c * 0.05)
    np.testing.assert_allclose(dv, np.broadcast_to(-c * np.eye(2), dv.shape), atol=1e-10 * c)


def test_centre_jacobian_is_continuous_for_smooth_films() -> None:
    """2 pi and Guembel films are analytic at the centre: dF/dq(1e-12) == dF/dq(0)."""
    rng = np.random.default_rng(32)
    psi = rng.uniform(-np.pi, np.pi, 64)
    vy, vz = rng.normal(size=(2, 64)) * 0.05
    for model in ("none", "guembel"):
        sfd = paper_sfd(model)
        dq0, _ = sfd.jacobian(0.0, 0.0, vy, vz)
        dq1, _ = sfd.jacobian(1e-12 * C * np.cos(psi), 1e-12 * C * np.sin(psi), vy, vz)
        scale = sfd.coefficient / C * 0.05
        np.testing.assert_allclose(dq1, dq0, atol=1e-9 * scale)
        if model == "none":  # dF/dq = 0 at the centre (F depends on q through eps^2, q q^T)
            np.testing.assert_allclose(dq0, 0.0, atol=1e-12 * scale)
        else:  # Guembel: 3 K/C int over the half facing v of (n.v) n n^T, here nonzero
            assert np.abs(dq0).max() > 0.5 * scale


def test_pi_film_centre_kink() -> None:
    """The pi film is Lipschitz but not differentiable at eps = 0 (its film turns with psi):
    the limits of dF/dq depend on the direction; at eps = 0 the mean of them (0) is returned,
    and along a fixed direction the Jacobian is continuous in eps."""
    sfd = paper_sfd("pi")
    psi = np.linspace(-np.pi, np.pi, 64, endpoint=False)
    vy, vz = 0.03, -0.04
    dq12, _ = sfd.jacobian(1e-12 * C * np.cos(psi), 1e-12 * C * np.sin(psi), vy, vz)
    dq8, _ = sfd.jacobian(1e-8 * C * np.cos(psi), 1e-8 * C * np.sin(psi), vy, vz)
    scale = sfd.coefficient / C * 0.05
    assert np.abs(dq12).max() > scale  # a true kink, not a 0/0 artefact
    np.testing.assert_allclose(dq12, dq8, atol=1e-6 * scale)
    np.testing.assert_allclose(dq12.mean(axis=0), 0.0, atol=1e-10 * scale)
    dq0, _ = sfd.jacobian(0.0, 0.0, vy, vz)
    np.testing.assert_array_equal(dq0, np.zeros((2, 2)))


def test_guembel_at_zero_velocity() -> None:
    """F = 0; dF/dv is the mean over velocity directions: half the 2 pi film's."""
    g, full = paper_sfd("guembel"), paper_sfd("none")
    F, dq, dv = g.force_and_jacobian(0.4 * C, -0.3 * C, 0.0, 0.0)
    np.testing.assert_array_equal(F, 0.0)
    np.testing.assert_array_equal(dq, 0.0)
    _, dv_full = full.jacobian(0.4 * C, -0.3 * C, 1.0, 0.0)
    np.testing.assert_allclose(dv, 0.5 * dv_full, rtol=1e-13)
    a = np.linspace(0, 2 * np.pi, 256, endpoint=False)
    _, dv_dirs = g.jacobian(0.4 * C, -0.3 * C, 1e-3 * np.cos(a), 1e-3 * np.sin(a))
    np.testing.assert_allclose(dv_dirs.mean(axis=0), dv, rtol=1e-10)


@pytest.mark.parametrize("cavitation", MODELS)
def test_contact_raises_typed_error(cavitation: str) -> None:
    sfd = paper_sfd(cavitation)
    y = np.array([0.1, 0.5, 0.9991, 0.2]) * C
    with pytest.raises(JournalContactError) as info:
        sfd.force(y, 0.0, 0.01, 0.02)
    err = info.value
    assert err.eps == pytest.approx(0.9991, rel=1e-12)
    assert (err.y, err.z, err.vy, err.vz) == (y[2], 0.0, 0.01, 0.02)
    assert "eps_max=0.999" in str(err)
    with pytest.raises(JournalContactError):
        sfd.jacobian(0.0, 1.5 * C, 0.0, 0.0)
    Fy, _ = sfd.force(0.9989 * C, 0.0, 0.01, 0.0)  # just below: finite, large
    assert np.isfinite(Fy) and Fy < 0


def test_custom_eps_max_and_bad_inputs() -> None:
    sfd = SFD(0.0051, 0.026, 0.017, 1.27e-4, eps_max=0.9)
    with pytest.raises(JournalContactError):
        sfd.force(0.9 * 1.27e-4, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="not finite"):
        sfd.force(np.nan, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="not finite"):
        sfd.force(0.0, 0.0, np.inf, 0.0)
    for kwargs in ({"cavitation": "half"}, {"eps_max": 1.0}, {"eps_max": 0.0}):
        with pytest.raises(ConfigError):
            SFD(0.0051, 0.026, 0.017, 1.27e-4, **kwargs)
    with pytest.raises(ConfigError, match=r"^clearance: got"):
        SFD(0.0051, 0.026, 0.017, -1.0)
