"""A branch started from a time-domain orbit (``rotorsfd response --from-orbit``): the
Fourier fit of the last period, its Newton correction, and the continuation both ways that
stops when the branch closes on itself (an isola).

Independent check: a Duffing oscillator with amplitude-dependent damping
``x'' + (c + d1 x^2 + d2 x^4) x' + x + k3 x^3 = F cos(w t)`` has, for these numbers, an
isola beside its main resonance. With one harmonic the HB equations are the
describing-function equations, whose solution set is known in closed form:
``a^2 [(1 + 3 k3 a^2 / 4 - w^2)^2 + w^2 c_e(a)^2] = F^2``,
``c_e(a) = c + d1 a^2 / 4 + d2 a^4 / 8``. The orbit is found by scipy's DOP853 (not the
package's Newmark) started near the isola.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorsfd.analyses.orbit_branch import (
    continue_both_ways,
    correct_orbit,
    fit_samples,
    join_segments,
)
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.harmonic.problem import PeriodicProblem

c, d1, d2, k3, F = 0.1, -0.16, 0.04, 0.05, 0.05


def problem() -> PeriodicProblem:
    one = np.eye(1)
    Z = np.zeros((1, 1))

    def forcing(lam, H):
        f = np.zeros((H + 1, 1), dtype=complex)
        f[1, 0] = F
        return f

    def force(q, v):
        return -(k3 * q**3 + (d1 * q**2 + d2 * q**4) * v)

    def jac(q, v):
        dq = -(3 * k3 * q**2 + (2 * d1 * q + 4 * d2 * q**3) * v)
        dv = -(d1 * q**2 + d2 * q**4)
        return dq[..., None], dv[..., None]

    return PeriodicProblem(
        n_dof=1, nl_dofs=np.array([0]), matrices=lambda lam: (one, c * one, one),
        dmatrices=lambda lam: (Z, Z, Z), forcing=forcing,
        dforcing=lambda lam, H: np.zeros((H + 1, 1), dtype=complex),
        frequency=lambda lam: lam, dfrequency=lambda lam: 1.0, nl_force=force,
        nl_jacobian=jac, scaling=1.0, name="duffing-isola")


def isola_curve():
    """(a, w_low, w_high) of the one-harmonic solution set for a >= 1 (the isola)."""
    a = np.linspace(1.0, 3.0, 400001)
    b = 1 + 0.75 * k3 * a**2
    ce = c + d1 * a**2 / 4 + d2 * a**4 / 8
    B, Cq = 2 * b - ce**2, b**2 - F**2 / a**2
    disc = B**2 - 4 * Cq
    ok = disc >= 0
    return a[ok], np.sqrt((B[ok] - np.sqrt(disc[ok])) / 2), \
        np.sqrt((B[ok] + np.sqrt(disc[ok])) / 2)


W = 1.065


@pytest.fixture(scope="module")
def orbit():
    """The stable isola orbit at w = 1.065 by DOP853 from the analytic upper isola point
    (400 periods), sampled on the last period (256 points, absolute time)."""
    a, _, wh = isola_curve()
    i = np.argmin(np.abs(wh - W) + 10 * (a < 1.9))     # the upper part of the isola
    amp = a[i]
    b = 1 + 0.75 * k3 * amp**2
    ce = c + d1 * amp**2 / 4 + d2 * amp**4 / 8
    phi = np.arctan2(W * ce, b - W**2)

    def rhs(t, y):
        x, v = y
        return [v, F * np.cos(W * t) - (c + d1 * x**2 + d2 * x**4) * v - x - k3 * x**3]

    T = 2 * np.pi / W
    n = 400
    t = (n - 1) * T + np.arange(257) * T / 256
    sol = solve_ivp(rhs, (0, n * T), [amp * np.cos(phi), amp * W * np.sin(phi)],
                    method="DOP853", rtol=1e-11, atol=1e-12, t_eval=t)
    x = sol.y[0]
    one_back = solve_ivp(rhs, (0, (n - 1) * T), [amp * np.cos(phi), amp * W * np.sin(phi)],
                         method="DOP853", rtol=1e-11, atol=1e-12).y[0, -1]
    return t, x, one_back


def test_the_ode_orbit_is_a_settled_isola_orbit(orbit) -> None:
    _, x, one_back = orbit
    assert abs(x[0] - one_back) < 1e-8           # periodic: x((n-1)T) twice
    assert abs(x[0] - x[-1]) < 1e-7
    assert 1.9 < np.max(np.abs(x)) < 2.2         # on the isola, not the main branch


def test_fit_and_correction_reproduce_the_orbit(orbit) -> None:
    """H = 7: the fit alone differs from the samples by its truncation; the Newton-
    corrected HB orbit reproduces the DOP853 orbit to 2e-4 of its amplitude ~2 over the
    period (the truncation at H = 7); with H = 1 it is off by far more (> 1e-3)."""
    t, x, _ = orbit
    fit = fit_samples(t, {0: x}, W, 7, 1)
    assert fit.t.size == 256
    assert fit.difference() < 2e-4
    sol = correct_orbit(problem(), fit, 7)
    assert fit.difference(sol.X) < 2e-4
    sol1 = correct_orbit(problem(), fit, 1)
    assert fit.difference(sol1.X) > 1e-3
    # phase kept: X_1 of the fit with absolute time matches the corrected one
    assert abs(sol.X[1, 0] - fit.X[1, 0]) < 1e-3


def test_isola_closes_and_its_folds_are_the_analytic_ones(orbit) -> None:
    """H = 1 from the fitted orbit, range (0.9, 1.2): the branch goes up, turns at the
    upper fold, runs down past the start speed on the other side, turns at the lower fold
    and comes back: it closes within 1e-3 of its start. Its extreme speeds are the
    analytic isola's w_min, w_max to 2e-5 (the point nearest the fold, ds_max 0.01:
    checked against the parabola through the three points around it)."""
    t, x, _ = orbit
    prob = problem()
    sol = correct_orbit(prob, fit_samples(t, {0: x}, W, 1, 1), 1)
    br = continue_both_ways(prob, W, sol.X, 1, 0.9, 1.2, ds_max=0.01, closure_tol=1e-3,
                            n_samples=64)
    assert br.info["closed"]
    assert "isola" in br.message
    a_num = np.abs(br.X[:, 1, 0])
    assert a_num.min() > 1.5                    # never on the main branch
    _, wl, wh = isola_curve()
    assert np.max(br.lam) == pytest.approx(wh.max(), abs=2e-5)
    assert np.min(br.lam) == pytest.approx(wl.min(), abs=2e-5)
    assert len(br.folds()) == 2
    # every point satisfies the amplitude equation (the branch is the analytic curve)
    w, amp = br.lam, a_num
    b = 1 + 0.75 * k3 * amp**2
    ce = c + d1 * amp**2 / 4 + d2 * amp**4 / 8
    assert np.max(np.abs(amp**2 * ((b - w**2) ** 2 + w**2 * ce**2) - F**2)) < 1e-8
    assert br.lam[-1] == pytest.approx(W, abs=0.01)


def test_open_branch_runs_both_ways_and_joins() -> None:
    """Plain Duffing (no isola) from w = 0.5: towards 0.9 and towards 0.3; the joined
    branch runs from 0.3 to 0.9 monotonically with the start inside; points of both legs
    are the solutions Newton finds from the linear start at their speeds (1e-6)."""
    from rotorsfd.harmonic.examples import duffing

    prob = duffing()
    br = continue_both_ways(prob, 0.5, None, 3, 0.3, 0.9, ds_max=0.05, n_samples=32)
    assert not br.info["closed"] and br.success
    assert br.lam[0] == pytest.approx(0.3) and br.lam[-1] == pytest.approx(0.9)
    assert np.all(np.diff(br.lam) > 0) and np.all(np.diff(br.s) > 0)
    assert br.lam[br.info["start_index"]] == pytest.approx(0.5)
    for i in (1, br.info["start_index"] - 1, br.n_points - 2):   # both legs: solutions
        ref = solve_periodic(prob, br.lam[i], 3, n_samples=32)   # from the linear start
        assert np.max(np.abs(ref.X - br.X[i])) < 1e-6 * np.abs(ref.X).max()
    assert np.all(br.tangents[:, -1] > 0)
    p = br.point_at(0.5 * (br.s[1] + br.s[2]))    # re-solved in the reversed leg
    assert br.lam[1] < p.lam < br.lam[2] and p.dlam_ds > 0


def test_join_segments_needs_one_lam_scale() -> None:
    from rotorsfd.harmonic.examples import duffing

    a = continue_periodic(duffing(), 0.5, 0.6, 1, n_samples=16)
    b = continue_periodic(duffing(), 0.5, 0.9, 1, n_samples=16)
    with pytest.raises(ValueError, match="lam_scale"):
        join_segments([(a, True), (b, False)])


def test_cli_response_from_orbit(tmp_path) -> None:
    """Small rotor: simulate at Omega~ = 0.9 (one attractor), then ``response
    --from-orbit``: the corrected HB orbit is within 1e-3 C of the recorded journal and
    disk orbit, the branch is open, runs over the whole range and contains the start."""
    from rotors import small_rotor_toml
    from rotorsfd import api
    from rotorsfd.cli import main

    cfg = small_rotor_toml(tmp_path / "small.toml", unbalance="100 g*mm",
                           reference="800 rad/s")
    assert main(["simulate", str(cfg), "--speed-ratio", "0.9", "-q", "--lyapunov-periods",
                 "0", "--set", "analysis.simulate.periods=300", "--set",
                 "analysis.simulate.poincare_periods=10", "-o", str(tmp_path / "td")]) == 0
    r = api.run_response(api.load_config(cfg), from_orbit=tmp_path / "td", progress=False,
                         stability_options=False)
    assert r.info["orbit_difference"] < 1e-3
    assert not r.info["closed"] and r.success
    lo, hi = r.branch.lam.min(), r.branch.lam.max()
    assert lo < 720.0 < hi
    assert r.branch.lam[r.info["start_index"]] == pytest.approx(720.0, rel=1e-12)
    assert "HB orbit within" in r.summary()
    assert main(["response", str(cfg), "--from-orbit", str(tmp_path / "td"), "-q",
                 "--set", "analysis.stability.enabled=false", "-o",
                 str(tmp_path / "br")]) == 0
    assert (tmp_path / "br" / "branch.csv").stat().st_size > 0
