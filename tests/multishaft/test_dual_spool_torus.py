"""The two-frequency (torus) response of the shipped dual-spool rotor with unbalances on both
spools (examples/dual_spool_unbalance.toml; issue 20 items 3 and 5). Independent checks: a
long time integration from rest that runs each shaft's unbalance at its own speed, the
quasi-periodic Hill exponents against the Lyapunov exponent, and, at a rational speed
ratio r = 3/2, the periodic harmonic balance at the common period 4 pi / Omega_LP."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.io.config import config_from_dict, load_config, read_config
from rotorsfd.model.build import build_system
from rotorsfd.quasiperiodic import TorusLattice, solve_torus
from rotorsfd.quasiperiodic.dual_frequency import common_period_problem, dual_spool_problem

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "dual_spool_unbalance.toml"


@pytest.fixture(scope="module")
def system():
    return build_system(load_config(EXAMPLE))


@pytest.mark.slow   # about 7 s CPU: the torus at H = 4, 300 periods of Newmark, the Hill matrix
def test_torus_equals_long_time_integration_and_hill_equals_lyapunov(system) -> None:
    """At Omega_LP = 160 rad/s (the first resonance of the HP unbalance, the LP film at
    eps 0.41) the motion integrated from rest for 300 LP periods (T/800) settles on the
    torus to 3.4e-4 C; the largest Lyapunov exponent there (integration on the torus) and
    the largest real part of the quasi-periodic Hill exponents agree to 1e-3."""
    from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs
    from rotorsfd.quasiperiodic.torus_hill import torus_hill
    from rotorsfd.quasiperiodic.torus_stability import torus_lyapunov

    C, s = system.length_scale, system.nl_dofs
    problem = dual_spool_problem(system)
    speed = 160.0
    torus = solve_torus(problem, speed, TorusLattice(4, 4), tol=1e-10)
    run = integrate_periods(time_domain_inputs(system, speed), 0.0, 0.0,
                            steps_per_period=800, periods=300, record_dofs=s,
                            record_periods=20, poincare_periods=1)
    q = torus.time_series(run.t)[:, s]
    assert np.all(np.isfinite(torus.X))
    assert 0.3 < np.abs(q).max() / C < 0.6                  # the film works
    lat = torus.lattice                                      # combination lines present
    assert np.abs(torus.X[lat.index(1, -2), s]).max() > 1e-5 * C
    assert np.abs(run.q - q).max() < 1e-3 * C
    ly = torus_lyapunov(system, lat, torus.X, speed, 1.8 * speed)
    small = solve_torus(problem, speed, TorusLattice(2, 2), tol=1e-10)
    hill = torus_hill(problem, small.lattice, small.X, speed, (16, 16), 40 * speed)
    assert ly.stable and hill.stable
    assert abs(hill.per_period - ly.per_period) < 1e-3 * abs(ly.per_period) + ly.uncertainty


def test_rational_ratio_torus_is_the_periodic_orbit_at_the_common_period() -> None:
    """r = 3/2: the motion is periodic at w0 = Omega_LP / 2 (the LP unbalance on harmonic
    2, the HP one on 3); the torus (box H = 3) restricted to its line through (0, 0) is
    the periodic HB orbit (H = 16) to 7.6e-7 C (the box truncation: 2.6e-8 C at H = 4),
    the orbit reaching 0.2 C."""
    from rotorsfd.harmonic.periodic import solve_periodic

    raw = read_config(EXAMPLE)
    raw["rotor"]["shafts"][1]["speed_ratio"] = 1.5
    system = build_system(config_from_dict(raw))
    C, s = system.length_scale, system.nl_dofs
    speed = 185.0
    torus = solve_torus(dual_spool_problem(system), speed, TorusLattice(3, 3), tol=1e-10)
    periodic = solve_periodic(common_period_problem(system, 3, 2), speed, 16, tol=1e-10)
    t = np.linspace(0.0, 4 * np.pi / speed, 101)
    q_periodic = (np.exp(1j * np.outer(t, np.arange(17) * speed / 2)) @ periodic.X).real
    q_torus = torus.time_series(t)
    assert 0.1 < np.abs(q_periodic[:, s]).max() / C < 0.5
    assert np.abs(q_torus - q_periodic)[:, s].max() < 2e-6 * C


def test_the_periodic_harmonic_balance_refuses_a_second_spools_unbalance(system) -> None:
    from rotorsfd.errors import ConfigError

    with pytest.raises(ConfigError, match=r"shaft 'hp' \(speed ratio 1.8\).*two-frequency"):
        system.periodic_problem()
    with pytest.raises(ConfigError, match="p/q"):
        common_period_problem(system, 3, 2)          # 3/2 is not the ratio 1.8


def test_per_harmonic_condensation_equals_the_block_condensation(system) -> None:
    """HarmonicCondenser (one LU per harmonic) against the generic TorusCondenser (one LU
    per k1 block) at a shift and speed: Ht, Pt and their exact speed derivatives, and the
    recovered coefficients; the derivatives also against central differences."""
    from rotorsfd.quasiperiodic.dual_frequency import HarmonicCondenser
    from rotorsfd.quasiperiodic.torus_linear import TorusCondenser

    problem = dual_spool_problem(system)
    lat = TorusLattice(2, 2)
    m = problem.m
    rng = np.random.default_rng(3)
    Kr, Cr = np.diag(rng.uniform(1e5, 1e6, m)), np.diag(rng.uniform(10.0, 100.0, m))
    fast, ref = HarmonicCondenser(problem, lat), TorusCondenser(problem, lat)
    for c in (fast, ref):
        c.set_shift(Kr, Cr, 150.0)
    a, b = fast.condense(158.0), ref.condense(158.0)
    for name in ("Ht", "Pt", "dHt", "dPt"):
        x, y = getattr(a, name), getattr(b, name)
        assert np.abs(x - y).max() <= 1e-10 * np.abs(y).max(), name
    xs = rng.normal(size=(lat.n_real, m)) * 1e-5
    G = rng.normal(size=(lat.n_real, m))
    X1, X2 = fast.recover(a, xs, G), ref.recover(b, xs, G)
    assert np.abs(X1 - X2).max() <= 1e-10 * np.abs(X2).max()
    h = 1e-3
    up, down = fast.condense(158.0 + h, deriv=False), fast.condense(158.0 - h, deriv=False)
    fd = (up.Ht - down.Ht) / (2 * h)
    assert np.abs(fd - a.dHt).max() <= 1e-5 * np.abs(a.dHt).max()     # O(h^2): 1.2e-6


def test_per_harmonic_response_derivative_equals_the_block_one(system) -> None:
    """``response_derivative`` (dPt + dHt g, what the torus residual's dR/dlam uses) of the
    per-harmonic condenser = the block condenser's = dPt + dHt g of the same condenser."""
    from rotorsfd.quasiperiodic.dual_frequency import HarmonicCondenser
    from rotorsfd.quasiperiodic.torus_linear import TorusCondenser

    problem = dual_spool_problem(system)
    lat = TorusLattice(2, 2)
    m = problem.m
    rng = np.random.default_rng(5)
    Kr, Cr = np.diag(rng.uniform(1e5, 1e6, m)), np.diag(rng.uniform(10.0, 100.0, m))
    fast, ref = HarmonicCondenser(problem, lat), TorusCondenser(problem, lat)
    for c in (fast, ref):
        c.set_shift(Kr, Cr, 150.0)
    g = rng.normal(size=(lat.n_real, m))
    a = fast.response_derivative(fast.condense(158.0, deriv=False), g)
    b = ref.response_derivative(ref.condense(158.0, deriv=False), g)
    full = fast.condense(158.0)
    c = full.dPt + (full.dHt @ g.reshape(-1)).reshape(g.shape)
    assert np.abs(a - b).max() <= 1e-10 * np.abs(b).max()
    assert np.abs(a - c).max() <= 1e-10 * np.abs(b).max()
