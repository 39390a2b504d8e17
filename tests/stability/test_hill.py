"""Hill's method vs Newmark monodromy vs a Magnus/solve_ivp reference."""

from __future__ import annotations

import numpy as np
import pytest
from stability_helpers import ltp3, match_error, reference_monodromy

from rotorsfd.stability.hill import fourier_coefficients, hill_floquet, two_sided
from rotorsfd.stability.monodromy import monodromy_magnus4, monodromy_newmark


def test_fourier_convention():
    """x(t) = a0 + a1 cos wt + b1 sin wt + a2 cos 2wt -> X = [a0, a1 - i b1, a2]."""
    t = np.arange(16) * 2 * np.pi / 16
    x = 0.5 + 2 * np.cos(t) + 3 * np.sin(t) - np.cos(2 * t)
    X = fourier_coefficients(x, 3)
    assert np.allclose(X, [0.5, 2 - 3j, -1, 0])
    c = two_sided(X)
    assert np.allclose(c[3], 0.5) and np.allclose(c[4], (2 - 3j) / 2)
    assert np.allclose(c[2], (2 + 3j) / 2)


def _hat(fun, T, L=12, N=64):
    t = np.arange(N) * T / N
    return fourier_coefficients(np.array([fun(x) for x in t]), L)


@pytest.mark.parametrize("method", ["symmetric", "koopman"])
def test_hill_ltp3_vs_solve_ivp(method):
    s = ltp3()
    ref = np.linalg.eigvals(reference_monodromy(s["M"], s["D"], s["K"], s["T"], s["nl"],
                                                s["dFdq"], s["dFdv"]))
    r = hill_floquet(s["M"], s["D"], s["K"], 2 * np.pi / s["T"], nl_dofs=s["nl"],
                     dFdq_hat=_hat(s["dFdq"], s["T"]), dFdv_hat=_hat(s["dFdv"], s["T"]),
                     n_harmonics=10, method=method)
    assert match_error(r.multipliers, ref) < 1e-8
    assert r.liouville_error < 1e-8


def _jeffcott_asym(spin, dk=0.2, c=0.02):
    """Jeffcott rotor with an asymmetric shaft, fixed frame: K(t) periodic, T = pi/spin."""
    M, D, K = np.eye(2), c * np.eye(2), np.eye(2)

    def kq(t):
        a = 2 * spin * t
        return -dk * np.array([[np.cos(a), np.sin(a)], [np.sin(a), -np.cos(a)]])

    return M, D, K, np.pi / spin, kq


def _mathieu3(omega, eps=0.3):
    """3-DOF damped Mathieu chain, K(t) = K0 (1 + eps cos wt) + 0.1 eps sin(2wt) I."""
    K0 = np.array([[2.0, -1, 0], [-1, 2, -1], [0, -1, 2]])
    M, D = np.eye(3), 0.02 * K0 + 0.01 * np.eye(3)

    def kq(t):
        return -(eps * np.cos(omega * t) * K0 + 0.1 * eps * np.sin(2 * omega * t) * np.eye(3))

    return M, D, K0, 2 * np.pi / omega, kq


CASES = ([("jeffcott", s) for s in (0.85, 0.90, 0.91, 1.0, 1.12)]
         + [("mathieu3", w) for w in (1.0, 1.3, 1.53, 1.6)])


@pytest.mark.parametrize(("kind", "p"), CASES)
def test_newmark_hill_agree(kind, p):
    """Stability decision and critical multiplier: Newmark (N=400) vs Hill (H=8) vs
    Magnus-4 reference, including cases near the instability boundaries."""
    M, D, K, T, kq = _jeffcott_asym(p) if kind == "jeffcott" else _mathieu3(p)
    nl = np.arange(M.shape[0])
    ref = monodromy_magnus4(M, D, K, T, nl_dofs=nl, dFdq=kq, n_intervals=200)
    nm = monodromy_newmark(M, D, K, T, nl_dofs=nl, dFdq=kq, n_intervals=400)
    hs = hill_floquet(M, D, K, 2 * np.pi / T, nl_dofs=nl, dFdq_hat=_hat(kq, T),
                      n_harmonics=8)
    hk = hill_floquet(M, D, K, 2 * np.pi / T, nl_dofs=nl, dFdq_hat=_hat(kq, T),
                      n_harmonics=8, method="koopman")
    assert nm.stable == ref.stable == hs.stable == hk.stable
    assert abs(hs.max_abs - ref.max_abs) < 1e-8
    assert abs(hk.max_abs - ref.max_abs) < 1e-8
    assert abs(nm.max_abs - ref.max_abs) < 2e-4
    assert match_error(nm.multipliers, ref.multipliers) < 2e-3
    if not ref.stable:
        assert nm.crossing_type == hs.crossing_type == ref.crossing_type
