"""Monodromy matrix of the linearised (perturbation) equation along a periodic orbit.

Perturbation equation (paper eq. 30, signs derived from ``M q'' + D q' + K q = F_nl``)::

    M dq'' + (D - P C_nl(t) P^T) dq' + (K - P K_nl(t) P^T) dq = 0,
    K_nl = dF_nl/dq,  C_nl = dF_nl/dq'  (m x m, on the nonlinear DOFs; P selects them).

Newmark average acceleration (gamma = 1/2, beta = 1/4) over ``N`` intervals ``h = T/N``.
Written as a state transition on ``(x_j, v_j)`` (the acceleration eliminated exactly with
the equation of motion at ``t_j``, ``M a_j = -D_j v_j - K_j x_j``; nothing is dropped)::

    S_{j+1} x_{j+1} = (4/h^2 M + 2/h D_{j+1} - K_j) x_j + (4/h M + D_{j+1} - D_j) v_j
    v_{j+1}        = 2/h (x_{j+1} - x_j) - v_j
    S_{j+1}        = 4/h^2 M + 2/h D_{j+1} + K_{j+1}

This is the trapezoidal rule on ``y' = A(t) y`` (second order, A-stable, symplectic for
undamped constant systems) and equals the paper's eq. 35-36 (``E_j``, ``F_j``, ``T_j``);
the term the paper neglects in eq. 34 is identically zero in this derivation.
``Phi = T_{N-1} ... T_0``. The rank-m time dependence is exploited with Woodbury:
``S_{j+1}^-1 = S_0^-1 + Z W (I - G W)^-1 P^T S_0^-1``, ``Z = S_0^-1 P``, ``G = P^T Z``,
``W = 2/h C_nl + K_nl``, so each step costs two ``n x n @ n x 2n`` products. The loops
(Newmark and generalized-alpha) run compiled, :mod:`rotorsfd.stability.monodromy_kernels`
(one numba loop, same arithmetic); ``compiled=False`` runs the numpy loop, the reference
they are tested against (same multipliers to 1e-10; about 20-80x slower on the 8-10 DOF
Craig-Bampton models of the branch analyses).

The trap (tested): the scheme is non-dissipative and maps a mode with ``omega h >> 1``
to a per-step rotation ``~ pi - 4/(omega h)``; that slow beat meets a harmonic k of the
periodic Jacobian when ``omega ~ 4 N^2 / (k pi T)`` and produces a first-order
*numerical* parametric-resonance tongue (``|mu| = 1.08`` for a 10 % stiffness modulation
while the exact system is neutral). Remedies here: the Craig-Bampton reduced model
(``floquet_multipliers``) or generalized-alpha (``monodromy_generalized_alpha``).

``monodromy_magnus4`` is a fourth-order alternative (Gauss-point Magnus exponential),
exact for constant coefficients, used as a reference.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np
import scipy.linalg as sla
from numpy.typing import ArrayLike, NDArray

from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.stability.floquet import (
    STABILITY_TOL,
    FloquetResult,
    liouville_log_det,
    sort_multipliers,
)
from rotorsfd.stability.monodromy_kernels import generalized_alpha_loop, newmark_loop
from rotorsfd.stability.reduction import craig_bampton

if TYPE_CHECKING:
    from rotorsfd.second_order import SecondOrderSystem

JacobianInput = Callable[[float], ArrayLike] | ArrayLike | None
"""A callable ``t -> (m, m)``, or samples ``(N+1, m, m)`` at ``t_j = j T/N`` (``j = 0..N``),
or ``(N, m, m)`` (periodic, ``t_N`` = ``t_0``), or None (zero)."""


def sample_jacobian(jac: JacobianInput, period: float, n_intervals: int,
                    m: int) -> NDArray[np.float64]:
    """Samples ``(N+1, m, m)`` of a Jacobian input at ``t_j = j T/N``, ``j = 0..N``."""
    N = n_intervals
    if jac is None:
        return np.zeros((N + 1, m, m))
    if callable(jac):
        t = np.linspace(0.0, period, N + 1)
        return np.array([np.asarray(jac(tj), float).reshape(m, m) for tj in t])
    a = np.asarray(jac, float)
    if a.ndim == 2 and m == 1:
        a = a.reshape(-1, 1, 1)
    if a.shape == (N, m, m):
        a = np.concatenate([a, a[:1]], axis=0)
    if a.shape != (N + 1, m, m):
        raise ConfigError("jacobian samples", a.shape,
                          f"shape ({N + 1}, {m}, {m}) or ({N}, {m}, {m}) for N={N}")
    return np.ascontiguousarray(a)


def _check_period(period: float, n_intervals: int) -> None:
    if not (np.isfinite(period) and period > 0):
        raise ConfigError("period", period, "a finite period > 0")
    if int(n_intervals) < 1:
        raise ConfigError("n_intervals", n_intervals, "at least 1")


def _finite(Phi: NDArray, method: str, period: float) -> NDArray:
    if not np.all(np.isfinite(Phi)):
        raise ConvergenceError(f"{method} monodromy not finite (T={period:.6g}): check the "
                               "Jacobian samples for NaN/inf")
    return Phi


def _check_square(M: ArrayLike, D: ArrayLike, K: ArrayLike):
    M, D, K = (np.atleast_2d(np.asarray(x, float)) for x in (M, D, K))
    n = M.shape[0]
    for name, x in (("M", M), ("D", D), ("K", K)):
        if x.shape != (n, n):
            raise ConfigError(name, x.shape, f"square ({n}, {n}) like M")
    return M, D, K


def _prepare(M: ArrayLike, D: ArrayLike, K: ArrayLike, period: float, n_intervals: int,
             nl_dofs: ArrayLike) -> tuple[NDArray, NDArray, NDArray, NDArray, int, float]:
    """Checked (M, D, K), the nonlinear DOF indices, N and the step h = T / N."""
    M, D, K = _check_square(M, D, K)
    _check_period(period, n_intervals)
    N = int(n_intervals)
    return M, D, K, np.asarray(nl_dofs, dtype=np.intp).ravel(), N, period / N


def _trace_MinvD(M: NDArray, D: NDArray, nl: NDArray, Cn: NDArray,
                 Mn: NDArray | None = None) -> NDArray:
    """tr(M^-1 (D - P C_nl(t_j) P^T)) at every sample: the Liouville integrand (with an
    added mass ``Mn``, ``M_j = M - P Mn_j P^T`` in place of M)."""
    if Mn is not None:
        out = np.empty(Cn.shape[0])
        for j in range(Cn.shape[0]):
            Mj, Dj = M.copy(), D.copy()
            Mj[np.ix_(nl, nl)] -= Mn[j]
            Dj[np.ix_(nl, nl)] -= Cn[j]
            out[j] = float(np.trace(np.linalg.solve(Mj, Dj)))
        return out
    Minv = np.linalg.inv(M)
    tr0 = float(np.sum(Minv * D.T))
    if not nl.size:
        return np.full(Cn.shape[0], tr0)
    MinvP = Minv[np.ix_(nl, nl)]  # tr(MinvP C_t) = sum_ij MinvP_ij C_t,ji
    return tr0 - Cn.reshape(Cn.shape[0], -1) @ MinvP.T.ravel()


def _newmark_numpy(AB: NDArray, AE: NDArray, Z: NDArray, G: NDArray, nl: NDArray,
                   Kn: NDArray, Cn: NDArray, h: float) -> NDArray:
    """The Newmark recursion in numpy (the reference of ``newmark_loop``): ``[X; V]``."""
    n, m, N = AB.shape[0], nl.size, Kn.shape[0] - 1
    X = np.hstack([np.eye(n), np.zeros((n, n))])
    V = np.hstack([np.zeros((n, n)), np.eye(n)])
    Im = np.eye(m)
    for j in range(N):
        Xp, Vp = X[nl], V[nl]
        Y = AB @ X + AE @ V
        if m:
            rP = -(2.0 / h * Cn[j + 1] - Kn[j]) @ Xp - (Cn[j + 1] - Cn[j]) @ Vp
            Y += Z @ rP
            W = 2.0 / h * Cn[j + 1] + Kn[j + 1]
            Y += Z @ (W @ np.linalg.solve(Im - G @ W, Y[nl]))
        V = 2.0 / h * (Y - X) - V
        X = Y
    return np.vstack([X, V])


def _generalized_alpha_numpy(SM: NDArray, SD: NDArray, SK: NDArray, Z: NDArray,
                             G: NDArray, nl: NDArray, Kn: NDArray, Cn: NDArray,
                             A: NDArray, h: float, am: float, af: float, g: float,
                             b: float, Mn: NDArray | None = None) -> NDArray:
    """The generalized-alpha recursion in numpy (the reference of
    ``generalized_alpha_loop``): ``[X; V]``."""
    n, m, N = SM.shape[0], nl.size, Kn.shape[0] - 1
    X = np.hstack([np.eye(n), np.zeros((n, n))])
    V = np.hstack([np.zeros((n, n)), np.eye(n)])
    Im = np.eye(m)
    for j in range(N):
        Xp = X + h * V + h**2 * (0.5 - b) * A
        Vp = V + h * (1 - g) * A
        xs, vs = af * X + (1 - af) * Xp, af * V + (1 - af) * Vp
        Y = -am * (SM @ A) - SD @ vs - SK @ xs
        if m:
            rP = (af * (Cn[j] @ V[nl] + Kn[j] @ X[nl])
                  + (1 - af) * (Cn[j + 1] @ Vp[nl] + Kn[j + 1] @ Xp[nl]))
            Y += Z @ rP
            W = (1 - af) * (g * h * Cn[j + 1] + b * h**2 * Kn[j + 1])
            if Mn is not None:   # the added mass: M_j = M - P Mn_j P^T
                Y += Z @ (am * Mn[j] @ A[nl])
                W = W + (1 - am) * Mn[j + 1]
            Y += Z @ (W @ np.linalg.solve(Im - G @ W, Y[nl]))
        A = Y
        X = Xp + b * h**2 * A
        V = Vp + g * h * A
    return np.vstack([X, V])


def monodromy_newmark(M: ArrayLike, D: ArrayLike, K: ArrayLike, period: float, *,
                      nl_dofs: ArrayLike = (), dFdq: JacobianInput = None,
                      dFdv: JacobianInput = None, n_intervals: int = 400,
                      tol: float = STABILITY_TOL, compiled: bool = True,
                      dFda: JacobianInput = None) -> FloquetResult:
    """Floquet multipliers by average-acceleration Newmark (module docstring recursion).

    Parameters
    ----------
    M, D, K : constant (n, n) linear matrices (D includes gyroscopic and base terms).
    period : T of the orbit.
    nl_dofs : the m DOFs where the nonlinear force acts.
    dFdq, dFdv : ``dF_nl/dq``, ``dF_nl/dq'`` on the orbit (see ``JacobianInput``).
    n_intervals : N (paper: 400).
    dFda : ``dF_nl/dq''`` on the orbit (a force of the acceleration: the added mass, mass
        ``M - P dFda(t) P^T``), None without; then the same average-acceleration scheme
        runs with the acceleration carried (the generalized-alpha recursion with
        ``a_m = a_f = 0, beta = 1/4, gamma = 1/2``: the mass varies, so it cannot be
        eliminated with the constant M).
    compiled : the recursion in one compiled loop
        (:func:`rotorsfd.stability.monodromy_kernels.newmark_loop`, the same arithmetic);
        False: the numpy loop (the reference, ~50x slower on 8 DOF).

    Returns a ``FloquetResult`` with the (2n, 2n) monodromy for the state ``(q, q')``.
    """
    M, D, K, nl, N, h = _prepare(M, D, K, period, n_intervals, nl_dofs)
    n, m = M.shape[0], nl.size
    Kn = sample_jacobian(dFdq, period, N, m)
    Cn = sample_jacobian(dFdv, period, N, m)
    if dFda is not None and m:
        Mn = sample_jacobian(dFda, period, N, m)
        Phi = _finite(_alpha_recursion(M, D, K, nl, h, Kn, Cn, Mn, 0.0, 0.0, 0.5, 0.25,
                                       compiled), "newmark", period)
        mu = sort_multipliers(np.linalg.eigvals(Phi))
        trace = _trace_MinvD(M, D, nl, Cn, Mn)
        return FloquetResult(mu, float(period), "newmark", liouville_log_det(trace, period),
                             Phi, tol, {"n_intervals": N, "n_dof": n})

    S0 = 4.0 / h**2 * M + 2.0 / h * D + K
    S0inv = np.linalg.inv(S0)
    AB = S0inv @ (4.0 / h**2 * M + 2.0 / h * D - K)
    AE = S0inv @ (4.0 / h * M)
    Z = np.ascontiguousarray(S0inv[:, nl])
    G = np.ascontiguousarray(Z[nl, :])
    if compiled:
        c = np.ascontiguousarray  # one compiled specialisation (C layout) for every input
        Phi = newmark_loop(c(AB), c(AE), Z, G, nl.astype(np.int64), Kn, Cn, float(h))
    else:
        Phi = _newmark_numpy(AB, AE, Z, G, nl, Kn, Cn, h)
    Phi = _finite(Phi, "newmark", period)
    mu = sort_multipliers(np.linalg.eigvals(Phi))
    trace = _trace_MinvD(M, D, nl, Cn)
    return FloquetResult(mu, float(period), "newmark", liouville_log_det(trace, period),
                         Phi, tol, {"n_intervals": N, "n_dof": n})


def _alpha_recursion(M: NDArray, D: NDArray, K: NDArray, nl: NDArray, h: float,
                     Kn: NDArray, Cn: NDArray, Mn: NDArray | None, am: float, af: float,
                     g: float, b: float, compiled: bool) -> NDArray:
    """The monodromy ``[X; V]`` of the alpha recursion (``monodromy_generalized_alpha``)
    with the Jacobian samples ``Kn, Cn`` and the added mass ``Mn`` (or None)."""
    m = nl.size
    S0 = (1 - am) * M + (1 - af) * (g * h * D + b * h**2 * K)
    S0inv = np.linalg.inv(S0)
    SM, SD, SK = S0inv @ M, S0inv @ D, S0inv @ K
    Z = np.ascontiguousarray(S0inv[:, nl])
    G = np.ascontiguousarray(Z[nl, :])
    Mt0, Dt0, Kt0 = M.copy(), D.copy(), K.copy()
    if m:
        Dt0[np.ix_(nl, nl)] -= Cn[0]
        Kt0[np.ix_(nl, nl)] -= Kn[0]
        if Mn is not None:
            Mt0[np.ix_(nl, nl)] -= Mn[0]
    A0 = -np.linalg.solve(Mt0, np.hstack([Kt0, Dt0]))  # -M_0^-1 (D_0 V + K_0 X)
    if compiled:
        c = np.ascontiguousarray  # one compiled specialisation (C layout) for every input
        return generalized_alpha_loop(c(SM), c(SD), c(SK), Z, G, nl.astype(np.int64), Kn,
                                      Cn, c(A0), float(h), am, af, g, b,
                                      np.zeros((1, m, m)) if Mn is None else c(Mn),
                                      Mn is not None)
    return _generalized_alpha_numpy(SM, SD, SK, Z, G, nl, Kn, Cn, A0, h, am, af, g, b, Mn)


def monodromy_generalized_alpha(M: ArrayLike, D: ArrayLike, K: ArrayLike, period: float,
                                *, nl_dofs: ArrayLike = (), dFdq: JacobianInput = None,
                                dFdv: JacobianInput = None, n_intervals: int = 400,
                                rho_inf: float = 0.6, tol: float = STABILITY_TOL,
                                compiled: bool = True, dFda: JacobianInput = None
                                ) -> FloquetResult:
    """Floquet multipliers by generalized-alpha (Chung & Hulbert 1993), second order.

    ``alpha_m = (2 rho - 1)/(rho + 1)``, ``alpha_f = rho/(rho + 1)``,
    ``gamma = 1/2 - alpha_m + alpha_f``, ``beta = (1 - alpha_m + alpha_f)^2 / 4``; balance
    at the alpha-points with the matrices weighted like the states::

        (1-a_m) M a_{j+1} + a_m M a_j + (1-a_f)(D_{j+1} v_{j+1} + K_{j+1} x_{j+1})
                                      + a_f (D_j v_j + K_j x_j) = 0
        x_{j+1} = x_j + h v_j + h^2 ((1/2 - beta) a_j + beta a_{j+1})
        v_{j+1} = v_j + h ((1 - gamma) a_j + gamma a_{j+1})

    with ``a_0 = -M^-1 (D_0 v_0 + K_0 x_0)``; the monodromy is the map
    ``(x_0, v_0) -> (x_N, v_N)``. Unresolved modes (``omega h >> 1``) are damped to
    ``|mu| ~ rho_inf^N ~ 0`` instead of sitting on the unit circle; resolved modes keep
    second-order accuracy (algorithmic damping ``O((omega h)^3)``). ``rho_inf < 1``;
    default 0.6: on the paper rotor at N = 400 it brings the max |mu| of the full model
    to the SFD-coupled multiplier of the reference (6e-5 off) while the partially
    resolved modes (``omega h ~ 0.3..3``) drop below it; the modal error constant grows
    by ~1.5 from rho_inf = 0.99 to 0.5 (tests). ``compiled``, ``dFda`` (the added mass
    ``M_j = M - P dFda_j P^T`` in the balance): as ``monodromy_newmark``.
    """
    if not 0.0 <= rho_inf < 1.0:
        raise ConfigError("rho_inf", rho_inf, "0 <= rho_inf < 1")
    M, D, K, nl, N, h = _prepare(M, D, K, period, n_intervals, nl_dofs)
    n, m = M.shape[0], nl.size
    am = (2 * rho_inf - 1) / (rho_inf + 1)
    af = rho_inf / (rho_inf + 1)
    g = 0.5 - am + af
    b = 0.25 * (1 - am + af) ** 2
    Kn = sample_jacobian(dFdq, period, N, m)
    Cn = sample_jacobian(dFdv, period, N, m)
    Mn = sample_jacobian(dFda, period, N, m) if dFda is not None and m else None
    Phi = _alpha_recursion(M, D, K, nl, h, Kn, Cn, Mn, am, af, g, b, compiled)
    Phi = _finite(Phi, "generalized-alpha", period)
    mu = sort_multipliers(np.linalg.eigvals(Phi))
    trace = _trace_MinvD(M, D, nl, Cn, Mn)
    return FloquetResult(mu, float(period), "generalized-alpha",
                         liouville_log_det(trace, period), Phi, tol,
                         {"n_intervals": N, "n_dof": n, "rho_inf": rho_inf})


def _first_order(Minv: NDArray, D: NDArray, K: NDArray) -> NDArray:
    n = D.shape[0]
    return np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ K, -Minv @ D]])


def monodromy_magnus4(M: ArrayLike, D: ArrayLike, K: ArrayLike, period: float, *,
                      nl_dofs: ArrayLike = (),
                      dFdq: Callable[[float], ArrayLike] | None = None,
                      dFdv: Callable[[float], ArrayLike] | None = None,
                      n_intervals: int = 100, tol: float = STABILITY_TOL) -> FloquetResult:
    """Floquet multipliers by the fourth-order Magnus integrator (callable Jacobians).

    Per step ``Omega = h/2 (A1 + A2) + sqrt(3)/12 h^2 [A2, A1]`` with ``A1, A2`` at the
    Gauss points ``t + (1/2 -+ sqrt(3)/6) h``; ``Phi <- expm(Omega) Phi``. Exact (to expm
    accuracy) for constant coefficients; error O(h^4) otherwise. Cost O(N (2n)^3 * ~20).
    """
    M, D, K, nl, N, h = _prepare(M, D, K, period, n_intervals, nl_dofs)
    n, m = M.shape[0], nl.size
    Minv = np.linalg.inv(M)
    zero = np.zeros((m, m))

    def A(t: float) -> NDArray:
        Dt, Kt = D.copy(), K.copy()
        if m:
            Kt[np.ix_(nl, nl)] -= np.asarray(dFdq(t), float).reshape(m, m) if dFdq else zero
            Dt[np.ix_(nl, nl)] -= np.asarray(dFdv(t), float).reshape(m, m) if dFdv else zero
        return _first_order(Minv, Dt, Kt)

    c1, c2 = 0.5 - np.sqrt(3) / 6, 0.5 + np.sqrt(3) / 6
    A1 = np.array([A((j + c1) * h) for j in range(N)])
    A2 = np.array([A((j + c2) * h) for j in range(N)])
    Om = 0.5 * h * (A1 + A2) + np.sqrt(3) / 12 * h**2 * (A2 @ A1 - A1 @ A2)
    E = sla.expm(Om)  # batched over the N steps
    Phi = np.eye(2 * n)
    for j in range(N):
        Phi = E[j] @ Phi
    log_det = float(0.5 * h * np.trace(A1 + A2, axis1=1, axis2=2).sum())
    mu = sort_multipliers(np.linalg.eigvals(_finite(Phi, "magnus4", period)))
    return FloquetResult(mu, float(period), "magnus4", log_det, Phi, tol,
                         {"n_intervals": N, "n_dof": n})


def floquet_multipliers(M: ArrayLike, D: ArrayLike, K: ArrayLike, period: float, *,
                        nl_dofs: ArrayLike = (), dFdq: JacobianInput = None,
                        dFdv: JacobianInput = None, n_intervals: int = 400,
                        reduction: str | None = "craig-bampton", n_modes: int | None = None,
                        omega_max: float | None = None, scheme: str = "newmark",
                        rho_inf: float = 0.6, tol: float = STABILITY_TOL,
                        compiled: bool = True, dFda: JacobianInput = None) -> FloquetResult:
    """Floquet multipliers by Newmark, on the full model or a Craig-Bampton reduced one.

    ``reduction=None`` is the paper's literal method (full model, N = 400).
    ``reduction='craig-bampton'`` keeps ``nl_dofs`` and the fixed-interface modes with
    ``omega <= omega_max`` (default ``omega_max = N / (4 T)``, i.e. ``omega h <= 1/4``:
    the scheme's relative error in modal decay rate, ``(omega h)^2 / 4``, stays below
    1.6 %) and/or the ``n_modes`` lowest. The reduced model's 2 r multipliers approximate
    the physically relevant (nonlinear-DOF-coupled) ones of the full model; the dropped
    ones belong to stiff interior modes that Newmark does not resolve (it compresses their
    frequencies towards pi/h, where they can meet spurious parametric resonances) and
    that sit, undamped, at ``|mu| ~ 1`` in the exact model as well.
    ``scheme='generalized-alpha'`` (with ``rho_inf``) damps unresolved modes instead.
    ``compiled=False`` runs the numpy reference loop (same multipliers to round-off).
    ``dFda``: the added mass of a force of the acceleration on the orbit (the reduction
    keeps the nonlinear DOFs physical, so it acts on the same rows), None without.
    """
    if scheme == "newmark":
        def run(*a, **k):
            return monodromy_newmark(*a, compiled=compiled, **k)
    elif scheme == "generalized-alpha":
        def run(*a, **k):
            return monodromy_generalized_alpha(*a, rho_inf=rho_inf, compiled=compiled,
                                               **k)
    else:
        raise ConfigError("scheme", scheme, "'newmark' or 'generalized-alpha'")
    if reduction is None:
        return run(M, D, K, period, nl_dofs=nl_dofs, dFdq=dFdq, dFdv=dFdv,
                   n_intervals=n_intervals, tol=tol, dFda=dFda)
    if reduction != "craig-bampton":
        raise ConfigError("reduction", reduction, "None or 'craig-bampton'")
    if n_modes is None and omega_max is None:
        omega_max = 0.25 * n_intervals / period
    red = craig_bampton(M, D, K, nl_dofs, n_modes=n_modes, omega_max=omega_max)
    res = run(red.M, red.D, red.K, period, nl_dofs=red.nl_dofs, dFdq=dFdq, dFdv=dFdv,
              n_intervals=n_intervals, tol=tol, dFda=dFda)
    res.method += "-cb"
    res.info.update(n_dof_full=np.asarray(M).shape[0], n_modes=red.omegas.size,
                    omega_max_kept=float(red.omegas.max()) if red.omegas.size else 0.0)
    return res


@dataclass(frozen=True)
class MonodromyOptions:
    """How the monodromy is computed (:func:`floquet_multipliers`): ``n_intervals`` N over
    the period, ``reduction`` (``"craig-bampton"`` or None: the full model), its
    ``n_modes`` / ``omega_max``, the ``scheme`` (``"newmark"`` or ``"generalized-alpha"``
    with ``rho_inf``), the stability tolerance and the compiled loop."""

    n_intervals: int = 400
    reduction: str | None = "craig-bampton"
    n_modes: int | None = None
    omega_max: float | None = None
    scheme: str = "newmark"
    rho_inf: float = 0.6
    tol: float = STABILITY_TOL
    compiled: bool = True


def system_multipliers(system: SecondOrderSystem, dFdq: JacobianInput = None,
                       dFdv: JacobianInput = None,
                       options: MonodromyOptions | None = None,
                       dFda: JacobianInput = None) -> FloquetResult:
    """Floquet multipliers of a periodic orbit of a
    :class:`~rotorsfd.second_order.SecondOrderSystem` with constant matrices (the
    perturbation equation of the module docstring over its period ``T = 2 pi / Omega``):
    ``dFdq``, ``dFdv`` the force law's Jacobians on the orbit (:data:`JacobianInput`),
    ``options`` a :class:`MonodromyOptions`; ``dFda`` the acceleration Jacobian on the
    orbit of a law with fluid inertia (its added mass; required for such a law)."""
    o = options if options is not None else MonodromyOptions()
    if system.time_varying is not None and system.time_varying.n_terms:
        raise ConfigError("base", "time-varying", "the orbit's monodromy needs constant "
                          "matrices (a constant base motion)")
    if system.has_inertia and dFda is None:
        raise ValueError("a force law with fluid inertia needs its acceleration Jacobian "
                         "dFda on the orbit (the added mass of the monodromy)")
    M, D, K = system.M, system.D, system.K
    if o.reduction is None:          # the full model's monodromy: dense (CSR above 400 DOFs)
        from rotorsfd.model.lowrank import dense

        M, D, K = dense(M), dense(D), dense(K)
    return floquet_multipliers(M, D, K, system.period,
                               nl_dofs=system.nl_dofs, dFdq=dFdq, dFdv=dFdv,
                               n_intervals=o.n_intervals, reduction=o.reduction,
                               n_modes=o.n_modes, omega_max=o.omega_max, scheme=o.scheme,
                               rho_inf=o.rho_inf, tol=o.tol, compiled=o.compiled,
                               dFda=dFda)
