"""Period-2 branch of the paper case examples/paper_clearance.toml (C/R 0.728 %, U = 252
g mm, pitching 10 rad/s) switched from the period-1 branch's first period doubling at
H = 12 (Omega/Omega_ref ~ 1.0331), against the time domain at 1.04, where the period-1
orbit is unstable and the integrator settles on a period-2 orbit.

The time domain needs a fine step there (|X_1| of the journal at 200 / 400 / 800 / 1600
steps per period: 0.0044 / 0.0056 / 0.0061 / 0.0065 C for y): the reference is 1600."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.simulate import run_simulation, system_from_config
from rotorsfd.harmonic.branch_switching import switch_period_doubling
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.stability.branch_stability import branch_stability

pytestmark = pytest.mark.slow

CFG = "examples/paper_clearance.toml"
C = 0.127e-3


def test_period_two_branch_agrees_with_the_time_domain():
    cfg = api.load_config(CFG, [])
    td = run_simulation(cfg, speed_ratio=1.04, steps_per_period=1600, poincare_periods=20,
                        record_periods=20, lyapunov_periods=0, progress=False)
    assert td.motion_name == "period-2"
    ref = td.speed / 1.04
    p = system_from_config(cfg).periodic_problem()
    b1 = continue_periodic(p, 0.98 * ref, 1.045 * ref, 12, limit_max=0.995, tol=1e-8)
    pds = [b for b in branch_stability(b1, p).bifurcations if b.kind == "period-doubling"]
    assert abs(pds[0].lam / ref - 1.0331) < 5e-4
    pt = b1.point_at(pds[0].s)
    sw = switch_period_doubling(p, pt.lam, pt.X, (0.98 * ref, 1.12 * ref), delta=0.02,
                                limit_max=0.995)
    assert sw.legs[0].H == 48                                  # 4 H harmonics of w/2
    # the PDs of the period-2 HB equations: where the period-1 branch at H = 24-32 has
    # them by the monodromy matrix (1.0358, 1.0494), not at H = 12's 1.0331 / 1.0538
    assert abs(sw.lam_bifurcation / ref - 1.0356) < 5e-4
    assert sw.closed and abs(sw.lam_rejoin / ref - 1.0479) < 5e-4
    (st,) = sw.stability()
    leg = sw.legs[0]
    i = int(np.argmin(np.abs(leg.lam - td.speed)))
    assert st.stable[i]                                        # stable where the TD settles
    X2 = solve_periodic(sw.problem, td.speed, leg.H, leg.X[i], tol=1e-8,
                        limit_max=0.995).X[:, p.nl_dofs]
    # Poincare points of the HB period-2 orbit (t = 0 and T) against the time domain's
    k = np.arange(leg.H + 1)
    t = np.array([0.0, 2 * np.pi / td.speed])
    hb = (np.exp(0.5j * td.speed * np.outer(t, k)) @ X2).real / C
    j = td.column(td.element_node)
    pq = td.poincare_q[-2:, j, :] / C
    assert np.linalg.norm(pq[0] - pq[1]) > 0.03                 # a real period 2
    for q in pq:
        assert np.min(np.linalg.norm(hb - q, axis=1)) < 2e-3    # C
    # Omega/2 amplitude of the journal
    tt, q = td.t, td.q[:, j, :]
    T2 = 4 * np.pi / td.speed
    n2 = int(np.floor((tt[-1] - tt[0]) / T2 - 1e-9))
    keep = tt >= tt[-1] - n2 * T2 - 1e-12
    tt, q = tt[keep][:-1], q[keep][:-1]
    a_td = np.abs(2 * np.mean(q * np.exp(-0.5j * td.speed * tt)[:, None], axis=0)) / C
    a_hb = np.abs(X2[1]) / C
    np.testing.assert_allclose(a_td, a_hb, rtol=0.04)
