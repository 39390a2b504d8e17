"""The HB torus of the paper rotor with its SFD under harmonic pitching against a long
time integration of the same system by the compiled Newmark code (which runs harmonic base
laws), started on the torus: the journal orbit and the spectral lines at k1 Omega + k2 w_b
(amplitudes by a least-squares fit of the lattice's frequencies to the integrated series)
agree to 1e-3 C."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_system
from rotorsfd.quasiperiodic import TorusLattice, solve_torus, torus_problem
from rotorsfd.quasiperiodic.torus_fourier import derivative, synthesize

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "paper_pitching.toml"
#: harmonic pitching w_by = A0 w_b sin(w_b t), A0 = 0.05 rad, w_b = 60 rad/s (irrational
#: against Omega = 0.9 x 811.3 rad/s), U = 144.02 g mm of the example
PITCHING = ["base.pitching.law=harmonic", "base.pitching.value=0 rad/s",
            "base.pitching.frequency=60 rad/s", "base.pitching.angle_amplitude=0.05 rad"]


def line_amplitudes(t: np.ndarray, q: np.ndarray, omegas: np.ndarray) -> np.ndarray:
    """|X_k| of ``q(t) = Re(sum X_k e^{i omega_k t})`` by least squares on (cos, sin) of
    the given frequencies (omega_0 = 0 the mean): (nk, columns of q)."""
    cols = [np.ones_like(t)]
    for w in omegas[1:]:
        cols += [np.cos(w * t), np.sin(w * t)]
    coef = np.linalg.lstsq(np.column_stack(cols), q, rcond=None)[0]
    return np.vstack([np.abs(coef[:1]), np.hypot(coef[1::2], coef[2::2])])


@pytest.mark.slow     # about 2 minutes on 2 cores: a torus of the 84-DOF rotor, 2.4 s of Newmark
def test_paper_rotor_torus_against_newmark():
    system = build_system(load_config(EXAMPLE, PITCHING))
    C = system.length_scale
    omega = 0.9 * 811.3
    lat = TorusLattice(4, 3)
    torus = solve_torus(torus_problem(system), omega, lat, alias_tol=1e-6)
    w = lat.frequencies(omega, 60.0)
    s = system.nl_dofs
    x = to_real(torus.X)
    q0, v0 = x[0] + x[1::2].sum(axis=0), derivative(x, w)[1::2].sum(axis=0)
    periods, spp, record = 280, 400, 200          # record 200 rotor periods = 1.72 s
    run = integrate_periods(time_domain_inputs(system, omega), q0, v0, steps_per_period=spp,
                            periods=periods, record_dofs=s, record_periods=record,
                            poincare_periods=1)
    t, q = run.t, run.q[:, : s.size]
    q_hb = synthesize(lat, torus.X[:, s], omega, 60.0, t)
    orbit_error = np.abs(q - q_hb).max() / C
    assert np.abs(q_hb).max() / C > 0.3           # a large orbit, not a linear one
    assert orbit_error < 1e-3, orbit_error
    lines_td = line_amplitudes(t, q, w)
    lines_hb = np.abs(torus.X[:, s])
    line_error = np.abs(lines_td - lines_hb).max() / C
    print(f"orbit {orbit_error:.3g} C, lines {line_error:.3g} C, grid {torus.grid}")
    assert line_error < 1e-3
    # the combination lines are resolved: (1, -2) and (2, -1) above 5e-4 C in both
    for k in ((1, -2), (2, -1)):
        j = lat.index(*k)
        assert lines_hb[j].max() > 5e-4 * C and lines_td[j].max() > 5e-4 * C
