"""Branches of tori by the generic arc-length continuation: in the speed and in the
unbalance, every point a solution of the torus equations (re-solved alone from the
linear start), and the elements' validity limit ending a branch."""

from __future__ import annotations

import numpy as np
import pytest
from torus_models import small_system

from rotorsfd.quasiperiodic import TorusLattice, continue_torus, solve_torus, torus_problem

PITCHING = 'pitching = { law = "harmonic", frequency = "120 rad/s", angle_amplitude = "0.01 rad" }'
C = 1.27e-4


def test_speed_branch_points_are_tori(tmp_path):
    """Omega from 500 to 700 rad/s: the branch reaches the end with a sampling error < 1e-6 at
    every point (the grid doubled where needed); two of its points equal
    the torus solved alone at their speed (1e-7 C)."""
    system = small_system(tmp_path, PITCHING)
    problem = torus_problem(system)
    lat = TorusLattice(2, 1)
    branch = continue_torus(problem, 500.0, 700.0, lat, ds=0.1, ds_max=0.3)
    assert branch.success, branch.message
    assert branch.lam[0] == 500.0 and abs(branch.lam[-1] - 700.0) < 1e-9
    assert np.all(np.diff(branch.lam) > 0) and branch.n_points >= 3
    s = problem.nl_dofs
    for i in (branch.n_points // 2, branch.n_points - 1):
        alone = solve_torus(problem, float(branch.lam[i]), lat, grid=branch.grid,
                            tol=1e-10)
        assert np.abs(alone.X[:, s] - branch.X[i][:, s]).max() < 1e-7 * C
    # the unbalance response grows towards the rotor's critical speed
    amp = branch.amplitude(int(s[0]), 1, 0)
    assert amp[-1] > 1.5 * amp[0]
    assert branch.aliasing.max() < 1e-6      # the grid grew where the orbit needed it


@pytest.mark.slow   # about 6 s on a loaded 2-core machine
def test_validity_limit_ends_an_unbalance_branch(tmp_path):
    """Raising the unbalance at 700 rad/s until the journal eccentricity reaches
    limit_max = 0.6: the branch stops with the corrector's limit message, its last point
    just below the limit."""
    system = small_system(tmp_path, PITCHING)
    problem = torus_problem(system, "unbalance", speed=700.0)
    branch = continue_torus(problem, 2e-5, 2e-3, TorusLattice(2, 1), grid=(32, 16),
                            ds=0.1, ds_max=0.3, ds_min=1e-3, limit_max=0.6)
    assert not branch.success
    assert "state limit" in branch.message, branch.message
    assert 0.45 < branch.limit[-1] < 0.6
    assert branch.lam[-1] < 2e-3
