"""Largest Lyapunov exponent by two nearby trajectories (Benettin et al. 1980).

A reference and a perturbed trajectory run with the same compiled stepper; every
``renorm_every`` steps the separation ``d = sqrt(|dq|^2 + |dv|^2 / w^2)`` (``w``: the
velocity scale, the forcing frequency by default) is measured, ``ln(d/d0)`` accumulated
and the perturbation rescaled to ``d0`` along its current direction::

    lambda = sum ln(d_j / d0) / (t_end - t_start)      [1/s]
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from rotorsfd.errors import ConvergenceError
from rotorsfd.timedomain import newmark as nm
from rotorsfd.timedomain.forcing import Forcing, TimeVaryingMatrices
from rotorsfd.timedomain.integrate import (
    MESSAGES,
    contact_error,
    initial_state,
    prepare,
    run,
)
from rotorsfd.timedomain.step_records import StepOptions

if TYPE_CHECKING:
    from rotorsfd.second_order import SecondOrderSystem

#: The step of a Lyapunov run: Newmark with the Newton iteration converged to 1e-12 (the
#: perturbation of ``d0 ~ 1e-7`` of the state must not drown in the iteration's error).
LYAPUNOV_STEP = StepOptions(newton_rtol=1e-12)

Projector = Callable[[np.ndarray, np.ndarray], tuple[np.ndarray, np.ndarray]]
"""``(dq, dv) -> (dq, dv)``: a linear map of perturbations (displacement, velocity)."""


@dataclass(frozen=True)
class LyapunovResult:
    """``exponent`` [1/s]; ``per_period`` = exponent times the forcing period (or
    ``nan``); ``history``: running estimates after each renormalisation;
    ``half_spread``: |estimate over the second half - estimate over the first half|."""

    exponent: float
    per_period: float
    history: np.ndarray
    times: np.ndarray
    half_spread: float
    d0: float
    renorm_every: int


def largest_lyapunov(*args: Any, project: Projector | None = None,
                     **kwargs: Any) -> LyapunovResult:
    """Largest Lyapunov exponent of the system of :func:`integrate` (same inputs): the
    exponent of :func:`lyapunov_exponents` with one perturbation, ``project`` applied to
    it (None: the whole state)."""
    return lyapunov_exponents(*args, projectors=(project,), **kwargs)[0]


def lyapunov_exponents(M: Any, D: Any, K: Any, nl_dofs: Any, kernel: Any, params: Any,
                       forcing: Forcing | None, dt: float | None = None,
                       n_steps: int | None = None, q0: Any = 0.0, v0: Any = 0.0, *,
                       steps_per_period: int | None = None, n_periods: float | None = None,
                       transient_steps: int = 0, renorm_every: int | None = None,
                       d0: float | None = None, velocity_scale: float | None = None,
                       seed: int = 0, t0: float = 0.0,
                       time_varying: TimeVaryingMatrices | None = None,
                       method: str = "newmark", alpha: float = 0.05, rho_inf: float = 0.9,
                       newton_rtol: float = 1e-12,
                       projectors: tuple[Projector | None, ...] = (None,),
                       inertial_kernel: Any = None) -> list[LyapunovResult]:
    """Largest Lyapunov exponents of the system of :func:`integrate` (same inputs), one
    per entry of ``projectors``, all around one reference trajectory (each perturbation
    costs one trajectory, the reference is shared; the same random start direction,
    projected).

    ``n_steps`` (or ``n_periods``) counts the measured steps after ``transient_steps``.
    ``renorm_every`` defaults to one forcing period (or 100 steps); ``d0`` (absolute, in
    the units of ``q``) to ``1e-7`` times the largest ``|q|`` or ``|v|/w`` at the end of
    the transient (``1e-10`` if the state is zero).

    A projector ``project(dq, dv) -> (dq, dv)`` is applied to its perturbation at the
    start and before each measurement, so that directions it removes (e.g. the neutral,
    undamped high modes: :func:`modal_projector`) neither grow nor enter ``d``; the
    exponent is then the largest one of the remaining subspace (None: the whole state).
    """
    if steps_per_period is not None or n_periods is not None:
        if forcing is None or not forcing.omega > 0.0 or steps_per_period is None \
                or n_periods is None:
            raise ValueError("steps_per_period and n_periods need forcing.omega > 0")
        dt = forcing.period / steps_per_period
        n_steps = round(n_periods * steps_per_period)
    if dt is None or n_steps is None:
        raise ValueError("give either (dt, n_steps) or (steps_per_period, n_periods)")
    omega = forcing.omega if forcing is not None else 0.0
    if renorm_every is None:
        renorm_every = round(2 * math.pi / (omega * dt)) if omega > 0 else 100
    renorm_every = max(1, int(renorm_every))
    w = velocity_scale if velocity_scale is not None else (omega if omega > 0 else 1.0)
    total = transient_steps + n_steps
    ps = prepare(M, D, K, nl_dofs, kernel, params, forcing, dt, total, t0=t0,
                 time_varying=time_varying, method=method, alpha=alpha, rho_inf=rho_inf,
                 inertial_kernel=inertial_kernel)
    n = ps.n_dof
    opts = dict(newton_rtol=newton_rtol, record_initial=False)

    def advance(state: Any, steps: int) -> None:
        status, smp, _ = run(ps, state, steps, **opts)
        if status == nm.CONTACT:
            m = ps.nl.size
            raise contact_error(smp["fail"][:m], smp["fail"][m:],
                                 ps.t0 + (state.step + 1) * dt, state.step, None)
        if status != nm.OK:
            raise ConvergenceError(f"Lyapunov run: {MESSAGES.get(status)} at step "
                                   f"{state.step + 1}")

    ref = initial_state(ps, q0, v0)
    if transient_steps:
        advance(ref, transient_steps)
    if d0 is None:
        size = max(float(np.max(np.abs(ref.X[:n]))), float(np.max(np.abs(ref.X[n:2 * n]))) / w)
        d0 = 1e-7 * size if size > 0.0 else 1e-10
    rng = np.random.default_rng(seed)
    dirn0 = rng.standard_normal(2 * n)
    perts = []
    for project in projectors:
        dirn = dirn0.copy()
        if project is not None:
            pq_, pv_ = project(dirn[:n], w * dirn[n:])
            dirn = np.concatenate([pq_, pv_ / w])
        dirn /= math.sqrt(dirn[:n] @ dirn[:n] + dirn[n:] @ dirn[n:])
        perts.append(initial_state(ps, ref.X[:n] + d0 * dirn[:n],
                                   ref.X[n:2 * n] + d0 * w * dirn[n:], step=ref.step))
    t_start = ps.t0 + ref.step * dt
    logs: list[list[float]] = [[] for _ in projectors]
    times = []
    done = 0
    while done < n_steps:
        k = min(renorm_every, n_steps - done)
        advance(ref, k)
        done += k
        times.append(ps.t0 + ref.step * dt)
        for i, project in enumerate(projectors):
            pert = perts[i]
            advance(pert, k)
            dq = pert.X[:n] - ref.X[:n]
            dv = pert.X[n:2 * n] - ref.X[n:2 * n]
            if project is not None:
                dq, dv = project(dq, dv)
            d = math.sqrt(dq @ dq + (dv @ dv) / (w * w))
            if not (d > 0.0 and math.isfinite(d)):
                raise ConvergenceError(f"Lyapunov run: separation {d} at step {ref.step}")
            logs[i].append(math.log(d / d0))
            s = d0 / d
            perts[i] = initial_state(ps, ref.X[:n] + s * dq, ref.X[n:2 * n] + s * dv,
                                     step=ref.step)
    times_a = np.array(times)
    out = []
    for lg in logs:
        logs_a = np.array(lg)
        hist = np.cumsum(logs_a) / (times_a - t_start)
        lam = float(hist[-1])
        half = len(logs_a) // 2
        if half >= 1:
            t_mid = times_a[half - 1]
            first = logs_a[:half].sum() / (t_mid - t_start)
            second = logs_a[half:].sum() / (times_a[-1] - t_mid)
            spread = float(abs(second - first))
        else:
            spread = math.nan
        per = lam * 2 * math.pi / omega if omega > 0 else math.nan
        out.append(LyapunovResult(lam, per, hist, times_a, spread, float(d0), renorm_every))
    return out


def system_lyapunov(system: SecondOrderSystem, q0: Any = 0.0, v0: Any = 0.0, *,
                    options: StepOptions | dict[str, Any] | None = None,
                    **kwargs: Any) -> list[LyapunovResult]:
    """:func:`lyapunov_exponents` of a :class:`~rotorsfd.second_order.SecondOrderSystem`
    with the scheme and Newton tolerance of ``options`` (default :data:`LYAPUNOV_STEP`);
    ``kwargs``: the step, the run length, ``t0``, ``projectors``, ..."""
    o = LYAPUNOV_STEP if options is None else StepOptions.of(options)
    return lyapunov_exponents(system.M, system.D, system.K, system.nl_dofs, system.kernel,
                              system.params, system.forcing, q0=q0, v0=v0,
                              time_varying=system.time_varying, newton_rtol=o.newton_rtol,
                              inertial_kernel=system.inertial_kernel, **o.scheme, **kwargs)


def modal_projector(M: np.ndarray, basis: np.ndarray) -> Projector:
    """M-orthogonal projection of displacements and velocities onto ``span(basis)``
    (n, k): ``P x = V (V^T M V)^-1 V^T M x``; with the Craig-Bampton basis of the low modes
    it removes the high modes' components."""
    V = np.asarray(basis, dtype=float)
    MV = np.asarray(M @ V) if sp.issparse(M) else np.asarray(M, dtype=float) @ V
    G = np.linalg.inv(V.T @ MV)
    L = G @ MV.T                                   # (k, n): coordinates of M-projection

    def project(dq: np.ndarray, dv: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        return V @ (L @ dq), V @ (L @ dv)

    return project
