"""Brute-force bifurcation diagram: Poincare points of the time-domain motion against the
rotor speed, swept up and then down (``[analysis.bifurcation_diagram]``).

At each speed the integration starts from the end state of the previous speed, runs
``settle_periods`` and records the Poincare points of ``record_periods`` more. A speed
with no previous state (the first of a sweep, unless the sweep before ended at the same
speed, and the speed after a failed one) starts *fresh*: by default on the HB periodic
solution at that speed (:func:`~rotorsfd.analyses.simulate.hb_start`, H of
``[analysis.response]``), so that the start's transient does not reach the clearance,
and from the displaced state of ``[analysis.simulate] initial_displacement`` when no HB
solution can be computed (time-varying base, no SFD, no convergence); with
``start_state="displaced"`` the first speed of a sweep starts displaced (the speed after
a failed one still from the HB orbit). Each speed records its start (``previous``, ``hb`` or
``displaced``). Runs at each speed start at t = 0, so the unbalance angle ``Omega t`` is
continuous (every run lasts a whole number of periods); a time-varying base law restarts
its phase at each speed. Coexisting attractors show as a difference of the up and down
sweeps (jumps and hysteresis). A speed whose journal reaches its validity limit (contact)
ends there as a result (``ended = "limit"``, issue 22 item 3: the CLI warns and exits 0); a
speed whose time stepping fails numerically is ``ended = "failed"`` (exit 1); either way
the reason is recorded and the sweep goes on at the next speed from a fresh start.

``run_bifurcation_diagram(system, settings, simulate=..., context=...)`` takes the
``[analysis.bifurcation_diagram]`` and ``[analysis.simulate]`` sections and a
:class:`~rotorsfd.analyses.context.RunContext`; ``run_bifurcation_diagram(config)`` is that
call on the config's (:func:`~rotorsfd.analyses.context.config_context`).

The step is that of ``[analysis.simulate]``: ``steps_per_period = "auto"`` (default) runs
each speed's settling periods at T/200, halves the step over the last
``step_check_periods`` of them until one halving moves the journal orbit by less than
``step_tolerance`` (:mod:`~rotorsfd.analyses.step_control`) and records
``record_periods`` at the accepted step; a fixed step is checked by one halving.
"""

from __future__ import annotations

import math
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rotorsfd.analyses.context import RunContext, system_context
from rotorsfd.analyses.simulate import classify
from rotorsfd.analyses.step_control import integrate_controlled
from rotorsfd.analyses.td_integration import (
    DIRECTIONS,
    scheme_options,
    time_domain_inputs,
    with_reduction,
)
from rotorsfd.analyses.td_start import displaced_state, hb_start
from rotorsfd.errors import ConfigError, ConvergenceError, ElementDomainError, RotorsfdError
from rotorsfd.io import atomic
from rotorsfd.io.schema import BifurcationDiagramAnalysis, Config, SimulateAnalysis
from rotorsfd.model import dofs
from rotorsfd.model.node_names import NodeNames, node_words
from rotorsfd.model.system import RotorSystem

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

FIELD = "analysis.bifurcation_diagram"
#: Fresh starts of a sweep (``run_bifurcation_diagram(start_state=...)``).
FRESH_STARTS = ("hb", "displaced")
#: How a speed that did not run to its end is named in the summary, by its ``ended``.
END_WORDS = {"limit": "ended at a validity limit", "failed": "failed"}


@dataclass
class SpeedPoint:
    """One speed of a sweep: its Poincare points ``(n_p, n_nodes, 2)`` (y, z) and
    velocities, the motion class and the peak journal eccentricity (or the contact)."""

    direction: str
    speed: float
    poincare_t: np.ndarray
    poincare_q: np.ndarray
    poincare_v: np.ndarray
    motion: str
    n_distinct: int | None
    max_eccentricity: float | None
    contact: str | None = None
    settled: bool = True
    start: str = "previous"     #: the initial state: "previous", "hb" or "displaced"
    steps_per_period: int | None = None     #: the step of the recorded periods
    step_error: float | None = None         #: change of the last halving [C]
    step_converged: bool | None = None      #: that change below step_tolerance
    ended: str = "range"    #: "range" (ran), "limit" (contact) or "failed" (numerics)


@dataclass
class BifurcationDiagramResult:
    """The sweeps (``points`` in run order) and how they were made."""

    points: list[SpeedPoint]
    nodes: tuple[int, ...]
    reference_speed: float | None
    clearance: float | None
    settings: dict[str, Any]
    elapsed: float = 0.0
    title: str = ""
    notes: list[str] = field(default_factory=list)
    #: shaft-wise node names of a multi-shaft rotor (None: one shaft)
    node_names: NodeNames | None = None

    FILES = ("diagram.csv", "speeds.csv", "diagram.png", "diagram.json")

    @property
    def contacts(self) -> list[SpeedPoint]:
        """The speeds that did not run to their end (contact or a numerical failure)."""
        return [p for p in self.points if p.contact is not None]

    @property
    def failures(self) -> list[SpeedPoint]:
        """The speeds whose time stepping failed numerically (``ended = "failed"``)."""
        return [p for p in self.points if p.ended == "failed"]

    @property
    def success(self) -> bool:
        """No numerical failure (a speed ended at a validity limit is a result)."""
        return not self.failures

    @property
    def ended(self) -> str:
        """``"failed"`` if a speed failed numerically, else ``"limit"`` if one ended at
        an element's validity limit, else ``"range"`` (the response's vocabulary)."""
        ends = {p.ended for p in self.points}
        return "failed" if "failed" in ends else "limit" if "limit" in ends else "range"

    def table(self) -> dict[str, np.ndarray]:
        """``diagram.csv``: ``direction, speed_rad_s, speed_ratio, node, period, y, z, vy,
        vz`` (one row per Poincare point and node; SI: m, m/s; ``period`` counts from the
        start of that speed's run), and for a multi-shaft rotor ``shaft, shaft_node``."""
        cols: dict[str, list[Any]] = {k: [] for k in (
            "direction", "speed_rad_s", "speed_ratio", "node", "period", "y", "z", "vy",
            "vz")}
        ref = self.reference_speed
        for p in self.points:
            n_p = p.poincare_t.size
            per = np.rint(p.poincare_t * p.speed / (2 * math.pi)).astype(int)
            for j, node in enumerate(self.nodes):
                cols["direction"] += [p.direction] * n_p
                cols["speed_rad_s"] += [p.speed] * n_p
                cols["speed_ratio"] += [p.speed / ref if ref else math.nan] * n_p
                cols["node"] += [node] * n_p
                cols["period"] += list(per)
                cols["y"] += list(p.poincare_q[:, j, 0])
                cols["z"] += list(p.poincare_q[:, j, 1])
                cols["vy"] += list(p.poincare_v[:, j, 0])
                cols["vz"] += list(p.poincare_v[:, j, 1])
        if not ref:
            cols.pop("speed_ratio")
        out = {k: np.asarray(v) for k, v in cols.items()}
        if self.node_names is not None:     # a multi-shaft rotor: the node's shaft
            out["shaft"], out["shaft_node"] = self.node_names.arrays(out["node"])
        return out

    def speeds_table(self) -> dict[str, np.ndarray]:
        """``speeds.csv``: per speed ``direction, speed_rad_s, speed_ratio, motion,
        n_distinct_poincare (-1: unknown), max_eccentricity (-1: none), contact (0/1: the
        speed did not run to its end), ended (``range``, ``limit``: the journal reached its
        validity limit, ``failed``: the time stepping failed; diagram.json says why),
        settled (0:
        a period-n class whose Poincare points still drift), start`` (initial state:
        ``previous`` speed's end state, ``hb`` orbit or ``displaced``), ``steps_per_period``
        of the recorded periods, ``step_error`` (change of the last halving of the step,
        in C; -1: not checked) and ``step_converged`` (0/1: below step_tolerance). The
        motion is classified without a Lyapunov exponent (Poincare points and spectral
        lines)."""
        ref = self.reference_speed
        cols = {"direction": [p.direction for p in self.points],
                "speed_rad_s": [p.speed for p in self.points],
                "speed_ratio": [p.speed / ref if ref else math.nan for p in self.points],
                "motion": [p.motion for p in self.points],
                "n_distinct_poincare": [-1 if p.n_distinct is None else p.n_distinct
                                        for p in self.points],
                "max_eccentricity": [-1.0 if p.max_eccentricity is None
                                     else p.max_eccentricity for p in self.points],
                "contact": [p.contact is not None for p in self.points],
                "ended": [p.ended for p in self.points],
                "settled": [p.settled for p in self.points],
                "start": [p.start for p in self.points],
                "steps_per_period": [-1 if p.steps_per_period is None else p.steps_per_period
                                     for p in self.points],
                "step_error": [-1.0 if p.step_error is None else p.step_error
                               for p in self.points],
                "step_converged": [bool(p.step_converged) for p in self.points]}
        if not ref:
            cols.pop("speed_ratio")
        return {k: np.asarray(v) for k, v in cols.items()}

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """Write ``diagram.csv``, ``speeds.csv``, ``diagram.json`` (settings, contacts)
        and ``diagram.png`` atomically."""
        # deferred: io.branch_files (loads xarray, pandas, multiprocessing)
        from rotorsfd.io.branch_files import write_table

        out = Path(directory)
        paths = {"diagram.csv": write_table(out / "diagram.csv", self.table()),
                 "speeds.csv": write_table(out / "speeds.csv", self.speeds_table()),
                 "diagram.json": atomic.write_json(out / "diagram.json", atomic.json_safe({
                     "settings": self.settings, "nodes": list(self.nodes),
                     "clearance_m": self.clearance, "elapsed_s": self.elapsed,
                     "ended": self.ended,
                     "contacts": [{"direction": p.direction, "speed_rad_s": p.speed,
                                   "start": p.start, "ended": p.ended,
                                   "message": p.contact} for p in self.contacts],
                     "notes": self.notes, "title": self.title}))}
        if plots:
            paths.update(atomic.save_figures(self.plot(), out))
        return paths

    def to_dataset(self) -> xr.Dataset:
        """The Poincare points (dimension ``point``: the rows of :meth:`table`) and the
        speeds (dimension ``run``: the rows of :meth:`speeds_table`), SI units."""
        # deferred: xarray is heavy (loaded only when this runs)
        import xarray as xr

        units = {"speed_rad_s": "rad/s", "y": "m", "z": "m", "vy": "m/s", "vz": "m/s",
                 "max_eccentricity": "1", "step_error": "1"}
        data = {f"poincare_{k}": ("point", v, {"units": units.get(k, "1")})
                for k, v in self.table().items()}
        data |= {f"run_{k}": ("run", v, {"units": units.get(k, "1")})
                 for k, v in self.speeds_table().items()}
        return xr.Dataset(data, attrs={"title": self.title, "ended": self.ended})

    def plot(self) -> dict[str, Figure]:
        """``diagram.png``: Poincare y (in C) of every node against Omega~ (or the
        speed)."""
        # deferred: plots.timedomain (loads matplotlib)
        from rotorsfd.plots.timedomain import bifurcation_figure

        table = self.table()
        x_name = "speed_ratio" if self.reference_speed else "speed_rad_s"
        label = r"$\tilde\Omega = \Omega / \Omega_{ref}$" if self.reference_speed \
            else r"$\Omega$ [rad/s]"
        return {"diagram.png": bifurcation_figure(
            table, nodes=self.nodes, x_name=x_name, x_label=label,
            scale=self.clearance or 1.0, unit="C" if self.clearance else "m",
            title=self.title,
            node_labels={n: node_words(self.node_names, n) for n in self.nodes})}

    def summary(self) -> str:
        """Speeds, sweeps, motion counts, contacts."""
        counts: dict[str, int] = {}
        for p in self.points:
            counts[p.motion] = counts.get(p.motion, 0) + 1
        lines = [f"{len(self.points)} runs ({self.settings['direction']}), "
                 f"{self.settings['settle_periods']} + {self.settings['record_periods']} "
                 f"periods each, {self.elapsed:.1f} s",
                 "motions: " + ", ".join(f"{k} {v}" for k, v in sorted(counts.items()))]
        steps = sorted({p.steps_per_period for p in self.points if p.steps_per_period})
        errors = [p.step_error for p in self.points if p.step_error is not None]
        if steps:
            text = (f"time step ({self.settings['steps_per_period']}): T/{steps[0]}"
                    + (f" to T/{steps[-1]}" if len(steps) > 1 else ""))
            if errors:
                text += f"; largest change of the last halving {max(errors):.2g} C"
            lines.append(text)
        bad = [p for p in self.points if p.step_converged is False]
        if bad:
            lines.append(f"warning: at {len(bad)} speeds the step did not meet "
                         f"step_tolerance = {self.settings['step_tolerance']:g} (speeds.csv "
                         'step_converged = 0); set analysis.simulate.steps_per_period = '
                         '"auto" or raise max_steps_per_period')
        starts: dict[str, int] = {}
        for p in self.points:
            starts[p.start] = starts.get(p.start, 0) + 1
        lines.append("starts: " + ", ".join(f"{k} {v}" for k, v in sorted(starts.items())))
        lines += [f"{END_WORDS[p.ended]} ({p.direction} sweep, {p.start} start) at "
                  f"{p.speed:.6g} rad/s: {p.contact}" for p in self.contacts]
        lines += [f"note: {n}" for n in self.notes]
        return "\n".join(lines)


def sweep_speeds(start: float, stop: float, n: int, direction: str
                 ) -> list[tuple[str, float]]:
    """``(direction, speed)`` in run order: up from the lower bound, then down."""
    lo, hi = sorted((float(start), float(stop)))
    up = list(np.linspace(lo, hi, n))
    runs: list[tuple[str, float]] = []
    if direction in ("up", "up-down"):
        runs += [("up", s) for s in up]
    if direction in ("down", "up-down"):
        runs += [("down", s) for s in up[::-1]]
    return runs


def run_bifurcation_diagram(config_or_system: Config | RotorSystem,
                            settings: BifurcationDiagramAnalysis | None = None, *,
                            simulate: SimulateAnalysis | None = None,
                            context: RunContext | None = None,
                            search_path: Path | None = None, start: float | None = None,
                            stop: float | None = None, n: int | None = None,
                            direction: str | None = None, settle_periods: int | None = None,
                            record_periods: int | None = None,
                            steps_per_period: int | None = None, scheme: str | None = None,
                            alpha: float | None = None,
                            initial_displacement: float | None = None,
                            from_hb: bool = False, start_state: str = "hb",
                            harmonics: int | None = None,
                            reference_speed: float | None = None,
                            nodes: Sequence[int] | None = None, progress: bool = True,
                            title: str | None = None) -> BifurcationDiagramResult:
    """Sweep the speed (rad/s): ``settings`` the ``[analysis.bifurcation_diagram]``
    section, ``simulate`` the ``[analysis.simulate]`` one (scheme, step, initial
    displacement), ``context`` the reference speed, H of the HB start, nodes and title
    (defaults: an empty configuration's; from a Config: its sections and
    :func:`config_context`, the same code). The speed range is the settings' (in
    Omega~ on the reference speed) unless ``start``/``stop`` are given.

    ``start_state`` the fresh start (module docstring): ``"hb"`` (default; the displaced
    state where no HB solution can be computed) or ``"displaced"``; ``from_hb=True`` is
    ``"hb"`` (kept for the command line)."""
    # deferred: tqdm is heavy (loaded only when this runs)
    from tqdm import tqdm

    system, ctx, config = system_context(config_or_system, "simulate", context=context,
                                         search_path=search_path,
                                         reference_speed=reference_speed)
    bd = (settings if settings is not None else config.analysis.bifurcation_diagram
          if config else BifurcationDiagramAnalysis())
    sim = (simulate if simulate is not None else config.analysis.simulate if config
           else SimulateAnalysis())
    ref = ctx.reference_speed
    if start is None or stop is None:
        ref = ctx.reference(system)
        lo, hi = bd.speed_range.bounds(ref)
        start = lo if start is None else start
        stop = hi if stop is None else stop
    H = harmonics or ctx.harmonics
    name = ctx.title if title is None else title
    out_nodes = tuple(nodes) if nodes else ctx.output_nodes(system)
    if from_hb:
        start_state = "hb"
    if start_state not in FRESH_STARTS:
        raise ConfigError("start_state", start_state,
                          f"must be one of {', '.join(FRESH_STARTS)}")
    if not (start > 0 and stop > 0 and start != stop):
        raise ConfigError(f"{FIELD}.speed_range", (start, stop),
                          "speeds must be > 0 and differ")
    n = n or bd.speed_range.n
    direction = direction or bd.direction
    settle = bd.settle_periods if settle_periods is None else settle_periods
    rec = record_periods or bd.record_periods
    spp = steps_per_period or sim.steps_per_period
    n_chk = sim.step_check_periods
    if spp == "auto" and (settle < 1 or n_chk < 1):
        raise ConfigError(f"{FIELD}.settle_periods", settle, "must be >= 1 with "
                          'analysis.simulate.steps_per_period = "auto" (the step is '
                          "chosen on the settling periods; step_check_periods >= 1 too)")
    primary = system.primary_node
    j = out_nodes.index(primary) if primary in out_nodes else 0
    opts = scheme_options(scheme or sim.scheme, sim.alpha if alpha is None else alpha)
    disp = sim.initial_displacement if initial_displacement is None else initial_displacement
    rd = [dofs.dof_index(nd, d) for nd in out_nodes for d in DIRECTIONS]
    clearance = system.length_scale
    runs = sweep_speeds(start, stop, n, direction)
    settings = {"speed_start_rad_s": min(start, stop), "speed_stop_rad_s": max(start, stop),
                "n_speeds": n, "direction": direction, "settle_periods": settle,
                "record_periods": rec, "steps_per_period": spp, **opts,
                "step_tolerance": sim.step_tolerance, "step_check_periods": n_chk,
                "max_steps_per_period": sim.max_steps_per_period,
                "initial_state": (f"HB (H={H}), displaced {disp:g} m where it fails"
                                  if start_state == "hb" else f"displaced {disp:g} m"),
                "reference_speed_rad_s": ref}
    nn = len(out_nodes)

    points: list[SpeedPoint] = []
    notes: list[str] = []

    def fresh(d: str, speed: float, hb: bool) -> tuple[np.ndarray, np.ndarray, str]:
        """(q0, v0, start) at speed: the HB orbit (if hb), or the displaced state."""
        if hb:
            try:
                return (*hb_start(system, speed, H), "hb")
            except (RotorsfdError, FloatingPointError, np.linalg.LinAlgError) as exc:
                notes.append(f"{d} sweep at {speed:.6g} rad/s: no HB start ("
                             f"{' '.join(str(exc).split())}); displaced {disp:g} m instead")
        return displaced_state(system.n_dof, disp), np.zeros(system.n_dof), "displaced"

    state: tuple[np.ndarray, np.ndarray] | None = None
    origin, restart = "previous", False
    tic = time.perf_counter()
    bar = tqdm(total=len(runs), desc="bifurcation diagram", disable=not progress,
               file=sys.stderr, dynamic_ncols=True, leave=False)
    try:
        for d, speed in runs:
            bar.update()
            if state is None:
                # after a failed speed always the HB orbit if there is one
                q0, v0, origin = fresh(d, speed, start_state == "hb" or restart)
                state = (q0, v0)
            bar.set_postfix_str(f"{d} {speed / ref if ref else speed:.4g}")
            inputs = with_reduction(time_domain_inputs(
                system, speed, horizon=(settle + rec + 1) * 2 * math.pi / speed),
                sim.reduction, sim.reduction_cutoff)
            try:
                run_ = integrate_controlled(
                    inputs, state[0], state[1], steps_per_period=spp, periods=settle + rec,
                    record_dofs=rd, record_periods=rec, poincare_periods=rec,
                    check_column=j, check_node=out_nodes[j], check_periods=n_chk,
                    tolerance=sim.step_tolerance,
                    max_steps_per_period=sim.max_steps_per_period, method_options=opts,
                    chunk_periods=settle + rec,
                    check_clearance=clearance if out_nodes[j] == primary else None)
            except (ElementDomainError, ConvergenceError) as exc:
                msg = " ".join(str(exc).split())
                empty = np.zeros((0, nn, 2))
                limit = isinstance(exc, ElementDomainError)
                points.append(SpeedPoint(d, speed, np.zeros(0), empty, empty,
                                         "contact" if limit else "failed", None, None, msg,
                                         start=origin, ended="limit" if limit else "failed"))
                notes.append(f"{d} sweep: {'contact' if limit else 'failed'} at "
                             f"{speed:.6g} rad/s ({origin} start); the sweep goes on from a "
                             "fresh start")
                state, restart = None, True
                continue
            start_of_run, origin, restart = origin, "previous", False
            tr, ctl = run_.trajectory, run_.control
            step = ctl.steps_per_period if ctl is not None else int(spp)
            state = (tr.q_final, tr.v_final)
            mc = classify(tr.poincare_q, tr.poincare_v, tr.q, tr.v,
                          2 * math.pi / speed / step, speed, first=2 * j,
                          n_record=rec * step)
            eps = None
            if clearance is not None and primary in out_nodes:
                eps = float(np.max(np.hypot(tr.q[:, 2 * j], tr.q[:, 2 * j + 1]))) / clearance
            points.append(SpeedPoint(
                d, speed, tr.poincare_t, tr.poincare_q.reshape(-1, nn, 2),
                tr.poincare_v.reshape(-1, nn, 2), mc.motion if mc else "unclassified",
                mc.evidence.get("n_distinct_poincare") if mc else None, eps,
                settled=bool(mc.evidence.get("settled", True)) if mc else True,
                start=start_of_run, steps_per_period=step,
                step_error=None if ctl is None else ctl.error,
                step_converged=None if ctl is None else ctl.converged))
    finally:
        bar.close()
    return BifurcationDiagramResult(points, out_nodes, ref, clearance, settings,
                                    time.perf_counter() - tic, name, notes,
                                    NodeNames.of(system.rotor))

