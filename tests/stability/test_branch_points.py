"""Branch points of periodic orbits against closed forms (Mathieu characteristic values)
and a second method (shooting), and a fold that must not be typed as one.

The case (derived here): a linear forced oscillator y'' + c_y y' + k_y y = F cos(w t)
pumps an undamped nonlinear one, x'' + (1 + kappa y^2) x + alpha x^2 + g x^3 = 0. On the
orbit x = 0 (y(t) = Re(Y e^{i w t}), |Y| = F / |k_y - w^2 + i c_y w|) a perturbation of x
obeys x'' + (1 + e + e cos(2 w t + 2 phi)) x = 0 with e = kappa |Y|^2 / 2, i.e. Mathieu's
equation x_zz + (a - 2 q cos 2z) x = 0 in z = w t + phi, a = (1 + e) / w^2,
q = -e / (2 w^2). Its T-periodic solutions (period 2 pi in z: ce_1, se_1 at
a = a_1(|q|), b_1(|q|); ce_2, se_2 at a_2(|q|), b_2(|q|)) are where the x = 0 branch
meets a second one: branch points, exactly (the HB of the x = 0 orbit is exact: y is
linear). The symmetry x -> -x makes every one a pitchfork when alpha = 0; with alpha != 0
the ce_2 edge (the mode has a mean and 2w: x^2 projects back on it) is transcritical, the
se_2 edge (sin 2z, sin 4z: x^2 has no such part) stays a pitchfork.
"""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq, fsolve
from scipy.special import mathieu_a, mathieu_b

from rotorsfd.harmonic.examples import duffing
from rotorsfd.harmonic.orbit_branch import continue_both_ways
from rotorsfd.harmonic.periodic import BORDERED, continue_periodic
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.bifurcations import BranchSample
from rotorsfd.stability.branch_points import (
    bordered_tests,
    branch_system,
    stored_signs,
    switch_branch_point,
)
from rotorsfd.stability.branch_stability import (
    FloquetEvaluator,
    StabilityOptions,
    branch_stability,
    located_critical,
    reported_kind,
)
from rotorsfd.stability.branch_typing import branch_point_scan, type_branch_points

KY, CY, KAPPA, G3, H = 4.0, 0.2, 1.0, 1.0, 8


def pumped(F: float = 1.0, alpha: float = 0.0) -> PeriodicProblem:
    """DOFs (x, y), lam = w (module docstring)."""
    M, D, K, Z = np.eye(2), np.diag([0.0, CY]), np.diag([1.0, KY]), np.zeros((2, 2))

    def forcing(lam: float, h: int) -> np.ndarray:
        f = np.zeros((h + 1, 2), complex)
        f[1, 1] = F
        return f

    def force(q, v):
        x, y = q[..., 0], q[..., 1]
        return np.stack([-KAPPA * y**2 * x - alpha * x**2 - G3 * x**3, np.zeros_like(x)], -1)

    def jacobian(q, v):
        x, y = q[..., 0], q[..., 1]
        Jq = np.zeros((*q.shape[:-1], 2, 2))
        Jq[..., 0, 0] = -KAPPA * y**2 - 2 * alpha * x - 3 * G3 * x**2
        Jq[..., 0, 1] = -2 * KAPPA * y * x
        return Jq, np.zeros_like(Jq)

    return PeriodicProblem(
        n_dof=2, nl_dofs=np.array([0, 1]), matrices=lambda lam: (M, D, K),
        dmatrices=lambda lam: (Z, Z, Z), forcing=forcing,
        dforcing=lambda lam, h: np.zeros((h + 1, 2), complex), frequency=lambda lam: lam,
        dfrequency=lambda lam: 1.0, nl_force=force, nl_jacobian=jacobian,
        name="pumped Mathieu oscillator")


def mathieu_edge(F: float, edge, lo: float, hi: float) -> float:
    """The w in [lo, hi] where a(w) = edge(|q(w)|) (module docstring)."""
    def gap(w: float) -> float:
        e = KAPPA * (F / abs(KY - w**2 + 1j * CY * w)) ** 2 / 2
        return (1 + e) / w**2 - edge(e / (2 * w**2))
    return brentq(gap, lo, hi, xtol=1e-14)


@pytest.fixture(scope="module")
def first_tongue():
    p = pumped()
    branch = continue_periodic(p, 0.8, 1.6, H, ds=0.02, ds_max=0.05)
    return p, branch, branch_stability(branch, p)


def test_pitchforks_where_mathieu_says(first_tongue):
    *_, st = first_tongue
    assert [reported_kind(b) for b in st.bifurcations] == ["pitchfork", "pitchfork"]
    exact = [mathieu_edge(1.0, lambda q: mathieu_a(1, q), 1.0, 1.03),
             mathieu_edge(1.0, lambda q: mathieu_b(1, q), 1.03, 1.06)]
    for b, w in zip(st.bifurcations, exact, strict=True):
        assert b.lam == pytest.approx(w, rel=1e-9)          # measured 4e-12
        # the Floquet crossing (Newmark, 200 intervals) next to it, and +1 there
        assert b.info["floquet_lam"] == pytest.approx(w, rel=1e-4)
        assert abs(located_critical(b) - 1.0) < 1e-3
        assert b.info["second_slope"] < 1e-6               # the second branch: lam' = 0
    assert [r["type"] for r in st.rows()] == ["pitchfork", "pitchfork"]


def test_second_branch_both_ways_is_a_mirror_pair_and_a_periodic_orbit(first_tongue):
    p, _, st = first_tongue
    point = st.bifurcations[0].info["branch_point"]
    sw = switch_branch_point(p, point, (0.8, 1.6), delta=0.02, ds_max=0.05)
    a, b = sw.legs
    assert a.success and b.success
    for leg in sw.legs:   # starts at the branch point, on its right (hardening x)
        assert leg.lam[0] == pytest.approx(point.lam, abs=1e-3)
        assert np.all(leg.lam >= point.lam)
        assert abs(leg.X[0, 1, 0]) == pytest.approx(0.02, rel=0.01)   # |x_1| = delta
    # x -> -x: the two legs are one orbit family's mirror images
    assert np.max(np.abs(a.X[:, :, 0] + b.X[:, :, 0])) < 1e-10
    assert np.max(np.abs(a.lam - b.lam)) < 1e-12
    # near the pitchfork |x_1| ~ c sqrt(w - w*): the ratio settles
    r = np.abs(a.X[:4, 1, 0]) / np.sqrt(a.lam[:4] - point.lam)
    assert np.ptp(r) / r[0] < 2e-3
    # a second method: the HB orbit at w ~ 1.2 is a fixed point of the period map
    i = int(np.argmin(np.abs(a.lam - 1.2)))
    w, X = a.lam[i], a.X[i]
    k = np.arange(X.shape[0])
    q0, v0 = X.sum(0).real, ((1j * k * w) @ X).real
    s0 = np.array([q0[0], v0[0], q0[1], v0[1]])

    def rhs(t, s):
        x, v, y, u = s
        return [v, -x - KAPPA * y * y * x - G3 * x**3, u, np.cos(w * t) - CY * u - KY * y]

    def period_map(s):
        return solve_ivp(rhs, (0, 2 * np.pi / w), s, method="DOP853", rtol=1e-12,
                         atol=1e-13).y[:, -1]

    fixed = fsolve(lambda s: period_map(s) - s, s0, xtol=1e-13)
    assert np.max(np.abs(fixed - s0)) < 1e-6 * np.abs(X[1, 0])   # measured 6e-8


def test_transcritical_and_pitchfork_of_the_second_tongue():
    p = pumped(F=3.0, alpha=0.5)
    branch = continue_periodic(p, 0.52, 0.7, H, ds=0.02, ds_max=0.05)
    st = branch_stability(branch, p)
    assert [reported_kind(b) for b in st.bifurcations] == ["transcritical", "pitchfork"]
    tr, pf = st.bifurcations
    assert tr.lam == pytest.approx(mathieu_edge(3.0, lambda q: mathieu_a(2, q), 0.55, 0.575),
                                   rel=1e-9)
    assert pf.lam == pytest.approx(mathieu_edge(3.0, lambda q: mathieu_b(2, q), 0.575, 0.6),
                                   rel=1e-9)
    assert tr.info["second_slope"] > 0.05 and pf.info["second_slope"] < 1e-6
    # the transcritical second branch crosses lam*: its legs start on either side (the
    # one to the left turns back at a fold 2e-3 further), the mean of x grows from 0
    point = tr.info["branch_point"]
    sw = switch_branch_point(p, point, (0.52, 0.7), delta=0.01, ds_max=0.02,
                             max_points=12)
    sides = [np.sign(leg.lam[0] - point.lam) for leg in sw.legs]
    assert sides == [1.0, -1.0]
    for leg in sw.legs:
        assert abs(leg.lam[0] - point.lam) < 1e-3
        assert np.all(np.abs(leg.X[1:, 0, 0]) > np.abs(leg.X[0, 0, 0]))


def test_a_fold_is_no_branch_point():
    """Hardening Duffing (H = 5): two turning points, where the bordered determinant keeps
    its sign (tau_BP), so both stay saddle-nodes."""
    p = duffing(c=0.05, k=1.0, k3=1.0, F=0.3)
    branch = continue_periodic(p, 0.5, 4.0, 5)
    assert branch.folds().size == 2
    tests = bordered_tests(branch_system(p, branch), p, branch)
    assert np.all(tests > 0) or np.all(tests < 0)
    assert branch_point_scan(branch, p).intervals == []
    st = branch_stability(branch, p)
    assert [reported_kind(b) for b in st.bifurcations] == ["saddle-node", "saddle-node"]


def test_a_singular_hb_jacobian_without_a_multiplier_crossing_is_reported(first_tongue):
    """The determinant alone (no Floquet crossing announced, e.g. under-resolved
    multipliers): the branch point is still located, typed and reported, with the
    multipliers at its point."""
    p, branch, st = first_tongue
    scan = branch_point_scan(branch, p)
    samples = [BranchSample(float(branch.s[i]), float(branch.lam[i]),
                            st.multipliers[i, : st.n_multipliers[i]]) for i in
               range(branch.n_points)]
    ev = FloquetEvaluator(p, StabilityOptions())
    messages: list[str] = []
    found = type_branch_points([], scan, branch, p, samples,
                               lambda lam, X: ev(lam, X).multipliers, StabilityOptions(),
                               messages)
    assert [reported_kind(b) for b in found] == ["pitchfork", "pitchfork"]
    assert [b.lam for b in found] == pytest.approx([b.lam for b in st.bifurcations],
                                                   rel=1e-12)
    assert all(b.via == "determinant" for b in found)
    # near +1 there: 2e-5 from the Newmark step's crossing, where an undamped tongue edge
    # moves the pair (mu, 1/mu) as the square root of the distance
    assert all(abs(located_critical(b) - 1.0) < 2e-2 for b in found)
    assert len(messages) == 2 and "without a Floquet multiplier crossing" in messages[0]


def test_branch_points_on_adaptive_harmonics_branches():
    """H per point (``adaptive_harmonics``): intervals where H changes are tested in one
    system; the pitchforks are still found and typed (at H = 2: 5e-5 from Mathieu's edges,
    the truncation), and a Duffing branch whose H goes 3 -> 5 -> 3 -> 1 past its folds has
    no branch point."""
    p = pumped()
    branch = continue_periodic(p, 0.8, 1.6, H, ds=0.02, ds_max=0.05,
                               adaptive_harmonics=True, H_min=2, H_max=12)
    assert len(set(branch.info["harmonics"])) > 1
    st = branch_stability(branch, p)
    assert [reported_kind(b) for b in st.bifurcations] == ["pitchfork", "pitchfork"]
    exact = [mathieu_edge(1.0, lambda q: mathieu_a(1, q), 1.0, 1.03),
             mathieu_edge(1.0, lambda q: mathieu_b(1, q), 1.03, 1.06)]
    assert [b.lam for b in st.bifurcations] == pytest.approx(exact, rel=1e-4)
    d = duffing(c=0.05, k=1.0, k3=1.0, F=0.3)
    branch = continue_periodic(d, 0.5, 4.0, 3, adaptive_harmonics=True, H_max=15)
    assert len(set(branch.info["harmonics"])) >= 3 and branch.folds().size == 2
    assert branch_point_scan(branch, d).intervals == []


def _without_stored_signs(branch):
    return dataclasses.replace(branch, info={k: v for k, v in branch.info.items()
                                             if k not in BORDERED})


def test_the_continuation_signs_give_the_re_evaluated_scan(first_tongue):
    """The signs of tau_BP the continuation took at its points (one HB system per run)
    bracket the same branch points as the scan that re-evaluates every point in one system
    of the branch's scaling (a second evaluation: the shift fixed at another point), on a
    fixed-H branch, an adaptive-H branch (pairs across an H change are re-evaluated) and
    a fold with none; a reversed branch's stale signs are not used."""
    p, branch, _ = first_tongue
    stored = branch_point_scan(branch, p)
    assert np.all(np.isfinite(branch.info["bordered_sign"]))
    assert stored.systems == {}                          # nothing re-evaluated
    again = branch_point_scan(_without_stored_signs(branch), p)
    assert stored.intervals == again.intervals and len(stored.intervals) == 2
    assert np.all(stored.tests * again.tests > 0) or np.all(stored.tests * again.tests < 0)
    adaptive = continue_periodic(p, 0.8, 1.6, H, ds=0.02, ds_max=0.05,
                                 adaptive_harmonics=True, H_min=2, H_max=12)
    Hs = adaptive.info["harmonics"]
    assert len(set(Hs)) > 1
    scan = branch_point_scan(adaptive, p)
    assert scan.intervals == branch_point_scan(_without_stored_signs(adaptive), p).intervals
    assert len(scan.intervals) == 2
    new = np.flatnonzero(np.diff(adaptive.info["bordered_system"]) != 0) + 1
    Ns = adaptive.info["n_samples"]
    assert set(scan.systems) <= {(int(Hs[j]), int(Ns[j])) for j in new}
    d = duffing(c=0.05, k=1.0, k3=1.0, F=0.3)
    fold = continue_periodic(d, 0.5, 4.0, 5)
    assert branch_point_scan(fold, d).intervals == [] and fold.folds().size == 2
    flipped = dataclasses.replace(branch, tangents=-branch.tangents)
    assert np.all(np.isnan(stored_signs(flipped)[0]))
    assert branch_point_scan(flipped, p).intervals == stored.intervals


def test_signs_of_a_branch_joined_from_legs_both_ways():
    """A branch continued both ways from a point inside the range (legs joined, the lower
    one reversed: its tangents and so its signs negated) brackets the pitchforks as the
    re-evaluated scan does; the junction pair is re-evaluated (two systems)."""
    p = pumped()
    X0 = continue_periodic(p, 1.3, 1.31, H).X[0]
    joined = continue_both_ways(p, 1.3, X0, H, 0.8, 1.6, ds=0.02, ds_max=0.05)
    assert np.unique(joined.info["bordered_system"]).size == 2
    assert np.all(np.isfinite(stored_signs(joined)[0]))
    scan = branch_point_scan(joined, p)
    assert scan.intervals == branch_point_scan(_without_stored_signs(joined), p).intervals
    assert len(scan.intervals) == 2 and len(scan.systems) == 1


def test_a_joined_adaptive_branch_keeps_its_harmonics_per_point():
    """The legs' per-point H, N_f and truncation errors are joined with their points (the
    last leg's alone were kept: a joined adaptive branch looked uniform in H), so the scan
    tests each interval in its own H."""
    p = pumped()
    X0 = continue_periodic(p, 1.3, 1.31, H).X[0]
    kw = {"ds": 0.02, "ds_max": 0.05, "adaptive_harmonics": True, "H_min": 2, "H_max": 12}
    joined = continue_both_ways(p, 1.3, X0, H, 0.8, 1.6, **kw)
    n = joined.n_points
    for key in ("harmonics", "n_samples", "truncation_error"):
        assert np.shape(joined.info[key]) == (n,)
    assert len(set(joined.info["harmonics"])) > 1
    low = continue_periodic(p, 1.3, 0.8, H, X0, lam_scale=0.8, **kw)   # the lower leg
    k = low.n_points - 1                         # reversed, without the shared start point
    assert np.array_equal(joined.lam[:k], low.lam[::-1][:-1])
    assert list(joined.info["harmonics"][:k]) == list(low.info["harmonics"][::-1][:-1])
    scan = branch_point_scan(joined, p)
    assert scan.intervals == branch_point_scan(_without_stored_signs(joined), p).intervals
    assert len(scan.intervals) == 2
