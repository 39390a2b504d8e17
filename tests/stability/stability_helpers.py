"""Shared small systems and helpers for the stability tests."""

from __future__ import annotations

import numpy as np
from scipy.integrate import solve_ivp
from scipy.optimize import linear_sum_assignment


def match_error(a: np.ndarray, b: np.ndarray) -> float:
    """Max distance between two multiplier sets after optimal matching."""
    a, b = np.asarray(a, complex), np.asarray(b, complex)
    cost = np.abs(a[:, None] - b[None, :])
    i, j = linear_sum_assignment(cost)
    return float(cost[i, j].max())


def reference_monodromy(M, D, K, period, nl_dofs, dFdq, dFdv=None, rtol=1e-11):
    """Monodromy from scipy solve_ivp (DOP853) of the variational equations."""
    n = M.shape[0]
    nl = np.asarray(nl_dofs)
    Minv = np.linalg.inv(M)

    def rhs(t, y):
        Kt, Dt = K.copy(), D.copy()
        Kt[np.ix_(nl, nl)] -= dFdq(t)
        if dFdv is not None:
            Dt[np.ix_(nl, nl)] -= dFdv(t)
        A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ Kt, -Minv @ Dt]])
        return (A @ y.reshape(2 * n, 2 * n)).ravel()

    sol = solve_ivp(rhs, (0.0, period), np.eye(2 * n).ravel(), method="DOP853",
                    rtol=rtol, atol=1e-13)
    return sol.y[:, -1].reshape(2 * n, 2 * n)


def ltp3() -> dict:
    """3-DOF damped, gyroscopically coupled system with a rank-2 periodic Jacobian."""
    M = np.diag([1.0, 2.0, 1.5])
    K = np.array([[3.0, -1.0, 0.0], [-1.0, 4.0, -1.0], [0.0, -1.0, 2.0]])
    D = 0.05 * K + 0.3 * np.array([[0, 1.0, 0], [-1.0, 0, 0], [0, 0, 0]])
    T = 2.0
    w = 2 * np.pi / T

    def kq(t):
        return np.array([[-0.8 * np.cos(w * t), 0.2 * np.sin(w * t)],
                         [0.1, -0.5 * np.cos(2 * w * t)]])

    def kv(t):
        return np.array([[0.05 * np.sin(w * t), 0.0], [0.0, -0.02 * np.cos(w * t)]])

    return {"M": M, "D": D, "K": K, "T": T, "nl": [0, 2], "dFdq": kq, "dFdv": kv}
