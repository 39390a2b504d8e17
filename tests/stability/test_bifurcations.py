"""Bifurcation test functions, detection and location on synthetic branches."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.stability.bifurcations import (
    BifurcationMonitor,
    BranchSample,
    crossing_signs,
    detect,
    find_bifurcations,
    locate,
)
from rotorsfd.stability.floquet import multiplier_type

S_SN, S_PD, S_NS = 2.0 + 1 / 7, 3.5 + 1 / 11, 5.0 + 1 / 3


def lam_a(s):
    return 1.0 + 0.1 * s + 0.01 * s**2


def mu_a(s):
    """Multipliers given analytically: real one through +1 at S_SN, real one through -1
    at S_PD, complex pair leaving the circle at S_NS, and some small ones."""
    r = 0.6 + 0.4 * (s - 4.0) / (S_NS - 4.0)
    pair = r * np.exp(1j * np.array([1.2, -1.2]))
    return np.concatenate([[1.0 + 0.3 * (s - S_SN), -(1.0 + 0.2 * (s - S_PD))], pair,
                           [0.1, -0.05, 0.02 + 0.01j, 0.02 - 0.01j]])


def solve_a(s):
    return lam_a(s), mu_a(s)


def test_crossing_signs_and_types():
    assert crossing_signs(mu_a(1.0))["saddle-node"] != crossing_signs(mu_a(3.0))["saddle-node"]
    assert (crossing_signs(mu_a(3.0))["period-doubling"]
            != crossing_signs(mu_a(4.0))["period-doubling"])
    assert (crossing_signs(mu_a(5.0))["secondary-hopf"]
            != crossing_signs(mu_a(5.5))["secondary-hopf"])
    assert multiplier_type(1.01 + 0j) == "saddle-node"
    assert multiplier_type(-1.01 + 0j) == "period-doubling"
    assert multiplier_type(0.6 + 0.8j) == "secondary-hopf"


def test_neutral_saddle_is_not_hopf():
    """Two real multipliers with product passing 1 flip tau_NS but are no bifurcation."""
    a = BranchSample(0.0, 1.0, np.array([0.5, 1.9, 0.1]))
    b = BranchSample(1.0, 1.1, np.array([0.5, 2.1, 0.1]))
    assert crossing_signs(a.multipliers)["secondary-hopf"] != crossing_signs(
        b.multipliers)["secondary-hopf"]
    assert [br.kind for br in detect([a, b])] == []


@pytest.mark.parametrize("rtol", [1e-6, 1e-9])
def test_locate_three_types(rtol):
    s = np.linspace(0.0, 7.0, 15)
    samples = [BranchSample.from_solve(x, solve_a(x)) for x in s]
    calls = []

    def counted(x):
        calls.append(x)
        return solve_a(x)

    found = find_bifurcations(samples, counted, rtol=rtol)
    assert [b.kind for b in found] == ["saddle-node", "period-doubling", "secondary-hopf"]
    for b, s_true in zip(found, (S_SN, S_PD, S_NS), strict=True):
        lam_true = lam_a(s_true)
        assert abs(b.lam - lam_true) <= rtol * abs(lam_true)
        assert abs(abs(b.critical) - 1.0) < 1e-5
    _re, im, ab = found[2].critical_multiplier
    assert abs(im) > 0.5 and abs(ab - 1) < 1e-5
    assert found[0].critical.real > 0 and found[1].critical.real < 0
    assert len(calls) < 60


def test_fold_by_tangent_and_multiplier():
    """A fold: lam(s) = 1.2 - 0.05 (s - 3)^2 with a multiplier through +1 at s = 3;
    located by dlam/ds and by the multiplier, to 1e-6 relative."""

    def solve(s):
        return (1.2 - 0.05 * (s - 3.0) ** 2, np.array([1.0 + 0.2 * (s - 3.0), 0.3, -0.2]),
                -0.1 * (s - 3.0))

    samples = [BranchSample.from_solve(x, solve(x)) for x in (1.0, 2.2, 3.4, 4.6)]
    br = detect(samples)
    assert len(br) == 1 and br[0].kind == "saddle-node" and br[0].via == "tangent"
    b = locate(br[0], solve, rtol=1e-6)
    assert abs(b.lam - 1.2) <= 1e-6 * 1.2
    # without the tangent information: multiplier-based location
    solve2 = lambda s: solve(s)[:2]  # noqa: E731
    samples2 = [BranchSample.from_solve(x, solve2(x)) for x in (1.0, 2.2, 3.4, 4.6)]
    b2 = find_bifurcations(samples2, solve2, rtol=1e-6)[0]
    assert b2.kind == "saddle-node" and b2.via == "multiplier"
    assert abs(b2.lam - 1.2) <= 1e-6 * 1.2
    assert abs(b2.s - 3.0) < 1e-2


def test_monitor_hook_and_interpolated_estimate():
    mon = BifurcationMonitor()
    kinds = []
    for x in np.linspace(0.0, 7.0, 29):
        kinds += [br.kind for br in mon(x, lam_a(x), mu_a(x))]
    assert kinds == ["saddle-node", "period-doubling", "secondary-hopf"]
    est = find_bifurcations(mon.samples)  # no solve_at: linear interpolation
    assert abs(est[0].s - S_SN) < 1e-9  # mu is linear in s there


def test_sample_exactly_on_crossing():
    """A sample exactly at mu = +1 is reported once and returned as the point."""
    samples = [BranchSample.from_solve(x, solve_a(x)) for x in (1.0, S_SN, 3.0)]
    found = find_bifurcations(samples, solve_a)
    assert [b.kind for b in found] == ["saddle-node"]
    assert found[0].s == S_SN


def test_location_ignores_near_neutral_distractors():
    """Undamped structural modes give multipliers at |mu| = 1 - 1e-10 (paper rotor, full
    model); the crossing pair and real multiplier are tracked, not the nearest to the
    circle."""
    distract = np.concatenate([(1 - 1e-10) * np.exp(1j * np.array([0.3, -0.3, 2.0, -2.0])),
                               [1 - 1e-9, -(1 - 1e-9)]])

    def solve(s):
        lam, mu = solve_a(s)
        return lam, np.concatenate([mu, distract])

    samples = [BranchSample.from_solve(x, solve(x)) for x in np.linspace(0.0, 7.0, 15)]
    found = find_bifurcations(samples, solve, rtol=1e-6)
    assert [b.kind for b in found] == ["saddle-node", "period-doubling", "secondary-hopf"]
    for b, s_true in zip(found, (S_SN, S_PD, S_NS), strict=True):
        assert abs(b.lam - lam_a(s_true)) <= 1e-6 * lam_a(s_true)
    assert abs(np.angle(found[2].critical) - 1.2) < 1e-6


def test_dead_band_ignores_noise_crossings():
    """Multipliers wobbling at 1 +- 1e-9 (round-off on undamped modes) raise no event."""
    a = BranchSample(0.0, 1.0, np.array([1 - 1e-9, -(1 + 1e-9), 0.5]))
    b = BranchSample(1.0, 1.1, np.array([1 + 1e-9, -(1 - 1e-9), 0.5]))
    assert detect([a, b]) == []
    assert len(detect([a, b], dead_band=0.0)) == 2
