"""The condensed torus residual: exact Jacobians (against central differences) and the
condensation (the recovered all-DOF torus solves the uncondensed equations)."""

from __future__ import annotations

import numpy as np
import pytest
from torus_models import small_system

from rotorsfd.errors import ConfigError
from rotorsfd.harmonic.fourier import to_complex, to_real
from rotorsfd.quasiperiodic.torus_continuation import solve_torus
from rotorsfd.quasiperiodic.torus_fourier import TorusLattice, block_vectors
from rotorsfd.quasiperiodic.torus_linear import column_operator
from rotorsfd.quasiperiodic.torus_residual import TorusHB, torus_force
from rotorsfd.quasiperiodic.torus_system import base_frequency, torus_problem

PITCHING = 'pitching = { law = "harmonic", frequency = "120 rad/s", angle_amplitude = "0.05 rad" }'
ROLLING = ('rolling = { law = "harmonic", frequency = "90 rad/s", amplitude = "8 rad/s", '
           'value = "2 rad/s" }\nz = { law = "harmonic", frequency = "90 rad/s", '
           'amplitude = "0.1 mm" }')
C = 1.27e-4


@pytest.mark.parametrize(("base", "parameter", "lam"), [
    (PITCHING, "speed", 700.0), (ROLLING, "speed", 650.0), (PITCHING, "unbalance", 4e-5)])
def test_jacobians_are_exact(tmp_path, base, parameter, lam):
    """dR/dxs and dR/dlam of the condensed residual = central differences (1e-7 rel.),
    for pitching, and rolling with a mean rate plus heave (C_base(t), dw/dt terms)."""
    system = small_system(tmp_path, base)
    problem = torus_problem(system, parameter, speed=700.0)
    lat = TorusLattice(2, 2)
    hb = TorusHB(problem, lat, 8, 8)
    xs = np.random.default_rng(0).normal(size=(lat.n_real, problem.m)) * 0.05 * C
    hb.set_shift(xs, lam)
    _, J, dR = hb.residual(xs, lam)
    h = 1e-6 * C
    Jfd = np.empty_like(J)
    for i in range(J.shape[1]):
        d = np.zeros(J.shape[1])
        d[i] = h
        Jfd[:, i] = (hb.residual(xs.ravel() + d, lam, False)[0]
                     - hb.residual(xs.ravel() - d, lam, False)[0]).ravel() / (2 * h)
    assert np.abs(J - Jfd).max() < 1e-7 * np.abs(J).max()
    hl = 1e-6 * lam
    dfd = (hb.residual(xs, lam + hl, False)[0]
           - hb.residual(xs, lam - hl, False)[0]).ravel() / (2 * hl)
    assert np.abs(dR - dfd).max() < 1e-6 * np.abs(dR).max()


def test_condensed_torus_solves_the_full_equations(tmp_path):
    """The all-DOF torus recovered from the condensed solution satisfies the uncondensed
    balance ``Z X = F + S^T G`` of every k1 column (the fictitious shift cancels)."""
    system = small_system(tmp_path, PITCHING.replace("0.05 rad", "0.01 rad"),
                          unbalance="80 g*mm")
    problem = torus_problem(system)
    lat = TorusLattice(3, 2)
    sol = solve_torus(problem, 700.0, lat, tol=1e-10)
    s = problem.nl_dofs
    xs = to_real(sol.X[:, s])
    G = torus_force(problem, TorusHB(problem, lat, *sol.grid).aft, xs, 700.0).G
    F = problem.forcing(700.0, lat)
    SG = np.zeros_like(F)
    SG[:, s] = to_complex(G)
    cols_X, cols_F = block_vectors(lat, sol.X), block_vectors(lat, F + SG)
    for k1 in range(lat.H1 + 1):
        Z, _ = column_operator(problem, lat, k1, 700.0)
        res = Z @ cols_X[k1].ravel() - cols_F[k1].ravel()
        assert np.abs(res).max() < 1e-8 * np.abs(cols_F[k1]).max()
    assert 0.1 < np.abs(sol.X[:, s]).max() / C < 0.9      # a real nonlinear orbit
    # a torus: combination lines by the film alone (k1 + k2 odd: the film force is odd)
    assert np.abs(sol.X[lat.index(2, 1), s]).max() > 1e-5 * C


def test_base_laws_the_torus_rejects(tmp_path):
    """A constant base, or two harmonic laws at different frequencies: one-line errors
    naming the field."""
    with pytest.raises(ConfigError, match="base"):
        base_frequency(small_system(tmp_path, 'pitching = { law = "constant", value = "3 rad/s" }'))
    two = PITCHING + ('\nyawing = { law = "harmonic", frequency = "100 rad/s", '
                      'amplitude = "1 rad/s" }')
    with pytest.raises(ConfigError, match=r"base\.yawing\.frequency"):
        base_frequency(small_system(tmp_path, two))


def test_banded_columns_on_the_paper_rotor():
    """The 84-DOF paper rotor takes the banded path (the column blocks written into band
    storage, compiled LU): its condensed operators equal the dense solve of the column
    blocks of ``column_operator`` (1e-10 rel.), and dR/dlam (one solve per column through
    the response) equals central differences (1e-6 rel.)."""
    from pathlib import Path

    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_system
    from rotorsfd.quasiperiodic.torus_columns import column_pattern, half_bandwidth

    root = Path(__file__).resolve().parents[2]
    system = build_system(load_config(root / "examples" / "paper_harmonic_pitching.toml"))
    problem = torus_problem(system)
    lat, lam = TorusLattice(2, 2), 700.0
    D, K = problem.coefficients(lam)
    beta = half_bandwidth(problem.M[None], D, K, *problem.dcoefficients(lam))
    assert column_pattern(problem.n_dof, 5, D.shape[0] - 1, beta).banded
    hb = TorusHB(problem, lat, 16, 16)
    C_paper = system.length_scale
    xs = np.random.default_rng(2).normal(size=(lat.n_real, problem.m)) * 0.1 * C_paper
    hb.set_shift(xs, lam)
    cond = hb.condenser.condense(lam, deriv=False)
    F = block_vectors(lat, problem.forcing(lam, lat))
    n, s = problem.n_dof, problem.nl_dofs
    for k1 in range(lat.H1 + 1):
        Z, _ = column_operator(problem, lat, k1, lam)
        p = 2 * lat.h(k1) + 1
        dl = hb.condenser.delta(k1)
        for r in range(p):
            Z[np.ix_(r * n + s, r * n + s)] += dl[r]
        rhs = np.zeros((p * n, p * s.size + 1), dtype=complex)
        rhs[(np.arange(p)[:, None] * n + s[None, :]).ravel(), np.arange(p * s.size)] = 1.0
        rhs[:, -1] = F[k1].ravel()
        ref = np.linalg.solve(Z, rhs)
        got = np.column_stack([cond.C[k1], cond.u[k1]])
        assert np.abs(got - ref).max() <= 1e-10 * np.abs(ref).max()
        assert np.abs(ref[:, :-1]).max() > 0
    _, _, dR = hb.residual(xs, lam)
    hl = 1e-6 * lam
    dfd = (hb.residual(xs, lam + hl, False)[0]
           - hb.residual(xs, lam - hl, False)[0]).ravel() / (2 * hl)
    assert np.abs(dR - dfd).max() < 1e-6 * np.abs(dR).max()
