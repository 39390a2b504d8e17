"""The journal bearing element against the short-bearing closed forms, and its speed
dependence through harmonic balance and Floquet (the oil-whirl threshold)."""

from __future__ import annotations

import numpy as np
import pytest
from jb_rigid_rotor import (
    CLEARANCE,
    G,
    bearing,
    friswell_coefficients,
    ocvirk_load,
    rigid_rotor_problem,
)
from scipy.optimize import brentq

from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.harmonic.residual import FullHB
from rotorsfd.stability.orbit import orbit_floquet

SPEED = 300.0


def equilibrium(element, load: float) -> np.ndarray:
    """The journal position where the static film force carries ``load`` [N] acting in -z
    (Newton with the element's exact Jacobian)."""
    q = np.array([0.1, -0.1]) * CLEARANCE
    for _ in range(100):
        F, Jq, _ = element.force_and_jacobian(q, np.zeros(2))
        dq = np.linalg.solve(Jq, np.array([0.0, load]) - F)
        while np.hypot(*(q + dq)) >= 0.99 * CLEARANCE:
            dq *= 0.5
        q = q + dq
        if np.max(np.abs(dq)) < 1e-14 * CLEARANCE:
            return q
    raise AssertionError("no equilibrium")


@pytest.mark.parametrize("load", [10.0, 100.0, 1000.0, 5000.0])
def test_equilibrium_locus_and_coefficients_match_the_short_bearing_closed_forms(load):
    """Over Sommerfeld numbers from 3e-2 to 16 (eps 0.03-0.85): the equilibrium eccentricity
    carries the Ocvirk load, the attitude angle is ``atan(pi sqrt(1 - eps^2) / (4 eps))``
    ahead of the load in the direction of rotation, and ``K = -dF/dq``, ``C = -dF/dv`` at
    the equilibrium are Friswell et al.'s closed forms (1e-6)."""
    e = bearing().with_parameter("speed", SPEED)
    q = equilibrium(e, load)
    eps = np.hypot(*q) / CLEARANCE
    assert ocvirk_load(eps, SPEED) == pytest.approx(load, rel=1e-9)
    down = np.array([0.0, -1.0])
    u = q / np.hypot(*q)
    attitude = np.arctan2(down[0] * u[1] - down[1] * u[0], down @ u)
    assert attitude == pytest.approx(np.arctan(np.pi * np.sqrt(1 - eps**2) / (4 * eps)),
                                     rel=1e-9)
    _, Jq, Jv = e.force_and_jacobian(q, np.zeros(2))
    a, b = friswell_coefficients(eps)   # in (y, z): u = y horizontal, v = z up
    np.testing.assert_allclose(-Jq * CLEARANCE / load, a, rtol=1e-6, atol=1e-9 * abs(a).max())
    np.testing.assert_allclose(-Jv * CLEARANCE * SPEED / load, b, rtol=1e-6,
                               atol=1e-9 * abs(b).max())


@pytest.mark.parametrize("cavitation", ["pi", "none"])
def test_kernel_jacobians_and_speed_derivative(cavitation):
    """The compiled kernel equals the numpy law; the Jacobians and dF/dOmega equal central
    differences (1e-6)."""
    e = bearing(cavitation).with_parameter("speed", SPEED)
    rng = np.random.default_rng(3)
    q = rng.uniform(-0.6, 0.6, (5, 2)) * CLEARANCE
    v = rng.uniform(-1, 1, (5, 2)) * SPEED * CLEARANCE
    F, Jq, Jv = e.force_and_jacobian(q, v)
    for n in range(5):
        f, a, b = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
        assert e.kernel(q[n].copy(), v[n].copy(), e.kernel_params, f, a, b) == 0
        np.testing.assert_allclose(f, F[n], rtol=1e-13, atol=1e-13 * abs(F[n]).max())
        np.testing.assert_allclose(a, Jq[n], rtol=1e-12, atol=1e-12 * abs(Jq[n]).max())
        np.testing.assert_allclose(b, Jv[n], rtol=1e-12, atol=1e-12 * abs(Jv[n]).max())
    hq, hv = 1e-6 * CLEARANCE, 1e-6 * SPEED * CLEARANCE
    for j in range(2):
        d = np.zeros(2)
        d[j] = 1.0
        fd_q = (e.force(q + hq * d, v) - e.force(q - hq * d, v)) / (2 * hq)
        fd_v = (e.force(q, v + hv * d) - e.force(q, v - hv * d)) / (2 * hv)
        np.testing.assert_allclose(fd_q, Jq[..., :, j], rtol=1e-6, atol=1e-6 * abs(Jq).max())
        np.testing.assert_allclose(fd_v, Jv[..., :, j], rtol=1e-6, atol=1e-6 * abs(Jv).max())
    h = 1e-5 * SPEED
    fd = (e.with_parameter("speed", SPEED + h).force(q, v)
          - e.with_parameter("speed", SPEED - h).force(q, v)) / (2 * h)
    dF = e.dforce(q, v, "speed")
    np.testing.assert_allclose(dF, fd, rtol=1e-6, atol=1e-6 * abs(fd).max())


def test_a_bearing_without_speed_says_so():
    with pytest.raises(ValueError, match="speed is not set"):
        bearing().force(np.zeros(2), np.zeros(2))


@pytest.mark.parametrize("condensed", [True, False])
def test_hb_parameter_derivative_includes_the_force_dependence_on_speed(condensed):
    """dR/dlam of the condensed and the full HB residual equals central differences in lam
    at fixed unknowns (the force's own speed dependence included: without it the error is
    of the order of dR/dlam itself)."""
    p = rigid_rotor_problem(10.0, unbalance=1e-5)
    H, N = 3, 32
    X = np.zeros((H + 1, 2), dtype=complex)
    X[0] = [8e-6, -12e-6]
    X[1] = [3e-6, -3e-6j]
    x = to_real(X)
    hb = CondensedHB(p, H, N) if condensed else FullHB(p, H, N)
    lam, h = 800.0, 1e-3
    if condensed:
        hb.set_shift(x, lam)
    _, _, dR = hb.residual(x, lam)
    Rp = hb.residual(x, lam + h, jac=False)[0].ravel()
    Rm = hb.residual(x, lam - h, jac=False)[0].ravel()
    fd = (Rp - Rm) / (2 * h)
    np.testing.assert_allclose(dR, fd, rtol=1e-6, atol=1e-7 * abs(fd).max())


def test_oil_whirl_threshold_from_floquet_matches_the_linear_threshold():
    """The balanced rigid rotor (10 kg on the bearing): the speed where the largest Floquet
    multiplier of its HB solution (the equilibrium) reaches the unit circle equals, to
    1e-3, the speed where the linearised rotor ``m s^2 + C s + K`` with the closed-form
    coefficients at the Ocvirk equilibrium loses stability (independent of the element's
    code)."""
    m = 10.0
    W = m * G

    def eps_of(speed):
        return brentq(lambda e: ocvirk_load(e, speed) - W, 1e-9, 1 - 1e-12, xtol=1e-15)

    def linear_growth(speed):
        a, b = friswell_coefficients(eps_of(speed))
        K, C = W / CLEARANCE * a, W / (CLEARANCE * speed) * b
        A = np.block([[np.zeros((2, 2)), np.eye(2)], [-K / m, -C / m]])
        return np.max(np.linalg.eigvals(A).real)

    threshold = brentq(linear_growth, 200.0, 3000.0, xtol=1e-8)
    p = rigid_rotor_problem(m)

    def multiplier_excess(speed):
        X0 = np.zeros((3, 2), dtype=complex)
        X0[0, 1] = -eps_of(speed) * CLEARANCE
        sol = solve_periodic(p, speed, 2, X0, tol=1e-10)
        fl = orbit_floquet(*p.matrices(speed), sol.X, speed, p.nl_dofs,
                           p.law(speed).jacobian, method="newmark", n_intervals=400)
        return float(np.max(np.abs(fl.multipliers))) - 1.0

    found = brentq(multiplier_excess, 0.8 * threshold, 1.25 * threshold, xtol=1e-3)
    assert found == pytest.approx(threshold, rel=1e-3)


def test_continuation_in_speed_with_the_speed_dependent_bearing():
    """A branch of the unbalanced rigid rotor continued in the speed (dR/dlam with the
    bearing's dF/dOmega) passes through the single-point solutions (1e-8 C)."""
    p = rigid_rotor_problem(10.0, unbalance=2e-6)
    H = 3
    X0 = np.zeros((H + 1, 2), dtype=complex)
    X0[0, 1] = -0.3 * CLEARANCE
    first = solve_periodic(p, 300.0, H, X0, tol=1e-10)
    branch = continue_periodic(p, 300.0, 700.0, H, first.X, ds=0.05, max_points=200,
                               tol=1e-10)
    assert branch.lam[-1] == pytest.approx(700.0, rel=1e-6)
    for i in range(1, branch.n_points, max(1, branch.n_points // 4)):
        point = solve_periodic(p, float(branch.lam[i]), H, branch.X[i], tol=1e-12)
        np.testing.assert_allclose(branch.X[i], point.X, atol=1e-8 * CLEARANCE)
