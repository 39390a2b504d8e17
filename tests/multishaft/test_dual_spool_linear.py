"""Linear analyses of a dual-spool rotor (issue 20 items 2, 3, 5) against the closed form of
two Jeffcott-like shafts coupled at their disks (dual_jeffcott.py): the modes against the
speed of either spool, the critical speeds of each spool's unbalance, and the two-frequency
unbalance response by the torus and by time integration."""

from __future__ import annotations

import numpy as np
import pytest
from dual_jeffcott import HP, LP, RATIO, rotor, translation_frequencies, translation_response

from rotorsfd.linear.campbell import campbell
from rotorsfd.linear.critical import line_critical_speeds
from rotorsfd.model.multishaft import SpoolSpeed
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance

U_LP, U_HP = 2e-4, 1.5e-4       # kg m (200 g mm, 150 g mm)


def closed_form_frequencies(lp_speed: float) -> np.ndarray:
    """The 8 lowest frequencies at the LP speed: the coupled translations (y and z alike)
    and each disk's tilt pair at its own shaft's speed."""
    return np.sort(np.concatenate([np.repeat(translation_frequencies(), 2), LP.tilt(lp_speed),
                                   HP.tilt(RATIO * lp_speed)]))


@pytest.mark.parametrize("spool", ["lp", "hp"])
def test_campbell_against_either_spool_is_the_closed_form(spool: str) -> None:
    view = SpoolSpeed(rotor(damped=False), spool)
    speeds = np.array([0.0, 400.0, 1500.0, 3000.0])       # of the spool asked for
    res = campbell(view, speeds, n_modes=8)
    for k, s in enumerate(speeds):
        lp_speed = s / view.ratio
        ref = closed_form_frequencies(lp_speed)
        np.testing.assert_allclose(np.sort(res.frequencies[k]), ref, rtol=5e-8)
    # the speed matters: the diagram's top frequency (a forward tilt) rises by > 20 %
    assert res.frequencies[-1].max() > 1.2 * res.frequencies[0].max()


def test_critical_speeds_of_each_spools_unbalance_are_the_closed_form() -> None:
    """Against the LP speed: the LP line w = Omega_LP meets the translations at w_i and
    the forward tilts at sqrt(k_t / (Id - Ip r_s)); the HP line w = r Omega_LP at w_i / r
    and sqrt(k_t / (r (Id r - Ip r_s)))."""
    view = SpoolSpeed(rotor(damped=False), "lp")
    lines = {"lp": view.harmonic("lp"), "hp": view.harmonic("hp")}
    assert lines == {"lp": 1.0, "hp": pytest.approx(RATIO)}
    found = line_critical_speeds(view, lines, n=4, whirl="forward", speed_range=(0.0, 3000.0),
                                 n_grid=61, xtol=1e-10)
    wt = translation_frequencies()
    for name, h in lines.items():
        ref = np.sort(np.concatenate([wt / h, [LP.tilt_critical(h, 1.0),
                                               HP.tilt_critical(h, RATIO)]]))
        ref = ref[ref < 3000.0][:4]
        got = np.array([c.speed_rad_s for n, c in found if n == name])
        assert got.size == ref.size >= 3
        np.testing.assert_allclose(got, ref, rtol=5e-8)
    speeds = [c.speed_rad_s for _, c in found]
    assert speeds == sorted(speeds)


def _system(damped: bool = True) -> RotorSystem:
    return RotorSystem(rotor(damped=damped), (), [Unbalance(2, U_LP), Unbalance(5, U_HP, 0.7)])


def _closed_form(speed: float) -> tuple[np.ndarray, np.ndarray]:
    """The disks' y amplitudes at the LP line (1, 0) and the HP line (0, 1)."""
    w_hp = RATIO * speed
    lp = translation_response(speed, np.array([U_LP * speed**2, 0.0]))
    hp = translation_response(w_hp, np.array([0.0, U_HP * w_hp**2 * np.exp(0.7j)]))
    return lp, hp


def test_linear_torus_is_the_closed_form_response() -> None:
    from rotorsfd.quasiperiodic import TorusLattice, solve_torus
    from rotorsfd.quasiperiodic.dual_frequency import dual_spool_problem

    system = _system()
    problem = dual_spool_problem(system)
    assert problem.frequencies(300.0) == (300.0, pytest.approx(RATIO * 300.0))
    for speed in (300.0, 620.0):            # near the first LP and HP criticals
        sol = solve_torus(problem, speed, TorusLattice(2, 2))
        lat = sol.lattice
        lp, hp = _closed_form(speed)
        y = [4, 16]                                        # y of nodes 2 and 5
        for k, ref in (((1, 0), lp), ((0, 1), hp)):
            X = sol.X[lat.index(*k)]
            np.testing.assert_allclose(X[y], ref, rtol=1e-7)
            np.testing.assert_allclose(X[[5, 17]], -1j * ref, rtol=1e-7)   # z = -i y
        rest = [i for i, k in enumerate(lat.k) if tuple(k) not in ((1, 0), (0, 1))]
        assert np.abs(sol.X[rest]).max() < 1e-12 * np.abs(sol.X).max()


def test_time_integration_runs_each_unbalance_at_its_own_speed() -> None:
    """From the closed-form state at t = 0 (disks; the massless rest from the torus, which
    the test above checks), 30 LP periods of Newmark stay on the closed-form motion."""
    from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs
    from rotorsfd.quasiperiodic import TorusLattice, solve_torus
    from rotorsfd.quasiperiodic.dual_frequency import dual_spool_problem
    from rotorsfd.quasiperiodic.torus_stability import torus_state

    system = _system()
    speed = 620.0
    inputs = time_domain_inputs(system, speed)
    assert sorted(h.multiple for h in inputs.forcing.harmonics) == [1.0, RATIO]
    sol = solve_torus(dual_spool_problem(system), speed, TorusLattice(1, 1))
    q0, v0 = torus_state(sol.lattice, sol.X, speed, RATIO * speed)
    run = integrate_periods(inputs, q0, v0, steps_per_period=800, periods=30,
                            record_dofs=[4, 16], record_periods=30, poincare_periods=1)
    lp, hp = _closed_form(speed)
    t = run.t
    ref = (np.exp(1j * speed * t)[:, None] * lp[None]
           + np.exp(1j * RATIO * speed * t)[:, None] * hp[None]).real
    scale = np.abs(ref).max()
    assert np.abs(run.q - ref).max() < 5e-4 * scale     # Newmark's phase error, growing in t
