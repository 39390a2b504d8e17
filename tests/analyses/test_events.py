"""Transient events: a sudden unbalance (a blade loss) at a given time, at a constant speed
and under a coast-down speed law, against scipy's DOP853 of the same linear equations
written out by hand."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotors import linear_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.runup import run_speed_law
from rotorsfd.errors import ConfigError
from rotorsfd.model import dofs
from rotorsfd.model.unbalance import Unbalance
from rotorsfd.timedomain.speed_law import ConstantSpeed, RampSpeed

T_EVENT = 0.012
U_LOSS = 3e-4               # kg m: the lost blade's unbalance
PHASE = 0.7
RISE = 0.002                # s: the loss grows over 2 ms


@pytest.fixture(scope="module")
def system(tmp_path_factory):
    path = linear_rotor_toml(tmp_path_factory.mktemp("events") / "r.toml", unbalance="5 g*mm",
                             extra=f'\n[[unbalance]]\nnode = 3\nmagnitude = "{U_LOSS} kg*m"\n'
                                   f'phase = "{PHASE} rad"\nstart = "{T_EVENT} s"\n'
                                   f'rise_time = "{RISE * 1e3} ms"\n')
    return api.build_system(api.load_config(path))


def _reference(system, law, t_eval):
    """M q'' + (C + W(t) G) q' + (K - W'(t) P21) q = sum_u U_u h_u(t) [W^2 (cos, sin)
    + W' (sin, -cos)](theta + eta_u) at y, z of the unbalance's node, h_u the half-cosine
    rise from t_u over its rise time."""
    from rotorsfd.model.base_terms import base_basis

    r = system.rotor
    M, C, K, G = (np.asarray(x, float) for x in (r.M, r.C, r.K, r.G))
    b = base_basis(r)
    P21 = 0.5 * (b.matrix("PS") + b.matrix("PJ"))
    Minv = np.linalg.inv(M)

    def rhs(t, x):
        q, v = np.split(x, 2)
        W, dW, th = float(law.omega(t)), float(law.domega(t)), float(law.angle(t))
        f = np.zeros(r.n_dof)
        for u in system.unbalances:
            if t >= u.start:
                h = 1.0 if u.rise_time == 0 or t >= u.start + u.rise_time else \
                    np.sin(0.5 * np.pi * (t - u.start) / u.rise_time) ** 2
                phi = th + u.phase
                f[dofs.dof_index(u.node, "y")] += h * u.magnitude * (W**2 * np.cos(phi)
                                                                     + dW * np.sin(phi))
                f[dofs.dof_index(u.node, "z")] += h * u.magnitude * (W**2 * np.sin(phi)
                                                                     - dW * np.cos(phi))
        a = Minv @ (f - (C + W * G) @ v - (K - dW * P21) @ q)
        return np.concatenate([v, a])

    ev = np.sort(np.r_[t_eval, T_EVENT])
    sol = solve_ivp(rhs, (0.0, T_EVENT), np.zeros(2 * r.n_dof), method="DOP853", rtol=1e-9,
                    atol=1e-14, t_eval=ev[ev <= T_EVENT])
    sol2 = solve_ivp(rhs, (T_EVENT, t_eval[-1]), sol.y[:, -1], method="DOP853", rtol=1e-9,
                     atol=1e-14, t_eval=t_eval[t_eval > T_EVENT])
    y = np.concatenate([sol.y[:, :np.count_nonzero(t_eval <= T_EVENT)], sol2.y], axis=1)
    return y[: r.n_dof].T


def test_unbalance_config_and_bad_start(system):
    assert [u.start for u in system.unbalances] == [0.0, T_EVENT]
    assert system.unbalances[1].rise_time == pytest.approx(RISE)
    with pytest.raises(ConfigError, match=r"unbalance\.start"):
        Unbalance(3, 1e-4, 0.0, -1.0)


@pytest.mark.parametrize(("law", "order_ratio"),
                         [(ConstantSpeed(700.0), 3.0),
                          pytest.param(RampSpeed(700.0, 350.0, 0.03, t_start=T_EVENT), 2.5,
                                       marks=pytest.mark.slow)],
                         ids=["constant", "coast-down after the loss"])
def test_blade_loss_matches_solve_ivp(system, law, order_ratio):
    """The response to an unbalance appearing at t = 12 ms over 2 ms (a blade loss; then a
    coast-down at -11 700 rad/s^2 or none): Newmark at T/800 against DOP853 with the event
    as a break point, within 2e-3 of the response's peak, second order (4x from T/400;
    above 2.5x with the ramp, whose corner, W' jumping to the rate, is a step of the
    tangential force)."""
    rec = range(system.n_dof)
    runs = [run_speed_law(system, law, 0.04, steps_per_period=s, record_dofs=rec)
            for s in (400, 800)]
    ref = _reference(system, law, runs[1].t)
    peak = np.max(np.abs(ref))
    before = runs[1].t < T_EVENT
    after_peak = np.max(np.abs(ref[~before]))
    assert after_peak > 5 * np.max(np.abs(ref[before]))        # the loss dominates
    err_f = np.max(np.abs(runs[1].q - ref))
    err_c = np.max(np.abs(runs[0].q - ref[::2]))
    assert err_f < 2e-3 * peak
    assert order_ratio < err_c / err_f < 5.0, (err_c, err_f)


def test_constant_speed_simulate_sees_the_event(system):
    """The constant-speed inputs (``simulate`` at one speed) carry the event: equal to the
    speed-law run under a constant law (1e-12 of the peak)."""
    from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs

    W = 700.0
    inputs = time_domain_inputs(system, W)
    rec = list(range(system.n_dof))
    a = integrate_periods(inputs, 0.0, 0.0, steps_per_period=200, periods=5,
                          record_dofs=rec, record_periods=5, poincare_periods=1)
    b = run_speed_law(system, ConstantSpeed(W), 5 * 2 * np.pi / W, steps_per_period=200,
                      record_dofs=rec)
    n = min(a.q.shape[0], b.q.shape[0])
    scale = np.max(np.abs(b.q))
    assert np.max(np.abs(a.q[:n] - b.q[:n])) < 1e-10 * scale
