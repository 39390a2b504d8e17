"""Time-domain simulation of the rotor-SFD system at one speed (paper section 4.3, Fig. 23).

``run_simulation(config_or_system, speed) -> SimulationResult`` integrates

    M q'' + (C + Omega G + C_base(t)) q' + (K + K_base(t)) q = F_mu(t) + F_base(t) + F_sfd

with :func:`rotorsfd.timedomain.integrate` machinery, in chunks of rotor periods (exact
continuation of the compiled loop). A constant base gives constant matrices, the constant
load ``F_base`` (gravity through the base state) and the unbalance harmonics; a harmonic or
callable base gives ``TimeVaryingMatrices`` and series loads from
:func:`~rotorsfd.model.base_terms.time_varying_terms` and
:func:`~rotorsfd.model.unbalance.unbalance_series` (coefficients that stay constant over the
run are folded into the constant matrices) (:mod:`~rotorsfd.analyses.td_integration`).
The step is ``T / steps_per_period`` with ``T = 2 pi / Omega``: ``"auto"`` (default) halves
it from T/200 until one halving moves the journal orbit by less than ``step_tolerance``,
a fixed number is checked by one halving (:mod:`~rotorsfd.analyses.step_control`);
Poincare points are taken once per rotor period at ``t = k T``. The motion is classified
on the recorded periods (:func:`classify`) with the Lyapunov exponent of
:mod:`~rotorsfd.analyses.td_lyapunov` (neutral high modes excluded).

Initial state: every node displaced by ``initial_displacement`` in y and z (translations
only, rotations and velocities zero; the paper's "every node displaced 1 um"), or the HB
periodic solution at that speed (``from_hb``): ``q(0) = Re sum X_k``,
``v(0) = Re sum i k Omega X_k``; with ``hb_phase = p`` the state of that orbit a fraction
p of the period later, ``X_k exp(i k 2 pi p)``, put at t = 0 (off the orbit unless it is
symmetric: a way to land on a coexisting attractor); or the final state of a previous run
(``initial_state``: its ``timeseries.nc`` or directory, :func:`load_state`).
``timeseries.nc`` stores the final state of every DOF (``final_displacement``,
``final_velocity``) with its time ``t_final_s`` and the rotor phase ``Omega t mod 2 pi``.
A run from a saved state at the same speed continues it exactly (t0 = the saved time);
at another speed it starts at the time where the new rotor phase equals the saved one
(constant base), so the unbalance force has no phase jump.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.analyses.context import RunContext, build, system_context
from rotorsfd.analyses.simulation_result import (
    FILE_SAMPLES_PER_PERIOD,
    SimulationResult,
    file_stride,
)
from rotorsfd.analyses.step_control import (
    AUTO_START,
    STEP_TOLERANCE,
    StepCheck,
    StepControl,
    integrate_controlled,
)
from rotorsfd.analyses.td_integration import (
    DIRECTIONS,
    FIELD,
    TimeDomainInputs,
    Trajectory,
    integrate_periods,
    reduction_check,
    reduction_summary,
    scheme_options,
    stepped_system,
    time_domain_inputs,
    with_reduction,
)
from rotorsfd.analyses.td_lyapunov import lyapunov_pair
from rotorsfd.analyses.td_start import (
    SavedState,
    displaced_state,
    hb_start,
    hb_state,
    load_state,
    shift_phase,
    timeseries_path,
)
from rotorsfd.errors import ConfigError, ConvergenceError, ElementDomainError
from rotorsfd.model import dofs
from rotorsfd.model.node_names import NodeNames
from rotorsfd.model.system import RotorSystem
from rotorsfd.timedomain import (
    LyapunovResult,
    MotionClass,
    classify_motion,
)

__all__ = [
    "DIRECTIONS",
    "FIELD",
    "FILE_SAMPLES_PER_PERIOD",
    "STEP_TOLERANCE",
    "RunContext",
    "SavedState",
    "SimulationResult",
    "StepCheck",
    "StepControl",
    "TimeDomainInputs",
    "Trajectory",
    "classify",
    "displaced_state",
    "file_stride",
    "hb_start",
    "hb_state",
    "integrate_periods",
    "load_state",
    "run_simulation",
    "scheme_options",
    "shift_phase",
    "system_from_config",
    "time_domain_inputs",
    "timeseries_path",
]

from rotorsfd.io.schema import Config, SimulateAnalysis

REDUCTION_CHECK_PERIODS = 10
"""Periods of the reduction check (at most ``step_check_periods``; 0 turns it off too)."""


# ---- running ------------------------------------------------------------------------------


def system_from_config(config: Config, search_path: Path | None = None) -> RotorSystem:
    """The :class:`RotorSystem` of a configuration (:func:`~rotorsfd.analyses.context.build`)."""
    return build(config, search_path)


def _progress_bar(enabled: bool, total: int, desc: str) -> Any:
    # deferred: tqdm is heavy (loaded only when this runs)
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, disable=not enabled, file=sys.stderr,
                dynamic_ncols=True, leave=False, unit="period")


def run_simulation(config_or_system: Config | RotorSystem, speed: float | None = None, *,
                   settings: SimulateAnalysis | None = None,
                   context: RunContext | None = None,
                   speed_ratio: float | None = None, search_path: Path | None = None,
                   reference_speed: float | None = None, scheme: str | None = None,
                   alpha: float | None = None, steps_per_period: int | None = None,
                   periods: int | None = None, poincare_periods: int | None = None,
                   record_periods: int | None = None, lyapunov_periods: int | None = None,
                   initial_displacement: float | None = None, from_hb: bool = False,
                   hb_phase: float = 0.0, initial_state: str | Path | SavedState | None = None,
                   harmonics: int | None = None, q0: Any = None, v0: Any = None,
                   nodes: Sequence[int] | None = None, chunk_periods: int | None = None,
                   progress: bool = True, title: str | None = None,
                   step_check_periods: int | None = None,
                   step_tolerance: float | None = None,
                   max_steps_per_period: int | None = None,
                   reduction: str | None = None,
                   reduction_cutoff: float | None = None,
                   speed_law: Any = None, overlay: str | Path | None = None
                   ) -> SimulationResult:
    """Integrate the nonlinear rotor at one speed and classify the motion.

    ``run_simulation(system, speed, settings=..., context=...)``: ``settings`` the
    ``[analysis.simulate]`` section (default: its defaults, the paper's: 200 steps per
    period checked, 2000 periods, 100 Poincare periods, 1 um, Newmark), ``context`` the
    reference speed, HB settings, nodes and title (:class:`RunContext`; default: an empty
    configuration's). ``run_simulation(config)`` is that call with
    ``build(config)``, ``config.analysis.simulate`` and :func:`config_context`: the two
    paths cannot disagree. Keyword arguments override the settings (``speed`` [rad/s] or
    ``speed_ratio``; ``reference_speed`` the context's Omega_ref; without one a speed
    ratio is taken on the first forward critical speed).
    ``record_periods`` (default
    ``poincare_periods``): periods kept in the time series; ``lyapunov_periods`` (default
    ``min(100, periods)``, 0: none): length of the Lyapunov run from the final state.
    ``q0, v0`` override the initial state (full DOF vectors). ``from_hb`` with
    ``hb_phase`` (fraction of the period): start on the HB orbit shifted by that phase;
    ``initial_state``: the final state of a previous run (``timeseries.nc``, its
    directory, or a :class:`SavedState`), see the module docstring for its start time.
    ``steps_per_period`` (default ``[analysis.simulate]``): ``"auto"`` (the step halved
    from T/200 until one halving changes the journal orbit by less than
    ``step_tolerance`` [C], at most ``max_steps_per_period``; the transient at T/200, the
    recorded periods at the accepted step: :mod:`~rotorsfd.analyses.step_control`) or an
    integer, checked by one halving over the last ``step_check_periods`` (0: off).
    ``result.step_check`` (a :class:`StepControl`) holds the halvings and the achieved
    error; a step that fails the tolerance puts a warning in the summary.
    ``speed_law`` (default ``[analysis.simulate] speed_law``; a config table or a
    :mod:`~rotorsfd.timedomain.speed_law` law): a run-up or coast-down instead
    (:func:`~rotorsfd.analyses.runup_simulation.run_speed_law_simulation`, a RunUpResult;
    ``overlay`` a branch.nc of ``rotorsfd response`` drawn over its envelope).
    ``reduction`` / ``reduction_cutoff`` (default ``[analysis.simulate]``, "auto" and 40):
    the step on the Craig-Bampton model with the fixed-interface modes up to
    ``reduction_cutoff`` x Omega (:func:`~rotorsfd.analyses.td_integration.with_reduction`);
    the settings report the kept coordinates and the cutoff, and ``reduction_check``:
    the check node's orbit over the last :data:`REDUCTION_CHECK_PERIODS` periods from the
    final state against the full step (models up to 400 DOF) or the reduced step at 4x
    the cutoff, in C (the orbit's largest value without an element there; an upper
    estimate, :func:`~rotorsfd.analyses.td_integration.reduction_check`).

    A journal reaching its element's validity limit (contact) ends the run as a result
    (issue 22): ``result.ended == "limit"``, the periods recorded up to there, the
    warning :attr:`SimulationResult.message`; a numerical failure raises.
    """
    system, ctx, config = system_context(config_or_system, "simulate", context=context,
                                         search_path=search_path,
                                         reference_speed=reference_speed)
    sim = (settings if settings is not None else config.analysis.simulate if config
           else SimulateAnalysis())
    search_path = ctx.search_path
    ref = ctx.reference_speed
    H = harmonics or ctx.harmonics
    h_samples = ctx.response.n_samples
    name = ctx.title if title is None else title
    out_nodes = tuple(nodes) if nodes else ctx.output_nodes(system)
    config_toml = ctx.config_toml
    law = speed_law if speed_law is not None else sim.speed_law
    if speed is None and speed_ratio is None and law is None:
        speed, speed_ratio = sim.speed, sim.speed_ratio
    if speed is None and speed_ratio is not None and ref is None:
        ref = ctx.reference(system)
    if law is not None:            # a run-up / coast-down: analyses/runup_simulation.py
        from rotorsfd.analyses.runup_simulation import law_of, run_speed_law_simulation

        if speed is not None or speed_ratio is not None:
            raise ConfigError(f"{FIELD}.speed_law", "with a speed", "give a speed law or "
                              "one speed (speed, speed_ratio, --speed), not both")
        return run_speed_law_simulation(
            system, law_of(law, search_path), sim=sim, nodes=out_nodes, title=name,
            steps_per_period=steps_per_period, periods=periods, scheme=scheme,
            alpha=alpha, initial_displacement=initial_displacement, overlay=overlay,
            config_toml=config_toml or "")
    if speed is None and speed_ratio is not None:
        speed = speed_ratio * ref
    if speed is None or not speed > 0.0:
        raise ConfigError(f"{FIELD}.speed", speed, "give the rotor speed (> 0): --speed, "
                          "--speed-ratio, or speed/speed_ratio in [analysis.simulate]")
    speed = float(speed)
    spp_setting = steps_per_period if steps_per_period is not None \
        else sim.steps_per_period
    auto = spp_setting == "auto"
    if not auto and not (isinstance(spp_setting, int | np.integer) and spp_setting >= 8):
        raise ConfigError(f"{FIELD}.steps_per_period", spp_setting,
                          '"auto" or an integer >= 8')
    tol = sim.step_tolerance if step_tolerance is None else float(step_tolerance)
    cap = sim.max_steps_per_period if max_steps_per_period is None \
        else int(max_steps_per_period)
    if not tol > 0.0:
        raise ConfigError(f"{FIELD}.step_tolerance", tol, "must be > 0")
    spp = AUTO_START if auto else int(spp_setting)
    if auto and cap < 2 * spp:
        raise ConfigError(f"{FIELD}.max_steps_per_period", cap,
                          f"must be >= {2 * spp} for steps_per_period = \"auto\"")
    n_per = periods or sim.periods
    n_pc = poincare_periods or sim.poincare_periods
    n_rec = record_periods or n_pc
    n_ly = min(100, n_per) if lyapunov_periods is None else int(lyapunov_periods)
    n_chk = sim.step_check_periods if step_check_periods is None else int(step_check_periods)
    if n_chk < 0 or (auto and n_chk < 1):
        raise ConfigError(f"{FIELD}.step_check_periods", n_chk,
                          "must be >= 1 with steps_per_period = \"auto\"" if auto
                          else "must be >= 0 (0: off)")
    for label, value in (("poincare_periods", n_pc), ("record_periods", n_rec)):
        if not 1 <= value <= n_per:
            raise ConfigError(f"{FIELD}.{label}", value, f"must be in 1..periods = {n_per}")
    n_keep = max(n_rec, n_pc)
    if auto:
        if n_per <= n_keep:
            raise ConfigError(f"{FIELD}.periods", n_per, "must exceed the recorded "
                              f"periods ({n_keep}) with steps_per_period = \"auto\" "
                              "(the step is chosen on the periods before them)")
        n_chk = min(n_chk, n_per - n_keep)
    else:
        n_chk = min(n_chk, n_pc)           # the last n_chk periods of the recorded ones
    scheme = scheme or sim.scheme
    alpha = sim.alpha if alpha is None else alpha
    opts = scheme_options(scheme, alpha)
    disp = sim.initial_displacement if initial_displacement is None else initial_displacement
    T = 2.0 * math.pi / speed
    n = system.n_dof
    t_start = 0.0
    if sum(x for x in (q0 is not None or v0 is not None, from_hb,
                       initial_state is not None)) > 1:
        raise ConfigError("initial state", "several", "give one of q0/v0, from_hb and "
                          "initial_state")
    if q0 is not None or v0 is not None:
        start = "given"
        q_init = np.zeros(n) if q0 is None else np.asarray(q0, float)
        v_init = np.zeros(n) if v0 is None else np.asarray(v0, float)
    elif initial_state is not None:
        saved = initial_state if isinstance(initial_state, SavedState) \
            else load_state(initial_state)
        if saved.q.size != n:
            raise ConfigError("initial_state", saved.source, f"has {saved.q.size} DOFs, "
                              f"this model {n}")
        q_init, v_init = saved.q.copy(), saved.v.copy()
        t_start = saved.start_time(speed) if system.base.is_constant else saved.t
        start = (f"final state of {saved.source or 'a previous run'} (t = {saved.t:.6g} s "
                 f"at {saved.speed:.6g} rad/s; this run starts at t = {t_start:.6g} s)")
    elif from_hb:
        if not len(system.elements) or not system.base.is_constant:
            raise ConfigError("from_hb", True, "the HB start needs a nonlinear element and "
                              "a constant base motion (start from the displaced state "
                              "instead)")
        start = f"HB periodic solution (H={H})" + (
            f" shifted by {hb_phase:g} of the period" if hb_phase else "")
        q_init, v_init = hb_start(system, speed, H, h_samples, phase=hb_phase)
    else:
        start = f"every node displaced {disp:g} m in y and z"
        q_init, v_init = displaced_state(n, disp), np.zeros(n)
    inputs = time_domain_inputs(system, speed,
                                horizon=t_start + (n_per + n_ly + 1) * T)
    cut = sim.reduction_cutoff if reduction_cutoff is None else float(reduction_cutoff)
    tic_red = time.perf_counter()
    inputs = with_reduction(inputs, reduction or sim.reduction, cut)
    elapsed_reduction = time.perf_counter() - tic_red
    rd = [dofs.dof_index(nd, d) for nd in out_nodes for d in DIRECTIONS]
    clearance = system.length_scale
    primary = system.primary_node
    jc = _first_column(out_nodes, primary)
    settings = {"speed_rad_s": speed, "speed_ratio": speed / ref if ref else None,
                "reference_speed_rad_s": ref, "scheme": scheme, **opts,
                "step_control": "auto" if auto else "fixed",
                "step_tolerance": tol, "max_steps_per_period": cap if auto else None,
                "steps_per_period": spp, "periods": n_per, "poincare_periods": n_pc,
                "record_periods": n_rec, "lyapunov_periods": n_ly,
                "step_check_periods": n_chk, "initial_state": start,
                "initial_displacement_m": disp, "start_time_s": t_start,
                "time_varying_matrices": inputs.time_varying is not None,
                **reduction_summary(inputs, cut), "elapsed_reduction_s": elapsed_reduction}
    bar = _progress_bar(progress, n_per, "simulate")
    last = [0]

    def tick(done: int) -> None:
        bar.update(done - last[0])
        last[0] = done

    tic = time.perf_counter()
    try:
        run_ = integrate_controlled(
            inputs, q_init, v_init, steps_per_period="auto" if auto else spp, periods=n_per,
            record_dofs=rd, record_periods=n_keep, poincare_periods=n_pc,
            check_column=jc, check_node=out_nodes[jc], check_periods=n_chk, tolerance=tol,
            max_steps_per_period=cap, method_options=opts, chunk_periods=chunk_periods,
            check_clearance=clearance if out_nodes[jc] == primary else None,
            t0=t_start, progress=tick, on_contact="end")
    finally:
        bar.close()
    traj, control, eps_run = run_.trajectory, run_.control, run_.max_eccentricity_run
    ended = traj.ended is not None
    spp = control.steps_per_period if control is not None else spp
    settings["periods_run"] = run_.periods_run
    settings["steps_per_period"] = spp
    settings["dt_s"] = T / spp
    settings["elapsed_integration_s"] = time.perf_counter() - tic
    if control is not None:
        settings["elapsed_step_control_s"] = control.elapsed
    nn = len(out_nodes)
    q = traj.q.reshape(-1, nn, 2)
    v = traj.v.reshape(-1, nn, 2)
    pq = traj.poincare_q.reshape(-1, nn, 2)
    pv = traj.poincare_v.reshape(-1, nn, 2)
    notes: list[str] = []
    if ended:
        notes.append("no Lyapunov exponent, no motion class: the run ended at the "
                     "element's validity limit")
    if inputs.reduction is not None and n_chk > 0 and not ended:
        # the reduction against the full step (or a 4x finer cutoff on large models),
        # the check node's orbit over a few periods from the final state
        tic_chk = time.perf_counter()
        try:
            settings.update(reduction_check(
                inputs, (traj.q_final, traj.v_final, traj.t_final), steps_per_period=spp,
                periods=min(REDUCTION_CHECK_PERIODS, n_chk),
                record_dofs=rd[2 * jc:2 * jc + 2],
                scale=clearance if out_nodes[jc] == primary else None))
        except (ElementDomainError, ConvergenceError) as exc:
            notes.append(f"no reduction check: {' '.join(str(exc).split())}")
        settings["elapsed_reduction_check_s"] = time.perf_counter() - tic_chk
    lyap = lyap_full = None
    tic_ly = time.perf_counter()
    if n_ly > 0 and not ended:
        try:
            # on the model the run stepped (the reduced one with "auto")
            ly_inputs, ly_state = stepped_system(inputs, (traj.q_final, traj.v_final,
                                                          traj.t_final))
            pair = lyapunov_pair(ly_inputs, ly_state, steps_per_period=spp, periods=n_ly)
            lyap, lyap_full = pair.reduced, pair.full
            settings["lyapunov_modes_kept"] = pair.n_modes
            settings["lyapunov_omega_max_rad_s"] = pair.omega_max
        except (ElementDomainError, ConvergenceError) as exc:
            notes.append(f"no Lyapunov exponent: {' '.join(str(exc).split())}")
    settings["elapsed_lyapunov_s"] = time.perf_counter() - tic_ly
    motion = None if ended else classify(traj.poincare_q, traj.poincare_v, traj.q, traj.v,
                                         T / spp, speed, lyap, first=2 * jc,
                                         n_record=n_keep * spp)
    if motion is None and not ended:
        notes.append("fewer than 8 Poincare points: motion not classified")
    elapsed = time.perf_counter() - tic
    eps_rec = None
    if clearance is not None and primary in out_nodes and q.shape[0]:
        j = out_nodes.index(primary)
        eps_rec = float(np.max(np.hypot(q[:, j, 0], q[:, j, 1]))) / clearance
    elif clearance is not None:
        eps_rec = eps_run
    return SimulationResult(speed, ref, tuple(out_nodes), traj.t, q, v, traj.poincare_t, pq,
                            pv, motion, lyap, clearance, primary, settings, eps_rec,
                            eps_run, traj.q_final, traj.v_final,
                            traj.t_final, elapsed, name, notes, control, lyap_full,
                            traj.element_diagnostics, config_toml,
                            "limit" if ended else "range",
                            " ".join(str(traj.ended).split()) if ended else "",
                            NodeNames.of(system.rotor))


def _first_column(nodes: Sequence[int], node: int | None) -> int:
    return list(nodes).index(node) if node in nodes else 0


def classify(pq: np.ndarray, pv: np.ndarray, q: np.ndarray, v: np.ndarray, dt: float,
             speed: float, lyapunov: LyapunovResult | None = None, *, first: int = 0,
             n_record: int | None = None) -> MotionClass | None:
    """:func:`~rotorsfd.timedomain.classify_motion` on recorded columns ``(.., 2 n_nodes)``
    (y, z of each node); the spectrum of column ``first`` over the last ``n_record``
    samples (a whole number of periods); None with fewer than 8 Poincare points.

    The section is the *displacements* of every recorded node, all in one scale (the
    largest peak-to-peak of the recorded orbits): a point repeats when
    ``max |P[k+n] - P[k]| <= 1e-3`` of that scale. Per-coordinate scales let a node with a
    small orbit, and velocities, which carry a lightly damped high mode's free vibration
    (``omega_h / Omega`` times its displacement; the rotor has no structural damping), call
    a period-1 orbit quasi-periodic; the velocities' spread is reported
    (``poincare_velocity_spread``, relative to the orbit's velocity range) but does not
    decide."""
    if pq.shape[0] < 8:
        return None
    order = [first] + [i for i in range(q.shape[1]) if i != first]
    m = q.shape[0] if n_record is None else min(n_record, q.shape[0])
    qs, vs = q[-m:][:, order], v[-m:][:, order]
    scale = float(np.max(np.ptp(qs, axis=0))) or 1.0
    mc = classify_motion(pq[:, order], qs, dt, speed, lyapunov, scale=scale)
    v_scale = float(np.max(np.ptp(vs, axis=0))) or 1.0
    ev = {**mc.evidence, "section": "displacements of the recorded nodes, one scale",
          "section_scale_m": scale,
          "poincare_spread": float(np.max(np.ptp(pq, axis=0))) / scale,
          "poincare_velocity_spread": float(np.max(np.ptp(pv, axis=0))) / v_scale}
    n = mc.period
    if n is not None:
        # consecutive points within tolerance but drifting along a curve: not settled
        settled = ev.get("n_distinct_poincare", n) <= n and "converging" not in ev
        ev["settled"] = settled
        if "converging" in ev:
            pass                                  # classify_motion's note says why
        elif not settled:
            ev["note"] = (f"{ev['n_distinct_poincare']} distinct Poincare points for a "
                          f"period-{n} classification: the points still drift (a slow "
                          "transient); run more periods")
        elif n == 1 and ev["poincare_velocity_spread"] > 1e-3:
            ev["note"] = (f"the velocities at the Poincare points spread by "
                          f"{ev['poincare_velocity_spread']:.2g} of their range while the "
                          f"displacements repeat within {ev['poincare_spread']:.2g}: the "
                          "free vibration of a lightly damped high mode (not part of the "
                          "classification)")
    return MotionClass(mc.motion, ev)
