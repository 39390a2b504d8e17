"""The linear time-periodic steady state of the torus against an independent computation:
the periodic solution at a rational ratio w_b / Omega = 1/2 by a fourth-order Magnus
exponential integrator (Gauss points) of the time-domain inputs (the integrator's own
assembly of C_base(t), K_base(t), F_base(t) and F_mu(t)) over the common period T0,
``y0 = (I - Phi(T0))^-1 y_p(T0)``."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.linalg import expm
from torus_models import small_system

from rotorsfd.analyses.td_integration import time_domain_inputs
from rotorsfd.quasiperiodic.torus_continuation import solve_torus
from rotorsfd.quasiperiodic.torus_fourier import TorusLattice
from rotorsfd.quasiperiodic.torus_system import torus_problem

PITCHING = 'pitching = { law = "harmonic", frequency = "300 rad/s", angle_amplitude = "0.1 rad" }'


def magnus_periodic(inputs, period: float, steps: int, every: int):
    """Periodic response of ``M q'' + D(t) q' + K(t) q = f(t)`` over one period by the
    Magnus-4 map of the state augmented with a constant 1; q at every ``every`` steps."""
    n = inputs.M.shape[0]
    Minv = np.linalg.inv(inputs.M)
    h = period / steps
    c = np.sqrt(3.0) / 6.0
    t = (np.arange(steps)[:, None] + np.array([0.5 - c, 0.5 + c])[None]) * h
    tv = inputs.time_varying
    d = [np.asarray(f(t.ravel())).reshape(t.shape) for f, _ in tv.damping]
    k = [np.asarray(f(t.ravel())).reshape(t.shape) for f, _ in tv.stiffness]
    forces = inputs.forcing.at(t.ravel(), n).reshape(*t.shape, n)

    def generator(i: int, g: int) -> np.ndarray:
        D = inputs.D + sum(a[i, g] * A for a, (_, A) in zip(d, tv.damping, strict=True))
        K = inputs.K + sum(a[i, g] * A for a, (_, A) in zip(k, tv.stiffness, strict=True))
        B = np.zeros((2 * n + 1, 2 * n + 1))
        B[:n, n:2 * n] = np.eye(n)
        B[n:2 * n, :n] = -Minv @ K
        B[n:2 * n, n:2 * n] = -Minv @ D
        B[n:2 * n, -1] = Minv @ forces[i, g]
        return B

    P = np.eye(2 * n + 1)
    kept = [P]
    for i in range(steps):
        B1, B2 = generator(i, 0), generator(i, 1)
        P = expm(h / 2 * (B1 + B2) + np.sqrt(3.0) * h * h / 12 * (B2 @ B1 - B1 @ B2)) @ P
        if (i + 1) % every == 0:
            kept.append(P)
    y0 = np.linalg.solve(np.eye(2 * n) - P[:2 * n, :2 * n], P[:2 * n, -1])
    q = np.array([Pk[:n, :2 * n] @ y0 + Pk[:n, -1] for Pk in kept])
    return np.arange(len(kept)) * every * h, q


@pytest.mark.parametrize("lattice", [TorusLattice(1, 8), TorusLattice(6, 6, "diamond")])
def test_linear_torus_equals_the_floquet_periodic_solution(tmp_path, lattice):
    """The small rotor with a damped linear support instead of the SFD, under harmonic
    pitching (w_b = 300 rad/s, 0.1 rad) at Omega = 600 rad/s: the torus (the box H1 = 1,
    H2 = 8, or the diamond |k1| + |k2| <= 6) sampled in time = the Magnus periodic
    solution (1e-6 of the largest displacement; Magnus at 400 steps is within about 1e-7
    of its limit)."""
    system = small_system(tmp_path, PITCHING, linear=True)
    sol = solve_torus(torus_problem(system), 600.0, lattice)
    inputs = time_domain_inputs(system, 600.0)
    assert inputs.time_varying is not None
    t, q_ref = magnus_periodic(inputs, 2 * np.pi / 300.0, 400, 20)
    q = sol.time_series(t)
    scale = np.abs(q_ref).max()
    assert np.abs(q - q_ref).max() < 1e-6 * scale
    # the base coupling matters at this level: dropping k2 beyond 1 changes the answer
    coarse = solve_torus(torus_problem(system), 600.0, TorusLattice(1, 1)).time_series(t)
    assert np.abs(coarse - q_ref).max() > 1e-5 * scale


def test_figure6_rotor_torus_equals_the_floquet_periodic_solution(tmp_path):
    """The paper's Figure 6 rotor (examples/fig6_duchemin_pitching.toml: the undamped
    linear single-disk rotor, no SFD) with an unbalance of 20 g mm at the disk, under
    harmonic pitching of 0.05 rad at w_b = 100 rad/s, Omega = 200 rad/s (w_b / Omega =
    1/2): the torus on the box (1, 8) sampled in time = the Magnus periodic solution over
    the common period (measured 1.5e-8 of the largest displacement; asserted 1e-6).
    Undamped, the two are sensitive near a mode at a multiple of w_b: at Omega = 250,
    w_b = 125 rad/s (2 w_b next to the backward mode at 254 rad/s) they differ by 1.1e-6,
    with Magnus converged to 3e-10 (docs/quasiperiodic.md)."""
    from pathlib import Path

    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_system

    example = Path(__file__).resolve().parents[2] / "examples" / "fig6_duchemin_pitching.toml"
    config = tmp_path / "fig6.toml"
    config.write_text(f'extends = "{example.as_posix()}"\n\n[[unbalance]]\nnode = 5\n'
                      'magnitude = "20 g*mm"\nphase = "0 deg"\n')
    system = build_system(load_config(config, [
        "base.pitching.frequency=100 rad/s", "base.pitching.angle_amplitude=0.05 rad"]))
    assert not len(system.elements)
    sol = solve_torus(torus_problem(system), 200.0, TorusLattice(1, 8))
    inputs = time_domain_inputs(system, 200.0)
    t, q_ref = magnus_periodic(inputs, 2 * np.pi / 100.0, 800, 40)
    q = sol.time_series(t)
    scale = np.abs(q_ref).max()
    assert scale > 1e-6                      # the disk moves by microns, not round-off
    assert np.abs(q - q_ref).max() < 1e-6 * scale
