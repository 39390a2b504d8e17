"""Task kinds of a sweep: what runs at one grid point.

A task is a picklable callable ``task(config, values) -> PointOutput`` (``config`` with the
point's values set, ``values`` those values by dotted path, SI) with a ``spec`` string
that names it and its options (it enters the resume key). An exception raised by a task
marks the point failed with its reason; the sweep goes on.

``PointOutput.scalars`` become one column each of ``summary.csv`` and a variable over the
grid axes in ``sweep.nc`` (``None`` = missing: an empty CSV cell, the netCDF fill value);
``PointOutput.arrays`` are per-point arrays with named dims (lengths may differ between
points: ``sweep.nc`` pads them and stores the length as ``n_<dim>``).

Kinds (``make_task("name:key=value,...")``):

- ``response``: a continuation branch (:func:`rotorsfd.analyses.response.run_response`)
  with stability; ``ok`` when it reaches the end of its range or ends at an element's
  validity limit (``ended``: ``range``, ``limit``; ``incomplete`` when it stops early:
  ``stopped``, ``failed``); summary: how it ended, bifurcation counts by type, unstable
  intervals and their total width (in Omega~ when the parameter is the speed: the paper's
  Figure 19 quantity), the peak r~ per output node and where it occurs.
- ``simulate``: a time integration (:func:`rotorsfd.analyses.simulate.run_simulation`);
  summary: motion class, max eccentricity, Lyapunov exponent, max r~ per node; Poincare
  points of the SFD node.
- ``stability-chart``: a stability chart of the linear rotor
  (:func:`rotorsfd.analyses.stability_chart.run_stability_chart`) per grid point;
  summary: unstable share, max |mu| and where; arrays: the chart.
- ``synthetic``: a cheap deterministic function of the grid values, for tests (options
  ``delay`` [s], ``fail_above`` (fails when the first value exceeds it), ``log`` (a file
  that gets one line per execution)).
"""

from __future__ import annotations

import dataclasses
import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any, Protocol

import numpy as np

from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.io.config import get_path
from rotorsfd.io.schema import Config

Scalar = bool | int | float | str | None

#: The reported types counted per sweep case (``n_<type>``): the codim-1 bifurcations and
#: the branch points (typed on the HB equations, or untyped ``branch-point``: the
#: names of ``stability.branch_result.BRANCH_POINT_KINDS``, written out here because
#: importing ``rotorsfd.stability`` brings numba into the sweep's start-up; a test keeps
#: the two equal).
BIFURCATION_TYPES = ("saddle-node", "period-doubling", "secondary-hopf", "pitchfork",
                     "transcritical", "branch-point")


@dataclass(frozen=True)
class ArrayOut:
    """A per-point array with named dims (e.g. ``("branch_point",)``)."""

    dims: tuple[str, ...]
    data: np.ndarray


@dataclass
class PointOutput:
    """What a task returns for one grid point. ``status`` 'ok', or 'incomplete' when the
    data are valid but partial (e.g. a branch that stopped early; ``message`` says why)."""

    scalars: dict[str, Scalar] = field(default_factory=dict)
    arrays: dict[str, ArrayOut] = field(default_factory=dict)
    status: str = "ok"
    message: str = ""


class Task(Protocol):
    """``task(config, values) -> PointOutput``; ``spec`` names the task and its options."""

    spec: str

    def __call__(self, config: Config, values: Mapping[str, float]) -> PointOutput: ...


# ---- synthetic (tests) ----------------------------------------------------------------------


@dataclass(frozen=True)
class SyntheticTask:
    """A cheap deterministic task: from the grid values v_i (SI) it returns
    ``total = sum v_i``, ``echo_i`` = the config field at axis i (read back from
    ``config``, proving the grid set it), and a ragged curve of ``3 + (i mod 3)`` points
    ``curve[k] = total * (k + 1)``."""

    delay: float = 0.0
    fail_above: float | None = None
    log: str | None = None

    @property
    def spec(self) -> str:
        """Name and the options that change results (not ``delay`` or ``log``)."""
        if self.fail_above is None:
            return "synthetic"
        return f"synthetic:fail_above={self.fail_above!r}"

    def __call__(self, config: Config, values: Mapping[str, float]) -> PointOutput:
        if self.log:
            with open(self.log, "a") as fh:
                fh.write(repr(tuple(values.values())) + "\n")
        if self.delay:
            time.sleep(self.delay)
        v = list(values.values())
        if self.fail_above is not None and v and v[0] > self.fail_above:
            raise ConvergenceError(f"synthetic failure: {v[0]!r} > {self.fail_above!r}")
        total = float(sum(v))
        scalars: dict[str, Scalar] = {"total": total}
        for i, path in enumerate(values):
            scalars[f"echo_{i}"] = float(get_path(config, path))
        scalars["even"] = round(total * 1e6) % 2 == 0
        scalars["label"] = "big" if total > 1 else "small"
        n = 3 + round(abs(total) * 1e6) % 3
        curve = total * np.arange(1, n + 1, dtype=float)
        return PointOutput(scalars, {"curve": ArrayOut(("sample",), curve)})


# ---- response ------------------------------------------------------------------------------


def unstable_intervals(x: Sequence[float], stable: Sequence[bool],
                       max_multiplier: Sequence[float] | None = None,
                       bifurcations_x: Sequence[float] = (),
                       bifurcations_point: Sequence[int] | None = None
                       ) -> list[tuple[float, float]]:
    """Intervals of the parameter x covered by unstable parts of a branch, merged.

    Each run of consecutive unstable points spans its points' x and its two boundaries.
    A boundary lies between an unstable point i and its stable neighbour j: the linear
    estimate of where ``|mu|max = 1`` (the midpoint without multipliers), replaced by a
    located bifurcation (e.g. a fold's turning point): one whose ``point`` (the nearest
    computed point on its unstable side, as in the bifurcation table) is i, or, without
    that index, one within |x_i - x_j| of the estimate. Matched one-to-one, nearest
    pairs first.
    """
    x = np.asarray(x, dtype=float)
    unstable = ~np.asarray(stable, dtype=bool)
    mm = None if max_multiplier is None else np.asarray(max_multiplier, dtype=float)
    runs: list[tuple[int, int]] = []
    i = 0
    while i < x.size:
        if unstable[i]:
            j = i
            while j + 1 < x.size and unstable[j + 1]:
                j += 1
            runs.append((i, j))
            i = j + 1
        else:
            i += 1
    ends: list[tuple[int, float, float, int]] = []  # (run, estimate, tolerance, i)
    for r, (a, b) in enumerate(runs):
        for i, j in ((a, a - 1), (b, b + 1)):
            if 0 <= j < x.size:
                t = 0.5
                if mm is not None and mm[i] != mm[j]:
                    t = min(max((1.0 - mm[j]) / (mm[i] - mm[j]), 0.0), 1.0)
                ends.append((r, x[j] + t * (x[i] - x[j]), abs(x[i] - x[j]) * (1 + 1e-9), i))
    value = [e for _, e, _, _ in ends]
    where = list(bifurcations_point) if bifurcations_point is not None \
        else [-1] * len(bifurcations_x)

    def matches(k: int, m: int) -> bool:
        _, e, tol, i = ends[k]
        return where[m] == i if where[m] >= 0 else abs(bifurcations_x[m] - e) <= tol

    pairs = sorted((abs(bx - ends[k][1]), k, m) for k in range(len(ends))
                   for m, bx in enumerate(bifurcations_x) if matches(k, m))
    used_end: set[int] = set()
    used_bif: set[int] = set()
    for _, k, m in pairs:
        if k not in used_end and m not in used_bif:
            value[k] = float(bifurcations_x[m])
            used_end.add(k)
            used_bif.add(m)
    spans = []
    for r, (a, b) in enumerate(runs):
        pts = [*x[a:b + 1].tolist(), *(v for end, v in zip(ends, value, strict=True)
                                       if end[0] == r)]
        spans.append((float(min(pts)), float(max(pts))))
    merged: list[tuple[float, float]] = []
    for lo, hi in sorted(spans):
        if merged and lo <= merged[-1][1]:
            merged[-1] = (merged[-1][0], max(merged[-1][1], hi))
        else:
            merged.append((lo, hi))
    return merged


def intervals_text(intervals: Sequence[tuple[float, float]]) -> str:
    """``"1.02:1.08;1.2:1.25"`` (full precision), ``"none"`` for none."""
    return ";".join(f"{lo!r}:{hi!r}" for lo, hi in intervals) or "none"


@dataclass(frozen=True)
class ResponseTask:
    """A response branch with stability at each grid point (``[analysis.response]``,
    ``[analysis.stability]``); ``search_path`` is the config file's folder."""

    search_path: str | None = None

    spec = "response"

    def __call__(self, config: Config, values: Mapping[str, float]) -> PointOutput:
        # deferred: analyses.response (loads numba, scipy, threadpoolctl)
        from rotorsfd.analyses.response import run_response

        result = run_response(config, search_path=None if self.search_path is None
                              else Path(self.search_path), progress=False)
        out = response_output(result)
        if result.stable is None and not config.analysis.stability.enabled:
            out.message = "stability disabled (analysis.stability.enabled = false)"
        return out


def response_output(result: Any) -> PointOutput:
    """Summary scalars and per-point arrays of a ResponseResult (its documented fields:
    branch, reference_speed, nodes, is_speed, parameter, stable, max_multiplier,
    bifurcations, deflection(node), success, message, and ``ended`` if it has one)."""
    branch = result.branch
    if branch.n_points == 0:
        raise ConvergenceError(f"no converged point: {result.message}")
    if result.is_speed:
        x, x_name = np.asarray(result.speeds) / result.reference_speed, "speed_ratio"
    else:
        x, x_name = np.asarray(branch.lam, dtype=float), "parameter"
    sc: dict[str, Scalar] = {"branch_points": int(branch.n_points),
                             "folds": len(branch.folds()) if hasattr(branch, "folds")
                             else None}            # a torus branch: no fold test
    arrays: dict[str, ArrayOut] = {f"branch_{x_name}": ArrayOut(("branch_point",), x)}
    has_stability = result.stable is not None
    bifs = list(result.bifurcations or [])
    for kind in BIFURCATION_TYPES:
        sc[f"n_{kind.replace('-', '_')}"] = (sum(b["type"] == kind for b in bifs)
                                             if result.bifurcations is not None else None)
    if has_stability:
        stable = np.asarray(result.stable, dtype=bool)
        mm = None if result.max_multiplier is None else np.asarray(result.max_multiplier)
        bx = [float(b["speed_ratio"] if result.is_speed else b["parameter"]) for b in bifs]
        where = [int(b["point"]) for b in bifs] if all("point" in b for b in bifs) else None
        iv = unstable_intervals(x, stable, mm, bx, where)
        sc["n_unstable_points"] = int(np.sum(~stable))
        sc["unstable_intervals"] = intervals_text(iv)
        sc[f"unstable_width_{x_name}"] = float(sum(hi - lo for lo, hi in iv))
        arrays["branch_stable"] = ArrayOut(("branch_point",), stable.astype(np.int8))
        if mm is not None:
            arrays["branch_max_multiplier"] = ArrayOut(("branch_point",), mm.astype(float))
        arrays["unstable_start"] = ArrayOut(("interval",), np.array([a for a, _ in iv]))
        arrays["unstable_stop"] = ArrayOut(("interval",), np.array([b for _, b in iv]))
        if bifs:
            arrays["bifurcation_type"] = ArrayOut(("bifurcation",), np.array(
                [str(b["type"]) for b in bifs]))
            arrays[f"bifurcation_{x_name}"] = ArrayOut(("bifurcation",), np.array(bx))
    else:
        sc["n_unstable_points"] = None
        sc["unstable_intervals"] = None
        sc[f"unstable_width_{x_name}"] = None
    for node in result.nodes:
        r = np.asarray(result.deflection(node), dtype=float)
        i = int(np.argmax(r))
        sc[f"peak_defl_{node}"] = float(r[i])
        sc[f"peak_{x_name}_{node}"] = float(x[i])
        if has_stability:
            sc[f"peak_stable_{node}"] = bool(result.stable[i])
        arrays[f"branch_defl_{node}"] = ArrayOut(("branch_point",), r)
    # a branch that ends at a validity limit is a result (issue 22 item 3)
    ended = getattr(result, "ended", "range" if result.success else "failed")
    sc["ended"] = ended
    status = "ok" if ended in ("range", "limit") else "incomplete"
    message = "" if ended == "range" else " ".join(str(result.message).split())
    if not has_stability and ended == "range":
        message = "no stability data (analysis.stability)"
    return PointOutput(sc, arrays, status, message)


# ---- simulate ------------------------------------------------------------------------------


@dataclass(frozen=True)
class SimulateTask:
    """A time integration at each grid point (``[analysis.simulate]``, the same step
    control: ``steps_per_period = "auto"`` by default); summary: motion class, speed, max
    SFD eccentricity, largest Lyapunov exponent and its uncertainty, the accepted steps
    per period, the change of the last halving (``step_error``, in C) and whether it met
    ``step_tolerance`` (``step_converged``), max r~ per output node; arrays: the
    Poincare points (y, z) of the SFD node (or first output node)."""

    search_path: str | None = None

    spec = "simulate"

    def __call__(self, config: Config, values: Mapping[str, float]) -> PointOutput:
        # deferred: analyses.simulate (loads numba, scipy, threadpoolctl)
        from rotorsfd.analyses.simulate import run_simulation

        result = run_simulation(config, search_path=None if self.search_path is None
                                else Path(self.search_path), progress=False)
        return simulate_output(result)


def simulate_output(result: Any) -> PointOutput:
    """Summary scalars and Poincare arrays of a SimulationResult."""
    ly = result.lyapunov
    sc: dict[str, Scalar] = {
        "motion": str(result.motion_name), "speed_rad_s": float(result.speed),
        "speed_ratio": finite_or_none(None if result.speed_ratio is None
                                      else float(result.speed_ratio)),
        "max_eccentricity": finite_or_none(None if result.max_eccentricity is None
                                           else float(result.max_eccentricity)),
        "lyapunov_per_s": None if ly is None else finite_or_none(float(ly.exponent)),
        "lyapunov_uncertainty_per_s": None if ly is None
        else finite_or_none(float(ly.half_spread)),
        "steps_per_period": int(result.settings["steps_per_period"])}
    ctl = result.step_check
    if ctl is not None:
        sc["step_error"] = finite_or_none(ctl.error)
        sc["step_converged"] = bool(ctl.converged)
    for j, node in enumerate(result.nodes):
        r = np.sqrt(np.sum(np.asarray(result.q)[:, j, :2] ** 2, axis=-1)).max()
        sc[f"max_radius_{node}"] = float(r)
        if result.clearance:
            sc[f"max_defl_{node}"] = float(r / result.clearance)
    j = result.column(result.plot_node)
    pq = np.asarray(result.poincare_q)[:, j, :2]
    arrays = {"poincare_y": ArrayOut(("poincare",), pq[:, 0].astype(float)),
              "poincare_z": ArrayOut(("poincare",), pq[:, 1].astype(float))}
    return PointOutput(sc, arrays)


# ---- stability chart -----------------------------------------------------------------------


@dataclass(frozen=True)
class StabilityChartTask:
    """A stability chart of the linear rotor at each grid point
    (``[analysis.stability_chart]``, e.g. swept over the speed or a support stiffness);
    summary: unstable share and the largest multiplier with where it occurs; arrays: the
    chart (``max |mu|`` and stable flags over ``chart_x`` x ``chart_y``)."""

    search_path: str | None = None

    spec = "stability-chart"

    def __call__(self, config: Config, values: Mapping[str, float]) -> PointOutput:
        # deferred: analyses.stability_chart (loads numba, scipy, threadpoolctl)
        from rotorsfd.analyses.stability_chart import run_stability_chart

        result = run_stability_chart(config, progress=False, search_path=None
                                     if self.search_path is None else Path(self.search_path))
        return chart_output(result)


def chart_output(result: Any) -> PointOutput:
    """Summary scalars and arrays of a ChartResult (``chart.max_abs``, ``chart.stable``,
    axes ``x``, ``y`` with ``path`` and ``values``)."""
    m = np.asarray(result.chart.max_abs, dtype=float)
    stable = np.asarray(result.chart.stable, dtype=bool)
    i, j = np.unravel_index(int(np.argmax(m)), m.shape)
    x, y = result.x, result.y
    sc: dict[str, Scalar] = {
        "chart_x": x.path, "chart_y": y.path, "chart_points": int(m.size),
        "unstable_points": int((~stable).sum()),
        "unstable_fraction": float((~stable).mean()),
        "max_multiplier": float(m[i, j]),
        "max_at_x": float(x.values[i]), "max_at_y": float(y.values[j])}
    dims = ("chart_x", "chart_y")
    arrays = {"chart_x_value": ArrayOut(dims[:1], np.asarray(x.values, dtype=float)),
              "chart_y_value": ArrayOut(dims[1:], np.asarray(y.values, dtype=float)),
              "chart_max_multiplier": ArrayOut(dims, m),
              "chart_stable": ArrayOut(dims, stable.astype(np.int8))}
    return PointOutput(sc, arrays)


# ---- registry --------------------------------------------------------------------------------

TASKS: dict[str, Callable[..., Any]] = {
    "response": ResponseTask,
    "simulate": SimulateTask,
    "stability-chart": StabilityChartTask,
    "synthetic": SyntheticTask,
}
PLANNED: tuple[str, ...] = ()


def _option(text: str) -> Any:
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text


def make_task(spec: str, *, search_path: str | os.PathLike[str] | None = None) -> Task:
    """A task from ``"name"`` or ``"name:key=value,key=value"`` (ConfigError if unknown)."""
    name, _, rest = spec.strip().partition(":")
    if name in PLANNED:
        raise ConfigError("analysis.sweep.task", name, "not available yet; available: "
                          + ", ".join(TASKS))
    if name not in TASKS:
        raise ConfigError("analysis.sweep.task", name, "allowed: " + ", ".join(TASKS))
    opts: dict[str, Any] = {}
    for item in filter(None, (s.strip() for s in rest.split(","))):
        key, sep, value = item.partition("=")
        if not sep:
            raise ConfigError("--task", spec, "expected NAME:KEY=VALUE,... (options are "
                              "key=value, comma separated)")
        opts[key.strip()] = _option(value.strip())
    if name in ("response", "simulate", "stability-chart") and search_path is not None:
        opts.setdefault("search_path", str(search_path))
    kind = TASKS[name]
    known = [f.name for f in dataclasses.fields(kind) if f.name != "search_path"] \
        if dataclasses.is_dataclass(kind) else None
    for key in opts if known is not None else ():
        if key not in known and key != "search_path":
            raise ConfigError("--task", spec, f"the {name} task has no option {key!r}; it "
                              "takes " + (", ".join(known) if known else "no options"))
    try:
        return TASKS[name](**opts)
    except TypeError as exc:
        raise ConfigError("--task", spec, f"bad option: {exc}") from None


def finite_or_none(value: Any) -> Scalar:
    """Floats that are not finite become None (missing), never NaN in the outputs."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
