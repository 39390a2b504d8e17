"""The reduced time step (timedomain/reduced.py): Craig-Bampton on the SFD DOFs plus the
fixed-interface modes up to a cutoff and the static load residuals, against the full step.

Tolerance: the default step's own error is about 1e-3 C (``step_tolerance``, one halving
of T/200); the reduction must stay far below it. Measured on the paper rotor at the default
cutoff 40 Omega: 2e-6 C in the transient from rest (100 periods) and 7e-7 C once settled
(300 periods; the same at T/800, so it is the reduction's, not the step's), 4e-6 C under
harmonic pitching with a 0.94 C orbit; asserted 5e-6 C and 2e-5 C (5e-3 and 2e-2 of the
step tolerance), and the difference must shrink when the cutoff is raised to 160 Omega
(more modes kept)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.simulate import run_simulation, system_from_config
from rotorsfd.analyses.td_integration import (
    integrate_periods,
    reduction_summary,
    time_domain_inputs,
    with_reduction,
)

ROOT = Path(__file__).resolve().parents[2]
W1 = 811.3          # first critical speed of the paper rotor [rad/s]


@pytest.fixture(scope="module")
def paper():
    system = system_from_config(api.load_config(ROOT / "examples" / "paper_rotor.toml"))
    return system, time_domain_inputs(system, 0.8 * W1)


def _orbit(inputs, system, periods: int, q0=None):
    rd = [0, 1, system.rotor.dof_index(8, "y"), system.rotor.dof_index(8, "z")]
    q0 = np.zeros(inputs.n_dof) if q0 is None else q0
    return integrate_periods(inputs, q0, 0.0, steps_per_period=200, periods=periods,
                             record_dofs=rd, record_periods=3, poincare_periods=30)


def test_basis_keeps_the_sfd_dofs_and_projects_exactly(paper) -> None:
    """Psi[nl] = [I 0]; P Psi = I (a recovered state re-enters exactly); the reduced static
    response to every load vector and to a boundary force is the full one (load
    residuals and constraint modes), against a dense solve of the full K."""
    inp = paper[1]
    red = with_reduction(inp, "auto", 40.0).reduction
    nl, m = inp.nl_dofs, inp.nl_dofs.size
    psi = red.basis
    np.testing.assert_array_equal(psi[nl, :m], np.eye(m))
    np.testing.assert_array_equal(psi[nl, m:], 0.0)
    np.testing.assert_allclose(red.projector @ psi, np.eye(red.n_dof), atol=1e-10)
    f = np.zeros(inp.n_dof)
    f[nl[0]] = 1e3                                   # a boundary force
    f += 0.7 * inp.forcing.harmonics[0].cos - 0.2 * inp.forcing.harmonics[0].sin
    q_full = np.linalg.solve(inp.K, f)
    q_red = red.physical(np.linalg.solve(red.model.K, psi.T @ f))
    assert np.max(np.abs(q_red - q_full)) < 1e-10 * np.max(np.abs(q_full))
    assert red.n_modes > 0 and red.n_residuals == 2 and red.n_dof < inp.n_dof / 4
    assert np.all(red.model.omegas <= 40.0 * inp.speed)


def test_paper_rotor_reduced_orbit_matches_full(paper) -> None:
    """Paper rotor, U = 0.1 oz in, Omega~ = 0.8, from rest, 100 periods x 200 steps: the
    SFD and disk orbits and the Poincare points of the reduced step within 5e-6 C of the
    full step (module docstring), closer at 160 Omega."""
    system, inp = paper
    C = system.length_scale
    full = _orbit(inp, system, 100)
    errs = {}
    for cut in (40.0, 160.0):
        red = _orbit(with_reduction(inp, "auto", cut), system, 100)
        errs[cut] = max(np.max(np.abs(red.q - full.q)),
                        np.max(np.abs(red.poincare_q - full.poincare_q))) / C
        np.testing.assert_allclose(red.q_final[inp.nl_dofs], full.q_final[inp.nl_dofs],
                                   atol=5e-6 * C, rtol=0)
    assert np.max(np.abs(full.q[:, :2])) > 0.05 * C          # a real orbit
    assert errs[40.0] < 5e-6, errs
    assert errs[160.0] < 0.5 * errs[40.0], errs


def test_moving_base_reduced_matches_full() -> None:
    """Harmonic pitching (5 rad/s at 123.4 rad/s, incommensurate with the speed) of the
    paper rotor at U = 144.02 g mm, Omega~ = 0.9: time-varying K_base(t), C_base(t) and
    base loads projected term by term; 60 periods from rest within 2e-5 C of the full
    step (an orbit of ~0.9 C), closer at 160 Omega."""
    cfg = api.load_config(ROOT / "examples" / "paper_rotor.toml", [
        'base.pitching={ law = "harmonic", amplitude = "5 rad/s", '
        'frequency = "123.4 rad/s" }', "unbalance[0].magnitude=144.02 g*mm"])
    system = system_from_config(cfg)
    C = system.length_scale
    speed = 0.9 * W1
    inp = time_domain_inputs(system, speed, horizon=100 * 2 * np.pi / speed)
    assert inp.time_varying is not None and inp.time_varying.n_terms > 0
    full = _orbit(inp, system, 60)
    errs = {}
    for cut in (40.0, 160.0):
        ri = with_reduction(inp, "auto", cut)
        assert ri.reduction.time_varying.n_terms == inp.time_varying.n_terms
        red = _orbit(ri, system, 60)
        errs[cut] = max(np.max(np.abs(red.q - full.q)),
                        np.max(np.abs(red.poincare_q - full.poincare_q))) / C
    assert np.max(np.abs(full.q[:, :2])) > 0.5 * C
    assert errs[40.0] < 2e-5, errs
    assert errs[160.0] < 0.5 * errs[40.0], errs


def test_chunked_and_restarted_runs_continue_exactly(paper) -> None:
    """A reduced run split in two (the second from the first's recovered physical state)
    is the unsplit run: the projector re-enters ``Psi p`` exactly."""
    system, inp = paper
    ri = with_reduction(inp, "auto", 40.0)
    rd = [0, 1]
    one = integrate_periods(ri, 0.0, 0.0, steps_per_period=100, periods=20, record_dofs=rd,
                            record_periods=1, poincare_periods=1)
    a = integrate_periods(ri, 0.0, 0.0, steps_per_period=100, periods=12, record_dofs=rd,
                          record_periods=1, poincare_periods=1)
    b = integrate_periods(ri, a.q_final, a.v_final, steps_per_period=100, periods=8,
                          record_dofs=rd, record_periods=1, poincare_periods=1, t0=a.t_final)
    C = system.length_scale
    np.testing.assert_allclose(b.q, one.q, atol=1e-12 * C, rtol=0)


def test_settings_report_the_reduction(tmp_path) -> None:
    """simulate's settings say what was stepped: "auto" the Craig-Bampton model with its
    cutoff, kept modes and DOFs; "none" the full model; a bad value names the field."""
    from rotorsfd.errors import ConfigError

    cfg = api.load_config(ROOT / "examples" / "paper_rotor.toml")
    kw = dict(speed_ratio=0.8, steps_per_period=100, periods=30, poincare_periods=10,
              lyapunov_periods=0, step_check_periods=5, progress=False)
    auto = run_simulation(cfg, **kw)
    none = run_simulation(cfg, reduction="none", **kw)
    s = auto.settings
    assert s["reduction"] == "craig-bampton" and s["reduction_cutoff"] == 40.0
    assert s["reduced_dof"] == 2 + s["reduction_modes"] + 2 < 84
    assert s["reduction_highest_mode_rad_s"] <= 40.0 * s["speed_rad_s"]
    assert none.settings["reduction"] == "none" and none.settings["reduced_dof"] == 84
    # the run's own check: 5 periods from its final state against the full step; the
    # full model starts there without its dropped modes' dynamic part and keeps their
    # free vibration (measured 1.4e-5 C, 1.3e-5 at T/200; the settled orbits: 7e-7 C)
    assert s["reduction_check_reference"] == "full step" and s["reduction_check_periods"] == 5
    assert 0.0 < s["reduction_check"] < 5e-5
    assert "reduction_check" not in none.settings
    C = auto.clearance
    # 30 periods after the 1 um start, whose high-mode part the projection drops
    # (measured 1.3e-5 C; it decays: 2.7e-6 C after 300 periods)
    assert np.max(np.abs(auto.q - none.q)) < 4e-5 * C
    with pytest.raises(ConfigError, match="reduction"):
        with_reduction(time_domain_inputs(system_from_config(cfg), 650.0), "modal")
    assert reduction_summary(time_domain_inputs(system_from_config(cfg), 650.0))[
        "reduction"] == "none"


def test_sparse_craig_bampton_equals_the_dense_one(paper) -> None:
    """The CSR path of large models (shift-invert Lanczos, sparse LU) against
    :func:`~rotorsfd.stability.reduction.craig_bampton` on the paper rotor: the same
    constraint modes (1e-12), kept frequencies (1e-9) and, the subspace being the same,
    the same eigenvalues of the reduced gyroscopic pencil (1e-9), whatever the modes'
    signs and rotations within a pair."""
    import scipy.linalg as sla
    import scipy.sparse as sp

    from rotorsfd.stability.reduction import craig_bampton
    from rotorsfd.timedomain.reduced import sparse_craig_bampton

    inp = paper[1]
    wmax = 40.0 * inp.speed
    dense = craig_bampton(inp.M, inp.D, inp.K, inp.nl_dofs, omega_max=wmax)
    sparse = sparse_craig_bampton(*(sp.csr_matrix(a) for a in (inp.M, inp.D, inp.K)),
                                  inp.nl_dofs, wmax)
    m = inp.nl_dofs.size
    assert sparse.n_dof == dense.n_dof > m + 4
    np.testing.assert_allclose(sparse.basis[:, :m], dense.basis[:, :m], atol=1e-12, rtol=0)
    np.testing.assert_allclose(sparse.omegas, dense.omegas, rtol=1e-9)

    def roots(r):
        n = r.n_dof
        A = np.block([[np.zeros((n, n)), np.eye(n)],
                      [-np.linalg.solve(r.M, r.K), -np.linalg.solve(r.M, r.D)]])
        lam = sla.eigvals(A)
        return lam[np.lexsort((lam.real, lam.imag))]

    np.testing.assert_allclose(roots(sparse), roots(dense), rtol=1e-9)


def test_free_interior_falls_back_to_the_full_step(paper) -> None:
    """An interior DOF with no stiffness once the nonlinear DOFs are fixed (exactly zero,
    or 1e-20 of the others: a mechanism) has no Craig-Bampton model, so "auto" steps the
    full model; with it stiff, the same model is reduced (3 stiff modes dropped)."""
    from dataclasses import replace

    from rotorsfd.timedomain import Forcing, HarmonicLoad

    inp = paper[1]
    forcing = Forcing(omega=100.0, harmonics=[HarmonicLoad(1.0, np.eye(6)[0])])
    for k2, reduced in ((0.0, False), (1e-20, False), (1e4, True)):
        K = np.diag([1e6, 1e6, k2, 1e8, 1e8, 1e8])
        small = replace(inp, M=np.eye(6), D=1e-3 * np.eye(6), K=K,
                        nl_dofs=np.array([0, 1]), forcing=forcing, time_varying=None,
                        speed=100.0)
        red = with_reduction(small, "auto", 40.0).reduction
        assert (red is not None) == reduced, k2
        if reduced:
            assert red.n_dof == 3 and red.n_modes == 1
