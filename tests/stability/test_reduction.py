"""Craig-Bampton reduced model vs full model (critical multipliers)."""

from __future__ import annotations

import numpy as np

from rotorsfd.stability.monodromy import (
    floquet_multipliers,
    monodromy_generalized_alpha,
    monodromy_magnus4,
    monodromy_newmark,
)
from rotorsfd.stability.reduction import craig_bampton


def _two_plane_chain(n=15, k=1e4, gyro=0.2):
    K1 = np.zeros((n, n))
    for i in range(n - 1):
        K1[i:i + 2, i:i + 2] += k * np.array([[1.0, -1.0], [-1.0, 1.0]])
    K1[-1, -1] += k
    Z = np.zeros((n, n))
    K = np.block([[K1, Z], [Z, K1]])
    G = np.zeros((2 * n, 2 * n))
    G[n // 2, n + n // 2], G[n + n // 2, n // 2] = gyro, -gyro
    return np.eye(2 * n), 1e-5 * K + G, K


def _case():
    """Principal parametric resonance of the first mode through a 2-DOF periodic
    Jacobian at the chain's end (an SFD-like support): critical multiplier ~ -1.108."""
    M, D, K = _two_plane_chain()
    n, ks, cs = 15, 2e3, 2.0
    nl = [0, n]
    Km = K.copy()
    Km[np.ix_(nl, nl)] += ks * np.eye(2)
    w = 2 * np.sqrt(np.linalg.eigvalsh(Km)[0])

    def kq(t):
        c, s = np.cos(w * t), np.sin(w * t)
        return -ks * np.array([[1 + 0.3 * c, 0.1 * s], [0.1 * s, 1 - 0.3 * c]])

    def kv(t):
        return -cs * np.array([[1 + 0.4 * np.cos(w * t), 0.2],
                               [-0.2, 1 + 0.4 * np.sin(2 * w * t)]])

    return M, D, K, 2 * np.pi / w, nl, kq, kv


def test_craig_bampton_structure():
    M, D, K = _two_plane_chain()
    red = craig_bampton(M, D, K, [0, 15], n_modes=4)
    assert red.n_dof == 6
    assert np.allclose(red.basis[[0, 15], :2], np.eye(2))
    assert np.allclose(red.basis[[0, 15], 2:], 0.0)
    # static exactness: boundary static stiffness equals the full model's condensation
    i = np.setdiff1d(np.arange(30), [0, 15])
    b = np.array([0, 15])
    Kc = K[np.ix_(b, b)] - K[np.ix_(b, i)] @ np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, b)])
    assert np.allclose(red.K[:2, :2], Kc)


def test_reduced_vs_full_critical_multiplier():
    """Critical multiplier of the reduced model (6 fixed-interface modes) within 1e-4 of
    the full model (Magnus reference and full Newmark), same crossing type."""
    M, D, K, T, nl, kq, kv = _case()
    kw = dict(nl_dofs=nl, dFdq=kq, dFdv=kv)
    ref = monodromy_magnus4(M, D, K, T, n_intervals=200, **kw)
    full = monodromy_newmark(M, D, K, T, **kw)
    red = floquet_multipliers(M, D, K, T, n_modes=6, **kw)
    assert red.method == "newmark-cb" and red.info["n_dof"] == 8
    assert not ref.stable and ref.crossing_type == "period-doubling"
    assert red.crossing_type == full.crossing_type == ref.crossing_type
    assert abs(red.max_abs - ref.max_abs) < 1e-4
    assert abs(red.max_abs - full.max_abs) < 1e-4
    assert abs(red.critical - ref.critical) < 1e-4
    # error decreases with the number of kept modes
    e2 = abs(floquet_multipliers(M, D, K, T, n_modes=2, **kw).max_abs - ref.max_abs)
    assert e2 > 10 * abs(red.max_abs - ref.max_abs)


def test_generalized_alpha_full_and_reduced():
    """Generalized-alpha (rho_inf = 0.6) on the full and on the reduced model: same
    critical multiplier as the reference to 1e-4."""
    M, D, K, T, nl, kq, kv = _case()
    kw = dict(nl_dofs=nl, dFdq=kq, dFdv=kv)
    ref = monodromy_magnus4(M, D, K, T, n_intervals=200, **kw)
    full = monodromy_generalized_alpha(M, D, K, T, **kw)
    red = floquet_multipliers(M, D, K, T, n_modes=6, scheme="generalized-alpha", **kw)
    assert red.method == "generalized-alpha-cb"
    for r in (full, red):
        assert r.crossing_type == ref.crossing_type
        assert abs(r.critical - ref.critical) < 1e-4
