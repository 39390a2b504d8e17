"""Stability of a torus by the Lyapunov route and by the quasi-periodic Hill method, each
against an independent computation: at w_b / Omega = 1/2 the torus started at phases
(0, 0) is the periodic orbit at the common period, whose largest Floquet multiplier
(Newmark on the Craig-Bampton model, the same step and mode cutoff) gives the exponent
ln |mu|max / T0; at an irrational ratio Hill against the Lyapunov route."""

from __future__ import annotations

import numpy as np
import pytest
from torus_models import heave_common_period_problem, small_system

from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.model.system import RotorSystem
from rotorsfd.quasiperiodic import TorusLattice, solve_torus, torus_problem
from rotorsfd.quasiperiodic.torus_hill import torus_hill
from rotorsfd.quasiperiodic.torus_stability import torus_lyapunov
from rotorsfd.stability.orbit import orbit_floquet

HEAVE, W_B, OMEGA = 3e-5, 350.0, 700.0


@pytest.mark.slow   # about 5 s: 300 rotor periods of three trajectories
def test_torus_lyapunov_is_the_floquet_exponent_at_a_rational_ratio(tmp_path):
    """Small SFD rotor, heave and unbalance: the reduced Lyapunov exponent per rotor
    period from the torus (300 periods, T/200) = ln |mu|max of the periodic orbit per
    rotor period (-0.0445), within its uncertainty (about 0.002); the torus is stable.
    The Hill exponent of the torus (box (2, 1), the same Craig-Bampton cutoff) = the
    Floquet one to 1e-3 relative (Newmark's discretisation at T/200)."""
    base = f'z = {{ law = "harmonic", frequency = "{W_B} rad/s", amplitude = "{HEAVE} m" }}'
    system = small_system(tmp_path, base, unbalance="100 g*mm")
    periodic = solve_periodic(heave_common_period_problem(system, HEAVE, W_B), OMEGA, 24,
                              tol=1e-10)
    T = 2 * np.pi / OMEGA
    M, D, K = RotorSystem(system.rotor, system.elements, system.unbalances).matrices(OMEGA)
    fl = orbit_floquet(M, D, K, periodic.X, OMEGA / 2, system.nl_dofs,
                       system.elements.jacobian, method="newmark-cb", n_intervals=400,
                       omega_max=100 / T)
    floquet = float(np.log(np.abs(fl.multipliers).max())) / 2    # T0 = 2 T
    torus = solve_torus(torus_problem(system), OMEGA, TorusLattice(6, 3), tol=1e-10)
    ly = torus_lyapunov(system, torus.lattice, torus.X, OMEGA, W_B, periods=300)
    assert floquet < -0.01 and ly.stable
    assert abs(ly.per_period - floquet) < max(2 * ly.uncertainty, 2e-3)
    small = solve_torus(torus_problem(system), OMEGA, TorusLattice(2, 1), tol=1e-10)
    hill = torus_hill(torus_problem(system), small.lattice, small.X, OMEGA, (24, 16),
                      omega_max=100 / T)
    assert hill.stable and abs(hill.per_period - floquet) < 1e-3 * abs(floquet)
    assert hill.weights[0] > 0.99          # the sorted exponent sits on the centre harmonic


@pytest.mark.slow   # about 12 s: a Hill matrix of 35 harmonics, 300 periods of Lyapunov
def test_torus_hill_against_lyapunov_at_an_irrational_ratio(tmp_path):
    """Harmonic pitching at w_b = 120 rad/s, Omega = 700 rad/s (an irrational ratio for
    the torus: no periodic orbit to compare with): the Hill exponent of the box (3, 2)
    torus per rotor period (-0.0423) = the Lyapunov route's (-0.0420 +/- 0.0016)."""
    base = ('pitching = { law = "harmonic", frequency = "120 rad/s", '
            'angle_amplitude = "0.01 rad" }')
    system = small_system(tmp_path, base, unbalance="100 g*mm")
    problem = torus_problem(system)
    T = 2 * np.pi / OMEGA
    torus = solve_torus(problem, OMEGA, TorusLattice(3, 2), tol=1e-10)
    hill = torus_hill(problem, torus.lattice, torus.X, OMEGA, (32, 32), omega_max=100 / T)
    ly = torus_lyapunov(system, torus.lattice, torus.X, OMEGA, 120.0, periods=300)
    assert hill.per_period < -0.01 and ly.stable
    assert abs(hill.per_period - ly.per_period) < max(2 * ly.uncertainty, 2e-3)
