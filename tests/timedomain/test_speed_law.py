"""Speed laws Omega(t): consistency of Omega, dOmega/dt and theta = int Omega, and the terms
of a varying speed derived independently (the unbalance force as -m_u rho'' by finite
differences; the gyroscopic stiffness -Ip Omega' from the disk's Lagrangian with sympy)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import quad

from rotorsfd.errors import ConfigError
from rotorsfd.model.unbalance import Unbalance, unbalance_series_law
from rotorsfd.timedomain.speed_law import (
    CallableSpeed,
    ConstantSpeed,
    RampSpeed,
    TableSpeed,
    speed_range,
)

LAWS = {
    "ramp": RampSpeed(200.0, 450.0, 0.5, t_start=0.1),
    "coast": RampSpeed(450.0, 200.0, 0.4),
    "table": TableSpeed(np.array([0.0, 0.2, 0.5, 0.9]), np.array([300.0, 320.0, 500.0, 480.0])),
    "callable": CallableSpeed(lambda t: 300.0 + 50.0 * np.sin(3.0 * t)),
    "constant": ConstantSpeed(400.0),
}


@pytest.mark.parametrize("name", sorted(LAWS))
def test_angle_is_the_integral_and_domega_the_derivative(name):
    law = LAWS[name]
    t = np.array([0.0, 0.05, 0.137, 0.31, 0.77, 1.2])
    exact = np.array([quad(lambda s: float(law.omega(np.asarray(s))), 0.0, ti,
                           epsabs=0.0, epsrel=1e-12, limit=200)[0] for ti in t])
    np.testing.assert_allclose(law.angle(t), exact, rtol=1e-10, atol=1e-10)
    h = 1e-6
    ts = np.array([0.05, 0.137, 0.31, 0.77])        # away from a ramp's corners
    fd = (law.omega(ts + h) - law.omega(ts - h)) / (2 * h)
    np.testing.assert_allclose(law.domega(ts), fd, rtol=1e-6, atol=1e-4)


def test_ramp_rate_ends_and_range():
    law = LAWS["ramp"]
    assert law.rate == pytest.approx(500.0)
    np.testing.assert_allclose(law.omega(np.array([0.0, 0.1, 0.35, 0.6, 2.0])),
                               [200.0, 200.0, 325.0, 450.0, 450.0])
    np.testing.assert_allclose(law.domega(np.array([0.05, 0.3, 0.7])), [0.0, 500.0, 0.0])
    assert speed_range(law, 1.0) == (200.0, 450.0)
    assert speed_range(LAWS["table"], 0.9)[1] == pytest.approx(500.0)


@pytest.mark.parametrize("kw, field", [
    ({"start": -1.0, "stop": 10.0, "duration": 1.0}, "start"),
    ({"start": 1.0, "stop": 10.0, "duration": 0.0}, "duration"),
])
def test_bad_ramp_names_the_field(kw, field):
    with pytest.raises(ConfigError, match=field):
        RampSpeed(**kw)


def test_bad_table():
    with pytest.raises(ConfigError, match="times"):
        TableSpeed(np.array([0.0, 0.0]), np.array([1.0, 2.0]))
    with pytest.raises(ConfigError, match="speeds"):
        TableSpeed(np.array([0.0, 1.0]), np.array([1.0, -2.0]))


@pytest.mark.parametrize("name", ["ramp", "table", "callable"])
def test_unbalance_force_is_minus_mass_times_acceleration(name):
    """F = -m_u d^2/dt^2 [e (cos phi, sin phi)], phi = theta(t) + eta, by a 4th-order
    central difference of the position: the tangential term's sign and factor."""
    law = LAWS[name]
    U, eta = 3e-4, 0.7                        # m_u e [kg m]
    pairs = unbalance_series_law([Unbalance(1, U, eta)], 4, law)
    t = np.array([0.13, 0.29, 0.41, 0.66])
    h = 1e-4

    def rho(s):
        phi = law.angle(s) + eta
        return np.array([np.cos(phi), np.sin(phi)])

    acc = (-rho(t + 2 * h) + 16 * rho(t + h) - 30 * rho(t) + 16 * rho(t - h)
           - rho(t - 2 * h)) / (12 * h * h)
    F = np.array([sum(c(t) * vec[i] for c, vec in pairs) for i in (0, 1)])
    np.testing.assert_allclose(F, -U * acc, rtol=0, atol=2e-6 * U * 500.0**2)
    if name == "ramp":                         # the tangential term is there (on the ramp)
        radial = U * law.omega(t) ** 2 * rho(t)
        assert np.max(np.abs(F - radial)) > 0.5 * U * 500.0 * 1.0


def test_gyroscopic_stiffness_of_a_varying_spin_from_the_lagrangian():
    """Disk with tilts (ty, tz), spin angle phi(t): axial rate phi' - tz' sin(ty)
    (derivations/base_motion.py); the linearised Lagrange equations are
    Id ty'' + Ip phi' tz' = 0 and Id tz'' - Ip phi' ty' - Ip phi'' ty = 0, the
    -Ip Omega' (tz, ty) entry that runup.py adds as -Omega' (PS + PJ) / 2."""
    sp = pytest.importorskip("sympy")
    t = sp.symbols("t")
    Id, Ip, eps = sp.symbols("I_d I_p epsilon", positive=True)
    phi = sp.Function("phi")(t)
    a, b = sp.Function("a")(t), sp.Function("b")(t)          # ty, tz
    w1 = sp.diff(phi, t) - sp.diff(b, t) * sp.sin(a)
    w2 = sp.diff(a, t)
    w3 = sp.diff(b, t) * sp.cos(a)
    L = sp.Rational(1, 2) * (Ip * w1**2 + Id * (w2**2 + w3**2))
    eqs = []
    for q in (a, b):
        e = sp.diff(sp.diff(L, sp.diff(q, t)), t) - sp.diff(L, q)
        e = e.subs({a: eps * a, b: eps * b}).doit()
        eqs.append(sp.expand(sp.series(e, eps, 0, 2).removeO() / eps))
    Om, dOm = sp.diff(phi, t), sp.diff(phi, t, 2)
    expect_ty = Id * sp.diff(a, t, 2) + Ip * Om * sp.diff(b, t)
    expect_tz = Id * sp.diff(b, t, 2) - Ip * Om * sp.diff(a, t) - Ip * dOm * a
    assert sp.simplify(sp.expand(eqs[0]) - expect_ty) == 0
    assert sp.simplify(sp.expand(eqs[1]) - expect_tz) == 0
