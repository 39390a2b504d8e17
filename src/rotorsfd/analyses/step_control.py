"""Time-step control of a time integration: how far the journal orbit moves when the step
is halved, and the automatic choice of the step (``steps_per_period = "auto"``).

Newmark average acceleration is second order: the orbit error at ``h = T/N`` is
``e(h) ~ c h^2``, so one halving changes the orbit by ``d = e(h) - e(h/2) ~ 3 e(h/2)``.
The *difference* ``d`` of one halving is the error measure reported (conservative: the
finer run of the pair is about ``d / 3`` from the converged orbit).

**Comparison of two runs from the same state** (:func:`compare_windows`), node ``node``,
lengths in C (or in the orbit's max radius without an SFD):

- both runs periodic with the same period n at the end of the window (the last 2n
  Poincare points repeat within ``tolerance / 4``), or the base run periodic and the
  finer one still settling: the largest distance between the two orbits at equal times
  over the last n periods (includes the Poincare points);
- otherwise (quasi-periodic, chaotic, or still settling): the orbit envelope, the larger
  change of the max and min radius over the window; trajectories of non-periodic motion
  diverge, so only such statistics can converge.

**Automatic step** (:func:`auto_step`), the cheap strategy: the transient runs at the
start step (``T/200``) to ``periods - record - window`` periods; from that state ``S0``
the last ``window`` periods are integrated again at ``T/400, T/800, ...`` (each compared
with the one before, every run from the same ``S0``) until one halving changes the orbit
by less than ``tolerance`` or the step reaches ``max_steps_per_period``; the finer run of
the last pair is accepted and continued (exact continuation of its state) over the
recorded periods. A run still settling (nearly but not yet periodic) is extended, both
runs of the pair, by ``window`` periods at a time (at most :data:`MAX_EXTENSIONS` times).
The transient's basin may depend on the step (a coarse transient can end near another
attractor than a fine one would); the class and the recorded orbit are those of the
accepted step, whatever attractor the refined runs settle on.
"""

from __future__ import annotations

import time
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from rotorsfd.analyses.td_integration import (
    DIRECTIONS,
    TimeDomainInputs,
    Trajectory,
    integrate_periods,
)
from rotorsfd.errors import ConvergenceError, ElementDomainError
from rotorsfd.model import dofs

STEP_TOLERANCE = 1e-3
"""Default tolerance of one halving [C] (``analysis.simulate.step_tolerance``)."""

MAX_EXTENSIONS = 4
"""A pair of runs still settling is extended by its window at most this many times."""

AUTO_START = 200
"""The start step of ``"auto"`` (the paper's T/200) and the transient's step."""


# ---- a window of one run ---------------------------------------------------------------


@dataclass(frozen=True)
class Window:
    """``periods`` periods of one run at ``T / steps_per_period`` from a common start:
    node's ``t, q`` (n, 2) at every step (both ends), its Poincare points ``pq`` (periods,
    2) at the ends of the periods, and the full final state ``end = (q, v, t)``."""

    steps_per_period: int
    periods: int
    t: np.ndarray
    q: np.ndarray
    pq: np.ndarray
    end: tuple[np.ndarray, np.ndarray, float]


def run_window(inputs: TimeDomainInputs, start: tuple[np.ndarray, np.ndarray, float], *,
               steps_per_period: int, periods: int, node: int,
               method_options: dict[str, Any] | None = None) -> Window:
    """Integrate ``periods`` periods from ``start = (q, v, t)`` recording ``node``."""
    rd = [dofs.dof_index(node, d) for d in DIRECTIONS]
    tr = integrate_periods(inputs, start[0], start[1], steps_per_period=steps_per_period,
                           periods=periods, record_dofs=rd, record_periods=periods,
                           poincare_periods=periods, method_options=method_options,
                           t0=start[2])
    return Window(int(steps_per_period), int(periods), tr.t, tr.q, tr.poincare_q,
                  (tr.q_final, tr.v_final, tr.t_final))


def extend_window(inputs: TimeDomainInputs, w: Window, periods: int, *, node: int,
                  method_options: dict[str, Any] | None = None) -> Window:
    """``w`` continued by ``periods`` more periods from its final state."""
    more = run_window(inputs, w.end, steps_per_period=w.steps_per_period, periods=periods,
                      node=node, method_options=method_options)
    return Window(w.steps_per_period, w.periods + periods,
                  np.concatenate([w.t, more.t[1:]]), np.concatenate([w.q, more.q[1:]]),
                  np.concatenate([w.pq, more.pq]), more.end)


def window_of(t: np.ndarray, q: np.ndarray, pq: np.ndarray, steps_per_period: int,
              periods: int, end: tuple[np.ndarray, np.ndarray, float]) -> Window:
    """The last ``periods`` periods of recorded samples ``t, q`` (every step, (n, 2)) and
    Poincare points ``pq`` of a run (as many as recorded, at most ``periods``)."""
    n = min(periods, (q.shape[0] - 1) // steps_per_period, pq.shape[0])
    k = n * steps_per_period + 1
    return Window(steps_per_period, n, t[-k:], q[-k:], pq[-n:], end)


def settled_period(pq: np.ndarray, tol: float, n_max: int = 16) -> int | None:
    """Smallest n with the last n Poincare points each within ``tol`` of the point n
    periods earlier (lengths in the units of ``pq``), or None."""
    for n in range(1, n_max + 1):
        if pq.shape[0] < 2 * n:
            return None
        if np.max(np.hypot(*(pq[-n:] - pq[-2 * n:-n]).T)) <= tol:
            return n
    return None


def poincare_drift(pq: np.ndarray, n_max: int = 16) -> float:
    """``min_n max |P_k - P_{k-n}|`` over the last n points: how far the section is from
    repeating (0 for a settled period-n orbit)."""
    best = np.inf
    for n in range(1, n_max + 1):
        if pq.shape[0] < 2 * n:
            break
        best = min(best, float(np.max(np.hypot(*(pq[-n:] - pq[-2 * n:-n]).T))))
    return float(best)


# ---- one halving ----------------------------------------------------------------------------


@dataclass(frozen=True)
class StepCheck:
    """Two runs of ``periods`` periods from the same state at ``steps_per_period = (base,
    fine)``, node ``node``, compared by :func:`compare_windows` (``compared`` says how).
    ``difference`` in ``unit`` (C, or the max orbit radius without an SFD);
    ``orbit_difference`` (periodic: over the last n periods), ``envelope_difference``;
    ``period``: the common period n, or None. ``error``: the fine run failed."""

    steps_per_period: tuple[int, int]
    periods: int
    node: int
    compared: str
    difference: float | None
    orbit_difference: float | None
    envelope_difference: float | None
    period: int | None
    unit: str
    tolerance: float = STEP_TOLERANCE
    error: str | None = None
    elapsed: float = 0.0

    @property
    def coarse(self) -> bool:
        """Halving the base step changes the orbit by more than the tolerance (or the
        fine run failed)."""
        return self.error is not None or (self.difference is not None
                                          and self.difference > self.tolerance)

    def as_dict(self) -> dict[str, Any]:
        return {"steps_per_period": list(self.steps_per_period), "periods": self.periods,
                "node": self.node, "compared": self.compared,
                "difference": self.difference, "unit": self.unit,
                "orbit_difference": self.orbit_difference,
                "envelope_difference": self.envelope_difference, "period": self.period,
                "tolerance": self.tolerance, "too_coarse": self.coarse,
                "error": self.error, "elapsed_s": self.elapsed}

    def line(self) -> str:
        a, b = self.steps_per_period
        head = f"T/{a} vs T/{b} (last {self.periods} periods, node {self.node})"
        if self.error is not None:
            return f"{head}: the run at T/{b} failed: {self.error}"
        return f"{head}: {self.compared} moves by {self.difference:.3g} {self.unit}"


def compare_windows(base: Window, fine: Window, *, node: int, scale: float, unit: str,
                    tolerance: float = STEP_TOLERANCE) -> StepCheck:
    """Compare two windows of equal length from the same state (module docstring)."""
    a, b = base.steps_per_period, fine.steps_per_period
    if b % a:
        raise ValueError(f"fine steps per period {b} is not a multiple of {a}")
    r = b // a
    fq = fine.q[::r]
    if fq.shape != base.q.shape or not np.allclose(fine.t[::r], base.t, rtol=0.0,
                                                   atol=1e-6 * (base.t[1] - base.t[0])):
        raise ValueError("the two windows' sample times differ")
    rb = np.hypot(base.q[:, 0], base.q[:, 1])
    rf = np.hypot(fq[:, 0], fq[:, 1])
    env = max(abs(float(rf.max() - rb.max())), abs(float(rf.min() - rb.min()))) / scale
    settle = 0.25 * tolerance * scale
    n_b, n_f = settled_period(base.pq, settle), settled_period(fine.pq, settle)
    orbit = None
    n = n_b if n_f is None else n_f
    if n is not None and (n_f == n_b or n_f is None):
        # both periodic, or the base run periodic and the finer one still settling
        k = n * a + 1
        orbit = float(np.max(np.hypot(*(fq[-k:] - base.q[-k:]).T))) / scale
        what = (f"period-{n} orbit over its last {n} period{'s' if n > 1 else ''} "
                "(Poincare points included)"
                + ("; the finer run still settling" if n_f is None else ""))
        diff = orbit
    else:
        what = (f"orbit envelope (max and min radius over {base.periods} periods; not "
                "periodic in both runs)")
        diff = env
    return StepCheck((a, b), base.periods, node, what, diff, orbit, env,
                     n if orbit is not None and n_f is not None else None, unit,
                    tolerance)


def check_scale(clearance: float | None, q: np.ndarray) -> tuple[float, str]:
    """(length scale, unit name) of the comparison: C, else the max orbit radius."""
    if clearance:
        return float(clearance), "C"
    return float(np.max(np.hypot(q[:, 0], q[:, 1]))) or 1.0, "x max orbit radius"


def failed_check(steps: tuple[int, int], periods: int, node: int, unit: str,
                 tolerance: float, exc: Exception, elapsed: float) -> StepCheck:
    """The record of a fine run that failed (contact or Newton)."""
    return StepCheck(steps, periods, node, "-", None, None, None, None, unit, tolerance,
                     " ".join(str(exc).split()), elapsed)


def halving_check(inputs: TimeDomainInputs, start: tuple[np.ndarray, np.ndarray, float],
                  base: Window, *, node: int, tolerance: float = STEP_TOLERANCE,
                  method_options: dict[str, Any] | None = None,
                  clearance: float | None = None) -> StepCheck:
    """``base`` (a window of a run at ``T/N`` that started at ``start``) against the same
    periods integrated again from ``start`` at ``T/2N``."""
    tic = time.perf_counter()
    scale, unit = check_scale(clearance, base.q)
    steps = (base.steps_per_period, 2 * base.steps_per_period)
    try:
        fine = run_window(inputs, start, steps_per_period=steps[1], periods=base.periods,
                          node=node, method_options=method_options)
    except (ElementDomainError, ConvergenceError) as exc:
        return failed_check(steps, base.periods, node, unit, tolerance, exc,
                            time.perf_counter() - tic)
    c = compare_windows(base, fine, node=node, scale=scale, unit=unit, tolerance=tolerance)
    return replace(c, elapsed=time.perf_counter() - tic)


# ---- the step of a run ----------------------------------------------------------------------


@dataclass(frozen=True)
class StepControl:
    """How the step of a run was chosen and how good it is.

    ``mode``: ``"auto"`` (halved until one halving changes the orbit by less than
    ``tolerance``, capped at ``max_steps_per_period``) or ``"fixed"`` (the given step,
    checked by one halving); ``steps_per_period``: the step of the recorded periods;
    ``checks``: the halvings, coarsest first; ``error``: the last halving's difference
    (the achieved error measure, in ``unit``)."""

    mode: str
    steps_per_period: int
    checks: tuple[StepCheck, ...]
    tolerance: float
    max_steps_per_period: int | None = None
    elapsed: float = 0.0

    @property
    def last(self) -> StepCheck | None:
        return self.checks[-1] if self.checks else None

    @property
    def error(self) -> float | None:
        return None if self.last is None else self.last.difference

    @property
    def unit(self) -> str:
        return "C" if self.last is None else self.last.unit

    @property
    def converged(self) -> bool:
        """The last halving changed the orbit by less than the tolerance."""
        return self.last is not None and not self.last.coarse

    def line(self) -> str:
        """One summary line."""
        if self.last is None:
            return f"time step T/{self.steps_per_period} ({self.mode}), not checked"
        c = self.last
        if self.mode == "auto":
            ladder = ", ".join(
                f"T/{k.steps_per_period[1]} "
                + ("failed" if k.difference is None else f"{k.difference:.2g}")
                for k in self.checks)
            return (f"time step (auto): T/{self.steps_per_period}; change per halving "
                    f"({c.unit}, last {c.periods} periods, node {c.node}): {ladder} "
                    f"(tolerance {self.tolerance:g})")
        return f"step check {c.line()}"

    def warning(self) -> str | None:
        """The warning of a step that fails the tolerance, naming the error and what to
        set; None when it passes."""
        c = self.last
        if c is None or self.converged:
            return None
        a, b = c.steps_per_period
        if self.mode == "auto":
            what = (f"the run at T/{b} failed ({c.error})" if c.error is not None else
                    f"the last halving (T/{a} to T/{b}) still moves the orbit by "
                    f"{c.difference:.3g} {c.unit}")
            return (f"the time step did not converge to step_tolerance = "
                    f"{self.tolerance:g} {c.unit} by max_steps_per_period = "
                    f"{self.max_steps_per_period}: {what}; raise "
                    "analysis.simulate.max_steps_per_period (or step_tolerance)")
        if c.error is not None:
            return (f"time step T/{a} may be too coarse here: the run at T/{b} from the "
                    f"same state failed; set analysis.simulate.steps_per_period = "
                    '"auto" (or a larger integer)')
        return (f"time step T/{a} is too coarse here: halving it moves the orbit by "
                f"{c.difference:.3g} {c.unit} (step_tolerance {self.tolerance:g} "
                f'{c.unit}); set analysis.simulate.steps_per_period = "auto" (or a '
                "larger integer)")

    def as_dict(self) -> dict[str, Any]:
        c = self.last
        return {"mode": self.mode, "steps_per_period": self.steps_per_period,
                "tolerance": self.tolerance, "unit": self.unit,
                "max_steps_per_period": self.max_steps_per_period,
                "difference": self.error, "converged": self.converged,
                "too_coarse": not self.converged if c is not None else None,
                "estimated_error": None if self.error is None else self.error / 3.0,
                "compared": None if c is None else c.compared,
                "periods": None if c is None else c.periods,
                "node": None if c is None else c.node,
                "halvings": [k.as_dict() for k in self.checks],
                "warning": self.warning(), "elapsed_s": self.elapsed}


def auto_step(inputs: TimeDomainInputs, start: tuple[np.ndarray, np.ndarray, float],
              base: Window, *, node: int, tolerance: float = STEP_TOLERANCE,
              max_steps_per_period: int = 3200,
              method_options: dict[str, Any] | None = None,
              clearance: float | None = None) -> tuple[StepControl, Window]:
    """Halve the step of ``base`` (a window that started at ``start``) until one halving
    changes the orbit by less than ``tolerance`` (module docstring). Returns the control
    record and the accepted (finest) window, whose ``end`` continues the run. A fine run
    that fails (contact) stops the ladder at the last window that ran."""
    tic = time.perf_counter()
    scale, unit = check_scale(clearance, base.q)
    checks: list[StepCheck] = []
    coarse = base
    kw = {"node": node, "method_options": method_options}
    while 2 * coarse.steps_per_period <= max_steps_per_period:
        t0 = time.perf_counter()
        steps = (coarse.steps_per_period, 2 * coarse.steps_per_period)
        try:
            fine = run_window(inputs, start, steps_per_period=steps[1],
                              periods=coarse.periods, **kw)
            c = compare_windows(coarse, fine, node=node, scale=scale, unit=unit,
                                tolerance=tolerance)
            extensions, step = 0, base.periods
            while (c.coarse and c.period is None and extensions < MAX_EXTENSIONS
                   and poincare_drift(fine.pq) <= 100.0 * tolerance * scale):
                # nearly periodic: still settling, run both on
                coarse = extend_window(inputs, coarse, step, **kw)
                fine = extend_window(inputs, fine, step, **kw)
                c = compare_windows(coarse, fine, node=node, scale=scale, unit=unit,
                                    tolerance=tolerance)
                extensions += 1
        except (ElementDomainError, ConvergenceError) as exc:
            checks.append(failed_check(steps, coarse.periods, node, unit, tolerance, exc,
                                       time.perf_counter() - t0))
            break
        checks.append(replace(c, elapsed=time.perf_counter() - t0))
        coarse = fine
        if not c.coarse:
            break
    ctl = StepControl("auto", coarse.steps_per_period, tuple(checks), tolerance,
                      max_steps_per_period, time.perf_counter() - tic)
    return ctl, coarse


@dataclass
class ControlledRun:
    """A run whose recorded periods were integrated at a controlled step: ``trajectory``
    (the recorded periods, columns of ``record_dofs``), the step record ``control`` (None:
    a fixed step not checked), the peak eccentricity over everything integrated and the
    periods integrated in the main line (more than asked when the ladder extended)."""

    trajectory: Trajectory
    control: StepControl | None
    max_eccentricity_run: float | None
    periods_run: int


def integrate_controlled(inputs: TimeDomainInputs, q0: Any, v0: Any, *,
                         steps_per_period: int | str, periods: int, record_dofs: Any,
                         record_periods: int, poincare_periods: int, check_column: int,
                         check_node: int, check_periods: int,
                         tolerance: float = STEP_TOLERANCE, max_steps_per_period: int = 3200,
                         method_options: dict[str, Any] | None = None,
                         chunk_periods: int | None = None,
                         check_clearance: float | None = None, t0: float = 0.0,
                         progress: Any = None, on_contact: str = "raise") -> ControlledRun:
    """``periods`` periods from ``(q0, v0)`` at ``t0`` with the step control of the module
    docstring: ``steps_per_period = "auto"`` (transient at :data:`AUTO_START`, the ladder
    over ``check_periods``, the last ``record_periods`` at the accepted step; needs
    ``periods > record_periods``) or an integer (one halving over the last
    ``check_periods <= poincare_periods``, 0: none). ``check_column``: the column pair
    (y at ``2 j``) of ``record_dofs`` that is node ``check_node``, compared in units of
    ``check_clearance`` (None: the orbit's max radius). ``on_contact="end"``: a contact
    ends the run as a result (:func:`integrate_periods`; ``trajectory.ended``, no step
    record), also one met by the step control's finer runs (their start's trajectory)."""
    common = {"record_dofs": record_dofs, "method_options": method_options,
              "chunk_periods": chunk_periods, "on_contact": on_contact}
    chk = {"node": check_node, "tolerance": tolerance, "method_options": method_options,
           "clearance": check_clearance}
    cols = slice(2 * check_column, 2 * check_column + 2)
    tick = progress or (lambda done: None)
    if steps_per_period != "auto":
        spp = int(steps_per_period)
        n_chk = min(check_periods, poincare_periods)
        tr = integrate_periods(inputs, q0, v0, steps_per_period=spp, periods=periods,
                               record_periods=record_periods,
                               poincare_periods=poincare_periods, progress=tick, t0=t0,
                               snapshot_period=periods - n_chk if n_chk else None, **common)
        if tr.ended is not None:
            return ControlledRun(tr, None, tr.max_eccentricity_run, _periods_of(tr))
        control = None
        if n_chk:
            tic = time.perf_counter()
            base = window_of(tr.t, tr.q[:, cols], tr.poincare_q[:, cols], spp, n_chk,
                             (tr.q_final, tr.v_final, tr.t_final))
            try:
                one = halving_check(inputs, tr.snapshot or (q0, v0, t0), base, **chk)
            except ElementDomainError as exc:
                if on_contact == "raise":
                    raise
                return ControlledRun(replace(tr, ended=exc), None, tr.max_eccentricity_run,
                                     periods)
            control = StepControl("fixed", spp, (one,), tolerance, None,
                                  time.perf_counter() - tic)
        return ControlledRun(tr, control, tr.max_eccentricity_run, periods)
    n_main = periods - record_periods
    n_chk = min(check_periods, n_main)
    if n_chk < 1:
        raise ValueError("auto step control needs periods > record_periods")
    main = integrate_periods(inputs, q0, v0, steps_per_period=AUTO_START, periods=n_main,
                             record_periods=n_chk, poincare_periods=n_chk, progress=tick,
                             t0=t0, snapshot_period=n_main - n_chk, **common)
    if main.ended is not None:
        return ControlledRun(main, None, main.max_eccentricity_run, _periods_of(main))
    s0 = main.snapshot or (q0, v0, t0)
    base = window_of(main.t, main.q[:, cols], main.poincare_q[:, cols], AUTO_START, n_chk,
                     (main.q_final, main.v_final, main.t_final))
    try:
        control, accepted = auto_step(inputs, s0, base,
                                      max_steps_per_period=max_steps_per_period, **chk)
    except ElementDomainError as exc:
        if on_contact == "raise":
            raise
        return ControlledRun(replace(main, ended=exc), None, main.max_eccentricity_run,
                             n_main)
    q1, v1, t1 = accepted.end
    tr = integrate_periods(inputs, q1, v1, steps_per_period=accepted.steps_per_period,
                           periods=record_periods, record_periods=record_periods,
                           poincare_periods=poincare_periods, t0=t1,
                           progress=lambda done: tick(n_main + done), **common)
    runs = [e for e in (main.max_eccentricity_run, tr.max_eccentricity_run) if e is not None]
    done = periods + accepted.periods - n_chk
    if tr.ended is not None:
        done = n_main + accepted.periods - n_chk + _periods_of(tr)
    return ControlledRun(tr, control, max(runs) if runs else None, done)


def _periods_of(tr: Trajectory) -> int:
    """Whole periods a run that ended at a contact integrated (its own count)."""
    period = getattr(tr.ended, "period", None)
    return int(period) if period is not None else 0
