"""Basis x coefficient decomposition: derivatives, time vectorisation; unbalance force."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.model import dof_index
from rotorsfd.model.base_motion import BaseMotion, BaseState, Harmonic
from rotorsfd.model.base_terms import (
    RATE_NAMES,
    assemble_base,
    base_basis,
    base_coefficient_derivatives,
    base_coefficients,
    disk_base_terms,
    shaft_base_terms,
)
from rotorsfd.model.unbalance import (
    Unbalance,
    unbalance_force,
    unbalance_harmonics,
    unbalance_harmonics_derivatives,
)

RNG = np.random.default_rng(3)


def _state(p: dict) -> BaseState:
    return BaseState(w=np.array([p["wx"], p["wy"], p["wz"]]),
                     dw=np.array([p["dwx"], p["dwy"], p["dwz"]]),
                     a0=np.array([0.3, p["ay"], p["az"]]))


def test_coefficient_derivatives_match_finite_differences():
    p = dict(zip(RATE_NAMES, RNG.normal(size=len(RATE_NAMES)) * 3, strict=True))
    p["speed"] = 420.0
    ders = base_coefficient_derivatives(_state(p), p["speed"])
    for name in RATE_NAMES:
        h = 1e-6 * max(1.0, abs(p[name]))
        hi, lo = dict(p), dict(p)
        hi[name] += h
        lo[name] -= h
        c_hi = base_coefficients(_state(hi), hi["speed"])
        c_lo = base_coefficients(_state(lo), lo["speed"])
        for attr in ("c_C", "c_K", "c_F"):
            fd = (getattr(c_hi, attr) - getattr(c_lo, attr)) / (2 * h)
            np.testing.assert_allclose(getattr(ders[name], attr), fd, atol=1e-6, err_msg=name)


def test_time_vectorised_coefficients_and_shaft_kernel(rotor):
    motion = BaseMotion(wx=0.5, wy=Harmonic(2.0, 9.0), z0=Harmonic(1e-3, 50.0))
    t = np.linspace(0.0, 0.4, 5)
    basis = base_basis(rotor)
    co = base_coefficients(motion.state(t), 300.0)
    assert co.c_K.shape == (12, t.size)
    F_all = np.tensordot(basis.vectors, co.c_F, axes=(0, 0))
    for i, ti in enumerate(t):
        _, K, F = assemble_base(rotor, motion.state(ti), 300.0, basis)
        np.testing.assert_allclose(F_all[:, i], F, rtol=1e-13, atol=1e-14)
        np.testing.assert_allclose(np.tensordot(co.c_K[:, i], basis.matrices, axes=(0, 0)), K)
    # element and disk kernels == the assembly of a one-element rotor with a disk at node 2
    from rotorsfd.model import Rotor

    el, d = rotor.shaft_elements[0], rotor.disks[0]
    one = Rotor([el], disks=[type(d)(2, d.mass, d.polar_inertia, d.diametral_inertia)],
                x_start=0.25)
    st = motion.state(0.1)
    Ce, Ke, Fe = shaft_base_terms(el, 0.25, st, 300.0)
    Cd, Kd, Fd = disk_base_terms(d, 0.25 + el.length, st, 300.0)
    Ce[4:, 4:] += Cd
    Ke[4:, 4:] += Kd
    Fe[4:] += Fd
    for got, want in zip(assemble_base(one, st, 300.0), (Ce, Ke, Fe), strict=True):
        np.testing.assert_allclose(got, want, rtol=1e-14, atol=1e-14 * np.abs(want).max())


def test_patterns_consistent_with_mass_matrix(rotor):
    basis = base_basis(rotor)
    M_t = basis.matrix("T11") + basis.matrix("T22")
    M_r = basis.matrix("D11") + basis.matrix("D22")
    np.testing.assert_allclose(M_t + M_r, rotor.M, atol=1e-14 * np.abs(rotor.M).max())
    np.testing.assert_allclose(basis.matrix("PJ"), -rotor.G, atol=1e-16)
    for name in ("TJ", "PJ", "DJ"):
        np.testing.assert_allclose(basis.matrix(name), -basis.matrix(name).T, atol=1e-16)


def test_unbalance_fixed_base_and_harmonics(rotor):
    unb = [Unbalance(3, 1.44e-4, 0.3), Unbalance(5, 0.7e-4, 2.0)]
    om = 811.3
    t = np.linspace(0, 0.01, 7)
    F = unbalance_force(unb, rotor, om, None, t)
    iy, iz = dof_index(3, "y"), dof_index(3, "z")
    np.testing.assert_allclose(F[iy], 1.44e-4 * om**2 * np.cos(om * t + 0.3), rtol=1e-14)
    np.testing.assert_allclose(F[iz], 1.44e-4 * om**2 * np.sin(om * t + 0.3), rtol=1e-14)
    st = BaseState.constant(w=(1.5, -3.0, 2.0))
    Fc, Fs = unbalance_harmonics(unb, rotor, om, st)
    F = unbalance_force(unb, rotor, om, st, t)
    np.testing.assert_allclose(F, np.outer(Fc, np.cos(om * t)) + np.outer(Fs, np.sin(om * t)),
                               atol=1e-12 * np.abs(F).max())


def test_unbalance_time_varying_rates_use_state_at_t(rotor):
    motion = BaseMotion(wx=Harmonic(3.0, 7.0), wy=Harmonic(2.0, 5.0, 0.4))
    unb = [Unbalance(3, 2e-4, 0.0)]
    t = np.linspace(0, 1, 9)
    F = unbalance_force(unb, rotor, 500.0, motion.state(t), t)
    for i in (0, 4, 8):
        Fi = unbalance_force(unb, rotor, 500.0, motion.state(t[i]), t[i])
        np.testing.assert_allclose(F[:, i], Fi, rtol=1e-14)


def test_unbalance_harmonic_derivatives(rotor):
    unb = [Unbalance(3, 1e-4, 0.7)]
    p = {"speed": 600.0, "wx": 1.2, "wy": -2.5, "wz": 0.8, "dwx": 0.4}

    def harm(q):
        st = BaseState(w=np.array([q["wx"], q["wy"], q["wz"]]),
                       dw=np.array([q["dwx"], 0.0, 0.0]), a0=np.zeros(3))
        return unbalance_harmonics(unb, rotor, q["speed"], st)

    st = BaseState(w=np.array([p["wx"], p["wy"], p["wz"]]), dw=np.array([p["dwx"], 0, 0]),
                   a0=np.zeros(3))
    ders = unbalance_harmonics_derivatives(unb, rotor, p["speed"], st)
    for name in p:
        h = 1e-5
        hi, lo = dict(p), dict(p)
        hi[name] += h
        lo[name] -= h
        for k in range(2):
            fd = (harm(hi)[k] - harm(lo)[k]) / (2 * h)
            np.testing.assert_allclose(ders[name][k], fd, atol=1e-8, err_msg=name)
        # one derivative alone (what the HB's dforcing asks for) is the same numbers
        one = unbalance_harmonics_derivatives(unb, rotor, p["speed"], st, only=name)
        assert list(one) == [name]
        for k in range(2):
            assert np.array_equal(one[name][k], ders[name][k])


def test_unbalance_validation():
    from rotorsfd.errors import ConfigError

    with pytest.raises(ConfigError):
        Unbalance(0, 1e-4)
    with pytest.raises(ConfigError):
        Unbalance(2, -1.0)


def test_time_varying_terms_and_unbalance_series(rotor):
    from rotorsfd.model.base_terms import time_varying_terms
    from rotorsfd.model.unbalance import unbalance_series

    motion = BaseMotion(wy=Harmonic(2.0, 9.0, 0.2), z0=Harmonic(1e-3, 50.0))
    basis = base_basis(rotor)
    damping, stiffness, force = time_varying_terms(basis, motion, 400.0)
    assert len(damping) == 0  # no rolling: no Coriolis matrix
    t = np.linspace(0.0, 0.3, 4)
    for i, ti in enumerate(t):
        _, K, F = assemble_base(rotor, motion.state(ti), 400.0, basis)
        K_s = sum(c(t)[i] * A for c, A in stiffness)
        F_s = sum(c(t)[i] * f for c, f in force)
        np.testing.assert_allclose(K_s, K, atol=1e-12 * np.abs(K).max())
        np.testing.assert_allclose(F_s, F, atol=1e-12 * np.abs(F).max())
    unb = [Unbalance(3, 1e-4, 0.5)]
    series = unbalance_series(unb, rotor, 400.0, motion)
    F_u = sum(np.outer(v, c(t)) for c, v in series)
    np.testing.assert_allclose(F_u, unbalance_force(unb, rotor, 400.0, motion.state(t), t),
                               rtol=1e-14, atol=1e-14)
    assert time_varying_terms(basis, BaseMotion(), 400.0) == ([], [], [])
