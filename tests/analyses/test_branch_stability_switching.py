"""Period doubling on a forced oscillator with quadratic and cubic stiffness (subharmonic
resonance of order 1/2 near w = 2): HB + Floquet locate the PD pair, branch switching
continues the period-2 branch, whose w/2 amplitude matches time integration (solve_ivp)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorsfd.harmonic.branch_switching import (
    doubled_coefficients,
    period_doubled,
    switch_period_doubling,
)
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.branch_stability import branch_stability

C, B, K3, F = 0.05, 0.5, 0.5, 0.5


def oscillator(c: float = C, k3: float = K3, amp: float = F) -> PeriodicProblem:
    """``x'' + c x' + x + b x^2 + k3 x^3 = F cos(w t)``, lam = w."""
    M, D, K, Z = np.eye(1), np.array([[c]]), np.eye(1), np.zeros((1, 1))

    def forcing(lam: float, H: int) -> np.ndarray:
        f = np.zeros((H + 1, 1), complex)
        f[1, 0] = amp
        return f

    return PeriodicProblem(
        n_dof=1, nl_dofs=np.array([0]), matrices=lambda lam: (M, D, K),
        dmatrices=lambda lam: (Z, Z, Z), forcing=forcing,
        dforcing=lambda lam, H: np.zeros((H + 1, 1), complex), frequency=lambda lam: lam,
        dfrequency=lambda lam: 1.0, nl_force=lambda q, v: -B * q**2 - k3 * q**3,
        nl_jacobian=lambda q, v: ((-2 * B * q - 3 * k3 * q**2)[..., None],
                                  np.zeros((*q.shape, 1))), name="quadratic-cubic oscillator")


def time_domain_subharmonic(w: float, y0: tuple[float, float], periods: int = 300) -> complex:
    """w/2 Fourier coefficient of x(t) over the last 20 periods 2T after ``periods``."""
    def rhs(t, y):
        x, v = y
        return [v, F * np.cos(w * t) - C * v - x - B * x**2 - K3 * x**3]

    T2 = 4 * np.pi / w
    sol = solve_ivp(rhs, (0, periods * T2), list(y0), method="DOP853", rtol=1e-10,
                    atol=1e-12, dense_output=True)
    t = np.linspace((periods - 20) * T2, periods * T2, 20 * 256, endpoint=False)
    return complex(2 * np.mean(sol.sol(t)[0] * np.exp(-0.5j * w * t)))


@pytest.fixture(scope="module")
def case():
    p = oscillator()
    branch = continue_periodic(p, 1.6, 2.4, 7, ds=0.05, ds_max=0.1)
    st = branch_stability(branch, p)
    return p, branch, st


def test_period_doubling_pair_located(case):
    _, branch, st = case
    assert [b.kind for b in st.bifurcations] == ["period-doubling", "period-doubling"]
    for row, b in zip(st.rows(), st.bifurcations, strict=True):
        assert row["multiplier_re"] < -1 - st.tol and row["multiplier_im"] == 0.0
        assert abs(b.critical + 1) < 5e-3          # -1 at the located point
        ia, ib = b.info["bracket"]
        assert min(branch.lam[ia], branch.lam[ib]) <= b.lam <= max(branch.lam[ia],
                                                                     branch.lam[ib])
    lo, hi = (b.lam for b in st.bifurcations)
    x = branch.lam
    assert np.all(~st.stable[(x > lo) & (x < hi)]) and np.all(st.stable[(x < lo) | (x > hi)])


def test_period_one_solution_solves_the_period_two_equations(case):
    p, branch, _ = case
    X2 = doubled_coefficients(branch.X[3])
    sol = solve_periodic(period_doubled(p), branch.lam[3], 2 * branch.H, X2, tol=1e-10)
    assert sol.iterations <= 1
    assert np.abs(sol.X[1::2]).max() < 1e-10          # no odd harmonic of w/2
    np.testing.assert_allclose(sol.X[0::2], X2[0::2], atol=1e-9)


def test_switch_to_the_period_two_branch_matches_time_integration(case):
    p, branch, st = case
    pd = st.bifurcations[0]
    pt = branch.point_at(pd.s)
    sw = switch_period_doubling(p, pt.lam, pt.X, (1.9, 2.1), delta=0.01, ds_max=0.05)
    assert sw.singular_value < 1e-8 and sw.coupling < 1e-12
    assert abs(sw.lam_bifurcation - pd.lam) < 1e-4     # HB PD (4H harmonics) = monodromy's
    leg = sw.legs[0]
    assert leg.success and len(sw.legs) == 1
    assert abs(leg.lam[0] - pd.lam) < 1e-3 and sw.subharmonic_amplitude(0)[0] < 0.05
    st2 = branch_stability(leg, sw.problem)
    assert st2.stable.all() and not st2.bifurcations   # supercritical: a stable branch
    w = 2.0                                            # period-1 unstable here
    i = int(np.argmin(np.abs(leg.lam - w)))
    X2 = solve_periodic(sw.problem, w, leg.H, leg.X[i], tol=1e-10).X
    assert abs(X2[1, 0]) > 0.3                         # a real period-2 orbit
    x0 = float(X2[:, 0].real.sum())
    v0 = float((0.5j * w * np.arange(leg.H + 1) * X2[:, 0]).real.sum())
    for y0 in ((x0 + 1e-3, v0), (0.0, 0.0)):           # near the orbit, and from rest
        a = time_domain_subharmonic(w, y0)
        assert abs(abs(a) - abs(X2[1, 0])) < 1e-7 * abs(X2[1, 0])


def test_subcritical_period_doubling_continues_past_the_fold():
    """Stronger forcing and damping (c 0.1, k3 0.1, F 1): the period-2 branch leaves the
    lower PD backwards (subcritical, unstable), folds and comes back stable: two legs."""
    p = oscillator(c=0.1, k3=0.1, amp=1.0)
    branch = continue_periodic(p, 1.4, 3.5, 7, ds=0.05, ds_max=0.1)
    pd = branch_stability(branch, p).bifurcations[0]
    assert pd.kind == "period-doubling"
    pt = branch.point_at(pd.s)
    sw = switch_period_doubling(p, pt.lam, pt.X, (1.4, 2.6))
    leg = sw.legs[0]
    assert len(sw.legs) == 2 and leg.lam[0] < pd.lam          # subcritical
    assert len(leg.folds()) >= 1 and leg.lam.min() < pd.lam - 0.05
    st = branch_stability(leg, sw.problem)
    assert not st.stable[0]                                    # born unstable
    assert st.bifurcations[0].kind == "saddle-node"            # regains stability at a fold
    assert st.stable[leg.folds()[0] + 2:].any()
    np.testing.assert_allclose(sw.legs[1].X[0], leg.X[-1])     # second leg starts there
    # the first leg stopped because it went back past its own first point, inside the
    # requested range (1.4, 2.6): the message says that, not "out of the range"
    assert "went above the start of its range" in leg.message
    assert "out of the range" not in leg.message and "turned back at a fold" in sw.message


def test_period_two_bubble_closes_at_the_second_period_doubling(case):
    """Over the whole range the period-2 branch born at the lower PD folds at w ~ 2.136 and
    ends on the period-1 branch at the upper PD (the branch and its T-shifted mirror are a
    closed bubble): traced once, ``closed``, rejoining where the monodromy says; its
    multipliers over 2T (``stability``) are +1 at the fold and at the upper PD."""
    p, branch, st = case
    pd1, pd2 = st.bifurcations
    pt = branch.point_at(pd1.s)
    sw = switch_period_doubling(p, pt.lam, pt.X, (1.6, 2.4), delta=0.01, ds_max=0.05)
    assert sw.closed and len(sw.legs) == 1 and "closed bubble" in sw.message
    assert abs(sw.lam_rejoin - pd2.lam) < 2e-3
    assert abs(sw.lam.max() - 2.1358) < 1e-3                    # the fold
    (s2,) = sw.stability()
    folds = sorted(b.lam for b in s2.bifurcations if b.kind == "saddle-node")
    assert abs(folds[0] - pd2.lam) < 1e-3 and abs(folds[-1] - 2.1358) < 1e-3
    lower = sw.lam < pd2.lam - 0.01
    amp = sw.subharmonic_amplitude(0)
    assert s2.stable[lower & (amp > 0.05)].all()                # stable from the lower PD
