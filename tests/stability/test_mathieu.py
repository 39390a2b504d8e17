"""Mathieu equation x'' + (delta + eps cos t) x = 0: transition curves.

Known expansions (T = 2 pi): first tongue (mu = -1, period 2T)
delta = 1/4 +- eps/2 - eps^2/8 -+ eps^3/32 + O(eps^4); second tongue (mu = +1)
delta = 1 - eps^2/12 + O(eps^4) and delta = 1 + 5 eps^2/12 + O(eps^4). The curves are
found by root finding on trace(Phi) -+ 2 along delta at fixed eps.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import brentq

from rotorsfd.stability.monodromy import monodromy_magnus4, monodromy_newmark


def _trace(delta: float, eps: float, method: str) -> float:
    def f(t):
        return np.array([[-eps * np.cos(t)]])

    args = (np.eye(1), np.zeros((1, 1)), np.array([[delta]]), 2 * np.pi)
    if method == "magnus4":
        r = monodromy_magnus4(*args, nl_dofs=[0], dFdq=f, n_intervals=40)
    else:
        r = monodromy_newmark(*args, nl_dofs=[0], dFdq=f, n_intervals=400)
    return float(np.trace(r.monodromy))


def _curves(eps: float, method: str) -> tuple[float, float, float, float]:
    def g(d, s):
        return _trace(d, eps, method) - s

    lo = brentq(g, 0.25 - eps, 0.25, args=(-2.0,), xtol=1e-13)
    hi = brentq(g, 0.25, 0.25 + eps, args=(-2.0,), xtol=1e-13)
    a = brentq(g, 1 - eps, 1.0 - 1e-9, args=(2.0,), xtol=1e-13)
    b = brentq(g, 1 + 1e-9, 1 + eps, args=(2.0,), xtol=1e-13)
    return lo, hi, a, b


@pytest.mark.parametrize("eps", [0.05, 0.1, 0.2])
@pytest.mark.parametrize("method", ["magnus4", "newmark"])
def test_mathieu_transition_curves(eps, method):
    lo, hi, a, b = _curves(eps, method)
    # Newmark N = 400: error in delta ~ 2 delta (w h)^2 / 12 ~ 4e-5 (delta ~ w^2)
    disc = 0.0 if method == "magnus4" else 5e-5
    tol3 = 0.05 * eps**3 + disc  # the neglected term is eps^3/32
    tol4 = 0.3 * eps**4 + disc  # neglected: 5 eps^4/3456 and -763 eps^4/3456
    assert abs(lo - (0.25 - eps / 2 - eps**2 / 8)) < tol3
    assert abs(hi - (0.25 + eps / 2 - eps**2 / 8)) < tol3
    assert abs(a - (1 - eps**2 / 12)) < tol4
    assert abs(b - (1 + 5 * eps**2 / 12)) < tol4


def test_mathieu_inside_tongue_unstable():
    """Inside the first tongue the critical multiplier is real negative (period
    doubling type), outside |mu| = 1 (undamped, conservative)."""
    f = lambda t: np.array([[-0.2 * np.cos(t)]])  # noqa: E731
    args = (np.eye(1), np.zeros((1, 1)))
    inside = monodromy_newmark(*args, np.array([[0.25]]), 2 * np.pi, nl_dofs=[0], dFdq=f)
    outside = monodromy_newmark(*args, np.array([[0.6]]), 2 * np.pi, nl_dofs=[0], dFdq=f)
    assert not inside.stable and inside.crossing_type == "period-doubling"
    assert outside.stable and abs(outside.max_abs - 1) < 1e-10
