"""Branch switching at a period-doubling point: the period-2 branch by harmonic balance.

At a period-doubling bifurcation of a T-periodic solution ``X`` (a Floquet multiplier
through -1) a 2T-periodic branch is born. In harmonics of ``w/2`` the period-1 solution
has only even harmonics, ``X2_{2k} = X_k`` (:func:`doubled_coefficients`), and it still
solves the period-2 HB equations (:func:`period_doubled`: same system, fundamental
``w/2``, forcing harmonic k moved to 2k). The HB Jacobian at that solution does not couple
even and odd harmonics; its odd block is singular exactly where a multiplier is -1 (the
HB counterpart of the monodromy's eigenvector: ``dq(t + T) = -dq(t)``). Its null vector
``phi`` (smallest singular vector) is the direction of the new branch: a point on it is
found by Newton on ``R(z) = 0, phi . z = delta`` (the odd part fixed to ``delta``, scaled
units), and the period-2 branch is continued from there (pseudo arc-length), first away
from the bifurcation (towards the side where that point lies: the period-2 branch of a
subcritical PD starts on the stable side of the period-1 branch), and, if it turns back at
a fold, on from its last point towards the other end of the range: one or two legs.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.branch import Branch
from rotorsfd.continuation.newton import newton_extended
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.periodic import _setup, continue_periodic
from rotorsfd.harmonic.problem import PeriodicProblem

ComplexArray = NDArray[np.complex128]


def period_doubled(problem: PeriodicProblem) -> PeriodicProblem:
    """The same system written with fundamental frequency ``w(lam)/2``: forcing harmonic
    k becomes harmonic 2k (odd harmonics unforced)."""
    n = problem.n_dof

    def spread(F: ComplexArray, H2: int) -> ComplexArray:
        out = np.zeros((H2 + 1, n), dtype=complex)
        out[0::2] = F[: H2 // 2 + 1]
        return out

    return PeriodicProblem(
        n_dof=n, nl_dofs=problem.nl_dofs, matrices=problem.matrices,
        dmatrices=problem.dmatrices,
        forcing=lambda lam, H: spread(problem.forcing(lam, H // 2), H),
        dforcing=lambda lam, H: spread(problem.dforcing(lam, H // 2), H),
        frequency=lambda lam: 0.5 * problem.frequency(lam),
        dfrequency=lambda lam: 0.5 * problem.dfrequency(lam),
        nl_force=problem.nl_force, nl_jacobian=problem.nl_jacobian,
        scaling=problem.scaling, nl_limit=problem.nl_limit,
        name=f"{problem.name} (period 2)", nl_force_jacobian=problem.nl_force_jacobian)


def doubled_coefficients(X: ComplexArray, H2: int | None = None) -> ComplexArray:
    """Coefficients in harmonics of ``w/2``: ``X2_{2k} = X_k`` (H2 default 2H)."""
    X = np.asarray(X, dtype=complex)
    H = X.shape[0] - 1
    H2 = 2 * H if H2 is None else int(H2)
    out = np.zeros((H2 + 1, X.shape[1]), dtype=complex)
    k = min(H, H2 // 2)
    out[0: 2 * k + 1: 2] = X[: k + 1]
    return out


@dataclass
class PeriodDoublingSwitch:
    """The period-2 branch born at a period-doubling point.

    ``legs``: one or two branches continued in ``problem`` (the :func:`period_doubled`
    problem: its ``frequency`` is ``w/2``, so ``X`` are coefficients of harmonics of
    ``w/2``), the second starting where the first turned back;
    ``lam_bifurcation``: where it was switched; ``singular_value``: the smallest singular
    value of the scaled odd-harmonic HB Jacobian there (0 at an exact PD);
    ``coupling``: the norm of its odd-even block relative to the Jacobian (0 in exact
    arithmetic); ``delta``: the odd amplitude of the first point (scaled units).
    """

    legs: list[Branch]
    problem: PeriodicProblem
    lam_bifurcation: float
    singular_value: float
    coupling: float
    delta: float

    @property
    def lam(self) -> NDArray[np.float64]:
        """Parameter of every point of the legs, in order."""
        return np.concatenate([b.lam for b in self.legs])

    @property
    def X(self) -> ComplexArray:
        """Coefficients (n_points, H+1, n_dof) of every point of the legs, in order."""
        return np.concatenate([b.X for b in self.legs])

    def subharmonic_amplitude(self, dof: int) -> NDArray[np.float64]:
        """``|X_1|`` (the w/2 component) of one DOF along the legs."""
        return np.abs(self.X[:, 1, dof])


def switch_period_doubling(problem: PeriodicProblem, lam: float, X: ComplexArray,
                           lam_range: tuple[float, float], *, H: int | None = None,
                           delta: float = 0.05,
                           n_samples: int | None = None, tol: float = 1e-8,
                           limit_max: float = 1.0, **continue_kw: Any
                           ) -> PeriodDoublingSwitch:
    """Continue the period-2 branch from the period-doubling point ``(lam, X)`` of
    ``problem`` (``X`` (H+1, n_dof), e.g. ``branch.point_at(bif.s).X``) within
    ``lam_range = (lo, hi)`` (module docstring: one or two legs).

    ``H``: harmonics of ``w/2`` (default 2 (H+1)); ``delta``: odd-harmonic amplitude of the
    first point along the null vector (scaled units: fractions of the problem's length
    scale); ``continue_kw`` go to :func:`~rotorsfd.harmonic.periodic.continue_periodic`.
    Raises ConvergenceError if no period-2 point is found.
    """
    X = np.asarray(X, dtype=complex)
    H2 = 2 * X.shape[0] if H is None else int(H)
    p2 = period_doubled(problem)
    X2 = doubled_coefficients(X, H2)
    lo, hi = sorted(lam_range)
    scale = (hi - lo) or max(abs(lam), 1.0)
    system, z0 = _setup(p2, H2, lam, X2, n_samples, True, scale, limit_max)
    e = np.zeros(system.n + 1)
    e[-1] = 1.0
    base = newton_extended(system, z0, e, float(z0[-1]), tol, 30)
    if not base.converged:
        raise ConvergenceError(f"{problem.name}: the period-1 solution at lam={lam:.9g} "
                               f"does not solve the period-2 equations: {base.message}")
    m = system.n // (2 * H2 + 1)
    rows = np.arange(2 * H2 + 1).reshape(-1, 1)
    harmonic = (rows + 1) // 2                       # 0, 1, 1, 2, 2, ...
    odd = np.nonzero(np.broadcast_to(harmonic % 2 == 1, (2 * H2 + 1, m)).ravel())[0]
    even = np.setdiff1d(np.arange(system.n), odd)
    J = base.J[:, :-1]
    _, sv, vt = np.linalg.svd(J[np.ix_(odd, odd)])
    coupling = float(np.linalg.norm(J[np.ix_(even, odd)]) / np.linalg.norm(J))
    a = np.zeros(system.n + 1)
    a[odd] = vt[-1]
    start = newton_extended(system, base.z + delta * a, a, delta, tol, 40)
    if not start.converged:
        raise ConvergenceError(f"{problem.name}: no period-2 point with odd amplitude "
                               f"{delta:g} near lam={lam:.9g}: {start.message}")
    X_start = system.coefficients(start.z)
    lam_start = system.from_z(start.z)[1]
    kw = {"tol": 1e-8, "limit_max": limit_max, "lam_scale": scale, **continue_kw}
    away = lo if lam_start < lam else hi
    legs = [continue_periodic(p2, lam_start, away, H2, X_start, n_samples=n_samples, **kw)]
    last = legs[0]
    if not last.success and "turned back" in last.message and last.n_points > 1:
        other = hi if away == lo else lo
        legs.append(continue_periodic(p2, float(last.lam[-1]), other, H2, last.X[-1],
                                      n_samples=n_samples, **kw))
    return PeriodDoublingSwitch(legs, p2, float(lam), float(sv[-1]), coupling, delta)
