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
  with stability; summary: bifurcation counts by type, unstable intervals and their total
  width (in Omega~ when the parameter is the speed: the paper's Figure 19 quantity), the
  peak r~ per output node and where it occurs.
- ``synthetic``: a cheap deterministic function of the grid values, for tests (options
  ``delay`` [s], ``fail_above`` (fails when the first value exceeds it), ``log`` (a file
  that gets one line per execution)).
"""

from __future__ import annotations

import math
import os
import time
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np

from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.io.schema import Config

Scalar = bool | int | float | str | None

BIFURCATION_TYPES = ("saddle-node", "period-doubling", "secondary-hopf")


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
        from rotorsfd.io.config import get_path

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
                       bifurcations_x: Sequence[float] = ()) -> list[tuple[float, float]]:
    """Intervals of the parameter x covered by unstable parts of a branch, merged.

    Each run of consecutive unstable points spans its points' x and its two boundaries;
    a boundary lies between an unstable point and its stable neighbour: the located
    bifurcation nearest to the linear estimate where ``|mu|max = 1`` (taken when it lies
    within one point spacing of it, e.g. a fold's turning point), else that estimate.
    """
    x = np.asarray(x, dtype=float)
    unstable = ~np.asarray(stable, dtype=bool)
    mm = None if max_multiplier is None else np.asarray(max_multiplier, dtype=float)
    bx = np.asarray(list(bifurcations_x), dtype=float)

    def boundary(i: int, j: int) -> float:  # i unstable, j its stable neighbour
        est = x[j] + 0.5 * (x[i] - x[j])
        if mm is not None and mm[i] != mm[j]:
            t = min(max((1.0 - mm[j]) / (mm[i] - mm[j]), 0.0), 1.0)
            est = x[j] + t * (x[i] - x[j])
        if bx.size:
            k = int(np.argmin(np.abs(bx - est)))
            if abs(bx[k] - est) <= abs(x[i] - x[j]) * (1 + 1e-9):
                return float(bx[k])
        return float(est)

    spans = []
    n = x.size
    i = 0
    while i < n:
        if not unstable[i]:
            i += 1
            continue
        j = i
        while j + 1 < n and unstable[j + 1]:
            j += 1
        pts = list(x[i:j + 1])
        if i > 0:
            pts.append(boundary(i, i - 1))
        if j + 1 < n:
            pts.append(boundary(j, j + 1))
        spans.append((min(pts), max(pts)))
        i = j + 1
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
        from pathlib import Path

        from rotorsfd.analyses.response import run_response

        result = run_response(config, search_path=None if self.search_path is None
                              else Path(self.search_path), progress=False)
        return response_output(result)


def response_output(result: Any) -> PointOutput:
    """Summary scalars and per-point arrays of a ResponseResult (its documented fields:
    branch, reference_speed, nodes, is_speed, parameter, stable, max_multiplier,
    bifurcations, deflection(node), success, message)."""
    branch = result.branch
    if branch.n_points == 0:
        raise ConvergenceError(f"no converged point: {result.message}")
    if result.is_speed:
        x, x_name = np.asarray(result.speeds) / result.reference_speed, "speed_ratio"
    else:
        x, x_name = np.asarray(branch.lam, dtype=float), "parameter"
    sc: dict[str, Scalar] = {"branch_points": int(branch.n_points),
                             "folds": len(branch.folds())}
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
        iv = unstable_intervals(x, stable, mm, bx)
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
    status = "ok" if result.success else "incomplete"
    message = "" if result.success else " ".join(str(result.message).split())
    if not has_stability and result.success:
        message = "no stability data (analysis.stability)"
    return PointOutput(sc, arrays, status, message)


# ---- registry --------------------------------------------------------------------------------

TASKS: dict[str, Callable[..., Any]] = {
    "response": ResponseTask,
    "synthetic": SyntheticTask,
}
PLANNED = ("simulate", "stability-chart")


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
            raise ConfigError("--task", spec, "options are key=value, comma separated")
        opts[key.strip()] = _option(value.strip())
    if name == "response" and search_path is not None:
        opts.setdefault("search_path", str(search_path))
    try:
        return TASKS[name](**opts)
    except TypeError as exc:
        raise ConfigError("--task", spec, f"bad option: {exc}") from None


def finite_or_none(value: Any) -> Scalar:
    """Floats that are not finite become None (missing), never NaN in the outputs."""
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value
