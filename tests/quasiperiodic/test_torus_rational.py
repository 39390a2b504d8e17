"""At a rational ratio w_b / Omega = 1/2 the torus restricted to its line through (0, 0)
is the periodic orbit at the common period 2 pi / w_b: the torus of the small SFD rotor
under harmonic heave against the periodic HB (:func:`rotorsfd.harmonic.periodic.
solve_periodic`) of the same rotor at the fundamental w0 = Omega / 2, with the unbalance
on harmonic 2 and the heave load on harmonic 1."""

from __future__ import annotations

import numpy as np
import pytest
from torus_models import heave_common_period_problem, small_system

from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.quasiperiodic import TorusLattice, solve_torus, torus_problem

C = 1.27e-4        # the SFD clearance [m]
HEAVE, W_B, OMEGA = 3e-5, 350.0, 700.0


@pytest.mark.slow   # about 6 s on a loaded 2-core machine (the periodic HB's kernels load)
def test_rational_torus_is_the_periodic_orbit(tmp_path):
    """Heave z0 = A sin(w_b t) loads the rotor with F_base = A w_b^2 sin(w_b t) fz
    (torus_models.heave_common_period_problem). The torus (box H1 = 6, H2 = 3) and the
    periodic HB (H = 24) give the same journal orbit to 1e-6 C over the common period;
    the orbit reaches 0.05-0.5 C."""
    base = f'z = {{ law = "harmonic", frequency = "{W_B} rad/s", amplitude = "{HEAVE} m" }}'
    system = small_system(tmp_path, base, unbalance="100 g*mm")
    common = heave_common_period_problem(system, HEAVE, W_B)
    periodic = solve_periodic(common, OMEGA, 24, tol=1e-10)
    t = np.linspace(0.0, 2 * np.pi / W_B, 61)
    q_periodic = (np.exp(1j * np.outer(t, np.arange(25) * OMEGA / 2)) @ periodic.X).real
    torus = solve_torus(torus_problem(system), OMEGA, TorusLattice(6, 3), tol=1e-10)
    q_torus = torus.time_series(t)
    s = system.nl_dofs
    assert 0.05 < np.abs(q_periodic[:, s]).max() / C < 0.5
    assert np.abs(q_torus - q_periodic)[:, s].max() < 1e-6 * C
    # a combination line of the film: (2, 1) turns at 2 Omega + w_b = 5 w0
    assert np.abs(torus.X[torus.lattice.index(2, 1), s]).max() > 1e-5 * C
