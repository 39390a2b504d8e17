"""Run-up through a critical speed under a speed law: the Newmark run against an
independent scipy solve_ivp (DOP853, rtol 1e-11) integration of the hand-written
equations of a disk on springs (Jeffcott with tilt: the gyroscopic Omega(t) G and the
-Ip Omega' stiffness are exercised), and the assembled inputs of a real rotor."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.runup import run_speed_law, speed_law_inputs
from rotorsfd.analyses.td_integration import TimeDomainInputs, time_domain_inputs
from rotorsfd.model.base_terms import base_basis
from rotorsfd.model.unbalance import Unbalance, unbalance_series_law
from rotorsfd.timedomain import Forcing, TimeVaryingMatrices
from rotorsfd.timedomain.speed_law import ConstantSpeed, RampSpeed

# disk on springs: y, z, ty, tz (node 1); omega_n = sqrt(k/m) = 316 rad/s, zeta = 0.02
m, k, Id, Ip, kt, kc = 10.0, 1.0e6, 0.05, 0.09, 2.0e4, 3.0e4
c = 2 * 0.02 * np.sqrt(k * m)
ct = 2 * 0.02 * np.sqrt(kt * Id)
U = 1e-4                                     # m_u e [kg m]
LAW = RampSpeed(200.0, 450.0, 0.5)           # Omega' = 500 rad/s^2 = 5e-3 omega_n^2
T_END = 0.5


def _matrices():
    M = np.diag([m, m, Id, Id])
    C = np.diag([c, c, ct, ct])
    K = np.array([[k, 0, 0, kc], [0, k, -kc, 0], [0, -kc, kt, 0], [kc, 0, 0, kt]], float)
    G = np.zeros((4, 4))
    G[2, 3], G[3, 2] = Ip, -Ip                # D(ty, tz) = +Ip Omega
    P21 = np.zeros((4, 4))
    P21[3, 2] = Ip                            # K(tz, ty) = -Ip Omega'
    return M, C, K, G, P21


def _inputs() -> TimeDomainInputs:
    M, C, K, G, P21 = _matrices()
    series = unbalance_series_law([Unbalance(1, U)], 4, LAW)
    tv = TimeVaryingMatrices(damping=[(LAW.omega, G)],
                             stiffness=[(lambda t: -LAW.domega(t), P21)])
    return TimeDomainInputs(M, C, K, np.zeros(0, np.int64), None, None,
                            Forcing(omega=450.0, series=series), tv, 450.0)


def _reference(t_eval: np.ndarray) -> np.ndarray:
    """The same equations written out: m y'' + c y' + k y + kc tz = U (W^2 cos + W' sin),
    ..., Id tz'' + ct tz' + kt tz + kc y - Ip W ty' - Ip W' ty = 0."""
    M, C, K, G, P21 = _matrices()
    Minv = np.linalg.inv(M)

    def rhs(t, x):
        q, v = x[:4], x[4:]
        W, dW, th = float(LAW.omega(t)), float(LAW.domega(t)), float(LAW.angle(t))
        f = np.array([U * (W**2 * np.cos(th) + dW * np.sin(th)),
                      U * (W**2 * np.sin(th) - dW * np.cos(th)), 0.0, 0.0])
        a = Minv @ (f - (C + W * G) @ v - (K - dW * P21) @ q)
        return np.concatenate([v, a])

    sol = solve_ivp(rhs, (0.0, t_eval[-1]), np.zeros(8), method="DOP853", rtol=1e-11,
                    atol=1e-16, t_eval=t_eval)
    assert sol.success
    return sol.y[:4].T


@pytest.fixture(scope="module")
def runs():
    inputs = _inputs()
    return [run_speed_law(None, LAW, T_END, steps_per_period=spp, record_dofs=range(4),
                          inputs=inputs) for spp in (400, 800)]


def test_newmark_runup_matches_solve_ivp(runs):
    """Second order (error ratio ~4 from one halving) and, Richardson-extrapolated,
    within 1e-6 of the largest amplitude of the reference (y, z and the tilts)."""
    coarse, fine = runs
    ref_f = _reference(fine.t)
    ref_c = ref_f[::2]
    np.testing.assert_allclose(fine.t[::2], coarse.t, rtol=0, atol=1e-12)
    scale = np.max(np.abs(ref_f), axis=0)
    err_c = np.max(np.abs(coarse.q - ref_c), axis=0) / scale
    err_f = np.max(np.abs(fine.q - ref_f), axis=0) / scale
    assert np.all(err_f < 1e-3)
    assert np.all((err_c / err_f > 3.5) & (err_c / err_f < 4.5)), (err_c, err_f)
    rich = (4.0 * fine.q[::2] - coarse.q) / 3.0
    err_r = np.max(np.abs(rich - ref_c), axis=0) / scale
    assert np.all(err_r < 1e-6), err_r


def test_runup_peak_is_lower_and_later_than_the_steady_one(runs):
    """Physics of a run-up (Lewis 1932): the passage peak is below the steady resonance
    peak and lags past the critical speed; the tangential force and the tilt terms are
    in the run (against a run without them the orbit differs)."""
    fine = runs[1]
    r = np.hypot(fine.q[:, 0], fine.q[:, 1])
    i = int(np.argmax(r))
    # steady 1X amplitude of the translational mode on the same model, at every speed
    M, C, K, G, _ = _matrices()
    w = np.linspace(200.0, 450.0, 2001)
    amp = []
    for W in w:
        A = -W**2 * M + 1j * W * (C + W * G) + K
        f = U * W**2 * np.array([1.0, -1j, 0.0, 0.0])      # (cos, sin) as a forward whirl
        amp.append(abs(np.linalg.solve(A, f)[0]))
    amp = np.array(amp)
    assert r[i] < 0.95 * amp.max()
    assert fine.omega[i] > w[np.argmax(amp)] + 2.0
    assert fine.t[-1] >= T_END - 1e-12                  # whole periods of the top speed
    assert fine.theta[-1] == pytest.approx(float(LAW.angle(fine.t[-1])), rel=1e-12)


@pytest.fixture(scope="module")
def small_system(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("runup")
    cfg = api.load_config(small_rotor_toml(
        tmp / "r.toml", base='pitching = { law = "constant", value = "6 rad/s" }'))
    return api.build_system(cfg)


def test_constant_law_inputs_equal_the_constant_speed_ones(small_system):
    """Under a constant law the speed-law inputs are those of time_domain_inputs at that
    speed (base rate 6 rad/s pitching: the base terms and the unbalance with them)."""
    W = 700.0
    a = speed_law_inputs(small_system, ConstantSpeed(W), 0.1)
    b = time_domain_inputs(small_system, W)
    t = np.linspace(0.0, 0.05, 37)

    def total(x, attr):
        base = getattr(x, attr).copy()
        pairs = [] if x.time_varying is None else getattr(
            x.time_varying, "damping" if attr == "D" else "stiffness")
        return [base + sum(np.asarray(cf(np.array([ti])))[0] * X for cf, X in pairs)
                for ti in t]

    for attr in ("D", "K"):
        for da, db in zip(total(a, attr), total(b, attr), strict=True):
            np.testing.assert_allclose(da, db, rtol=1e-12, atol=1e-9 * np.abs(db).max())
    fa, fb = a.forcing.at(t, a.n_dof), b.forcing.at(t, b.n_dof)
    np.testing.assert_allclose(fa, fb, rtol=1e-10, atol=1e-10 * np.abs(fb).max())


def test_varying_spin_stiffness_pattern(small_system):
    """P21 = (PS + PJ)/2 = int Ip N_tz^T N_ty dx (+ the disk's Ip on (tz, ty)):
    P21 - P21^T = PJ = -G (a Timoshenko shaft's rotation field involves the nodal
    translations too, so P21 is not confined to the rotation DOFs)."""
    basis = base_basis(small_system.rotor)
    P21 = 0.5 * (basis.matrix("PS") + basis.matrix("PJ"))
    G = np.asarray(small_system.rotor.G, float)
    np.testing.assert_allclose(P21 - P21.T, -G, atol=1e-12 * np.abs(G).max())
    ip_disk = 0.5 * 7810.0 * np.pi * 0.1**2 * 0.04 * 0.1**2     # the disk at node 3
    assert P21[4 * 2 + 3, 4 * 2 + 2] == pytest.approx(ip_disk, rel=0.05)
    assert P21[4 * 2 + 2, 4 * 2 + 3] == 0.0                       # only at (tz, ty)
