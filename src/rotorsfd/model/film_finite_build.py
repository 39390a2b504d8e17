"""Building the eps tables of the finite film (:mod:`rotorsfd.model.film_finite_table`):
the grid solver at the table's nodes, and the table's error against the solver measured
at the midpoint of every interval (the verified error bound of the surrogate)."""

from __future__ import annotations

import numpy as np

from rotorsfd.model.film_finite_kernels import (
    N_PARAMS,
    P_END_FLOW,
    P_EPS_MAX,
    P_LENGTH,
    P_N_AXIAL,
    P_N_THETA,
    P_RADIUS,
    P_TABLE_N,
    basis_fields,
    film_sums,
    table_matrices,
)
from rotorsfd.model.film_finite_table import TABLE_NODES, hermite_fields, table_eps

__all__ = ["field_table", "matrix_table"]


def matrix_table(params: np.ndarray) -> tuple[np.ndarray, tuple[float, float]]:
    """``params`` with the eps table appended, and the table's measured error
    ``(M, dM/deps)`` at the midpoints of its intervals."""
    n = TABLE_NODES
    eps_max = params[P_EPS_MAX]

    def exact(eps: float) -> tuple[np.ndarray, np.ndarray]:
        _, _, *m, d0, d1 = film_sums(eps, 1.0, 0.0, params)
        _, _, _, _, _, _, e0, e1 = film_sums(eps, 0.0, 1.0, params)
        return np.array(m), np.array([d0, e0, d1, e1])

    eps, deps_dt = table_eps(n, eps_max)
    data = np.empty((n, 8))
    for k in range(n):
        m, dm = exact(eps[k])
        c = (1.0 - eps[k]) * (1.0 + eps[k])
        scale = c**2.5
        data[k, :4] = scale * m
        data[k, 4:] = (scale * dm - 5.0 * eps[k] * c**1.5 * m) * deps_dt[k]
    out = np.concatenate([params[:N_PARAMS], data.ravel()])
    out[P_TABLE_N] = n
    t_mid = (np.arange(n - 1) + 0.5) / (n - 1)
    err_m = err_d = 0.0
    for eps_k in eps_max * (1.0 - (1.0 - t_mid) ** 2):
        m, dm = exact(eps_k)
        got = np.array(table_matrices(eps_k, out))
        err_m = max(err_m, float(np.abs(got[:4] - m).max() / np.abs(m).max()))
        err_d = max(err_d, float(np.abs(got[4:] - dm).max()
                                 / max(np.abs(dm).max(), np.abs(m).max())))
    return out, (err_m, err_d)


def field_table(params: np.ndarray) -> tuple[np.ndarray, tuple[float, float]]:
    """``params`` with the Guembel film's field table appended, and its measured error
    ``(Pi, dPi/deps)`` at the midpoints (relative to the largest ``|Pi|`` there)."""
    n = TABLE_NODES
    eps_max = params[P_EPS_MAX]
    lam = (0.5 * params[P_LENGTH] / params[P_RADIUS]) ** 2
    grid = (int(params[P_N_THETA]), int(params[P_N_AXIAL]), float(params[P_END_FLOW]))

    def exact(eps: float) -> tuple[np.ndarray, np.ndarray]:
        return basis_fields(eps, lam, grid[0], grid[1], grid[2], True)

    eps, deps_dt = table_eps(n, eps_max)
    blocks = []
    for k in range(n):
        f, df = exact(eps[k])
        c = (1.0 - eps[k]) * (1.0 + eps[k])
        blocks += [c**3 * f.ravel(), (c**3 * df - 6.0 * eps[k] * c**2 * f).ravel()
                   * deps_dt[k]]
    out = np.concatenate([params[:N_PARAMS], *blocks])
    out[P_TABLE_N] = n
    t_mid = (np.arange(n - 1) + 0.5) / (n - 1)
    err_f = err_d = 0.0
    for eps_k in eps_max * (1.0 - (1.0 - t_mid) ** 2):
        f, df = exact(eps_k)
        got_f, got_d = np.empty_like(f), np.empty_like(f)
        hermite_fields(eps_k, eps_max, out, N_PARAMS, n, got_f, got_d)
        scale = np.abs(f).max()
        err_f = max(err_f, float(np.abs(got_f - f).max() / scale))
        err_d = max(err_d, float(np.abs(got_d - df).max() / max(np.abs(df).max(), scale)))
    return out, (err_f, err_d)
