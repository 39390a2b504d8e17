"""Gyroscopic splitting of a rigid disk at midspan of a (nearly) massless pinned shaft.

At midspan of a symmetric pinned-pinned Euler-Bernoulli shaft, translation and tilt of
the disk decouple. Translation: k = 48 EI / L^3, w = sqrt(k / m), independent of Omega.
Tilt: a central moment M rotates the midspan by M L / (12 EI) (each half is a simply
supported beam of length L/2 with end moment M/2), so k_t = 12 EI / L. With
theta = tz + i (-ty) ~ exp(i w t) the tilt equation of the disk,
Id theta'' - i Ip Omega theta' + k_t theta = 0, gives
Id w^2 -/+ Ip Omega w - k_t = 0:

    w_F = ( Ip Omega + sqrt((Ip Omega)^2 + 4 Id k_t)) / (2 Id)   forward, rises with Omega
    w_B = (-Ip Omega + sqrt((Ip Omega)^2 + 4 Id k_t)) / (2 Id)   backward, falls
"""

from __future__ import annotations

import numpy as np
import pytest
from linear_helpers import pinned_pinned

from rotorsfd.linear import eigen
from rotorsfd.model import Disk, Material, Rotor, uniform_shaft

L, RI, RO = 0.6, 0.0, 0.02
LIGHT = Material(1.0, 211e9, 81.783e9)            # 1 kg/m^3: shaft mass ~ 1e-3 kg
DISK = Disk(node=5, mass=10.0, polar_inertia=0.08, diametral_inertia=0.05)


@pytest.fixture(scope="module")
def system():
    shaft = uniform_shaft(L, 8, RI, RO, LIGHT, shear_coefficient=1e9)   # Euler-Bernoulli
    return pinned_pinned(Rotor(shaft, disks=[DISK]))


def closed_form(speed: float) -> tuple[float, float, float]:
    ei = LIGHT.young_modulus * np.pi * RO**4 / 4.0
    w_t = np.sqrt(48.0 * ei / L**3 / DISK.mass)
    kt, ip, i_d = 12.0 * ei / L, DISK.polar_inertia, DISK.diametral_inertia
    root = np.sqrt((ip * speed) ** 2 + 4.0 * i_d * kt)
    return w_t, (ip * speed + root) / (2 * i_d), (-ip * speed + root) / (2 * i_d)


@pytest.mark.parametrize("speed", [0.0, 500.0, 3000.0])
def test_disk_tilt_splitting_matches_closed_form(system, speed):
    w_t, w_f, w_b = closed_form(speed)
    res = eigen(system, speed, 4)
    f, whirl = res.frequencies, res.whirl
    # translation pair (both whirls at w_t) is the lowest here
    np.testing.assert_allclose(f[:2], [w_t, w_t], rtol=2e-4)
    np.testing.assert_allclose(np.sort(f[2:4]), [w_b, w_f], rtol=2e-4)
    if speed > 0.0:
        assert whirl[2] == "backward" and whirl[3] == "forward"
        assert f[3] > f[2] * (1 + 1e-3)
    # well separated at speed: the check can fail if G had the wrong sign or size
    if speed == 3000.0:
        assert w_f / w_b > 1.5


def test_without_shaft_mass_limit_error_scales_with_shaft_mass():
    """Sanity of the 'massless' shaft: a 100x denser shaft moves the tilt frequency more."""
    def tilt_error(density: float) -> float:
        mat = Material(density, 211e9, 81.783e9)
        shaft = uniform_shaft(L, 8, RI, RO, mat, shear_coefficient=1e9)
        f = eigen(pinned_pinned(Rotor(shaft, disks=[DISK])), 500.0, 4).frequencies
        return abs(f[3] / closed_form(500.0)[1] - 1.0)

    assert tilt_error(100.0) > 10.0 * tilt_error(1.0)
