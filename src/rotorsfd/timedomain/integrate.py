"""Python API of the time integration: ``integrate(...) -> TimeResult``.

Integrates ``M q'' + D(t) q' + K(t) q = f(t) + F_nl(q[nl], q'[nl])`` (``forcing.py``)
with the compiled loop of ``newmark.py``. Cost per step: two (Newmark) or three
(generalized-alpha) products with an ``(n, n)`` matrix, plus, with time-varying
matrices, one product with each ``Kinv D_i``/``Kinv K_i`` per fixed-point pass
(typically 2-3 passes); the Newton iterations cost ``O(m^2)`` plus one kernel call each.
"""

from __future__ import annotations

import math
import time
from typing import TYPE_CHECKING, Any

import numpy as np

from rotorsfd.errors import ConvergenceError, JournalContactError
from rotorsfd.kernels import as_inertial_cfunc
from rotorsfd.model.lowrank import dense
from rotorsfd.timedomain import newmark as nm
from rotorsfd.timedomain.forcing import Forcing, TimeVaryingMatrices, sample_coefficient
from rotorsfd.timedomain.kernels import as_cfunc, null_inertial_kernel, null_kernel
from rotorsfd.timedomain.step_records import PreparedSystem, StepOptions, StepState, TimeResult

if TYPE_CHECKING:
    from rotorsfd.second_order import SecondOrderSystem


def _matrix(a: Any, n: int | None, name: str) -> np.ndarray:
    a = np.ascontiguousarray(dense(a))      # CSR or banded + low-rank: the full step's form
    if a.ndim != 2 or a.shape[0] != a.shape[1] or (n is not None and a.shape[0] != n):
        raise ValueError(f"{name}: expected a square ({n}, {n}) matrix, got {a.shape}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: non-finite entries")
    return a


def _vector(a: Any, n: int, name: str) -> np.ndarray:
    a = np.ascontiguousarray(np.broadcast_to(np.asarray(a, dtype=float), (n,)))
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name}: non-finite entries")
    return a.copy()


def prepare(M: Any, D: Any, K: Any, nl_dofs: Any, kernel: Any, params: Any,
            forcing: Forcing | None, dt: float, n_steps: int, *, t0: float = 0.0,
            time_varying: TimeVaryingMatrices | None = None, method: str = "newmark",
            alpha: float = 0.05, rho_inf: float = 0.9, inertial_kernel: Any = None
            ) -> PreparedSystem:
    """Validate the inputs, factorise the effective matrix and sample the coefficients
    on the grid ``t_k = t0 + k dt``, ``k = 0..n_steps``. ``inertial_kernel``: the law's
    inertial kernel when its force depends on the acceleration (then used instead of
    ``kernel``, :mod:`rotorsfd.kernels`)."""
    M = _matrix(M, None, "M")
    n = M.shape[0]
    D = _matrix(D, n, "D")
    K = _matrix(K, n, "K")
    nl = np.array(nl_dofs, dtype=np.int64).reshape(-1)
    if np.any(nl < 0) or np.any(nl >= n) or np.unique(nl).size != nl.size:
        raise ValueError(f"nl_dofs must be distinct indices in [0, {n}), got {nl}")
    if not (dt > 0.0 and math.isfinite(dt)):
        raise ValueError(f"dt must be > 0, got {dt}")
    if n_steps < 0:
        raise ValueError(f"n_steps must be >= 0, got {n_steps}")
    forcing = forcing if forcing is not None else Forcing()
    tv = time_varying if time_varying is not None else TimeVaryingMatrices()
    scheme = nm.Scheme.from_method(method, alpha=alpha, rho_inf=rho_inf)
    ops = nm.build_operators(M, D, K, nl, dt, scheme)
    kern = as_cfunc(kernel if kernel is not None else null_kernel)
    # own writeable copies: the compiled loop's types do not accept read-only arrays
    params = np.array(params if params is not None else [0.0], dtype=float).reshape(-1)
    if params.size == 0:
        params = np.zeros(1)

    f0 = _vector(forcing.constant if forcing.constant is not None else 0.0, n, "constant")
    harm = list(forcing.harmonics)
    hmult = np.array([float(hl.multiple) for hl in harm], dtype=float)
    fc = np.array([_vector(hl.cos, n, "harmonic cos") for hl in harm]).reshape(-1, n)
    fs = np.array([_vector(hl.sin if hl.sin is not None else 0.0, n, "harmonic sin")
                   for hl in harm]).reshape(-1, n)
    if harm and not forcing.omega > 0.0:
        raise ValueError("forcing.omega must be > 0 with harmonic loads")
    fj = np.array([_vector(vec, n, "series vector") for _, vec in forcing.series])
    fj = fj.reshape(-1, n)
    scoef = np.array([sample_coefficient(c, t0, dt, n_steps, f"series[{j}]")
                      for j, (c, _) in enumerate(forcing.series)]).reshape(-1, n_steps + 1)
    scoef = np.ascontiguousarray(scoef.T) if fj.shape[0] else np.zeros((1, 0))

    terms = [(c, X, 0) for c, X in tv.damping] + [(c, X, 1) for c, X in tv.stiffness]
    tvmat = np.array([_matrix(X, n, "time-varying matrix") for _, X, _ in terms])
    tvmat = tvmat.reshape(-1, n, n)
    tvkind = np.array([kind for _, _, kind in terms], dtype=np.int64)
    if terms:
        tvcoef = np.ascontiguousarray(np.array(
            [sample_coefficient(c, t0, dt, n_steps, f"time-varying[{i}]")
             for i, (c, _, _) in enumerate(terms)]).T)
        PX = np.ascontiguousarray(
            np.array([ops.solve(X) for X in tvmat]).reshape(-1, n, n))
    else:
        tvcoef = np.zeros((1, 0))
        PX = np.zeros((0, 1, 1))

    def kinv(rows: np.ndarray) -> np.ndarray:
        return np.ascontiguousarray(ops.solve(rows.T).T) if rows.shape[0] else \
            np.zeros((0, n))

    return PreparedSystem(
        ops=ops, kernel=kern, params=params, M=M, D=D, K=K, n_steps=int(n_steps),
        t0=float(t0), omega=float(forcing.omega), f0=f0, hmult=hmult, fc=fc, fs=fs, fj=fj,
        KF0=np.ascontiguousarray(ops.solve(f0)), KFc=kinv(fc), KFs=kinv(fs), KFj=kinv(fj),
        scoef=scoef, tvcoef=tvcoef, tvkind=tvkind, tvmat=tvmat, PX=PX,
        kernel_a=None if inertial_kernel is None else as_inertial_cfunc(inertial_kernel))


def prepare_system(system: SecondOrderSystem, dt: float, n_steps: int, *,
                   t0: float = 0.0,
                   options: StepOptions | dict[str, Any] | None = None) -> PreparedSystem:
    """:func:`prepare` of a :class:`~rotorsfd.second_order.SecondOrderSystem` (its
    matrices, nonlinear DOFs, force kernel, forcing and time-varying terms) with the
    scheme of ``options`` (:class:`StepOptions` or its keywords): the compiled loop's
    arrays packed once."""
    return prepare(system.M, system.D, system.K, system.nl_dofs, system.kernel,
                   system.params, system.forcing, dt, n_steps, t0=t0,
                   time_varying=system.time_varying, **StepOptions.of(options).scheme,
                   inertial_kernel=system.inertial_kernel)


def force_at_step(ps: PreparedSystem, k: int) -> np.ndarray:
    """External force ``f(t_k)`` (physical, not multiplied by ``Kinv``)."""
    t = ps.t0 + k * ps.ops.dt
    f = ps.f0.copy()
    for mult, c, s in zip(ps.hmult, ps.fc, ps.fs, strict=True):
        ph = mult * ps.omega * t
        f += math.cos(ph) * c + math.sin(ph) * s
    if ps.fj.shape[0]:
        f += ps.scoef[k] @ ps.fj
    return f


def matrices_at_step(ps: PreparedSystem, k: int) -> tuple[np.ndarray, np.ndarray]:
    """``D(t_k), K(t_k)``."""
    D, K = ps.D.copy(), ps.K.copy()
    for p, kind in enumerate(ps.tvkind):
        if kind == 0:
            D += ps.tvcoef[k, p] * ps.tvmat[p]
        else:
            K += ps.tvcoef[k, p] * ps.tvmat[p]
    return D, K


def initial_state(ps: PreparedSystem, q0: Any, v0: Any, step: int = 0) -> StepState:
    """State at global step ``step`` from ``q0, v0`` (scalars broadcast to every DOF):
    the nonlinear force, ``Kinv g``, and for generalized-alpha the acceleration
    ``a0 = M^-1 (g0 - D v0 - K q0)``."""
    n, nl = ps.n_dof, ps.nl
    q = _vector(q0, n, "q0")
    v = _vector(v0, n, "v0")
    m = nl.size
    F = np.zeros(m)
    Ja = np.zeros((m, m))
    if m and ps.kernel_a is not None:   # F(q0, v0, 0) and dF/da: F is affine in a
        status = nm.eval_inertial_kernel(ps.kernel_a, ps.params, np.ascontiguousarray(
            q[nl]), np.ascontiguousarray(v[nl]), np.zeros(m), F, np.zeros((m, m)),
            np.zeros((m, m)), Ja)
        if status != 0:
            raise contact_error(q[nl], v[nl], ps.t0 + step * ps.ops.dt, step, None)
    elif m:
        status = nm.eval_kernel(ps.kernel, ps.params, np.ascontiguousarray(q[nl]),
                                np.ascontiguousarray(v[nl]), F, np.zeros((m, m)),
                                np.zeros((m, m)))
        if status != 0:
            raise contact_error(q[nl], v[nl], ps.t0 + step * ps.ops.dt, step, None)
    Anl = None
    if ps.kernel_a is not None:
        # a0 from (M - S^T dF/da S) a0 = f + S^T F(q0, v0, 0) - D v0 - K q0
        Dk, Kk = matrices_at_step(ps, step)
        g = force_at_step(ps, step)
        g[nl] += F
        Me = ps.M.copy()
        Me[np.ix_(nl, nl)] -= Ja
        a0 = np.linalg.solve(Me, g - Dk @ v - Kk @ q)
        Anl = np.ascontiguousarray(a0[nl])
        F = F + Ja @ Anl
    T = np.zeros(n)
    for p, kind in enumerate(ps.tvkind):
        T -= ps.tvcoef[step, p] * (ps.PX[p] @ (v if kind == 0 else q))
    f = force_at_step(ps, step)
    G = ps.ops.solve(f) + ps.ops.B @ F + T
    parts = [q, v]
    if ps.ops.scheme.kind == nm.GENERALIZED_ALPHA:
        if Anl is not None:
            parts.append(a0)
        else:
            Dk, Kk = matrices_at_step(ps, step)
            g = f.copy()
            g[nl] += F
            parts.append(np.linalg.solve(ps.M, g - Dk @ v - Kk @ q))
    return StepState(np.concatenate(parts), F, np.ascontiguousarray(G), T, step, Anl)


def contact_error(y: np.ndarray, vy: np.ndarray, t: float, step: int,
                   result: TimeResult | None) -> JournalContactError:
    """Generic contact report: the kernel does not return the eccentricity ratio, so
    ``eps`` is NaN; ``y, z`` are the first two nonlinear DOFs."""
    y2 = list(np.asarray(y, float)[:2]) + [math.nan] * max(0, 2 - len(y))
    v2 = list(np.asarray(vy, float)[:2]) + [math.nan] * max(0, 2 - len(vy))
    err = JournalContactError(math.nan, y2[0], y2[1], v2[0], v2[1],
                              where=f"time integration, step {step + 1}, t={t:.9g} s")
    err.time, err.step = t, step
    err.q_nl, err.v_nl = np.asarray(y, float).copy(), np.asarray(vy, float).copy()
    err.result = result
    return err


#: What a stepping status means, for messages.
MESSAGES = {
    nm.OK: "integration finished",
    nm.CONTACT: "nonlinear kernel reported contact",
    nm.NEWTON_FAILED: "Newton iteration on the nonlinear DOFs did not converge",
    nm.TV_FAILED: "fixed-point iteration of the time-varying matrices did not converge "
                  "(reduce the step)",
    nm.NOT_FINITE: "the state became non-finite",
}


def run(ps: PreparedSystem, state: StepState, n_steps: int, *,
        record_dofs: np.ndarray | None = None, record_every: int = 1,
        record_start: int = 0, poincare_every: int = 0, poincare_start: int = 0,
        newton_rtol: float = 1e-10, newton_atol: float = 0.0, max_newton: int = 50,
        tv_rtol: float = 1e-12, max_tv: int = 50, record_initial: bool = True,
        ) -> tuple[int, dict[str, Any], np.ndarray]:
    """Advance ``state`` in place by ``n_steps`` (global steps ``state.step + 1 ..``).

    Returns ``(status, samples, info)``; does not raise on failure.
    """
    if state.step + n_steps > ps.n_steps:
        raise ValueError(f"run past the prepared horizon: {state.step} + {n_steps} > "
                         f"{ps.n_steps}")
    if record_every < 1:
        raise ValueError(f"record_every must be >= 1, got {record_every}")
    n, ops = ps.n_dof, ps.ops
    rd = np.array(record_dofs if record_dofs is not None else np.zeros(0), dtype=np.int64)
    k_a, k_b = state.step, state.step + n_steps

    def count(every: int, start: int) -> int:
        if every <= 0 or rd.size == 0:
            return 0
        lo = max(start, k_a + 1)
        return max(0, k_b // every - (lo - 1) // every) if lo <= k_b else 0

    n_rec = count(record_every, record_start)
    n_pc = count(poincare_every, poincare_start)
    rec_ok = rd.size > 0 and record_initial
    first_rec = rec_ok and k_a >= record_start and k_a % record_every == 0
    first_pc = rec_ok and poincare_every > 0 and k_a >= poincare_start \
        and k_a % poincare_every == 0
    rec_t = np.empty(n_rec + first_rec)
    rec_q = np.empty((rec_t.size, rd.size))
    rec_v = np.empty_like(rec_q)
    pc_t = np.empty(n_pc + first_pc)
    pc_q = np.empty((pc_t.size, rd.size))
    pc_v = np.empty_like(pc_q)
    info = np.zeros(nm.N_INFO, dtype=np.int64)
    t_a = ps.t0 + k_a * ops.dt
    if first_rec:
        rec_t[0], rec_q[0], rec_v[0] = t_a, state.X[rd], state.X[n + rd]
        info[nm.I_NREC] = 1
    if first_pc:
        pc_t[0], pc_q[0], pc_v[0] = t_a, state.X[rd], state.X[n + rd]
        info[nm.I_NPC] = 1
    m = ps.nl.size
    fail = np.zeros(2 * m)
    status = nm.run_steps(
        ps.kernel, ps.params, ops.scheme.kind, ops.coef, ops.A, ops.B, ops.S, ops.nl,
        ps.omega, ps.t0, ps.KF0, ps.hmult, ps.KFc, ps.KFs, ps.scoef, ps.KFj, ps.tvcoef,
        ps.tvkind, ps.PX, state.X, state.F, state.G, state.T, k_a, n_steps,
        rd, record_every, record_start, rec_t, rec_q, rec_v,
        poincare_every, poincare_start, pc_t, pc_q, pc_v,
        newton_rtol, newton_atol, max_newton, tv_rtol, max_tv, info, fail,
        *_inertial_arguments(ps, state))
    state.step = int(info[nm.I_STEP]) if n_steps else k_a
    nr, npc = int(info[nm.I_NREC]), int(info[nm.I_NPC])
    samples = dict(t=rec_t[:nr], q=rec_q[:nr], v=rec_v[:nr], pt=pc_t[:npc], pq=pc_q[:npc],
                   pv=pc_v[:npc], fail=fail)
    return int(status), samples, info


def _inertial_arguments(ps: PreparedSystem, state: StepState) -> tuple:
    """``(kernel_a, inertial, Anl)`` of the compiled loop: the inertial kernel and the
    nonlinear DOFs' acceleration, or a placeholder that the loop does not call."""
    if ps.kernel_a is None:
        return as_inertial_cfunc(null_inertial_kernel), False, np.zeros(ps.nl.size)
    if state.Anl is None:
        raise ValueError("the state of an inertial force law needs its nonlinear DOFs' "
                         "acceleration (initial_state)")
    return ps.kernel_a, True, state.Anl


def integrate(M: Any, D: Any, K: Any, nl_dofs: Any, kernel: Any, params: Any,
              forcing: Forcing | None, dt: float | None = None, n_steps: int | None = None,
              q0: Any = 0.0, v0: Any = 0.0, *, steps_per_period: int | None = None,
              n_periods: float | None = None, t0: float = 0.0,
              time_varying: TimeVaryingMatrices | None = None, method: str = "newmark",
              alpha: float = 0.05, rho_inf: float = 0.9,
              record_dofs: Any = None, record_every: int = 1, record_start: int = 0,
              poincare_every: int | None = None, poincare_start: int | None = None,
              newton_rtol: float = 1e-10, newton_atol: float = 0.0, max_newton: int = 50,
              tv_rtol: float = 1e-12, max_tv: int = 50,
              on_failure: str = "raise", inertial_kernel: Any = None) -> TimeResult:
    """Integrate ``M q'' + D(t) q' + K(t) q = f(t) + F_nl(q[nl], q'[nl])`` from ``t0``.

    Parameters
    ----------
    M, D, K : (n, n) constant parts of the matrices (``D`` includes ``Omega G``).
    nl_dofs, kernel, params : nonlinear DOFs and the compiled force kernel
        ``kernel(q_nl, v_nl, params, F, dFdq, dFdv) -> int`` (``None``: no force).
    forcing : :class:`Forcing` (constant, harmonic and series loads).
    dt, n_steps : step and number of steps; or ``steps_per_period`` and ``n_periods``
        with ``dt = 2 pi / (omega steps_per_period)``.
    q0, v0 : initial state (scalars broadcast: ``q0=1e-6`` displaces every DOF by 1 um).
    time_varying : :class:`TimeVaryingMatrices` ``D_i, K_i`` with their coefficients.
    method : ``"newmark"`` (average acceleration), ``"hht"`` (``alpha``) or
        ``"generalized-alpha"`` (``rho_inf``).
    record_dofs : DOFs to record (default: ``nl_dofs``, or all DOFs if there are none;
        ``"all"``); samples every ``record_every`` steps from step ``record_start``.
    poincare_every : Poincare sampling interval in steps (default: one forcing period
        when it is a whole number of steps, else off), from ``poincare_start`` (default
        ``record_start``).
    on_failure : ``"raise"`` (contact: ``JournalContactError``; other failures:
        ``ConvergenceError``) or ``"return"`` (``success=False`` and the samples so far).
    inertial_kernel : the law's inertial kernel when its force depends on the
        acceleration too (``kernel(q, v, a, params, F, dFdq, dFdv, dFda)``), else None.
    """
    if steps_per_period is not None or n_periods is not None:
        if forcing is None or not forcing.omega > 0.0:
            raise ValueError("steps_per_period/n_periods need forcing.omega > 0")
        if steps_per_period is None or n_periods is None or dt is not None \
                or n_steps is not None:
            raise ValueError("give either (dt, n_steps) or (steps_per_period, n_periods)")
        dt = forcing.period / steps_per_period
        n_steps = round(n_periods * steps_per_period)
    if dt is None or n_steps is None:
        raise ValueError("give either (dt, n_steps) or (steps_per_period, n_periods)")
    if on_failure not in ("raise", "return"):
        raise ValueError(f"on_failure must be 'raise' or 'return', got {on_failure!r}")
    ps = prepare(M, D, K, nl_dofs, kernel, params, forcing, dt, n_steps, t0=t0,
                 time_varying=time_varying, method=method, alpha=alpha, rho_inf=rho_inf,
                 inertial_kernel=inertial_kernel)
    n = ps.n_dof
    if record_dofs is None:
        rd = ps.nl if ps.nl.size else np.arange(n)
    elif isinstance(record_dofs, str) and record_dofs == "all":
        rd = np.arange(n)
    else:
        rd = np.asarray(record_dofs, dtype=np.int64).reshape(-1)
        if np.any(rd < 0) or np.any(rd >= n):
            raise ValueError(f"record_dofs out of range [0, {n})")
    spp = steps_per_period
    if spp is None and ps.omega > 0.0:
        ratio = 2.0 * math.pi / (ps.omega * dt)
        if abs(ratio - round(ratio)) < 1e-9 * ratio:
            spp = round(ratio)
    if poincare_every is None:
        poincare_every = spp or 0
    if poincare_start is None:
        poincare_start = record_start
    state = initial_state(ps, q0, v0)
    tic = time.perf_counter()
    status, smp, info = run(ps, state, n_steps, record_dofs=rd, record_every=record_every,
                            record_start=record_start, poincare_every=poincare_every,
                            poincare_start=poincare_start, newton_rtol=newton_rtol,
                            newton_atol=newton_atol, max_newton=max_newton, tv_rtol=tv_rtol,
                            max_tv=max_tv)
    elapsed = time.perf_counter() - tic
    steps_done = state.step
    n_newton = max(1, steps_done) if ps.nl.size else 1
    msg = MESSAGES.get(status, f"status {status}")
    if status != nm.OK:
        msg += f" at step {steps_done + 1} (t={ps.t0 + (steps_done + 1) * dt:.9g} s)"
    res = TimeResult(
        t=smp["t"], q=smp["q"], v=smp["v"], dofs=rd, poincare_t=smp["pt"],
        poincare_q=smp["pq"], poincare_v=smp["pv"], q_final=state.X[:n].copy(),
        v_final=state.X[n:2 * n].copy(), t_final=ps.t0 + steps_done * dt,
        steps_done=steps_done, dt=float(dt), omega=ps.omega, steps_per_period=spp,
        success=status == nm.OK, status=status, message=msg,
        newton_iterations_mean=float(info[nm.I_NEWTON_TOTAL]) / n_newton,
        newton_iterations_max=int(info[nm.I_NEWTON_MAX]),
        fixed_point_iterations_max=int(info[nm.I_TV_MAX]),
        contact_backtracks=int(info[nm.I_CONTACTS]), elapsed=elapsed, state=state)
    if status != nm.OK and on_failure == "raise":
        m = ps.nl.size
        if status == nm.CONTACT:
            raise contact_error(smp["fail"][:m], smp["fail"][m:],
                                 ps.t0 + (steps_done + 1) * dt, steps_done, res)
        raise ConvergenceError(msg)
    return res


def integrate_system(system: SecondOrderSystem, q0: Any = 0.0, v0: Any = 0.0, *,
                     options: StepOptions | dict[str, Any] | None = None,
                     **kwargs: Any) -> TimeResult:
    """:func:`integrate` of a :class:`~rotorsfd.second_order.SecondOrderSystem` with the
    scheme and tolerances of ``options``; ``kwargs``: the step and the recording
    (``dt, n_steps`` or ``steps_per_period, n_periods``, ``t0``, ``record_dofs``, ...)."""
    o = StepOptions.of(options)
    return integrate(system.M, system.D, system.K, system.nl_dofs, system.kernel,
                     system.params, system.forcing, q0=q0, v0=v0,
                     time_varying=system.time_varying, **o.scheme, **o.iteration,
                     inertial_kernel=system.inertial_kernel, **kwargs)
