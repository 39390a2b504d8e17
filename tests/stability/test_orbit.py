"""Floquet multipliers from HB-style Fourier coefficients of an orbit."""

from __future__ import annotations

import numpy as np
import pytest
from stability_helpers import match_error

from rotorsfd.stability.monodromy import monodromy_magnus4
from rotorsfd.stability.orbit import orbit_floquet, orbit_samples

K3, C3 = 10.0, 0.05


def nl_jacobian(q, v):
    """F = -K3 |q|^2 q - C3 v^3 (componentwise) on two DOFs."""
    r2 = np.sum(q**2, axis=-1)[..., None, None]
    dq = -K3 * (r2 * np.eye(2) + 2 * q[..., :, None] * q[..., None, :])
    dv = -3 * C3 * (v[..., :, None] ** 2) * np.eye(2)
    return dq, dv


def _system():
    M = np.diag([1.0, 1.0, 2.0, 1.5])
    K = np.array([[3.0, 0, -1, 0], [0, 3.0, 0, -1], [-1, 0, 4.0, -1], [0, -1, -1, 2.0]])
    G = np.zeros((4, 4))
    G[0, 1], G[1, 0] = 0.3, -0.3
    D = 0.02 * K + G
    X = np.zeros((4, 4), complex)  # H = 3 harmonics, all four DOFs
    X[0] = [0.05, -0.1, 0.0, 0.02]
    X[1] = [0.3 - 0.1j, -0.1 - 0.3j, 0.2, 0.1j]
    X[2] = [0.05j, 0.04, 0.0, 0.0]
    X[3] = [0.01, -0.02j, 0.0, 0.01]
    return M, D, K, X, 1.3, [0, 1]


def test_orbit_samples_convention():
    X = np.array([[0.5], [2 - 3j]])
    q, v = orbit_samples(X, 2.0, 8)
    t = np.arange(9) * np.pi / 8
    assert np.allclose(q[:, 0], 0.5 + 2 * np.cos(2 * t) + 3 * np.sin(2 * t))
    assert np.allclose(v[:, 0], -4 * np.sin(2 * t) + 6 * np.cos(2 * t))


@pytest.mark.parametrize("method", ["newmark", "newmark-cb", "generalized-alpha",
                                    "generalized-alpha-cb", "hill", "hill-koopman"])
def test_orbit_floquet_methods_agree(method):
    M, D, K, X, w, nl = _system()
    T = 2 * np.pi / w

    def at(kind):
        def f(t):
            k = np.arange(X.shape[0])
            e = np.exp(1j * k * w * t)
            q = (e @ X[:, nl]).real
            v = (e @ (1j * w * k[:, None] * X[:, nl])).real
            return nl_jacobian(q, v)[kind]
        return f

    ref = monodromy_magnus4(M, D, K, T, nl_dofs=nl, dFdq=at(0), dFdv=at(1), n_intervals=200)
    r = orbit_floquet(M, D, K, X, w, nl, nl_jacobian, method=method, n_harmonics=12,
                      n_modes=2)
    assert r.stable == ref.stable
    tol = 1e-6 if method.startswith("hill") else 5e-4
    assert abs(r.max_abs - ref.max_abs) < tol
    assert match_error(r.multipliers, ref.multipliers) < 10 * tol
