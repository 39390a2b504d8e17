"""A flexible rotor on two journal bearings (examples/journal_bearing_rotor.toml) through the
analyses: the oil-whirl onset that `response` locates (a Hopf of the balanced rotor's
equilibrium, by HB + Floquet on the reduced model) against the linear threshold of the
full linearised rotor (eigenvalues of the state matrix with the bearings' stiffness and
damping at the equilibrium: a second method)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import brentq

from rotorsfd.analyses.response import run_response
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.io.config import config_from_dict, read_toml
from rotorsfd.model.build import build_system

EXAMPLE = Path(__file__).parents[2] / "examples" / "journal_bearing_rotor.toml"


def balanced_config():
    raw = read_toml(EXAMPLE)
    raw.pop("unbalance")
    raw["analysis"]["response"]["speed_range"] = {"start": "600 rad/s",
                                                  "stop": "1300 rad/s"}
    return config_from_dict(raw)


@pytest.fixture(scope="module")
def response():
    return run_response(balanced_config(), progress=False)


def linear_growth(system, problem, speed: float, X: list) -> float:
    """Largest real part of the eigenvalues of the rotor linearised at its equilibrium at
    ``speed``: ``M s^2 + (D + C_b) s + (K + K_b)``, ``K_b = -dF/dq``, ``C_b = -dF/dv``."""
    sol = solve_periodic(problem, speed, 1, X[0], tol=1e-12)
    X[0] = sol.X
    nl = system.nl_dofs
    q0 = sol.X[0, nl].real
    _, Jq, Jv = system.elements_at(speed).force_and_jacobian(q0, np.zeros_like(q0))
    M, D, K = problem.matrices(speed)
    K, D = K.copy(), D.copy()
    K[np.ix_(nl, nl)] -= Jq
    D[np.ix_(nl, nl)] -= Jv
    n = K.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    return float(np.max(np.linalg.eigvals(A).real))


@pytest.mark.slow
def test_whirl_onset_is_the_linear_threshold(response):
    hopf = [b for b in response.bifurcations if b["type"] == "secondary-hopf"]
    assert len(hopf) == 1 and hopf[0]["status"] == "confirmed"
    located = hopf[0]["speed_rad_s"]
    assert abs(hopf[0]["located_multiplier_abs"] - 1.0) < 1e-3
    system = build_system(balanced_config())
    problem = system.periodic_problem("speed")
    start = [None]
    threshold = brentq(lambda s: linear_growth(system, problem, s, start), 800.0, 1300.0,
                       xtol=1e-6)
    assert located == pytest.approx(threshold, rel=1e-5)   # measured 1.7e-6
    # the whirl at about half the speed: the critical multiplier near -1
    assert hopf[0]["located_multiplier_re"] < -0.99


@pytest.mark.slow
def test_hb_orbit_matches_time_integration_below_the_whirl_onset():
    """The unbalanced rotor at 800 rad/s (stable, largest multiplier 0.84): the HB orbit
    (H = 4) against the compiled time integration of the same system with the bearings at
    that speed, started on the HB orbit and run 60 periods (1e-3 C)."""
    from rotorsfd.timedomain import Forcing, HarmonicLoad, integrate

    system = build_system(config_from_dict(read_toml(EXAMPLE)))
    problem = system.periodic_problem("speed")
    speed, H, C = 800.0, 4, 50e-6
    X = solve_periodic(problem, 400.0, H, None, tol=1e-10).X
    X = solve_periodic(problem, speed, H, X, tol=1e-11).X
    M, D, K = system.matrices(speed)
    Fc, Fs = system.unbalance_harmonics(speed)
    forcing = Forcing(omega=speed, constant=system.static_force(speed),
                      harmonics=[HarmonicLoad(1.0, Fc, Fs)])
    el = system.elements_at(speed)
    k = np.arange(H + 1)
    q0, v0 = np.real(X.sum(axis=0)), np.real((1j * speed * k[:, None] * X).sum(axis=0))
    n, steps = 60, 400
    res = integrate(M, D, K, system.nl_dofs, el.kernel, el.kernel_params, forcing, q0=q0, v0=v0,
                    steps_per_period=steps, n_periods=n, record_start=(n - 1) * steps,
                    record_dofs="all", method="generalized-alpha", rho_inf=0.6)
    assert res.success, res.message
    lateral = np.sort(np.r_[0:system.n_dof:4, 1:system.n_dof:4])
    q_hb = np.real(np.exp(1j * speed * np.outer(res.t, k)) @ X)
    error = np.abs(q_hb[:, lateral] - res.q[:, lateral]).max()
    assert error < 1e-3 * C
    assert 0.05 < el.limit(q_hb[:, system.nl_dofs]) < 0.5     # a loaded, eccentric journal


def test_static_of_a_rotor_held_by_its_bearings_says_why(tmp_path, capsys):
    """The linear static offset excludes the bearings: one line naming rotor.supports and
    where the equilibrium is, exit 2, nothing written."""
    from rotorsfd.cli import main

    status = main(["static", str(EXAMPLE), "-o", str(tmp_path / "st")])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1
    assert "rotor.supports" in err and "rotorsfd response" in err
    assert not (tmp_path / "st").exists()


@pytest.mark.slow
def test_half_speed_locking_is_reported_as_period_doubling():
    """With 5 g mm the whirl pair near -1 meets the real axis over a narrow speed range;
    the branch's points straddle it with a complex pair at both ends, so the crossing is
    found on a finer sampling: two period doublings, at the speeds where a real multiplier
    passes -1 by a direct bracketing of Floquet on single HB solves (1e-4)."""
    from rotorsfd.stability.orbit import orbit_floquet

    result = run_response(config_from_dict(read_toml(EXAMPLE)), progress=False)
    kinds = [b["type"] for b in result.bifurcations]
    assert "secondary-hopf" not in kinds and kinds.count("period-doubling") == 2
    system = build_system(config_from_dict(read_toml(EXAMPLE)))
    problem = system.periodic_problem("speed")
    X = [solve_periodic(problem, 900.0, 3, None, tol=1e-10).X]

    def locked(speed, which):
        """The first (which=0: most negative) or second real multiplier near -1, plus 1
        (1 while the pair is complex)."""
        X[0] = solve_periodic(problem, speed, 3, X[0], tol=1e-11).X
        M, D, K = problem.matrices(speed)
        mu = orbit_floquet(M, D, K, X[0], speed, problem.nl_dofs,
                           problem.law(speed).jacobian, n_intervals=800).multipliers
        real = np.sort(mu[(np.abs(mu.imag) < 1e-9) & (mu.real < -0.5)].real)
        return float(real[which]) + 1.0 if real.size > which else 1.0

    for which, (b, (lo, hi)) in enumerate(zip(
            sorted(result.bifurcations, key=lambda r: r["speed_rad_s"]),
            [(1010.0, 1060.0), (1060.0, 1100.0)], strict=True)):
        speed = brentq(locked, lo, hi, args=(which,), xtol=1e-6)
        assert b["speed_rad_s"] == pytest.approx(speed, rel=1e-4)
