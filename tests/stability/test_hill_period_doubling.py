"""Hill's method at a period doubling: the multiplier -1 (Floquet exponent with
``Im = w/2``) must come out real and negative, classified and located as a period
doubling (Mathieu's first tongue, exact boundaries), and spurious eigenvalues of the
truncated Hill matrix (real, hence centroid 0) must not outrank it."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.special import mathieu_a, mathieu_b

from rotorsfd.stability.bifurcations import BranchSample, find_bifurcations
from rotorsfd.stability.hill import _select_centred, fourier_coefficients, hill_floquet

EPS = 0.2


def _mathieu(delta: float, damping: float = 0.0, H: int = 10):
    """x'' + c x' + (delta + EPS cos t) x = 0, w = 1 (T = 2 pi)."""
    t = np.arange(64) * 2 * np.pi / 64
    return hill_floquet([[1.0]], [[damping]], [[delta]], 1.0, nl_dofs=[0],
                        dFdq_hat=fourier_coefficients(-EPS * np.cos(t), 2 * H),
                        n_harmonics=H)


def test_mathieu_first_tongue_is_period_doubling_at_exact_boundaries():
    """Boundaries of the first tongue: delta = b_1(2 EPS) / 4 and a_1(2 EPS) / 4
    (Mathieu characteristic values, x(t) = y(t/2)); inside, a real multiplier < -1."""
    lo, hi = mathieu_b(1, 2 * EPS) / 4, mathieu_a(1, 2 * EPS) / 4
    inside = _mathieu(0.5 * (lo + hi))
    assert inside.crossing_type == "period-doubling"
    assert inside.critical.imag == 0.0 and inside.critical.real < -1.5
    assert abs(np.prod(inside.multipliers) - 1.0) < 1e-10  # undamped: det Phi = 1

    def solve_at(s):
        return s, _mathieu(s).multipliers

    grid = np.linspace(lo - 0.03, hi + 0.03, 9)
    samples = [BranchSample(float(d), float(d), _mathieu(d).multipliers) for d in grid]
    found = find_bifurcations(samples, solve_at, rtol=1e-9)
    assert [b.kind for b in found] == ["period-doubling", "period-doubling"]
    assert abs(found[0].lam - lo) < 1e-6 and abs(found[1].lam - hi) < 1e-6


@pytest.mark.parametrize("damping", [0.02, 0.05])
def test_damped_mathieu_multiplier_through_minus_one(damping):
    """With damping c the multiplier is exp(-c pi) times that of the undamped equation
    at delta - c^2/4 (x = exp(-c t / 2) y): it crosses -1 inside the tongue (a generic
    crossing, real and negative on both sides), located to 1e-6 in delta."""
    lo, hi = mathieu_b(1, 2 * EPS) / 4, mathieu_a(1, 2 * EPS) / 4

    def solve_at(s):
        return s, _mathieu(s, damping).multipliers

    shift = damping**2 / 4  # x = exp(-c t / 2) y: y'' + (delta - c^2/4 + EPS cos t) y = 0
    mid = 0.5 * (lo + hi)
    samples = [BranchSample(float(d), float(d), solve_at(d)[1])
               for d in np.linspace(lo - 0.02, mid, 8) + shift]
    found = find_bifurcations(samples, solve_at, rtol=1e-10)
    assert [b.kind for b in found] == ["period-doubling"]
    b = found[0]
    assert b.critical.imag == 0.0 and abs(b.critical.real + 1.0) < 1e-6
    # the undamped multiplier there is -exp(c pi) (y: mu_y = mu_x exp(c T / 2))
    und = _mathieu(b.lam - shift).multipliers
    assert abs(und[0].real + np.exp(damping * np.pi)) < 1e-6


def test_spurious_real_eigenvalues_do_not_outrank_a_period_doubling_ladder():
    """Synthetic Hill spectrum (w = 1, H = 6): the ladder s + i (k + 1/2) of a
    period-doubling exponent (centroids -(k + 1/2)) and its mirror, the ladder of a real
    exponent r + i k, and three spurious real eigenvalues of the truncation (centroid 0,
    no ladder). Two exponents are selected: the PD one and r, not the spurious ones."""
    s, r = 0.01, -0.2
    k = np.arange(-6, 7)
    pd = np.concatenate([s + 1j * (k + 0.5), s - 1j * (k + 0.5)])
    pd_c = np.concatenate([-(k + 0.5), k + 0.5])
    re = r + 1j * k
    spur = np.array([-40.0, -7.0, 0.9])
    lam = np.concatenate([pd, re, spur])
    cen = np.concatenate([pd_c, -k.astype(float), np.zeros(3)])
    from rotorsfd.stability.hill import ladder_defect

    d = ladder_defect(lam, 1.0)
    assert np.all(d[-3:] > 0.5) and np.all(d[:-3][np.abs(cen[:-3]) < 5] < 1e-12)
    sel = _select_centred(lam, cen, 1.0, 2, defect=d)
    mu = np.sort(np.exp(lam[sel] * 2 * np.pi).real)
    assert mu == pytest.approx([-np.exp(2 * np.pi * s), np.exp(2 * np.pi * r)], rel=1e-12)
    old = _select_centred(lam, cen, 1.0, 2)  # centroid only: a spurious one wins, no PD
    assert max(old) >= lam.size - 3 and min(old) >= pd.size
