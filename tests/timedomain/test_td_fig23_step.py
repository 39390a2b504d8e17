"""The Figure 23 case (examples/paper/fig23_time_domain.toml: C/R = 0.728 %, U = 252 g mm,
w_by = 10 rad/s, H = 16) with the automatic step: what T/200 calls quasi-periodic at
Omega~ 1.07 is period-1 at the converged step, on the main branch and on the isola, and
the class agrees with Floquet; the isola's period-3 motion at 1.062 matches an
independent integration of the same equations (scipy DOP853, rtol 1e-8: the same points
to 1e-6 C as rtol 1e-10) to 2e-3 C.

Independent numbers (issue 26, own model + DOP853 at rtol 1e-10): the isola's Poincare
point at 1.075 (-0.2235, -0.9022) C; Floquet |mu|max 0.88-0.89 at 1.07 on the isola.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorsfd import api
from rotorsfd.analyses.orbit_branch import orbit_start
from rotorsfd.analyses.simulate import (
    hb_state,
    integrate_periods,
    run_simulation,
    system_from_config,
    time_domain_inputs,
)
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.model.dofs import dof_index
from rotorsfd.model.sfd_kernels import P_EPS_MAX
from rotorsfd.stability.branch_stability import FloquetEvaluator

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]
FIG23 = ROOT / "examples" / "paper" / "fig23_time_domain.toml"
# the schema default, written out: the example file may pin a fixed step of its own
AUTO = ["analysis.response.harmonics=16", 'analysis.simulate.steps_per_period="auto"']


@pytest.fixture(scope="module")
def case():
    config = api.load_config(FIG23, AUTO)
    system = system_from_config(config)
    return config, system, api.reference_speed(config, system)


def _floquet_of_orbit(system, result, H: int = 16):
    """HB solution through the run's last period (fit + Newton) and its multipliers."""
    problem = system.periodic_problem()
    sol, _, gap = orbit_start(problem, result, H)
    return FloquetEvaluator(problem)(result.speed, sol.X), gap


def _agrees_with_floquet(result, floquet) -> None:
    """A stable orbit (Floquet) is period-1 in the time domain, and its Lyapunov exponent
    (neutral high modes excluded) is negative within its uncertainty and equals
    ln |mu|max per period within the uncertainty plus 0.03."""
    assert floquet.stable and floquet.max_abs < 0.99
    assert result.motion_name == "period-1"
    ly = result.lyapunov
    err = ly.half_spread * result.period
    assert ly.per_period + err < 0.0
    assert abs(ly.per_period - math.log(floquet.max_abs)) < err + 0.03


def test_readme_start_at_1_07_is_period_1_by_default(case) -> None:
    """The README's start (HB orbit shifted by half a period) at 1.07: T/200 gives a torus;
    the automatic step converges (last halving < 1e-3 C) and the motion is period-1,
    stable by Floquet on the HB orbit through it."""
    config, system, _ = case
    r = run_simulation(config, speed_ratio=1.07, from_hb=True, hb_phase=0.5,
                       progress=False)
    ctl = r.step_check
    assert ctl.mode == "auto" and ctl.converged and ctl.steps_per_period >= 800
    assert r.motion_name == "period-1", r.summary()
    floquet, gap = _floquet_of_orbit(system, r)
    assert gap < 0.02                     # the H = 16 orbit is the time-domain orbit
    _agrees_with_floquet(r, floquet)


@pytest.fixture(scope="module")
def isola(case):
    """The isola's HB orbit at 1.07: found at T/200 from the shifted HB start at 1.075
    (where that step lands near the second attractor), fitted, HB-corrected, then moved
    to 1.07 by Newton; the time domain from it at 1.07 and from its end at 1.062."""
    config, system, ref = case
    find = run_simulation(config, speed_ratio=1.075, from_hb=True, hb_phase=0.5,
                          steps_per_period=200, lyapunov_periods=0, progress=False)
    C = system.length_scale
    assert find.poincare_q[-1, 0] / C == pytest.approx([-0.241, -0.901], abs=0.01)
    problem = system.periodic_problem()
    sol, _, _ = orbit_start(problem, find, 16)
    X = solve_periodic(problem, 1.07 * ref, 16, sol.X).X
    q0, v0 = hb_state(X, 1.07 * ref)
    r107 = run_simulation(config, speed_ratio=1.07, q0=q0, v0=v0, progress=False)
    r1062 = run_simulation(config, speed_ratio=1.062, q0=r107.q_final, v0=r107.v_final,
                           lyapunov_periods=0, progress=False)
    return X, r107, r1062


def test_isola_at_1_07_is_period_1_and_agrees_with_floquet(case, isola) -> None:
    """On the isola (Poincare point about (-0.09, -0.92) C, far from the main branch's
    (0.27, -0.83) C): period-1 at the converged step, Floquet |mu|max 0.88-0.89."""
    _, system, ref = case
    X, r, _ = isola
    C = system.length_scale
    assert r.step_check.converged
    assert r.poincare_q[-1, 0] / C == pytest.approx([-0.093, -0.920], abs=0.01)
    floquet = FloquetEvaluator(system.periodic_problem())(1.07 * ref, X)
    assert 0.85 < floquet.max_abs < 0.92
    _agrees_with_floquet(r, floquet)


def _dop853_poincare(inputs, q0, v0, t0: float, periods: int, rtol: float,
                     clearance: float) -> np.ndarray:
    """Journal Poincare points of ``M q'' + D q' + K q = f(t) + F_sfd(q, v)`` by DOP853
    (first-order form, M inverted; the film force from the model's kernel, its contact
    limit raised from eps 0.999 to 1 - 1e-9: the orbit reaches 0.994 and DOP853's trial
    stages pass 0.999, and beyond the clearance)."""
    n = inputs.M.shape[0]
    nl = np.asarray(inputs.nl_dofs)
    Minv = np.linalg.inv(inputs.M)
    A = np.zeros((2 * n, 2 * n))
    A[:n, n:] = np.eye(n)
    A[n:, :n], A[n:, n:] = -Minv @ inputs.K, -Minv @ inputs.D
    fo = inputs.forcing
    f0 = Minv @ fo.constant
    fc, fs = Minv @ fo.harmonics[0].cos, Minv @ fo.harmonics[0].sin
    B = Minv[:, nl]
    w = fo.omega
    F, jq, jv = np.zeros(nl.size), np.zeros((nl.size,) * 2), np.zeros((nl.size,) * 2)
    params = np.array(inputs.params, dtype=float)
    params[P_EPS_MAX] = 1.0 - 1e-9
    stages = [0]

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = np.ascontiguousarray(y[nl]), np.ascontiguousarray(y[n + nl])
        if inputs.kernel(q, v, params, F, jq, jv):
            # a trial stage beyond the clearance (never an accepted state, checked
            # below): the film force at eps = 1 - 1e-6 on the same ray, huge, so that
            # the step is rejected
            q = q * ((1.0 - 1e-6) * clearance / math.hypot(*q))
            if inputs.kernel(np.ascontiguousarray(q), v, params, F, jq, jv):
                raise FloatingPointError("journal contact")
            stages[0] += 1
        out = A @ y
        out[n:] += f0 + fc * math.cos(w * t) + fs * math.sin(w * t) + B @ F
        return out

    T = 2 * math.pi / w
    t_eval = t0 + T * np.arange(1, periods + 1)
    scale = np.concatenate([np.full(n, clearance), np.full(n, clearance * w)])
    sol = solve_ivp(rhs, (t0, t_eval[-1]), np.concatenate([q0, v0]), method="DOP853",
                    rtol=rtol, atol=rtol * scale, t_eval=t_eval, dense_output=True)
    assert sol.success, sol.message
    y = sol.sol(np.linspace(t0, t_eval[-1], 3000 * periods))[nl[:2]]
    assert np.max(np.hypot(*y)) / clearance < 0.999      # the accepted motion
    return sol.y[nl[:2]].T / clearance


def test_isola_period_3_at_1_062_matches_dop853(case, isola) -> None:
    """1.062 from the isola's 1.07 state: period-3 (three points > 3e-3 C apart) at the
    automatic step; from its final state the next three periods at that step and by
    DOP853 (rtol 1e-8) give the same Poincare points to 2e-3 C."""
    _, system, _ = case
    _, _, r = isola
    C = system.length_scale
    assert r.motion_name == "period-3" and r.step_check.converged, r.summary()
    last = r.poincare_q[-3:, 0] / C
    assert min(np.hypot(*(last[i] - last[j])) for i, j in ((0, 1), (1, 2), (0, 2))) > 3e-3
    inputs = time_domain_inputs(system, r.speed)
    spp = r.step_check.steps_per_period
    ours = integrate_periods(inputs, r.q_final, r.v_final, steps_per_period=spp, periods=3,
                             record_dofs=[dof_index(1, "y"), dof_index(1, "z")],
                             record_periods=1, poincare_periods=3, t0=r.t_final)
    ref_pts = _dop853_poincare(inputs, r.q_final, r.v_final, r.t_final, 3, 1e-8, C)
    gap = np.max(np.hypot(*(ours.poincare_q / C - ref_pts).T))
    assert gap < 2e-3
    # and the period-3 cycle repeats: three periods on land near the recorded points
    assert np.max(np.hypot(*(ref_pts - last).T)) < 2e-3
