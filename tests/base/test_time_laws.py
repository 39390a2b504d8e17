"""Time laws, base state and gravity in the rotating base frame."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.model.base_motion import (
    BaseMotion,
    CallableLaw,
    Constant,
    Harmonic,
    Off,
    UniformAcceleration,
    numerical_derivative,
)
from rotorsfd.model.gravity import Gravity, gravity_in_base, rotate_constant_rate

T = np.linspace(-0.7, 2.3, 11)


def _fd(f, t, h=1e-5):
    return (f(t + h) - f(t - h)) / (2 * h)


@pytest.mark.parametrize("law", [
    Harmonic(0.3, 7.0, 0.4), Harmonic(2.0, 1.5, -1.0, mean=0.5),
    UniformAcceleration(2.0, -1.0, 3.0),
    Constant(4.0), Off(),
    CallableLaw(lambda t: np.sin(3 * t) * np.exp(-t)),
    CallableLaw(lambda t: np.sin(3 * t) * np.exp(-t), df=lambda t: np.exp(-t) * (
        3 * np.cos(3 * t) - np.sin(3 * t))),
])
def test_law_derivatives_match_finite_differences(law):
    np.testing.assert_allclose(law.d1(T), _fd(law.value, T), rtol=1e-8, atol=1e-8)
    np.testing.assert_allclose(law.d2(T), _fd(law.d1, T), rtol=1e-6, atol=1e-6)
    assert law.value(T).shape == T.shape and law.d2(0.3).shape == ()


def test_paper_harmonic_pitching_law():
    a0, wb = 0.02, 40.0
    law = Harmonic(a0 * wb, wb)  # w_by = A0 w_b sin(w_b t)
    t = 0.013
    assert law.value(t) == pytest.approx(a0 * wb * np.sin(wb * t), rel=1e-15)
    assert law.d1(t) == pytest.approx(a0 * wb**2 * np.cos(wb * t), rel=1e-15)


def test_complex_step_and_central_difference_fallback():
    f = lambda t: np.cos(2 * t) ** 3  # noqa: E731
    exact = -6 * np.cos(2 * T) ** 2 * np.sin(2 * T)
    np.testing.assert_allclose(numerical_derivative(f, T), exact, rtol=1e-14, atol=1e-14)
    g = lambda t: float(np.cos(2 * t) ** 3)  # noqa: E731  scalar only, real only
    assert CallableLaw(g).d1(0.4) == pytest.approx(-6 * np.cos(0.8) ** 2 * np.sin(0.8), rel=1e-8)


def test_state_shapes_and_origin_acceleration():
    motion = BaseMotion(x0=Harmonic(1e-3, 30.0), y0=UniformAcceleration(0.5, 1.0),
                        z0=Harmonic(2e-3, 20.0, 0.3), wx=0.7, wy=Harmonic(0.2, 5.0),
                        wz=lambda t: 0.1 * t)
    st = motion.state(T)
    for field in (st.w, st.dw, st.a0, st.v0, st.g):
        assert field.shape == (3, T.size)
    i = 4
    s1 = motion.state(T[i])
    w, v = s1.w, s1.v0
    dv = np.array([law.d2(T[i]) for law in motion.translation])
    np.testing.assert_allclose(s1.a0, dv + np.cross(w, v), rtol=1e-14)
    np.testing.assert_allclose(st.a0[:, i], s1.a0, rtol=1e-14)
    np.testing.assert_allclose(st.dw[2], 0.1, rtol=1e-8)
    assert not motion.is_constant


def test_is_constant():
    assert BaseMotion(wy=4.0).is_constant
    assert BaseMotion(wx=1.0, wy=2.0, wz=3.0, z0=UniformAcceleration(0.0, 2.0)).is_constant
    assert BaseMotion(z0=UniformAcceleration(1.0)).is_constant
    assert not BaseMotion(wy=1.0, z0=UniformAcceleration(1.0)).is_constant
    assert not BaseMotion(wy=Harmonic(1.0, 2.0)).is_constant
    assert not BaseMotion(wy=1.0, gravity=Gravity()).is_constant
    assert BaseMotion(wy=1.0, gravity=Gravity(frame="base")).is_constant
    assert BaseMotion(wz=1.0, gravity=Gravity()).is_constant  # w parallel to g
    with pytest.raises(ConfigError):
        BaseMotion(wy="fast")


def test_gravity_constant_rate_closed_form():
    g = Gravity(9.81, (0.0, 0.0, -1.0))
    w = np.array([0.0, 2.0, 0.0])
    gt = rotate_constant_rate(g.vector, w, np.array([0.0, np.pi / 4]))
    np.testing.assert_allclose(gt[:, 1], [9.81, 0.0, 0.0], atol=1e-14)  # pitched nose-down
    # satisfies dg/dt = -w x g
    t = 0.37
    gt = lambda tt: rotate_constant_rate(g.vector, w, tt)  # noqa: E731
    dg = (gt(t + 1e-6) - gt(t - 1e-6)) / 2e-6
    np.testing.assert_allclose(dg, -np.cross(w, rotate_constant_rate(g.vector, w, t)), atol=1e-7)


def test_gravity_integrated_attitude_matches_fixed_axis_rotation():
    """w = (0, A sin(wb t), 0): rotation about fixed y by theta = A/wb (1 - cos wb t)."""
    amp, wb = 0.8, 6.0
    motion = BaseMotion(wy=Harmonic(amp, wb), gravity=Gravity(9.81))
    t = np.array([-0.4, 0.0, 0.3, 1.1, 2.0])
    gb = motion.state(t).g
    th = amp / wb * (1 - np.cos(wb * t))
    exact = 9.81 * np.array([np.sin(th), 0 * th, -np.cos(th)])
    np.testing.assert_allclose(gb, exact, atol=1e-8)
    # base-fixed approximation keeps g constant
    gb_fixed = BaseMotion(wy=Harmonic(amp, wb), gravity=Gravity(9.81, frame="base")).state(t).g
    np.testing.assert_allclose(gb_fixed, np.outer([0, 0, -9.81], np.ones(t.size)))
    # scalar t and gravity off
    assert gravity_in_base(Gravity(enabled=False), motion.rates, 0.5).shape == (3,)
    assert not motion.is_fixed and BaseMotion(gravity=Gravity(enabled=False)).is_fixed
