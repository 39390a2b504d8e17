"""Rotor-level time-domain checks: the linear rotor against the frequency-domain solution,
convergence onto stable HB orbits, the static term under constant pitching, the
time-varying (harmonic) base path against the frozen-coefficient limit, contact."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.simulate import (
    hb_state,
    run_simulation,
    system_from_config,
    time_domain_inputs,
)
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.model.base_motion import BaseMotion, CallableLaw, Harmonic
from rotorsfd.model.base_terms import base_coefficients
from rotorsfd.model.dofs import dof_index
from rotorsfd.model.supports import LinearSupport
from rotorsfd.model.system import RotorSystem

C = 0.127e-3
REF = 800.0


def _system(tmp_path, unbalance: str = "50 g*mm", base: str = "", extra: str = "",
            overrides: tuple[str, ...] = ()) -> RotorSystem:
    config = api.load_config(small_rotor_toml(tmp_path / "small.toml", unbalance=unbalance,
                                              base=base, reference=f"{REF} rad/s",
                                              extra=extra), overrides)
    return system_from_config(config)


def _orbit(X: np.ndarray, speed: float, t: np.ndarray, dof: int) -> np.ndarray:
    """q_dof(t) = Re sum_k X_k exp(i k speed t)."""
    k = np.arange(X.shape[0])
    return (X[:, dof][None, :] * np.exp(1j * np.outer(t, k) * speed)).sum(axis=1).real


@pytest.mark.parametrize("scheme,alpha", [("newmark", 0.0), ("hht", 0.05),
                                          ("generalized-alpha", 0.9)])
def test_linear_rotor_matches_frequency_domain(tmp_path, scheme, alpha) -> None:
    """SFD replaced by its small-eps damper c = pi mu R L^3 / (2 C^3), no nonlinear DOF:
    from rest, the steady state equals (K - w^2 M + i w D)^-1 (F_c - i F_s) to 1e-4 of its
    amplitude (800 steps per period; the transient decays through the damper). The error
    is the schemes' O(h^2) phase error: 1.1e-4 at 400 steps, 2.7e-5 at 800."""
    sfd_sys = _system(tmp_path)
    c = sfd_sys.elements[0].film.linear_damping
    rotor = sfd_sys.rotor.with_supports([LinearSupport(1, 0.0, 0.0, cyy=c, czz=c)])
    system = RotorSystem(rotor, (), sfd_sys.unbalances)
    speed = 0.9 * REF
    res = run_simulation(system, speed, steps_per_period=800, periods=1500,
                         poincare_periods=20, record_periods=2, lyapunov_periods=0,
                         initial_displacement=0.0, scheme=scheme, alpha=alpha,
                         nodes=[1, 3], progress=False)
    M, D, K = system.matrices(speed)
    Fc, Fs = system.unbalance_harmonics(speed)
    X1 = np.linalg.solve(K - speed**2 * M + 1j * speed * D, Fc - 1j * Fs)
    X = np.array([np.zeros_like(X1), X1])
    for j, node in enumerate((1, 3)):
        for d, name in enumerate("yz"):
            exact = _orbit(X, speed, res.t, dof_index(node, name))
            amp = np.abs(X1[dof_index(node, name)])
            err = np.max(np.abs(res.q[:, j, d] - exact)) / amp
            assert err < 1e-4, (scheme, node, name, err)
    assert res.motion.motion == "period-1"
    assert res.max_eccentricity is None


@pytest.mark.parametrize("ratio,eps_min", [(0.9, 0.05), (1.05, 0.5), (1.3, 0.05)])
def test_converges_onto_stable_hb_orbit(tmp_path, ratio, eps_min) -> None:
    """Small rotor with its SFD, U = 100 g mm (HB folds at Omega~ 1.094-1.098), speeds
    away from the folds (1.05: eps ~ 0.62, strongly nonlinear): started from the HB orbit
    (H = 8) displaced by 0.05 C at the journal, the integration returns to it:
    |q - q_HB| < 1e-3 C over the last period at the journal and the disk, compared at the
    same times."""
    system = _system(tmp_path, unbalance="100 g*mm")
    speed = ratio * REF
    sol = solve_periodic(system.periodic_problem(), speed, 8)
    q0, v0 = hb_state(sol.X, speed)
    q0[dof_index(1, "y")] += 0.05 * C
    res = run_simulation(system, speed, steps_per_period=400, periods=400,
                         poincare_periods=20, record_periods=1, lyapunov_periods=0,
                         q0=q0, v0=v0, nodes=[1, 3], progress=False)
    for j, node in enumerate((1, 3)):
        for d, name in enumerate("yz"):
            hb = _orbit(sol.X, speed, res.t, dof_index(node, name))
            assert np.max(np.abs(res.q[:, j, d] - hb)) < 1e-3 * C
    assert res.motion.motion == "period-1"
    assert eps_min < res.max_eccentricity < 1.0


def test_constant_pitching_mean_position_is_hb_static_term(tmp_path) -> None:
    """Constant pitching 10 rad/s (gyroscopic moment, base terms): the journal position
    averaged over the last period equals the HB static term X_0 to 1e-3 C; the same run
    through the time-varying path (a callable constant law) agrees to 1e-9 C."""
    system = _system(tmp_path, base='pitching = { law = "constant", value = "10 rad/s" }')
    speed = 0.8 * REF
    sol = solve_periodic(system.periodic_problem(), speed, 8)
    kw = dict(steps_per_period=200, periods=300, poincare_periods=10, record_periods=1,
              lyapunov_periods=0, nodes=[1], progress=False)
    res = run_simulation(system, speed, **kw)
    mean = res.q[:-1, 0, :].mean(axis=0)             # one whole period, end excluded
    X0 = sol.X[0, [dof_index(1, "y"), dof_index(1, "z")]].real
    assert np.max(np.abs(X0)) > 0.05 * C             # the offset is not trivial
    np.testing.assert_allclose(mean, X0, atol=1e-3 * C, rtol=0)

    tv = RotorSystem(system.rotor, system.elements, system.unbalances,
                     BaseMotion(wy=CallableLaw(lambda t: 10.0 + 0.0 * np.asarray(t))))
    assert not tv.base.is_constant
    inputs = time_domain_inputs(tv, speed)
    assert inputs.time_varying is None or inputs.time_varying.n_terms == 0  # folded
    res_tv = run_simulation(tv, speed, **kw)
    np.testing.assert_allclose(res_tv.q, res.q, atol=1e-9 * C, rtol=0)


def test_harmonic_pitching_follows_frozen_coefficients(tmp_path) -> None:
    """Slow harmonic pitching w_by = 10 sin(2 t) rad/s, no unbalance, with the SFD: the
    time-varying matrices (K_base(t), C_base(t)) and loads run, and the journal follows
    the frozen-coefficient static solution (K + K_base(t)) q = F_base(t) to 2e-3 of its
    peak (the dynamic corrections are O(w_b/w_n) and c w_b / k ~ 1e-4)."""
    sfd_sys = _system(tmp_path)
    base = BaseMotion(wy=Harmonic(mean=0.0, amplitude=10.0, frequency=2.0))
    system = RotorSystem(sfd_sys.rotor, sfd_sys.elements, (), base)
    speed = 0.75 * REF
    inputs = time_domain_inputs(system, speed)
    assert inputs.time_varying is not None and inputs.time_varying.n_terms > 0
    T_base = 2 * math.pi / 2.0
    n_per = math.ceil(T_base / (2 * math.pi / speed))
    basis = system.basis
    st0 = base.state(0.0)
    _, K_b, F_b = basis.combine(base_coefficients(st0, speed))
    q0 = np.linalg.solve(system.rotor.K + K_b, F_b)
    res = run_simulation(system, speed, steps_per_period=50, periods=n_per,
                         poincare_periods=10, record_periods=n_per, lyapunov_periods=0,
                         q0=q0, v0=np.zeros_like(q0), nodes=[1], progress=False)
    t = res.t[::25]
    st = base.state(t)
    co = base_coefficients(st, speed)
    iy, iz = dof_index(1, "y"), dof_index(1, "z")
    frozen = []
    for i in range(t.size):
        one = type(co)(co.c_C[:, i], co.c_K[:, i], co.c_F[:, i])
        _, K_b, F_b = basis.combine(one)
        q = np.linalg.solve(system.rotor.K + K_b, F_b)
        frozen.append(q[[iy, iz]])
    frozen = np.array(frozen)
    peak = np.max(np.abs(frozen))
    assert peak > 0.02 * C
    err = np.max(np.abs(res.q[::25, 0, :] - frozen))
    assert err < 2e-3 * peak, err / peak           # measured: 1.5e-4 of 0.49 C


def test_contact_ends_the_run_with_time_period_and_eccentricity(tmp_path) -> None:
    """The squeeze film alone keeps eps < 1 (its force is unbounded there); with a
    contact limit eps_max = 0.9 and U = 1000 g mm at resonance (steady eps ~ 0.96 without
    the limit) the run ends at the limit as a result (issue 22 item 3): ``ended`` is
    "limit", the message says where (time, rotor period) and why (eps at the limit) in
    one line, the recorded periods are the ones just before the contact (their eps below
    the limit and rising to it), and the files carry ``ended``."""
    import xarray as xr

    from rotorsfd.elements.sfd import SFDElement
    from rotorsfd.model.sfd import SFD

    base = _system(tmp_path, unbalance="1000 g*mm")
    e = base.elements[0]
    f = e.film
    sfd = SFD(f.viscosity, f.radius, f.length, f.clearance, f.cavitation, eps_max=0.9)
    system = RotorSystem(base.rotor, [SFDElement("sfd", e.node, sfd)], base.unbalances)
    res = run_simulation(system, 1.0 * REF, steps_per_period=200, periods=200,
                         poincare_periods=10, lyapunov_periods=0, progress=False)
    assert res.ended == "limit" and res.motion_name == "contact"
    msg = res.message
    assert "\n" not in msg and "rotor period" in msg and "t=" in msg
    eps = float(msg.split("eps=")[1].split()[0])
    assert 0.89 <= eps <= 0.95
    period = float(msg.split("rotor period ")[1].split()[0])
    assert 0 < period < 200
    assert res.settings["periods_run"] == int(period)
    # the last 10 periods before the contact, up to the last converged step
    T = 2 * np.pi / REF
    assert res.t.size > 0 and res.t[-1] == pytest.approx(res.t_final, abs=1e-12)
    assert res.t[-1] - res.t[0] == pytest.approx(min(10 * T, res.t_final), rel=1e-9)
    j = res.nodes.index(res.element_node)
    radius = np.hypot(res.q[:, j, 0], res.q[:, j, 1]) / res.clearance
    assert radius.max() < 0.9 and radius[-1] > 0.8
    assert res.max_eccentricity == pytest.approx(radius.max(), rel=1e-12)
    res.write(tmp_path / "out")
    summary = json.loads((tmp_path / "out" / "summary.json").read_text())
    assert summary["ended"] == "limit" and summary["outcome"] == msg
    with xr.open_dataset(tmp_path / "out" / "timeseries.nc") as ds:
        assert ds.attrs["ended"] == "limit" and "eps=" in ds.attrs["outcome"]
        np.testing.assert_allclose(ds["final_displacement"].values, res.q_final)


def test_gravity_settles_on_the_static_deflection(tmp_path) -> None:
    """Gravity enters through the base state (F_base = -m a_eff, a_eff = -g): without
    unbalance the journal settles at K^-1 F_base (the film carries no static load)."""
    system = _system(tmp_path, unbalance="0 g*mm", extra="\n[gravity]\nenabled = true\n")
    speed = 0.8 * REF
    res = run_simulation(system, speed, steps_per_period=100, periods=400,
                         poincare_periods=10, record_periods=1, lyapunov_periods=0,
                         nodes=[1, 3], progress=False)
    q_static = np.linalg.solve(system.matrices(speed)[2], system.static_force(speed))
    for j, node in enumerate((1, 3)):
        expect = q_static[[dof_index(node, "y"), dof_index(node, "z")]]
        assert expect[1] < -0.05 * C                 # it sags
        np.testing.assert_allclose(res.q[-1, j], expect, atol=1e-3 * C, rtol=0)


def test_harmonic_base_from_config_runs(tmp_path) -> None:
    """A harmonic pitching law from the config file goes through the time-varying path
    (K_base(t), C_base(t), F_base(t), unbalance with the base-rotation terms); base
    frequency incommensurate with the speed: quasi-periodic, a line at w_b / Omega."""
    config = api.load_config(small_rotor_toml(
        tmp_path / "small.toml", unbalance="50 g*mm", reference=f"{REF} rad/s",
        base='pitching = { law = "harmonic", amplitude = "5 rad/s", '
             'frequency = "56.5685 rad/s" }'))
    res = run_simulation(config, speed_ratio=0.9, steps_per_period=100, periods=200,
                         poincare_periods=40, lyapunov_periods=20, progress=False)
    assert res.settings["time_varying_matrices"]
    assert res.motion.motion == "quasi-periodic"   # base and rotor incommensurate
    ratios = np.array(res.motion.evidence["frequency_ratios"])
    assert np.min(np.abs(ratios - 56.5685 / 720.0)) < 2e-3   # the base frequency line
    assert 0.0 < res.max_eccentricity < 1.0
