"""A period-doubling curve against a closed form: the Mathieu equation's first instability
tongue. A damped linear oscillator y'' + c y' + y = F cos(w t) pumps the stiffness of an
undamped one, x'' + (1 + kappa y(t)) x = 0: on the orbit x = 0 (y the forced response,
amplitude |Y| = F / |1 - w^2 + i c w|) the x motion obeys Mathieu's equation
x'' + (1 + e cos(w t + phi)) x = 0, e = kappa |Y|; in z = (w t + phi) / 2,
x_zz + (a - 2 q cos 2z) x = 0 with a = 4 / w^2, q = -2 e / w^2. Its period-2T solutions
(ce_1, se_1) sit on the tongue edges a = a_1(q), b_1(q) (a_1(-q) = b_1(q)): the flips of the
x = 0 orbit. The (w, F) curve from pd_curve, started at a flip that Floquet locates on the
branch at F = 0.3, meets a = a_1(|q|) or b_1(|q|) (scipy.special.mathieu_a / mathieu_b) at
every point (1e-8; measured 9.6e-10 over 16 points, F = 0.1 .. 0.6)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import mathieu_a, mathieu_b

from rotorsfd.continuation.folds import FoldOptions
from rotorsfd.harmonic.fold_curve import TwoParameterProblem
from rotorsfd.harmonic.pd_curve import continue_period_doublings
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.branch_stability import branch_stability

C_Y, KAPPA, H = 0.2, 1.0, 4


def pumped(w: float | None = None, amp: float | None = None) -> PeriodicProblem:
    """DOFs (x, y); lam = w (``amp`` given) or lam = F (``w`` given)."""
    M = np.eye(2)
    D = np.diag([0.0, C_Y])
    K = np.eye(2)
    Z = np.zeros((2, 2))
    in_w = amp is not None

    def forcing(lam: float, h: int) -> np.ndarray:
        f = np.zeros((h + 1, 2), complex)
        f[1, 1] = amp if in_w else lam
        return f

    def dforcing(lam: float, h: int) -> np.ndarray:
        f = np.zeros((h + 1, 2), complex)
        f[1, 1] = 0.0 if in_w else 1.0
        return f

    def force(q, v):
        return np.stack([-KAPPA * q[..., 1] * q[..., 0], np.zeros_like(q[..., 0])], axis=-1)

    def jacobian(q, v):
        Jq = np.zeros((*q.shape[:-1], 2, 2))
        Jq[..., 0, 0] = -KAPPA * q[..., 1]
        Jq[..., 0, 1] = -KAPPA * q[..., 0]
        return Jq, np.zeros_like(Jq)

    return PeriodicProblem(
        n_dof=2, nl_dofs=np.array([0, 1]), matrices=lambda lam: (M, D, K),
        dmatrices=lambda lam: (Z, Z, Z), forcing=forcing, dforcing=dforcing,
        frequency=(lambda lam: lam) if in_w else (lambda lam: w),
        dfrequency=(lambda lam: 1.0) if in_w else (lambda lam: 0.0),
        nl_force=force, nl_jacobian=jacobian, name="pumped Mathieu oscillator")


def tongue_mismatch(w: float, F: float) -> float:
    """min over the two edges of |a - edge(|q|)| / a at (w, F)."""
    e = KAPPA * F / abs(1.0 - w**2 + 1j * C_Y * w)
    a, q = 4.0 / w**2, 2.0 * e / w**2
    return min(abs(a - mathieu_a(1, q)), abs(a - mathieu_b(1, q))) / a


@pytest.fixture(scope="module")
def curve():
    p = pumped(amp=0.3)
    branch = continue_periodic(p, 1.7, 2.4, H, ds=0.02, ds_max=0.05)
    st = branch_stability(branch, p)
    flips = sorted(b.lam for b in st.bifurcations if b.kind == "period-doubling")
    i = int(np.argmin(np.abs(branch.lam - flips[0])))
    problem = TwoParameterProblem(first=lambda F: pumped(amp=F),
                                  second=lambda w: pumped(w=w), names=("w", "F"))
    _, legs = continue_period_doublings(problem, branch.X[i], branch.lam[i], 0.3,
                                        (0.1, 0.6), H2=4 * H, N=64, scales=(1.0, 1.0),
                                        options=FoldOptions(ds=0.02, ds_max=0.05))
    return flips, legs


def test_floquet_flips_are_on_the_tongue_edges(curve):
    flips, _ = curve
    assert len(flips) == 2
    assert max(tongue_mismatch(w, 0.3) for w in flips) < 1e-4   # measured 1.0e-5


def test_pd_curve_is_the_mathieu_tongue_edge(curve):
    _, legs = curve
    assert all(leg.success for leg in legs), [leg.message for leg in legs]
    pts = [leg.system.embed(z) for leg in legs for z in leg.z]
    w, F = np.array([p[-2] for p in pts]), np.array([p[-1] for p in pts])
    assert F.min() < 0.11 and F.max() > 0.59
    err = max(tongue_mismatch(wi, Fi) for wi, Fi in zip(w, F, strict=True))
    assert err < 1e-8
