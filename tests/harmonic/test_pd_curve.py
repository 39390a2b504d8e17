"""Period-doubling curves in two parameters (harmonic/pd_curve.py) on the forced
oscillator with quadratic and cubic stiffness, x'' + c x' + x + b x^2 + k3 x^3 = F cos(w t),
whose subharmonic resonance of order 1/2 near w = 2 is bounded by a pair of flips: the
curve in (w, F) started from one flip located by Floquet on the branch at F = 0.5 passes
through the flips located the same independent way (monodromy multipliers through -1) on
branches at other forcings, and turns at the lowest forcing of the pair."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.continuation.folds import FoldOptions
from rotorsfd.harmonic.fold_curve import TwoParameterProblem
from rotorsfd.harmonic.pd_curve import continue_period_doublings
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.branch_stability import branch_stability

C, B, K3 = 0.05, 0.5, 0.5
H = 7


def oscillator(w: float | None = None, amp: float | None = None) -> PeriodicProblem:
    """The oscillator with lam = w (``amp`` given) or lam = F (``w`` given)."""
    M, D, K, Z = np.eye(1), np.array([[C]]), np.eye(1), np.zeros((1, 1))
    in_w = amp is not None

    def forcing(lam: float, h: int) -> np.ndarray:
        f = np.zeros((h + 1, 1), complex)
        f[1, 0] = amp if in_w else lam
        return f

    def dforcing(lam: float, h: int) -> np.ndarray:
        f = np.zeros((h + 1, 1), complex)
        f[1, 0] = 0.0 if in_w else 1.0
        return f

    return PeriodicProblem(
        n_dof=1, nl_dofs=np.array([0]), matrices=lambda lam: (M, D, K),
        dmatrices=lambda lam: (Z, Z, Z), forcing=forcing, dforcing=dforcing,
        frequency=(lambda lam: lam) if in_w else (lambda lam: w),
        dfrequency=(lambda lam: 1.0) if in_w else (lambda lam: 0.0),
        nl_force=lambda q, v: -B * q**2 - K3 * q**3,
        nl_jacobian=lambda q, v: ((-2 * B * q - 3 * K3 * q**2)[..., None],
                                  np.zeros((*q.shape, 1))), name="quadratic-cubic oscillator")


def flips(amp: float) -> list[float]:
    """The flips of the speed branch at forcing ``amp``, by Floquet (monodromy)."""
    p = oscillator(amp=amp)
    branch = continue_periodic(p, 1.6, 2.4, H, ds=0.05, ds_max=0.1)
    st = branch_stability(branch, p)
    return branch, st, sorted(b.lam for b in st.bifurcations if b.kind == "period-doubling")


@pytest.fixture(scope="module")
def curve():
    branch, st, _ = flips(0.5)
    pd = next(b for b in st.bifurcations if b.kind == "period-doubling")
    i = int(np.argmin(np.abs(branch.lam - pd.lam)))
    problem = TwoParameterProblem(first=lambda F: oscillator(amp=F),
                                  second=lambda w: oscillator(w=w), names=("w", "F"))
    return continue_period_doublings(problem, branch.X[i], branch.lam[i], 0.5, (0.2, 0.8),
                                     H2=4 * H, N=256, scales=(1.0, 1.0),
                                     options=FoldOptions(ds=0.02, ds_max=0.05))


def _speeds_at(legs, amp: float) -> list[float]:
    """Flip speeds of the curve at forcing ``amp`` (both legs, duplicates merged)."""
    w = sorted(float(leg.system.embed(z)[-2]) for leg in legs for z in leg.solve_at(amp))
    return [x for i, x in enumerate(w) if i == 0 or x - w[i - 1] > 1e-8]


@pytest.mark.parametrize("amp", [0.35, 0.7])
def test_curve_passes_through_the_flips_of_other_branches(curve, amp):
    _, legs = curve
    assert all(leg.success for leg in legs), [leg.message for leg in legs]
    w_curve = _speeds_at(legs, amp)
    _, _, w_floquet = flips(amp)
    assert len(w_curve) == 2 and len(w_floquet) == 2
    assert w_curve == pytest.approx(w_floquet, abs=1e-4)


def test_curve_turns_at_the_lowest_forcing_of_the_pair(curve):
    """One turn in F: below it no flip (the period-1 branch at that forcing is stable
    throughout), above it the pair."""
    _, legs = curve
    down = legs[0]
    assert len(down.cusps) == 1 and len(legs[1].cusps) == 0
    F_min = float(down.system.embed(down.cusps[0].z)[-1])
    assert 0.2 < F_min < 0.35
    assert flips(0.98 * F_min)[2] == []
    assert len(flips(1.05 * F_min)[2]) == 2
