"""Boundary of the bistable speed range as a curve: saddle-nodes of the speed response
continued in a second parameter (base pitching rate, unbalance, ...), with their cusp.

From the speed branch at ``range2[0]`` (HB-AFT, condensed), every saddle-node (turning
point ``dOmega/ds = 0``) is located and continued in (Omega, lam2) by the fold-augmented
system of :mod:`rotorsfd.continuation.folds` on the condensed HB residual of
:mod:`rotorsfd.harmonic.fold_curve`::

    R(xs, Omega, lam2) = 0,     g(xs, Omega, lam2) = 0     (g: bordered test function),

with exact ``dR/dOmega`` and ``dR/dlam2`` (:meth:`RotorSystem.two_parameter_problem`).
Between the two folds of a pair the middle (saddle) branch is unstable and the response
bistable; the unstable width at lam2 is the distance in Omega~ between the two fold
branches (the paper's Figure 19). Where the pair meets, the curve turns back in lam2:
a cusp, beyond which the bistability has vanished. Each turn starts a new ``segment``.

Per point: ``speed_rad_s``, ``speed_ratio`` = Omega / Omega_ref, the second parameter,
``max_eps`` = the largest validity measure of the elements over the orbit (an SFD's
eccentricity ratio |q - o| / C), ``aliasing`` (the sampling error of N_f in the
units of the Newton test: the change of the scaled residual if N_f doubled,
:meth:`TwoParameterHB.sampling_error
<rotorsfd.harmonic.fold_curve.TwoParameterHB.sampling_error>`, the criterion of
``continue_periodic``'s adaptive N_f rule) and ``amp_<n>_m`` = max_t sqrt(y^2 + z^2) [m]
at each output node.
"""

from __future__ import annotations

import dataclasses
import re
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.context import RunContext
from rotorsfd.analyses.response_inputs import TwoParameterInputs
from rotorsfd.analyses.response_words import PARAMETER_UNITS, column_slug, system_parameter
from rotorsfd.continuation.folds import FoldBranch, FoldOptions, locate_branch_fold
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.harmonic.fold_curve import TwoParameterHB, needed_n_samples, trace_fold_curves
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.harmonic.synthesis import max_radius, orbit_samples
from rotorsfd.harmonic.truncation import pad_harmonics
from rotorsfd.io import atomic
from rotorsfd.model import dofs
from rotorsfd.model.system import RotorSystem

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from rotorsfd.io.schema import Config, ResponseAnalysis

FloatArray = NDArray[np.float64]


@dataclass
class CuspPoint:
    """Where a fold pair meets (the bistability vanishes)."""

    speed_rad_s: float
    speed_ratio: float
    value: float            #: second parameter (SI)
    max_eps: float


@dataclass
class FoldCurve:
    """Fold curve(s) in (speed, second parameter); see the module docstring.

    ``curves`` the continued :class:`~rotorsfd.continuation.folds.FoldBranch` objects
    (one per saddle-node of the start branch not reached by an earlier curve);
    ``start_folds`` the speeds [rad/s] of the saddle-nodes of the speed branch at
    ``range2[0]``; ``table`` the per-point columns.
    """

    parameter: str
    range2: tuple[float, float]
    reference_speed: float
    H: int
    n_samples: int
    nodes: tuple[int, ...]
    start_folds: list[float]
    curves: list[FoldBranch] = field(repr=False)
    hb: TwoParameterHB = field(repr=False)
    table: dict[str, FloatArray] = field(repr=False)
    cusps: list[CuspPoint]
    success: bool
    message: str
    timings: dict[str, float] = field(default_factory=dict)
    title: str = ""             # the configuration's title (the figure's by default)

    FILES = ("fold_curve.csv", "fold_curve.json", "fold_curve.png")

    @property
    def units(self) -> str:
        return PARAMETER_UNITS[self.parameter]

    @property
    def value_column(self) -> str:
        """CSV column of the second parameter, e.g. ``base_pitching_rad_s``."""
        return f"{column_slug(self.parameter)}_{column_slug(self.units)}"

    @property
    def bistability_end(self) -> float | None:
        """Second-parameter value where the last fold pair meets: the extreme cusp in the
        direction of the range, when every curve came back to ``range2[0]``; None when
        a fold reaches ``range2[1]`` (the bistability persists) or there is no cusp."""
        v = self.table[self.value_column]
        span = self.range2[1] - self.range2[0]
        if not self.cusps or np.any(np.abs(v - self.range2[1]) <= 1e-9 * abs(span)):
            return None
        values = [c.value for c in self.cusps]
        return float(max(values) if span > 0 else min(values))

    def speeds_at(self, value: float) -> FloatArray:
        """Fold speeds [rad/s] at second-parameter ``value`` (SI), sorted, re-solved on
        the curves by Newton at fixed value (exact to the solver tolerance)."""
        out: list[float] = []
        for c in self.curves:
            for z in c.solve_at(value / self.hb.scales[1]):
                out.append(self.hb.from_z(z)[1])
        return np.unique(np.round(np.array(out), 9))

    def envelope(self, values: Sequence[float] | FloatArray
                 ) -> tuple[FloatArray, FloatArray, NDArray[np.int64]]:
        """(lowest, highest fold speed in Omega~, number of fold branches) at each value,
        by linear interpolation along each segment (NaN where there is none)."""
        values = np.atleast_1d(np.asarray(values, dtype=float))
        lo = np.full(values.size, np.inf)
        hi = np.full(values.size, -np.inf)
        count = np.zeros(values.size, dtype=np.int64)
        t = self.table
        key = np.stack([t["curve"], t["segment"]], axis=1)
        for c, s in np.unique(key, axis=0):
            sel = (t["curve"] == c) & (t["segment"] == s)
            v, r = t[self.value_column][sel], t["speed_ratio"][sel]
            order = np.argsort(v)
            v, r = v[order], r[order]
            inside = (values >= v[0]) & (values <= v[-1])
            ri = np.interp(values, v, r)
            lo = np.where(inside, np.minimum(lo, ri), lo)
            hi = np.where(inside, np.maximum(hi, ri), hi)
            count += inside
        none = count == 0
        lo[none], hi[none] = np.nan, np.nan
        return lo, hi, count

    def unstable_width(self, values: Sequence[float] | FloatArray) -> FloatArray:
        """Distance in Omega~ between the outermost fold branches at each value (0 where
        fewer than two), by linear interpolation (:meth:`envelope`; exact fold speeds at
        a value: :meth:`speeds_at`)."""
        lo, hi, count = self.envelope(values)
        return np.where(count >= 2, hi - lo, 0.0)

    # ---- files -------------------------------------------------------------------------
    def rows(self) -> tuple[list[str], list[tuple]]:
        cols = list(self.table)
        n = len(self.table["speed_rad_s"])
        return cols, [tuple(self.table[c][i].item() for c in cols) for i in range(n)]

    def summary(self) -> str:
        unit = "" if self.units == "1" else f" {self.units}"
        message = re.sub(r"lam=(\S+?)(;|$)", lambda m: f"{self.parameter} = "
                         f"{float(m.group(1)):.6g}{unit}{m.group(2)}", self.message)
        lines = [f"fold curve in (speed, {self.parameter}) over {self.range2[0]:g} .. "
                 f"{self.range2[1]:g}{unit}, H = {self.H}, N_f = {self.n_samples}: "
                 f"{len(self.table['speed_rad_s'])} points (aliasing <= "
                 f"{np.max(self.table['aliasing']):.1g}), {message}",
                 "saddle-nodes at the start: " + ", ".join(
                     f"Omega~ = {w / self.reference_speed:.5f}" for w in self.start_folds)]
        for c in self.cusps:
            lines.append(f"cusp (a fold pair meets): {self.parameter} = {c.value:.6g}"
                         f"{unit} at Omega~ = {c.speed_ratio:.5f} "
                         f"({c.speed_rad_s:.2f} rad/s), eccentricity {c.max_eps:.3f}")
        end = self.bistability_end
        if end is not None:
            lines.append(f"bistability vanishes at {self.parameter} = {end:.6g}{unit}")
        if not self.cusps:
            lines.append(f"no cusp in the range: the fold pair persists up to "
                         f"{self.range2[1]:g}{unit}")
        lines.append("time: " + ", ".join(f"{k} {v:.2f} s" for k, v in self.timings.items()))
        return "\n".join(lines)

    def to_json(self) -> dict[str, Any]:
        return {"parameter": self.parameter, "units": self.units,
                "range": list(self.range2), "reference_speed_rad_s": self.reference_speed,
                "harmonics": self.H, "n_samples": self.n_samples,
                "start_folds_rad_s": self.start_folds,
                "cusps": [vars(c) for c in self.cusps],
                "bistability_end": self.bistability_end, "success": self.success,
                "message": self.message, "timings_s": self.timings}

    def to_dataset(self) -> xr.Dataset:
        """The table on the ``point`` dimension (units and long names), the start
        saddle-nodes and the cusps; the settings as attributes."""
        ds = curves_dataset(self.table, self.parameter, self.units, self.value_column)
        ds.coords["start_fold"] = ("start_fold", np.asarray(self.start_folds, float),
                                   {"long_name": "saddle-node speed of the branch at the "
                                    "start value", "units": "rad/s"})
        cusps = {"cusp_speed": ([c.speed_rad_s for c in self.cusps], "rad/s",
                                "speed of the cusp"),
                 "cusp_speed_ratio": ([c.speed_ratio for c in self.cusps], "1",
                                      "speed of the cusp / reference speed"),
                 "cusp_value": ([c.value for c in self.cusps], self.units,
                                f"{self.parameter} at the cusp"),
                 "cusp_max_eps": ([c.max_eps for c in self.cusps], "1",
                                  "largest validity measure of the elements at the cusp")}
        for key, (values, unit, words) in cusps.items():
            ds[key] = ("cusp", np.asarray(values, float), {"long_name": words,
                                                            "units": unit})
        end = self.bistability_end
        ds.attrs.update(reference_speed_rad_s=self.reference_speed, harmonics=self.H,
                        n_samples=self.n_samples, range=np.asarray(self.range2, float),
                        bistability_end=np.nan if end is None else end,
                        success=int(self.success), message=self.message,
                        run_title=self.title)
        return ds

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """``fold_curve.csv`` (one row per point), ``fold_curve.json`` (cusps, start
        folds, timings), ``fold_curve.png`` (with ``plots``); atomically."""
        out = Path(directory)
        cols, rows = self.rows()
        paths = {"fold_curve.csv": atomic.write_csv(out / "fold_curve.csv", cols, rows),
                 "fold_curve.json": atomic.write_json(out / "fold_curve.json",
                                                      self.to_json())}
        if plots:
            paths.update(atomic.save_figures(self.plot(), out))
        return paths

    def plot(self) -> dict[str, Figure]:
        """``fold_curve.png``: Omega~ of the folds against the second parameter (bistable
        region shaded, cusps marked) and the unstable width (the paper's Figure 19),
        titled by :attr:`title`, through :func:`rotorsfd.plots.fold.fold_curve_figure`."""
        # deferred: plots.fold (loads matplotlib)
        from rotorsfd.plots.fold import fold_curve_figure

        t = self.table
        grid = np.linspace(min(self.range2), max(self.range2), 401)
        lo, hi, count = self.envelope(grid)
        return {"fold_curve.png": fold_curve_figure(
            t[self.value_column], t["speed_ratio"], t["curve"], grid=grid, lo=lo, hi=hi,
            count=count, cusps=[(c.value, c.speed_ratio) for c in self.cusps],
            parameter=self.parameter, units=self.units, H=self.H, title=self.title)}


#: units and long names of the columns of a curve table (``amp_<n>_m``: metres)
COLUMNS = {"curve": ("1", "curve number (per kind)"),
           "segment": ("1", "turns in the second parameter passed"),
           "s": ("1", "arc length along the curve (scaled variables)"),
           "speed_rad_s": ("rad/s", "rotor speed Omega"),
           "speed_ratio": ("1", "Omega / Omega_ref"),
           "max_eps": ("1", "largest validity measure of the elements over the orbit"),
           "aliasing": ("1", "change of the scaled residual if N_f doubled"),
           "kind": ("", "bifurcation: saddle-node, period-doubling or Neimark-Sacker")}


def curves_dataset(table: dict[str, NDArray], parameter: str, units: str,
                   value_column: str) -> xr.Dataset:
    """A curve table as a Dataset on ``point``, each column with its units and long
    name (:data:`COLUMNS`; the second parameter ``value_column`` in ``units``)."""
    # deferred: xarray is heavy (loaded only when this runs)
    import xarray as xr

    ds = xr.Dataset(attrs={"parameter": parameter, "units": units})
    for key, values in table.items():
        if key == value_column:
            unit, words = units, parameter
        elif key.startswith("amp_"):
            unit, words = "m", f"largest radius over the period at node {key[4:-2]}"
        else:
            unit, words = COLUMNS.get(key, ("", key))
        data = np.asarray(values, dtype=str) if key == "kind" else np.asarray(values)
        ds[key] = ("point", data, {"long_name": words, "units": unit})
    return ds


def _table(hb: TwoParameterHB, curves: list[FoldBranch], system: RotorSystem,
           ref: float, nodes: Sequence[int], value_column: str) -> dict[str, FloatArray]:
    cols: dict[str, list] = {k: [] for k in ("curve", "segment", "s", value_column,
                                              "speed_rad_s", "speed_ratio",
                                              "max_eps", "aliasing")}
    amp: dict[int, list] = {n: [] for n in nodes}
    el = system.elements
    for k, c in enumerate(curves):
        for z, seg, s in zip(c.z, c.segment, c.s, strict=True):
            _, speed, value = hb.from_z(z)
            X = hb.coefficients(z)
            cols["curve"].append(k)
            cols["segment"].append(int(seg))
            cols["s"].append(float(s))
            cols[value_column].append(value)
            cols["speed_rad_s"].append(speed)
            cols["speed_ratio"].append(speed / ref)
            cols["max_eps"].append(el.limit(orbit_samples(X[:, el.nl_dofs])[0]))
            cols["aliasing"].append(hb.sampling_error(z, hb.N))
            for n in nodes:
                iy, iz = dofs.dof_index(n, "y"), dofs.dof_index(n, "z")
                amp[n].append(float(max_radius(X[:, iy], X[:, iz])))
    out = {k: np.asarray(v, dtype=np.int64 if k in ("curve", "segment") else float)
           for k, v in cols.items()}
    for n in nodes:
        out[f"amp_{n}_m"] = np.asarray(amp[n])
    return out


def fold_curve(system: RotorSystem, speed_range: tuple[float, float], second_parameter: str,
               range2: tuple[float, float], H: int | None = 3, *,
               reference_speed: float | None = None, n_samples: int | None = None,
               nodes: Sequence[int] | None = None, options: FoldOptions | None = None,
               branch_options: dict[str, Any] | None = None,
               alias_tol: float | None = None, n_samples_max: int = 1024) -> FoldCurve:
    """Continue the saddle-nodes of the speed response in ``second_parameter``.

    ``speed_range`` (rad/s) of the speed branch computed at ``range2[0]``; its
    saddle-nodes are located and continued from ``range2[0]`` towards ``range2[1]``
    (SI; a RotorSystem parameter such as ``"base.pitching"`` or a config path such as
    ``"base.pitching.value"``). ``n_samples`` N_f (default: that of the speed branch);
    ``options`` the fold-curve steps; ``branch_options`` go to ``continue_periodic``.
    N_f: with ``n_samples=None``, the curves start with the largest N_f the speed
    branch's adaptive rule used at the points around its saddle-nodes; the criterion is
    that of the adaptive rule (one function:
    :meth:`~rotorsfd.harmonic.condensation.CondensedHB.sampling_error`): if the change of
    the scaled residual when N_f doubles exceeds ``alias_tol`` (default: the fold
    continuation's Newton tolerance ``options.tol``) at some point of the curves, N_f
    becomes the smallest power of two (up to ``n_samples_max``) that meets it at every
    point and the curves are traced again.
    ``H=None``: the speed branch chooses H along itself (``adaptive_harmonics``, the
    truncation tolerance of ``branch_options`` or the default) and the curves use the
    largest H it needed at the points around its saddle-nodes.
    ConfigError if the speed branch at ``range2[0]`` has no saddle-node; ConvergenceError
    if it stops (e.g. journal contact) before any.
    """
    param = system_parameter(second_parameter)
    if param == "speed":
        raise ConfigError("--parameter", second_parameter,
                          "the second parameter must differ from the speed")
    if range2[0] == range2[1]:
        raise ConfigError("--to", range2[1], "must differ from --from (the start value)")
    ref = RunContext(reference_speed).reference(system)   # an empty configuration's bound
    out_nodes = tuple(nodes) if nodes else system.output_nodes
    family = system.two_parameter_problem(param)
    t0 = time.perf_counter()
    bopts = dict(branch_options or {})
    if H is None:
        bopts["adaptive_harmonics"] = True
    branch = continue_periodic(family.first(range2[0]), speed_range[0], speed_range[1],
                               3 if H is None else H, n_samples=n_samples, **bopts)
    folds = [locate_branch_fold(branch, int(i)) for i in branch.folds()]
    if H is None:   # the largest H the branch needed around its saddle-nodes
        Hb = branch.info["harmonics"]
        H = int(max([Hb[min(int(i) + k, len(Hb) - 1)] for i in branch.folds()
                     for k in (0, 1)], default=3))
        m = family.first(range2[0]).m
        folds = [dataclasses.replace(p, xs=pad_harmonics(np.reshape(p.xs, (-1, m)),
                                                          H).ravel()) for p in folds]
    t1 = time.perf_counter()
    if not folds and not branch.success:
        raise ConvergenceError(
            f"the speed branch at {param} = {range2[0]:g} stopped before any saddle-node: "
            f"{branch.message}")
    if not folds:
        raise ConfigError("--from", range2[0],
                          f"the speed branch at {param} = {range2[0]:g} has no saddle-node "
                          f"in {speed_range[0]:.6g} .. {speed_range[1]:.6g} rad/s "
                          f"({branch.message}); start where the response is bistable")
    if n_samples:
        N = n_samples
    else:   # what the speed branch's adaptive rule chose around its saddle-nodes
        Nb = branch.info["n_samples"]
        N = int(max(Nb[min(int(i) + k, len(Nb) - 1)] for i in branch.folds() for k in (0, 1)))
    if alias_tol is None:
        alias_tol = (options or FoldOptions()).tol
    scales = (abs(speed_range[1] - speed_range[0]), abs(range2[1] - range2[0]))
    while True:
        hb, curves, messages = trace_fold_curves(family, H, N, scales, folds, range2, options)
        if n_samples is not None or N >= n_samples_max:
            break
        N_new = needed_n_samples(hb, curves, alias_tol, n_samples_max)
        if N_new <= N:
            break
        N = N_new
    t2 = time.perf_counter()
    col = f"{column_slug(param)}_{column_slug(PARAMETER_UNITS[param])}"
    table = _table(hb, curves, system, ref, out_nodes, col)
    cusps = []
    for c in curves:
        for cp in c.cusps:
            _, speed, value = hb.from_z(cp.z)
            X = hb.coefficients(cp.z)
            el = system.elements
            ecc = el.limit(orbit_samples(X[:, el.nl_dofs])[0])
            cusps.append(CuspPoint(speed, speed / ref, value, ecc))
    success = all(c.success for c in curves)
    timings = {"speed_branch": t1 - t0, "fold_curve": t2 - t1,
               "total": time.perf_counter() - t0}
    return FoldCurve(param, (float(range2[0]), float(range2[1])), ref, H, N, out_nodes,
                     [float(p.lam) for p in folds], curves, hb, table, cusps, success,
                     "; ".join(messages), timings)


def run_fold_curve(config_or_system: Config | RotorSystem, parameter: str, start: Any,
                   stop: Any, settings: ResponseAnalysis | None = None, *,
                   context: RunContext | None = None, search_path: Path | None = None,
                   harmonics: int | None = None,
                   options: FoldOptions | None = None) -> FoldCurve:
    """:func:`fold_curve` with the speed range, H ('auto': the speed branch chooses),
    output nodes of ``[analysis.response]`` and Omega_ref, title of the context.

    ``parameter`` a config path (``base.pitching.value``, ``unbalance[0].magnitude``,
    ...) or parameter name and ``start, stop`` its range (SI numbers or strings with
    units). From a :class:`RotorSystem`: ``settings`` (default: the context's,
    ``ResponseAnalysis()``) and ``context`` (default ``RunContext()``); from a Config:
    its system (one ``build``), section and context, through the same
    :meth:`TwoParameterInputs.from_system`."""
    inputs = TwoParameterInputs.resolve(config_or_system, parameter, start, stop, settings,
                                        context, "the fold curve needs", search_path)
    r = inputs.response
    H = harmonics or (None if r.adaptive_harmonics else r.start_harmonics)
    result = fold_curve(inputs.system, inputs.speed_range, inputs.param, inputs.range2, H,
                        reference_speed=inputs.reference_speed, nodes=inputs.nodes,
                        options=options)
    result.title = inputs.title
    return result
