"""Codimension-2 points on fold, period-doubling and Neimark-Sacker curves
(harmonic/codim2.py) where their locations are known independently.

The model: a forced Duffing oscillator y pumps three linear oscillators,

    y''  + c y'  + y + a y^3         = F cos(w t)
    x1'' + c1 x1' + k1 (1 + kap1 y) x1 = 0       (Mathieu: a flip near w = 2 sqrt(k1))
    x2'' + (c2 - beta y^2) x2' + k2 x2 = 0       (damping pumped: a secondary Hopf)
    x3'' + c3 x3' + k3 (1 + kap3 y) x3 = 0       (Mathieu: a +1 pair near w = sqrt(k3))

On the orbit (y the Duffing response, x = 0) each x block is a linear periodic system
with its own two multipliers, so every codimension-2 point of the y fold curve in (w, F)
is where one x block reaches its condition, which is checked without the Floquet code:

- fold-flip: the x1 multipliers of scipy's solve_ivp monodromy (along y(t) of the HB
  orbit) have one at -1;
- 1:1 resonance (a second +1): the x3 multipliers have one at +1;
- fold-Neimark-Sacker: Liouville, |mu|^2 = exp(-int (c2 - beta y^2) dt) for the complex
  x2 pair, so the pair is on the unit circle where c2 = beta <y^2>, the mean square of y
  from the HB coefficients (no monodromy at all).

Each is found along the fold curve by brentq on that condition (re-solving the curve at
fixed F) and compared with the located point (1e-4 in both parameters). The PD curve of
x1 and the NS curve of x2 meet the fold curve at the same points: there the y multiplier
reaches +1 (the +1 test on those curves), located independently of the fold curve's.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.integrate import solve_ivp
from scipy.optimize import brentq

from rotorsfd.continuation.folds import FoldOptions, locate_branch_fold
from rotorsfd.harmonic.codim2 import codim2_tests, curve_codim2
from rotorsfd.harmonic.fold_curve import TwoParameterProblem, trace_fold_curves
from rotorsfd.harmonic.ns_curve import continue_neimark_sacker
from rotorsfd.harmonic.pd_curve import continue_period_doublings
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.branch_options import StabilityOptions
from rotorsfd.stability.branch_stability import branch_stability
from rotorsfd.stability.floquet_evaluator import FloquetEvaluator

C, A3 = 0.05, 0.1
C1, K1, KAP1 = 0.005, 0.497, 0.05
C2, K2, BETA = 0.3, 0.5, 0.1
C3, K3, KAP3 = 0.002, 1.3, 0.3
H, N = 5, 32
SCALES = (0.8, 0.2)
OPTIONS = StabilityOptions(n_intervals=1600)


def pumped(w: float | None = None, F: float | None = None, c2: float = C2,
           k1: float = K1) -> PeriodicProblem:
    """The model with lam = w (``F`` given) or lam = F (``w`` given); x2's damping c2,
    x1's stiffness k1."""
    in_w = F is not None
    M, D = np.eye(4), np.diag([C, C1, c2, C3])
    K, Z = np.diag([1.0, k1, K2, K3]), np.zeros((4, 4))

    def forcing(lam, h):
        f = np.zeros((h + 1, 4), complex)
        f[1, 0] = F if in_w else lam
        return f

    def dforcing(lam, h):
        f = np.zeros((h + 1, 4), complex)
        f[1, 0] = 0.0 if in_w else 1.0
        return f

    def force(q, v):
        y, x1, x3 = q[..., 0], q[..., 1], q[..., 3]
        return np.stack([-A3 * y**3, -k1 * KAP1 * y * x1, BETA * y**2 * v[..., 2],
                         -K3 * KAP3 * y * x3], axis=-1)

    def jacobian(q, v):
        y, x1, x3 = q[..., 0], q[..., 1], q[..., 3]
        Jq = np.zeros((*q.shape[:-1], 4, 4))
        Jv = np.zeros_like(Jq)
        Jq[..., 0, 0] = -3 * A3 * y**2
        Jq[..., 1, 0], Jq[..., 1, 1] = -k1 * KAP1 * x1, -k1 * KAP1 * y
        Jq[..., 2, 0], Jv[..., 2, 2] = 2 * BETA * y * v[..., 2], BETA * y**2
        Jq[..., 3, 0], Jq[..., 3, 3] = -K3 * KAP3 * x3, -K3 * KAP3 * y
        return Jq, Jv

    return PeriodicProblem(
        n_dof=4, nl_dofs=np.arange(4), matrices=lambda lam: (M, D, K),
        dmatrices=lambda lam: (Z, Z, Z), forcing=forcing, dforcing=dforcing,
        frequency=(lambda lam: lam) if in_w else (lambda lam: w),
        dfrequency=(lambda lam: 1.0) if in_w else (lambda lam: 0.0),
        nl_force=force, nl_jacobian=jacobian, name="Duffing pumping three oscillators")


FAMILY = TwoParameterProblem(lambda F: pumped(F=F), lambda w: pumped(w=w), ("w", "F"))


def floquet(problem: PeriodicProblem, lam: float, X) -> np.ndarray:
    return FloquetEvaluator(problem, OPTIONS)(lam, X).multipliers


def block_multipliers(X, w: float, block: int, k1: float = K1) -> np.ndarray:
    """The two multipliers of x_block along y(t) = Re sum X_k exp(i k w t), by scipy's
    DOP853 monodromy (rtol 1e-11)."""
    y = X[:, 0]
    k = np.arange(y.size)

    def yt(t):
        return float(np.real(np.sum(y * np.exp(1j * k * w * t))))

    def rhs(t, s):
        x, v = s
        yy = yt(t)
        if block == 1:
            return [v, -C1 * v - k1 * (1 + KAP1 * yy) * x]
        if block == 2:
            return [v, -(C2 - BETA * yy**2) * v - K2 * x]
        return [v, -C3 * v - K3 * (1 + KAP3 * yy) * x]

    T = 2 * np.pi / w
    cols = [solve_ivp(rhs, (0, T), e, method="DOP853", rtol=1e-11, atol=1e-13).y[:, -1]
            for e in ([1.0, 0.0], [0.0, 1.0])]
    return np.linalg.eigvals(np.array(cols).T)


@pytest.fixture(scope="module")
def fold():
    b = continue_periodic(pumped(F=0.1), 0.8, 1.6, H, n_samples=N, ds_max=0.02)
    folds = [locate_branch_fold(b, int(i)) for i in b.folds()]
    hb, curves, _ = trace_fold_curves(FAMILY, H, N, SCALES, folds, (0.1, 0.3))
    upper = max(curves, key=lambda c: hb.from_z(c.z[-1])[1])
    points = curve_codim2("saddle-node", hb, upper, floquet, FAMILY.first)
    return hb, upper, points


def on_fold(fold, F: float):
    hb, upper, _ = fold
    (z,) = upper.solve_at(F / SCALES[1])
    _, w, _ = hb.from_z(z)
    return w, hb.coefficients(z)


def located(points, kind: str, below: float = 0.25):
    """The one point of ``kind`` with F < ``below``."""
    (p,) = [p for p in points if p.type == kind and p.lam2 < below]
    return p


def test_test_functions_of_known_multipliers():
    """psi_+1, psi_-1, psi_circle of hand-made multiplier sets (a fold's +1 removed)."""
    mu = np.array([1.0, 0.5, -0.8, 0.3 + 0.9j, 0.3 - 0.9j])
    v = codim2_tests("saddle-node", mu)
    assert v["-1"] == pytest.approx(1.5 * 0.2 * abs(1.3 + 0.9j) ** 2)
    assert v["circle"] == pytest.approx(0.9 - 1.0)
    # a second real multiplier at +1: the sum of the two nearest +1 deviations
    assert v["+1"] == pytest.approx((0.0 - 0.5) * (-1.8) * abs(-0.7 + 0.9j) ** 2)
    above = codim2_tests("saddle-node", [1.0, 1.0 + 1e-3, 0.2])["+1"]
    assert above == pytest.approx(1e-3 * (0.2 - 1.0))
    assert codim2_tests("saddle-node", [1.0, 1.0 - 1e-3, 0.2])["+1"] == pytest.approx(-above)
    # the computed own multiplier off by delta: the zero where the second is at 1 - delta
    assert codim2_tests("saddle-node", [1.0 + 2e-4, 1.0 - 2e-4, 0.2])["+1"] == 0.0
    pd = codim2_tests("period-doubling", np.array([-1.0, -1.01, 0.5]))
    assert pd["-1"] == pytest.approx(-0.01 * 1.5) and pd["+1"] == pytest.approx(-2.01 * -0.5)


def test_fold_flip_on_the_fold_curve(fold):
    p = located(fold[2], "fold-flip")
    assert abs(p.multiplier + 1.0) < 1e-6

    def x1_flip(F):
        w, X = on_fold(fold, F)
        return float(np.min(np.real(block_multipliers(X, w, 1)))) + 1.0

    F = brentq(x1_flip, 0.21, 0.235, xtol=1e-10)
    w, _ = on_fold(fold, F)
    assert p.lam2 == pytest.approx(F, rel=1e-4)     # measured 9.5e-7 (w: 3.0e-7)
    assert p.lam1 == pytest.approx(w, rel=1e-4)


def test_second_plus_one_on_the_fold_curve(fold):
    p = located(fold[2], "1:1 resonance")

    def x3_plus(F):
        w, X = on_fold(fold, F)
        return float(np.max(np.real(block_multipliers(X, w, 3)))) - 1.0

    F = brentq(x3_plus, 0.115, 0.13, xtol=1e-10)
    w, _ = on_fold(fold, F)
    # measured 7.4e-6 (w: 1.5e-6): the Newmark fold multiplier is 1 + 4e-5 at T/1600
    assert p.lam2 == pytest.approx(F, rel=1e-4)
    assert p.lam1 == pytest.approx(w, rel=1e-4)


def test_fold_neimark_sacker_on_the_fold_curve_is_liouvilles(fold):
    p = located(fold[2], "fold-Neimark-Sacker")
    assert abs(abs(p.multiplier) - 1.0) < 1e-6 and abs(p.multiplier.imag) > 0.1

    F = brentq(lambda F: C2 - BETA * mean_square(on_fold(fold, F)[1]), 0.13, 0.17,
               xtol=1e-12)
    w, X = on_fold(fold, F)
    assert p.lam2 == pytest.approx(F, rel=1e-4)     # measured 1.1e-9 (w: 2.7e-10)
    assert p.lam1 == pytest.approx(w, rel=1e-4)
    assert abs(abs(block_multipliers(X, w, 2)) - 1.0).max() < 1e-6    # Liouville itself


def test_located_to_the_tolerance_not_the_step(fold):
    """The points are re-solved on the curve and the test function is zero there: the
    bracket ends at 1e-9 in scaled arc length while the steps are ~0.02."""
    hb, upper, points = fold
    assert {p.type for p in points} >= {"fold-flip", "1:1 resonance",
                                        "fold-Neimark-Sacker"}
    steps = np.diff(upper.s)
    assert np.median(steps) > 1e-3
    for p in points:
        w = upper.solve_at(p.lam2 / SCALES[1])
        assert min(abs(hb.from_z(z)[1] - p.lam1) for z in w) < 1e-7


def first_of(F: float, kind: str):
    """The branch at F and its lowest-speed bifurcation of ``kind`` (Floquet)."""
    p = pumped(F=F)
    b = continue_periodic(p, 0.8, 1.6, H, n_samples=N, ds_max=0.02)
    st = branch_stability(b, p, OPTIONS)
    return b, min((x for x in st.bifurcations if x.kind == kind), key=lambda x: x.lam)


def pd_curve(family: TwoParameterProblem):
    """The x1 flip of the branch at F = 0.25 continued down in F: it reaches the fold
    curve at the fold-flip, where it turns (the flips of the upper and the middle branch
    meet there) and goes back up to 0.25."""
    b, flip = first_of(0.25, "period-doubling")
    pt = b.point_at(flip.s)
    hb, (leg,) = continue_period_doublings(family, pt.X, pt.lam, 0.25, (0.25, 0.15),
                                           H2=2 * H, N=2 * N, scales=SCALES,
                                           options=FoldOptions(ds=0.02, ds_max=0.05),
                                           both_ways=False)
    return hb, leg, curve_codim2("period-doubling", hb, leg, floquet, family.first)


@pytest.fixture(scope="module")
def pd_points():
    return pd_curve(FAMILY)


def mean_square(X) -> float:
    """<y^2> over a period of y = Re sum_k X_k0 exp(i k w t)."""
    y = X[:, 0]
    return float(abs(y[0]) ** 2 + 0.5 * np.sum(abs(y[1:]) ** 2))


def test_flip_neimark_sacker_on_the_period_doubling_curve_is_liouvilles():
    """With c2 = 0.55 the x2 pair crosses the unit circle on the PD curve's upper leg
    (<y^2> from 5.59 to 5.39 there): located by psi_circle, against brentq on Liouville's
    c2 = beta <y^2> along the leg (1e-4)."""
    c2 = 0.55
    family = TwoParameterProblem(lambda F: pumped(F=F, c2=c2),
                                 lambda w: pumped(w=w, c2=c2), ("w", "F"))
    hb, leg, points = pd_curve(family)
    (p,) = [q for q in points if q.type == "flip-Neimark-Sacker"]
    assert abs(abs(p.multiplier) - 1.0) < 1e-6 and abs(p.multiplier.imag) > 0.1

    def upper_leg(F):       # the leg of lower speed: the upper branch's flips
        z = min(leg.solve_at(F / SCALES[1]), key=lambda z: z[-2])
        full = leg.system.embed(z)
        return hb.from_z(full)[1], hb.coefficients(full)[::2]

    F = brentq(lambda F: c2 - BETA * mean_square(upper_leg(F)[1]), 0.2235, 0.249,
               xtol=1e-12)
    assert p.lam2 == pytest.approx(F, rel=1e-4)                 # measured 2.6e-8
    assert p.lam1 == pytest.approx(upper_leg(F)[0], rel=1e-4)


@pytest.fixture(scope="module")
def ns_points():
    """The x2 secondary Hopf of the branch at F = 0.2 continued down in F: it reaches the
    fold curve at the fold-Neimark-Sacker point (the y multiplier at +1)."""
    b, hopf = first_of(0.2, "secondary-hopf")
    pt = b.point_at(hopf.s)
    theta = abs(float(np.angle(hopf.critical))) / (2 * np.pi)
    hb, leg = continue_neimark_sacker(FAMILY, pt.X, pt.lam, 0.2, theta, (0.2, 0.1), H=H,
                                      N=N, K=H, scales=SCALES,
                                      options=FoldOptions(ds=0.05, ds_max=0.1))
    return hb, leg, curve_codim2("Neimark-Sacker", hb, leg, floquet, FAMILY.first)


def test_period_doubling_curve_meets_the_fold_curve_at_the_fold_flip(fold, pd_points):
    on_fold_curve = located(fold[2], "fold-flip")
    hb, leg, points = pd_points
    on_pd = located(points, "fold-flip")
    assert on_pd.curve == "period-doubling" and abs(on_pd.multiplier - 1.0) < 1e-6
    assert on_pd.lam2 == pytest.approx(on_fold_curve.lam2, rel=1e-4)   # measured 5.1e-7
    assert on_pd.lam1 == pytest.approx(on_fold_curve.lam1, rel=1e-4)
    # the PD curve's own turn in F is the same point (HB: the even block singular there;
    # measured 1.3e-5: the Newmark +1 against HB's)
    (turn,) = leg.cusps
    _, w, F = hb.from_z(leg.system.embed(turn.z))
    assert F == pytest.approx(on_pd.lam2, rel=1e-4) and w == pytest.approx(on_pd.lam1,
                                                                           rel=1e-4)


@pytest.mark.slow
def test_neimark_sacker_curve_meets_the_fold_curve_at_the_fold_ns(fold, ns_points):
    """6 s CPU (the NS curve's Jacobian by differences of the shifted Hill operator)."""
    on_fold_curve = located(fold[2], "fold-Neimark-Sacker")
    on_ns = located(ns_points[2], "fold-Neimark-Sacker")
    assert on_ns.curve == "Neimark-Sacker" and abs(on_ns.multiplier - 1.0) < 1e-6
    assert on_ns.lam2 == pytest.approx(on_fold_curve.lam2, rel=1e-4)   # measured 5.8e-6
    assert on_ns.lam1 == pytest.approx(on_fold_curve.lam1, rel=1e-4)


# ---- 1:1 resonance at the end of a Neimark-Sacker curve -----------------------------------
# y the Duffing oscillator at F = 0.2 pumps x4'' + (c4 - b4 y^2) x4' + (k4 + p4 y) x4 = 0,
# continued in (w, k4): the x4 pair is on the unit circle where c4 = b4 <y^2> (Liouville,
# k4 plays no part: the NS curve is w = w* at every k4), and its angle theta -> 0 where k4
# reaches the edge of x4's second Mathieu tongue (w ~ sqrt(k4)): the pair meets at +1.
C4, B4, P4, F4 = 0.29, 0.1, 0.15, 0.2


def whirl(w: float | None = None, k4: float | None = None) -> PeriodicProblem:
    """DOFs (y, x4); lam = w (``k4`` given) or lam = k4 (``w`` given)."""
    in_w = k4 is not None
    M, D, Z = np.eye(2), np.diag([C, C4]), np.zeros((2, 2))
    dK = Z if in_w else np.diag([0.0, 1.0])

    def forcing(lam, h):
        f = np.zeros((h + 1, 2), complex)
        f[1, 0] = F4
        return f

    def force(q, v):
        y, x = q[..., 0], q[..., 1]
        return np.stack([-A3 * y**3, B4 * y**2 * v[..., 1] - P4 * y * x], axis=-1)

    def jacobian(q, v):
        y, x = q[..., 0], q[..., 1]
        Jq = np.zeros((*q.shape[:-1], 2, 2))
        Jv = np.zeros_like(Jq)
        Jq[..., 0, 0] = -3 * A3 * y**2
        Jq[..., 1, 0], Jq[..., 1, 1] = 2 * B4 * y * v[..., 1] - P4 * x, -P4 * y
        Jv[..., 1, 1] = B4 * y**2
        return Jq, Jv

    return PeriodicProblem(
        n_dof=2, nl_dofs=np.arange(2),
        matrices=lambda lam: (M, D, np.diag([1.0, k4 if in_w else lam])),
        dmatrices=lambda lam: (Z, Z, dK), forcing=forcing,
        dforcing=lambda lam, h: np.zeros((h + 1, 2), complex),
        frequency=(lambda lam: lam) if in_w else (lambda lam: w),
        dfrequency=(lambda lam: 1.0) if in_w else (lambda lam: 0.0),
        nl_force=force, nl_jacobian=jacobian, name="Duffing pumping a whirl")


def test_one_one_resonance_ends_the_neimark_sacker_curve():
    """The NS curve from the secondary Hopf of the branch at k4 = 1.87 (theta = 0.146)
    runs down in k4 until theta reaches 0; its end (extrapolated from theta = 0.005 ..
    0.015, where the curve meets the x4 +1 set) against w* from Liouville (brentq on the
    HB speed branch's <y^2>) and k4* where scipy's x4 monodromy along y(t) at w* has
    trace 2 (both multipliers +1; det = 1 there by Liouville). 3 s CPU."""
    family = TwoParameterProblem(lambda k4: whirl(k4=k4), lambda w: whirl(w=w),
                                 ("w", "k4"))
    p = whirl(k4=1.87)
    b = continue_periodic(p, 0.8, 1.6, H, n_samples=N, ds_max=0.02)
    hopf = min((x for x in branch_stability(b, p).bifurcations
                if x.kind == "secondary-hopf"), key=lambda x: x.lam)
    pt = b.point_at(hopf.s)
    theta = abs(float(np.angle(hopf.critical))) / (2 * np.pi)
    hb, leg = continue_neimark_sacker(family, pt.X, pt.lam, 1.87, theta, (1.87, 1.2), H=H,
                                      N=N, K=2 * H, scales=(0.8, 0.7),
                                      options=FoldOptions(ds=0.05, ds_max=0.1))
    (end,) = curve_codim2("Neimark-Sacker", hb, leg, floquet, family.first)
    assert leg.ended_at == 0 and end.type == "1:1 resonance" and end.value == 0.0

    def excess(s):          # c4 - b4 <y^2> on the speed branch (y does not see k4)
        return C4 - B4 * mean_square(b.point_at(s).X)

    i = next(i for i in range(b.n_points - 1)
             if 1.1 < b.lam[i] < 1.25 and excess(b.s[i]) * excess(b.s[i + 1]) < 0)
    star = b.point_at(brentq(excess, b.s[i], b.s[i + 1], xtol=1e-14))
    w = star.lam

    def trace_minus_2(k4):
        y, k = star.X[:, 0], np.arange(star.X.shape[0])

        def rhs(t, s):
            yy = float(np.real(np.sum(y * np.exp(1j * k * w * t))))
            return [s[1], -(C4 - B4 * yy**2) * s[1] - (k4 + P4 * yy) * s[0]]

        cols = [solve_ivp(rhs, (0, 2 * np.pi / w), e, method="DOP853", rtol=1e-12,
                          atol=1e-14).y[:, -1] for e in ([1.0, 0.0], [0.0, 1.0])]
        return float(np.trace(np.array(cols).T)) - 2.0

    k4 = brentq(trace_minus_2, 1.5, 1.65, xtol=1e-12)
    assert end.lam1 == pytest.approx(w, rel=1e-4)       # measured 1e-9
    assert end.lam2 == pytest.approx(k4, rel=1e-4)      # measured 6e-8 (K = 5: 1.3e-4)


@pytest.mark.slow
def test_flip_neimark_sacker_on_the_neimark_sacker_curve():
    """With k1 = 0.393 the x1 flip tongue moves to w ~ 1.2, where the x2 NS curve from
    F = 0.2 runs down to the fold-NS point and back up on the middle branch: there an x1
    multiplier passes -1 (psi_-1 on the NS curve), against brentq along that leg on
    scipy's x1 monodromy (1e-4). 5 s CPU."""
    k1 = 0.393
    family = TwoParameterProblem(lambda F: pumped(F=F, k1=k1),
                                 lambda w: pumped(w=w, k1=k1), ("w", "F"))
    p = pumped(F=0.2, k1=k1)
    b = continue_periodic(p, 0.8, 1.6, H, n_samples=N, ds_max=0.02)
    hopf = min((x for x in branch_stability(b, p, OPTIONS).bifurcations
                if x.kind == "secondary-hopf"), key=lambda x: x.lam)
    pt = b.point_at(hopf.s)
    theta = abs(float(np.angle(hopf.critical))) / (2 * np.pi)
    hb, leg = continue_neimark_sacker(family, pt.X, pt.lam, 0.2, theta, (0.2, 0.1), H=H,
                                      N=N, K=H, scales=SCALES,
                                      options=FoldOptions(ds=0.05, ds_max=0.1))
    points = curve_codim2("Neimark-Sacker", hb, leg, floquet, family.first)
    (q,) = [q for q in points if q.type == "flip-Neimark-Sacker"]
    assert abs(q.multiplier + 1.0) < 1e-6

    def middle_leg(F):      # the leg of higher speed, after the turn at the fold-NS point
        z = max(leg.solve_at(F / SCALES[1]), key=lambda z: z[-3])
        base = leg.system.embed(z)
        return hb.from_z(base)[1], hb.coefficients(base)

    def x1_flip(F):
        w, X = middle_leg(F)
        return float(np.min(np.real(block_multipliers(X, w, 1, k1)))) + 1.0

    F = brentq(x1_flip, 0.154, 0.165, xtol=1e-12)
    assert q.lam2 == pytest.approx(F, rel=1e-4)         # measured 5.2e-6 (w: 3.2e-7)
    assert q.lam1 == pytest.approx(middle_leg(F)[0], rel=1e-4)
