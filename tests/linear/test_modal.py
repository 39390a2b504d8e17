"""Complex modes: damping ratio and log decrement against a damped oscillator, whirl."""

from __future__ import annotations

import numpy as np
import pytest
from linear_helpers import Constrained

from rotorsfd.errors import ConvergenceError
from rotorsfd.linear import LinearDynamics, eigen, log_decrement, mode_shapes, whirl_direction


class OneNode:
    """One node [y, z, ty, tz]: mass m on springs k (y, z) with dampers c, tilt J on kt."""

    n_dof = 4

    def __init__(self, m=2.0, k=8e4, c=16.0, j=0.01, kt=1e4, cyz=0.0):
        self.m, self.k, self.c, self.j, self.kt, self.cyz = m, k, c, j, kt, cyz

    def matrices(self, speed: float):
        mass = np.diag([self.m, self.m, self.j, self.j])
        damp = np.diag([self.c, self.c, 0.0, 0.0])
        damp[0, 1], damp[1, 0] = self.cyz, -self.cyz
        return mass, damp, np.diag([self.k, self.k, self.kt, self.kt])


def test_damping_ratio_and_log_decrement_of_damped_oscillator():
    s = OneNode()
    assert isinstance(s, LinearDynamics)
    wn = np.sqrt(s.k / s.m)
    zeta = s.c / (2 * np.sqrt(s.k * s.m))
    res = eigen(s, 0.0, 4)
    lam = res.eigenvalues[:2]
    np.testing.assert_allclose(lam, -zeta * wn + 1j * wn * np.sqrt(1 - zeta**2), rtol=1e-12)
    np.testing.assert_allclose(res.damping_ratios[:2], zeta, rtol=1e-12)
    np.testing.assert_allclose(res.log_decrements[:2], 2 * np.pi * zeta / np.sqrt(1 - zeta**2),
                               rtol=1e-12)
    np.testing.assert_allclose(log_decrement(s, 0.0, 2), res.log_decrements[:2])
    # undamped tilt modes: zero damping
    np.testing.assert_allclose(res.frequencies[2:], np.sqrt(s.kt / s.j), rtol=1e-12)
    assert np.all(np.abs(res.damping_ratios[2:]) < 1e-12)


def test_whirl_from_circulatory_coupling():
    """A skew velocity coupling c_yz (y'' + ... + cyz z' = ...) splits the pair into a
    forward and a backward circular mode: with D = [[c, g], [-g, c]] the forward mode
    (y + i z ~ exp(i w t)) has frequency shift -g/(2m), as the rotor's G with g = Omega Ip."""
    s = OneNode(c=0.0, cyz=40.0)
    res = eigen(s, 0.0, 2)
    shapes = mode_shapes(s, 0.0, 2)
    assert list(res.whirl) == ["backward", "forward"]
    assert res.frequencies[1] > res.frequencies[0]
    for j in range(2):
        y, z = shapes[0, j], shapes[1, j]
        circ = abs(abs(y) - abs(z)) / max(abs(y), abs(z))
        assert circ < 1e-9                           # circular orbits
    w0 = np.sqrt(s.k / s.m)
    g = s.cyz / s.m
    np.testing.assert_allclose(res.frequencies, [-g / 2 + np.hypot(w0, g / 2),
                                                 g / 2 + np.hypot(w0, g / 2)], rtol=1e-10)


def test_whirl_direction_rule():
    fwd = np.zeros(8, dtype=complex)
    fwd[4], fwd[5] = 1.0, -1j            # y = cos wt, z = sin wt at node 2: y -> z, forward
    assert whirl_direction(fwd) == "forward"
    assert whirl_direction(fwd.conj()) == "backward"
    ell = fwd.copy()
    ell[5] = -0.3j                       # elliptic, still forward
    assert whirl_direction(ell) == "forward"
    tilt = np.zeros(4, dtype=complex)
    tilt[3], tilt[2] = 1.0, 1j           # tz = cos, -ty = sin: slopes whirl forward
    assert whirl_direction(tilt) == "forward"


def test_isotropic_rotor_at_rest_gives_circular_pairs(paper):
    res = eigen(paper, 0.0, 6)
    assert list(res.whirl) == ["backward", "forward"] * 3
    np.testing.assert_allclose(res.frequencies[0::2], res.frequencies[1::2], rtol=1e-9)
    # mode shapes normalised: largest translation equals 1
    trans = np.abs(res.mode_shapes[np.r_[0:84:4, 1:84:4]])
    np.testing.assert_allclose(trans.max(axis=0), 1.0, rtol=1e-12)


def test_rigid_body_modes_dropped_and_singular_mass_reported():
    from rotorsfd.model import Material, Rotor, uniform_shaft

    free = Rotor(uniform_shaft(1.0, 6, 0.0, 0.02, Material(7810, 211e9, 81.783e9)))
    res = eigen(free, 0.0, 4)
    assert np.all(res.frequencies > 100.0)          # the 4 zero roots are not reported
    s = Constrained(OneNode(), [])
    s.matrices = lambda speed: (np.zeros((4, 4)), np.zeros((4, 4)), np.eye(4))
    with pytest.raises(ConvergenceError):
        eigen(s, 0.0)
