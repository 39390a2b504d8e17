"""Floquet multipliers of a harmonic-balance periodic solution (the bridge to HB).

The HB solver gives Fourier coefficients ``X`` (H+1, n) with
``q(t) = Re sum_k X_k exp(i k w t)`` (docs/INTERFACES.md); the model layer gives the
vectorised ``nl_jacobian(q_nl, v_nl) -> (dFdq, dFdv)`` (..., m, m). This module samples the
orbit and its Jacobians and calls the chosen Floquet method.
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rotorsfd.errors import ConfigError
from rotorsfd.stability.floquet import STABILITY_TOL, FloquetResult
from rotorsfd.stability.hill import (
    fourier_coefficients,
    hill_floquet,
    sampled_first_order_coefficients,
)
from rotorsfd.stability.monodromy import floquet_multipliers
from rotorsfd.stability.reduction import craig_bampton

NLJacobian = Callable[[NDArray, NDArray], tuple[NDArray, NDArray]]


@lru_cache(maxsize=8)
def _phases(n_intervals: int, n_harmonics: int, endpoint: bool) -> NDArray:
    """``e^{i k w t_j} = e^{2 pi i (j k mod N) / N}`` (j = 0..N or 0..N-1, k = 0..H-1):
    independent of w, so one table serves every point of a branch (read-only)."""
    N = int(n_intervals)
    jk = np.outer(np.arange(N + 1 if endpoint else N), np.arange(n_harmonics)) % N
    E = np.exp((2j * np.pi / N) * jk)
    E.flags.writeable = False
    return E


def orbit_samples(X: ArrayLike, omega: float, n_intervals: int, *,
                  endpoint: bool = True) -> tuple[NDArray, NDArray]:
    """``q(t_j)``, ``q'(t_j)`` at ``t_j = j T / N`` (j = 0..N, or 0..N-1 without endpoint):
    ``q = Re sum X_k e^{i k w t}``, ``q' = Re sum i k w X_k e^{i k w t}``."""
    X = np.asarray(X, dtype=complex)
    k = np.arange(X.shape[0])
    E = _phases(int(n_intervals), X.shape[0], bool(endpoint))
    return (E @ X).real, (E @ (1j * omega * k[:, None] * X)).real


def orbit_accelerations(X: ArrayLike, omega: float, n_intervals: int, *,
                        endpoint: bool = True) -> NDArray:
    """``q''(t_j) = Re sum -(k w)^2 X_k e^{i k w t}`` at the samples of
    :func:`orbit_samples`."""
    X = np.asarray(X, dtype=complex)
    k = np.arange(X.shape[0])
    E = _phases(int(n_intervals), X.shape[0], bool(endpoint))
    return (E @ (-((omega * k) ** 2)[:, None] * X)).real


def inertial_jacobians(jacobians: Callable, X: ArrayLike, omega: float, n_intervals: int,
                       *, endpoint: bool = True) -> tuple[NDArray, NDArray, NDArray]:
    """``(dF/dq, dF/dv, dF/da)`` on the orbit's samples of a force of the acceleration
    too, ``jacobians(q, v, a) -> (F, dF/dq, dF/dv, dF/da)``."""
    q, v = orbit_samples(X, omega, n_intervals, endpoint=endpoint)
    a = orbit_accelerations(X, omega, n_intervals, endpoint=endpoint)
    _, Jq, Jv, Ja = jacobians(q, v, a)
    return Jq, Jv, Ja


def orbit_floquet(M: ArrayLike, D: ArrayLike, K: ArrayLike, X: ArrayLike, omega: float,
                  nl_dofs: ArrayLike, nl_jacobian: NLJacobian, *,
                  method: str = "newmark-cb", n_intervals: int = 400,
                  n_harmonics: int = 8, n_modes: int | None = None,
                  omega_max: float | None = None, rho_inf: float = 0.6,
                  tol: float = STABILITY_TOL, nl_jacobians: Callable | None = None
                  ) -> FloquetResult:
    """Floquet multipliers of the periodic solution ``X`` (H+1, n) or (H+1, m) of
    ``M q'' + D q' + K q = f(t) + F_nl(q[nl], q'[nl])``, fundamental frequency ``omega``.

    ``method``: ``'newmark'`` (full model, the paper's literal method, N = n_intervals),
    ``'newmark-cb'`` (Craig-Bampton reduced, see ``floquet_multipliers``),
    ``'generalized-alpha'`` / ``'generalized-alpha-cb'`` (with ``rho_inf``),
    ``'hill'`` / ``'hill-koopman'`` (Hill with ``n_harmonics`` on the same reduced model;
    Jacobian harmonics up to ``2 n_harmonics`` from 8 (2 n_harmonics + 1) samples).
    ``nl_jacobians(q, v, a) -> (F, dF/dq, dF/dv, dF/da)``: a force of the acceleration
    too (fluid inertia), whose added mass ``dF/da`` joins the Newmark methods' mass.
    """
    nl = np.asarray(nl_dofs, dtype=np.intp).ravel()
    X = np.asarray(X, dtype=complex)
    n = np.asarray(M).shape[0]
    Xnl = X[:, nl] if X.shape[1] == n else X
    if Xnl.shape[1] != nl.size:
        raise ConfigError("X", X.shape, f"(H+1, {n}) or (H+1, {nl.size}) coefficients")
    T = 2 * np.pi / omega
    if method in ("newmark", "newmark-cb", "generalized-alpha", "generalized-alpha-cb"):
        Ja = None
        if nl_jacobians is not None:
            Jq, Jv, Ja = inertial_jacobians(nl_jacobians, Xnl, omega, n_intervals)
        else:
            Jq, Jv = nl_jacobian(*orbit_samples(Xnl, omega, n_intervals))
        return floquet_multipliers(M, D, K, T, nl_dofs=nl, dFdq=Jq, dFdv=Jv, dFda=Ja,
                                   n_intervals=n_intervals,
                                   reduction="craig-bampton" if method.endswith("-cb") else None,
                                   n_modes=n_modes, omega_max=omega_max,
                                   scheme=method.removesuffix("-cb"), rho_inf=rho_inf,
                                   tol=tol)
    if method in ("hill", "hill-koopman"):
        L = 2 * n_harmonics
        if n_modes is None and omega_max is None:
            omega_max = 0.25 * n_intervals / T
        red = craig_bampton(M, D, K, nl, n_modes=n_modes, omega_max=omega_max)
        hill_method = "koopman" if method == "hill-koopman" else "symmetric"
        if nl_jacobians is not None:   # a time-varying added mass: A(t) from samples
            Jq, Jv, Ja = inertial_jacobians(nl_jacobians, Xnl, omega, 4 * (2 * L + 1),
                                            endpoint=False)
            res = hill_floquet(red.M, red.D, red.K, omega, n_harmonics=n_harmonics,
                               method=hill_method, tol=tol,
                               A_hat=sampled_first_order_coefficients(
                                   red.M, red.D, red.K, red.nl_dofs, Jq, Jv, Ja, L))
            res.info.update(n_dof_full=n, n_modes=red.omegas.size)
            return res
        q, v = orbit_samples(Xnl, omega, 4 * (2 * L + 1), endpoint=False)
        Jq, Jv = nl_jacobian(q, v)
        res = hill_floquet(red.M, red.D, red.K, omega, nl_dofs=red.nl_dofs,
                           dFdq_hat=fourier_coefficients(Jq, L),
                           dFdv_hat=fourier_coefficients(Jv, L), n_harmonics=n_harmonics,
                           method=hill_method, tol=tol)
        res.info.update(n_dof_full=n, n_modes=red.omegas.size)
        return res
    raise ConfigError("method", method, "'newmark', 'newmark-cb', 'generalized-alpha', "
                      "'generalized-alpha-cb', 'hill' or 'hill-koopman'")
