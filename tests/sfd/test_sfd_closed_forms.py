"""Closed forms of the pi and 2 pi films, small-eps limits, rotation, dissipation, signs."""

from __future__ import annotations

import numpy as np
import pytest
from sfd_helpers import MODELS, C, paper_sfd, random_states

from rotorsfd.sfd import SFD


def polar(y, z, vy, vz, Fy, Fz):
    """eps, eps', psi', F_r, F_t from Cartesian state and force."""
    e = np.hypot(y, z)
    er = np.array([y, z]) / e
    et = np.array([-er[1], er[0]])
    v = np.array([vy, vz])
    F = np.array([Fy, Fz])
    return (e / C, (er * v).sum(0) / C, (et * v).sum(0) / e,
            (er * F).sum(0), (et * F).sum(0))


def test_pi_film_circular_centred_orbit() -> None:
    sfd = paper_sfd("pi")
    k = sfd.viscosity * sfd.radius * sfd.length**3 / C**2
    eps = np.linspace(0.05, 0.95, 19)
    psi, dpsi = 0.7, 812.0  # forward precession
    y, z = eps * C * np.cos(psi), eps * C * np.sin(psi)
    vy, vz = -dpsi * z, dpsi * y
    _, _, _, Fr, Ft = polar(y, z, vy, vz, *sfd.force(y, z, vy, vz))
    np.testing.assert_allclose(Fr, -k * 2 * eps**2 * dpsi / (1 - eps**2) ** 2, rtol=1e-12)
    np.testing.assert_allclose(Ft, -k * np.pi * eps * dpsi / (2 * (1 - eps**2) ** 1.5),
                               rtol=1e-12)
    # radial force points to the bearing centre, tangential force opposes the precession
    assert np.all(Fr < 0) and np.all(Ft < 0)


@pytest.mark.parametrize("cavitation", ["pi", "none"])
def test_paper_eq11_with_radial_squeeze(cavitation: str) -> None:
    """pi film (paper eq. 11) and 2 pi film, eps' != 0, random states."""
    sfd = paper_sfd(cavitation)
    k = sfd.viscosity * sfd.radius * sfd.length**3 / C**2
    y, z, vy, vz = random_states(200, 1, 0.01, 0.95)
    eps, deps, dpsi, Fr, Ft = polar(y, z, vy, vz, *sfd.force(y, z, vy, vz))
    s2 = 1 - eps**2
    if cavitation == "pi":
        fr = -k * (2 * eps**2 * dpsi / s2**2 + np.pi * (1 + 2 * eps**2) * deps / (2 * s2**2.5))
        ft = -k * (np.pi * eps * dpsi / (2 * s2**1.5) + 2 * eps * deps / s2**2)
    else:
        fr = -k * np.pi * (1 + 2 * eps**2) * deps / s2**2.5
        ft = -k * np.pi * eps * dpsi / s2**1.5
    scale = np.hypot(fr, ft)
    np.testing.assert_allclose(Fr / scale, fr / scale, atol=1e-12)
    np.testing.assert_allclose(Ft / scale, ft / scale, atol=1e-12)


def test_full_film_cartesian_form() -> None:
    """2 pi film: F = -(pi K) [v / (1-eps^2)^(3/2) + 3 qh qh^T v / (1-eps^2)^(5/2)]."""
    sfd = paper_sfd("none")
    y, z, vy, vz = random_states(100, 2, 0.0, 0.98)
    s2 = 1 - (y**2 + z**2) / C**2
    qv = (y * vy + z * vz) / C**2
    c0 = np.pi * sfd.coefficient
    Fy, Fz = sfd.force(y, z, vy, vz)
    np.testing.assert_allclose(Fy, -c0 * (vy / s2**1.5 + 3 * y * qv / s2**2.5), rtol=1e-11)
    np.testing.assert_allclose(Fz, -c0 * (vz / s2**1.5 + 3 * z * qv / s2**2.5), rtol=1e-11)


@pytest.mark.parametrize("model", MODELS)
def test_small_eps_is_linear_damper(model: str) -> None:
    sfd = paper_sfd(model)
    c_expected = np.pi * sfd.viscosity * sfd.radius * sfd.length**3 / (2 * C**3)
    if model == "none":
        c_expected *= 2
    assert sfd.linear_damping == pytest.approx(c_expected, rel=1e-14)
    y, z, vy, vz = random_states(50, 3, 0.0, 1e-7)
    Fy, Fz = sfd.force(y, z, vy, vz)
    # first-order correction O(eps): at most (4/pi) eps for the pi film (I1 = 2 eps),
    # (9/4) eps for the Guembel film (3 K/C int_half cos^4 = 9 pi K / 8C), 0 for 2 pi
    err = np.hypot(Fy + c_expected * vy, Fz + c_expected * vz) / (c_expected * np.hypot(vy, vz))
    eps = np.hypot(y, z) / C
    assert np.all(err <= (8 / np.pi) * eps + 1e-14)
    Fy0, Fz0 = sfd.force(0.0, 0.0, vy, vz)
    np.testing.assert_allclose(Fy0, -c_expected * vy, rtol=1e-14)
    np.testing.assert_allclose(Fz0, -c_expected * vz, rtol=1e-14)


@pytest.mark.parametrize("model", MODELS)
def test_rotation_equivariance(model: str) -> None:
    """F(Rot q, Rot v) = Rot F(q, v) and J(Rot q, Rot v) = Rot J Rot^T (random rotations)."""
    sfd = paper_sfd(model)
    y, z, vy, vz = random_states(100, 4)
    a = np.random.default_rng(5).uniform(-np.pi, np.pi, 100)
    rot = np.stack([np.stack([np.cos(a), -np.sin(a)], -1), np.stack([np.sin(a), np.cos(a)], -1)],
                   -2)
    q2 = np.einsum("nij,jn->in", rot, np.array([y, z]))
    v2 = np.einsum("nij,jn->in", rot, np.array([vy, vz]))
    F1, Jq1, Jv1 = sfd.force_and_jacobian(y, z, vy, vz)
    F2, Jq2, Jv2 = sfd.force_and_jacobian(q2[0], q2[1], v2[0], v2[1])
    fs = np.abs(F1).max(axis=1, keepdims=True)
    np.testing.assert_allclose(F2 / fs, np.einsum("nij,nj->ni", rot, F1) / fs, atol=1e-12)
    for J1, J2 in ((Jq1, Jq2), (Jv1, Jv2)):
        js = np.abs(J1).max(axis=(1, 2), keepdims=True)
        np.testing.assert_allclose(J2 / js, np.einsum("nij,njk,nlk->nil", rot, J1, rot) / js,
                                   atol=1e-11)


@pytest.mark.parametrize("model", MODELS)
def test_dissipative(model: str) -> None:
    """F.v = -mu R L^3 int_film (n.v)^2 / h^3 <= 0 for every film model; for the 2 pi
    film B >= pi I, so F.v <= -c |v|^2."""
    sfd = paper_sfd(model)
    y, z, vy, vz = random_states(2000, 6, 0.0, 0.99)
    Fy, Fz = sfd.force(y, z, vy, vz)
    power = Fy * vy + Fz * vz
    assert np.all(power <= 0)
    if model != "none":
        return
    bound = -sfd.linear_damping * (vy**2 + vz**2)
    assert np.all(power <= bound * (1 - 1e-12))


def test_guembel_identities() -> None:
    """Guembel = pi film on a forward circular orbit; F_G(v) - F_G(-v) = F_2pi(v)."""
    g, p, full = paper_sfd("guembel"), paper_sfd("pi"), paper_sfd("none")
    eps = np.linspace(0.0, 0.95, 11)
    y, z = eps * C * np.cos(2.0), eps * C * np.sin(2.0)
    vy, vz = -300.0 * z, 300.0 * y
    np.testing.assert_allclose(np.array(g.force(y, z, vy, vz)),
                               np.array(p.force(y, z, vy, vz)), rtol=1e-12, atol=1e-300)
    y, z, vy, vz = random_states(300, 7)
    Fg = np.array(g.force(y, z, vy, vz))
    Fm = np.array(g.force(y, z, -vy, -vz))
    Ff = np.array(full.force(y, z, vy, vz))
    np.testing.assert_allclose((Fg - Fm) / np.abs(Ff).max(0), Ff / np.abs(Ff).max(0),
                               atol=1e-12)


def test_backward_orbit_guembel_still_centring() -> None:
    g = paper_sfd("guembel")
    eps, dpsi = 0.5, -400.0
    y, z = eps * C, 0.0
    Fy, Fz = g.force(y, z, 0.0, dpsi * y)
    assert Fy < 0 and Fz > 0  # centring, opposing the backward precession


def test_from_ratios_and_broadcasting() -> None:
    sfd = SFD.from_ratios(0.0051, 1.27e-4, 0.00485, 0.325)
    assert sfd.radius == pytest.approx(1.27e-4 / 0.00485, rel=1e-15)
    assert sfd.length == pytest.approx(0.325 * 2 * sfd.radius, rel=1e-15)
    Fy, Fz = sfd.force(np.zeros((3, 1)), np.linspace(0, 5e-5, 4), 0.01, 0.0)
    assert Fy.shape == (3, 4) and Fz.shape == (3, 4)
    dq, dv = sfd.jacobian(np.zeros((3, 1)), np.linspace(0, 5e-5, 4), 0.01, 0.0)
    assert dq.shape == (3, 4, 2, 2) and dv.shape == (3, 4, 2, 2)
    Fy, Fz = sfd.force(1e-5, 0.0, 0.0, 0.01)
    assert np.ndim(Fy) == 0 and isinstance(float(Fy), float)


def test_generic_solver_form() -> None:
    """nl_force / nl_jacobian take (..., 2) arrays of (y, z) and (vy, vz)."""
    sfd = paper_sfd("pi")
    y, z, vy, vz = random_states(12, 8)
    q = np.stack([y, z], -1).reshape(3, 4, 2)
    v = np.stack([vy, vz], -1).reshape(3, 4, 2)
    F = sfd.nl_force(q, v)
    dq, dv = sfd.nl_jacobian(q, v)
    assert F.shape == (3, 4, 2) and dq.shape == dv.shape == (3, 4, 2, 2)
    Fy, Fz = sfd.force(y, z, vy, vz)
    np.testing.assert_array_equal(F.reshape(12, 2), np.stack([Fy, Fz], -1))
    np.testing.assert_array_equal(dq.reshape(12, 2, 2), sfd.jacobian(y, z, vy, vz)[0])
    np.testing.assert_array_equal(sfd.nl_force(q[0, 0], v[0, 0]), F[0, 0])
