"""Continuation in the base law: w_b and a law's amplitude, the problem interpolated
exactly from five builds (polynomial in the parameter)."""

from __future__ import annotations

import numpy as np
import pytest
from torus_models import small_system

from rotorsfd.quasiperiodic import TorusLattice, continue_torus, solve_torus
from rotorsfd.quasiperiodic.torus_base_parameters import (
    base_parameter_problem,
    with_base_value,
)
from rotorsfd.quasiperiodic.torus_residual import TorusHB
from rotorsfd.quasiperiodic.torus_system import torus_problem

BASE = ('pitching = { law = "harmonic", frequency = "120 rad/s", angle_amplitude = "0.01 rad" }'
        '\nz = { law = "harmonic", frequency = "120 rad/s", amplitude = "0.01 mm" }')
C = 1.27e-4


@pytest.mark.parametrize(("parameter", "hold", "value"), [
    ("base.frequency", "angle", 131.0), ("base.frequency", "rate", 109.0),
    ("base.pitching.amplitude", "angle", 1.7)])
def test_interpolated_problem_is_the_built_one(tmp_path, parameter, hold, value):
    """Between the nodes the interpolated coefficients and loads equal the problem built at
    that value (1e-10 relative), and dR/dlam matches central differences (1e-6)."""
    system = small_system(tmp_path, BASE)
    problem = base_parameter_problem(system, parameter, 700.0, hold)
    built = torus_problem(with_base_value(system, parameter, value, hold))
    lat = TorusLattice(2, 2)
    for a, b in zip(problem.coefficients(value), built.coefficients(700.0), strict=True):
        k = min(a.shape[0], b.shape[0])
        assert np.abs(a[:k] - b[:k]).max() < 1e-10 * np.abs(b).max()
    F, Fb = problem.forcing(value, lat), built.forcing(700.0, lat)
    assert np.abs(F - Fb).max() < 1e-10 * np.abs(Fb).max()
    assert problem.frequencies(value) == built.frequencies(700.0)
    hb = TorusHB(problem, lat, 8, 8)
    xs = np.random.default_rng(1).normal(size=(lat.n_real, problem.m)) * 0.05 * C
    hb.set_shift(xs, value)
    dR = hb.residual(xs, value)[2]
    h = 1e-6 * value
    dfd = (hb.residual(xs, value + h, False)[0]
           - hb.residual(xs, value - h, False)[0]).ravel() / (2 * h)
    assert np.abs(dR - dfd).max() < 1e-6 * np.abs(dR).max()


def test_branch_in_the_base_frequency(tmp_path):
    """w_b from 120 to 160 rad/s at the angle amplitude 0.01 rad: the branch reaches the
    end, and its last point is the torus solved alone with the law at 160 rad/s."""
    system = small_system(tmp_path, BASE)
    problem = base_parameter_problem(system, "base.frequency", 700.0)
    lat = TorusLattice(2, 1)
    branch = continue_torus(problem, 120.0, 160.0, lat, grid=(32, 32), ds=0.2, ds_max=0.5)
    assert branch.success, branch.message
    assert np.allclose(branch.wb, branch.lam) and abs(branch.lam[-1] - 160.0) < 1e-9
    alone = solve_torus(torus_problem(with_base_value(system, "base.frequency", 160.0)),
                        700.0, lat, grid=(32, 32), tol=1e-10)
    s = problem.nl_dofs
    assert np.abs(alone.X[:, s] - branch.X[-1][:, s]).max() < 1e-6 * C   # the branch tol
