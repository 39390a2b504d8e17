"""Fold, period-doubling and Neimark-Sacker curves of the speed response in (speed, lam2).

From the speed branch at ``range2[0]`` (HB-AFT, condensed, H harmonics) with its Floquet
stability (:func:`~rotorsfd.stability.branch_stability.branch_stability`):

- every located saddle-node is continued in (Omega, lam2) as a fold curve by
  :func:`rotorsfd.analyses.fold_curve.fold_curve` (the bordered test function on the HB
  Jacobian; turns in lam2 are cusps, where a fold pair meets);
- every located period doubling (a Floquet multiplier through -1) is continued as a
  period-doubling curve by :func:`rotorsfd.harmonic.pd_curve.continue_period_doublings`:
  the bordered test function on the odd-harmonic block of the HB Jacobian in harmonics of
  Omega/2, ``H2 = harmonics_factor * H`` of them (default 4 H, i.e. 2 H harmonics of
  Omega in the period-1 part: the 4H default of period-2 branch switching), with
  ``harmonics_factor * N_f`` AFT samples per period 2T. A turn of the curve in lam2 is
  where the two flips of a pair meet (beyond it no period doubling at that lam2).

- every located secondary Hopf (a multiplier pair through the unit circle at
  ``exp(+-i sigma T)``) is continued as a Neimark-Sacker curve by
  :func:`rotorsfd.harmonic.ns_curve.continue_neimark_sacker` (the shifted Hill operator,
  harmonics ``k Omega + sigma``, with K = H2 / 2 pairs: at sigma = Omega/2 the PD test's
  block); it ends where theta = sigma / Omega reaches 1/2 or 0 (the pair meets at -1
  or +1: a 1:2 or 1:1 resonance), located there.

Codimension-2 points where the curves meet (:mod:`rotorsfd.analyses.bifurcation_points`,
:mod:`rotorsfd.harmonic.codim2`): cusps, 1:1 and 1:2 resonances, fold-flip,
fold-Neimark-Sacker and flip-Neimark-Sacker points, each detected by a test function of
the Floquet multipliers along a curve (the stability options of the speed branch) and
located along the curve to 1e-9 of the ranges (not to the step); ``codim2`` lists them,
the summary and ``summary.json`` name them, the chart marks them.

A PD curve that passes ``range2[0]`` again at another located period doubling of the start
branch covers it (it is not continued twice), as for the fold curves.

Table (``curves.csv`` / ``curves.nc``), one row per point: ``kind`` ("saddle-node",
"period-doubling" or "Neimark-Sacker"), ``curve`` (numbered per kind), ``segment`` (turns
passed), ``s``, the second parameter, ``speed_rad_s``, ``speed_ratio`` = Omega /
Omega_ref, ``max_eps`` (the elements' largest validity measure over the orbit, over 2T for a flip),
``aliasing`` (the change of the scaled residual if N_f doubled) and ``amp_<n>_m``.
"""

from __future__ import annotations

import dataclasses
import re
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.bifurcation_points import Codim2Record, codim2_records
from rotorsfd.analyses.context import RunContext
from rotorsfd.analyses.fold_curve import FoldCurve, curves_dataset, fold_curve
from rotorsfd.analyses.modal import first_critical
from rotorsfd.analyses.response_inputs import TwoParameterInputs, stability_settings
from rotorsfd.analyses.response_words import PARAMETER_UNITS, column_slug, system_parameter
from rotorsfd.continuation.folds import FoldBranch, FoldOptions
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.harmonic.fold_curve import TwoParameterHB
from rotorsfd.harmonic.ns_curve import continue_neimark_sacker
from rotorsfd.harmonic.pd_curve import continue_period_doublings
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.harmonic.synthesis import max_radius, orbit_samples
from rotorsfd.io import atomic
from rotorsfd.model import dofs
from rotorsfd.model.system import RotorSystem
from rotorsfd.stability.bifurcation_check import checks_as_configured
from rotorsfd.stability.branch_stability import StabilityOptions, branch_stability, reported_kind

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from rotorsfd.io.schema import Config, ResponseAnalysis

FloatArray = NDArray[np.float64]

KINDS = ("saddle-node", "period-doubling", "Neimark-Sacker")

THETA_END = 1e-6
"""A Neimark-Sacker curve that did not end at its theta = 1/2 event (located) is cut at
the first point with theta = sigma / w > 1/2 - THETA_END: at theta = 1/2 the shifted Hill
operator is the period-doubling test's block, so every point of the PD curve solves the
NS equations too and the continuation could slide along it."""


@dataclass
class TurningPoint:
    """A turn of a curve in the second parameter (where the pair of its kind meets)."""

    #: "saddle-node" (a cusp), "period-doubling" or "Neimark-Sacker"
    kind: str
    speed_rad_s: float
    speed_ratio: float
    value: float            #: second parameter (SI)


@dataclass
class BifurcationCurves:
    """Fold and period-doubling curves in (speed, second parameter); module docstring."""

    parameter: str
    range2: tuple[float, float]
    reference_speed: float
    H: int
    H2: int
    n_samples_pd: int
    start_folds: list[float]
    start_period_doublings: list[float]
    table: dict[str, NDArray] = field(repr=False)
    turns: list[TurningPoint]
    fold: FoldCurve | None = field(repr=False)
    pd_hb: TwoParameterHB | None = field(repr=False)
    pd_curves: list[FoldBranch] = field(repr=False)
    ns_hb: TwoParameterHB | None = field(default=None, repr=False)
    ns_curves: list[FoldBranch] = field(default_factory=list, repr=False)
    start_secondary_hopfs: list[float] = field(default_factory=list)
    codim2: list[Codim2Record] = field(default_factory=list)
    success: bool = True
    message: str = ""
    timings: dict[str, float] = field(default_factory=dict)
    title: str = ""

    FILES = ("curves.csv", "curves.nc", "summary.json", "curves.png")

    @property
    def units(self) -> str:
        return PARAMETER_UNITS[self.parameter]

    @property
    def value_column(self) -> str:
        return f"{column_slug(self.parameter)}_{column_slug(self.units)}"

    def speeds_at(self, kind: str, value: float) -> FloatArray:
        """Speeds [rad/s] of the curves of ``kind`` at second-parameter ``value`` (SI),
        re-solved by Newton at fixed value, sorted, duplicates merged."""
        if kind == "saddle-node":
            return self.fold.speeds_at(value) if self.fold else np.zeros(0)
        hb, curves = ((self.pd_hb, self.pd_curves) if kind == "period-doubling"
                      else (self.ns_hb, self.ns_curves))
        out = []
        for c in curves:
            assert hb is not None
            for z in c.solve_at(value / hb.scales[1]):
                out.append(hb.from_z(c.system.embed(z))[1])
        return np.unique(np.round(np.array(out, dtype=float), 9))

    # ---- files -------------------------------------------------------------------------
    def summary(self) -> str:
        unit = "" if self.units == "1" else f" {self.units}"
        n = {k: int(np.sum(self.table["kind"] == k)) for k in KINDS}
        message = re.sub(r"lam=(\S+?)(;|$)", lambda m: f"{self.parameter} = "
                         f"{float(m.group(1)):.6g}{unit}{m.group(2)}", self.message)
        lines = [f"bifurcation curves in (speed, {self.parameter}) over {self.range2[0]:g} "
                 f".. {self.range2[1]:g}{unit}, H = {self.H} (period doubling: H2 = "
                 f"{self.H2} harmonics of Omega/2, N_f = {self.n_samples_pd}): "
                 f"{n['saddle-node']} saddle-node points, {n['period-doubling']} "
                 f"period-doubling points, {n['Neimark-Sacker']} Neimark-Sacker points; "
                 f"{message}",
                 "at the start: saddle-nodes " + (", ".join(
                     f"{w:.6g}" for w in self.start_folds) or "none") + " rad/s; "
                 "period doublings " + (", ".join(
                     f"{w:.6g}" for w in self.start_period_doublings) or "none") + " rad/s; "
                 "secondary Hopf " + (", ".join(
                     f"{w:.6g}" for w in self.start_secondary_hopfs) or "none") + " rad/s"]
        for t in self.turns:
            lines.append(f"{t.kind} curve turns at {self.parameter} = {t.value:.6g}{unit}, "
                         f"Omega~ = {t.speed_ratio:.5f} ({t.speed_rad_s:.2f} rad/s)")
        for c in self.codim2:
            lines.append(f"{c.type} ({c.meaning}) at {self.parameter} = {c.value:.7g}"
                         f"{unit}, Omega~ = {c.speed_ratio:.6f} ({c.speed_rad_s:.4f} "
                         f"rad/s), on the {c.curve} curve; test: {c.test}")
        if not self.codim2:
            lines.append("no codimension-2 point on the curves")
        lines.append("time: " + ", ".join(f"{k} {v:.2f} s" for k, v in self.timings.items()))
        return "\n".join(lines)

    def to_json(self) -> dict[str, Any]:
        return {"parameter": self.parameter, "units": self.units,
                "range": list(self.range2), "reference_speed_rad_s": self.reference_speed,
                "harmonics": self.H, "period_doubling_harmonics_of_half_speed": self.H2,
                "period_doubling_n_samples": self.n_samples_pd,
                "fold_n_samples": self.fold.n_samples if self.fold else None,
                "start_saddle_nodes_rad_s": self.start_folds,
                "start_period_doublings_rad_s": self.start_period_doublings,
                "start_secondary_hopfs_rad_s": self.start_secondary_hopfs,
                "turning_points": [vars(t) for t in self.turns],
                "codim2_points": [{**vars(c), "meaning": c.meaning} for c in self.codim2],
                "success": self.success, "message": self.message,
                "timings_s": self.timings}

    def to_dataset(self) -> xr.Dataset:
        """The table on ``point`` (``kind`` a string column), with units and long names;
        the settings as attributes (``curves.nc``)."""
        ds = curves_dataset(self.table, self.parameter, self.units, self.value_column)
        ds.attrs.update(harmonics=self.H, period_doubling_harmonics_of_half_speed=self.H2)
        return ds

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """``curves.csv``, ``curves.nc`` (one row per point, ``kind`` column),
        ``summary.json`` (start points, turns, timings), ``curves.png`` (with ``plots``);
        atomically."""
        out = Path(directory)
        cols = list(self.table)
        n = len(self.table["kind"])
        rows = [tuple(self.table[c][i].item() if hasattr(self.table[c][i], "item")
                      else self.table[c][i] for c in cols) for i in range(n)]
        paths = {"curves.csv": atomic.write_csv(out / "curves.csv", cols, rows),
                 "curves.nc": atomic.write_netcdf(self.to_dataset(), out / "curves.nc"),
                 "summary.json": atomic.write_json(out / "summary.json", self.to_json())}
        if plots:
            paths.update(atomic.save_figures(self.plot(), out))
        return paths

    def plot(self) -> dict[str, Figure]:
        """``curves.png``: the curves in the (Omega~, parameter) plane, turning points
        marked, titled by :attr:`title`
        (:func:`rotorsfd.plots.bifurcation_curves.bifurcation_curves_figure`)."""
        # deferred: plots.bifurcation_curves (loads matplotlib)
        from rotorsfd.plots.bifurcation_curves import bifurcation_curves_figure

        t = self.table
        return {"curves.png": bifurcation_curves_figure(
            t["kind"], t["curve"], t["speed_ratio"], t[self.value_column],
            turns=[(p.kind, p.speed_ratio, p.value) for p in self.turns],
            codim2=[(c.type, c.speed_ratio, c.value) for c in self.codim2],
            parameter=self.parameter, units=self.units, H=self.H,
            H2=self.H2 if self.pd_curves else None, title=self.title)}


def _curve_rows(kind: str, hb: TwoParameterHB | None, curves: list[FoldBranch],
                system: RotorSystem, ref: float, nodes: tuple[int, ...], value_column: str,
                cols: dict[str, list] | None = None) -> dict[str, list]:
    """Rows of ``curves`` (points ``leg.system.embed(z)`` of ``hb``) appended to ``cols``."""
    if cols is None:
        cols = {k: [] for k in ("kind", "curve", "segment", "s", value_column,
                                "speed_rad_s", "speed_ratio", "max_eps", "aliasing")}
        cols.update({f"amp_{n}_m": [] for n in nodes})
    el = system.elements
    for k, c in enumerate(curves):
        assert hb is not None
        for ze, seg, s in zip(c.z, c.segment, c.s, strict=True):
            z = c.system.embed(ze)
            _, speed, value = hb.from_z(z)
            X = hb.coefficients(z)
            cols["kind"].append(kind)
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
                cols[f"amp_{n}_m"].append(float(max_radius(X[:, iy], X[:, iz])))
    return cols


def _merge(fold: FoldCurve | None, pd: dict[str, list]) -> dict[str, NDArray]:
    """One table: the fold curve's rows (kind "saddle-node") then the PD rows."""
    cols = list(pd)
    out: dict[str, list] = {k: list(pd[k]) for k in cols}
    if fold is not None:
        n = len(fold.table["speed_rad_s"])
        for k in cols:
            head = ["saddle-node"] * n if k == "kind" else list(fold.table[k])
            out[k] = head + out[k]
    return {k: (np.asarray(v, dtype=object) if k == "kind" else
                np.asarray(v, dtype=np.int64 if k in ("curve", "segment") else float))
            for k, v in out.items()}


def at_limit(leg: FoldBranch, hb: TwoParameterHB, system: RotorSystem, limit_max: float
             ) -> FoldBranch:
    """``leg``, or, when it stopped because its last orbit is at an element's validity
    limit (``ElementSet.at_limit``: within 2 % of ``limit_max``), the same
    points marked a result that ends there (success, the element named), as a response
    branch that ends at the film's limit is."""
    if leg.success or not leg.z.shape[0]:
        return leg
    el = system.elements
    X = hb.coefficients(leg.system.embed(leg.z[-1]))
    reached = el.at_limit(orbit_samples(X[:, el.nl_dofs])[0], limit_max)
    if reached is None:
        return leg
    element, value = reached
    return dataclasses.replace(
        leg, success=True, message=f"ended where {element.describe()} reached "
        f"{element.limit_label} = {value:.3f}, the limit analysis.response.max_eccentricity"
        f" = {limit_max:g} (a result up to there; {leg.message})")


def bifurcation_curves(system: RotorSystem, speed_range: tuple[float, float],
                       second_parameter: str, range2: tuple[float, float], H: int = 3, *,
                       harmonics_factor: int = 4, reference_speed: float | None = None,
                       nodes: tuple[int, ...] | None = None,
                       options: FoldOptions | None = None,
                       stability_options: StabilityOptions | None = None,
                       branch_options: dict[str, Any] | None = None,
                       codim2: bool = True) -> BifurcationCurves:
    """Fold, period-doubling and Neimark-Sacker curves from the speed branch at
    ``range2[0]`` (SI), continued towards ``range2[1]`` (module docstring), and their
    codimension-2 points (``codim2=False``: only the cusps and the NS curves' ends, no
    Floquet multipliers along the curves). ConfigError if that branch has no saddle-node,
    period doubling or secondary Hopf; ConvergenceError if it stops first."""
    param = system_parameter(second_parameter)
    if param == "speed":
        raise ConfigError("--parameter", second_parameter,
                          "the second parameter must differ from the speed")
    if range2[0] == range2[1]:
        raise ConfigError("--to", range2[1], "must differ from --from (the start value)")
    if harmonics_factor not in (2, 4):
        raise ConfigError("harmonics_factor", harmonics_factor, "2 or 4")
    ref = float(reference_speed if reference_speed is not None else first_critical(system))
    out_nodes = tuple(nodes) if nodes else system.output_nodes
    family = system.two_parameter_problem(param)
    limit_max = float(dict(branch_options or {}).get("limit_max", 1.0))
    t0 = time.perf_counter()
    problem = family.first(range2[0])
    branch = continue_periodic(problem, speed_range[0], speed_range[1], H,
                               **dict(branch_options or {}))
    opts = stability_options or StabilityOptions()
    st = branch_stability(branch, problem, opts)
    found, messages, noted = [], [], {}
    # no curve starts from a bifurcation that vanishes at the check's H and M (an artefact)
    checks = checks_as_configured(branch, problem, st, opts) or [None] * len(st.bifurcations)
    for b, c in zip(st.bifurcations, checks, strict=True):
        if c is not None and c.vanished:
            messages.append(f"{reported_kind(b)} at {b.lam:.6g} rad/s not continued: "
                            f"{c.message}")
            continue
        found.append(b)
        if c is not None and not c.confirmed:
            noted[id(b)] = f" ({c.message})"
    flips = [b for b in found if b.kind == "period-doubling"]
    n_folds = len(branch.folds())
    t1 = time.perf_counter()
    where = (f"the speed branch at {param} = {range2[0]:g} in {speed_range[0]:.6g} .. "
             f"{speed_range[1]:.6g} rad/s")
    has_hopf = any(b.kind == "secondary-hopf" for b in found)
    if not n_folds and not flips and not has_hopf:
        if not branch.success:
            raise ConvergenceError(f"{where} stopped before any bifurcation: "
                                   f"{branch.message}")
        raise ConfigError("--from", range2[0], f"{where} has no saddle-node, period "
                          "doubling or secondary Hopf" + (f" that its check confirms "
                          f"({'; '.join(messages)})" if messages else "") +
                          "; start where the response has one")
    fold = None
    if n_folds:
        fold = fold_curve(system, speed_range, param, range2, H, reference_speed=ref,
                          nodes=out_nodes, options=options, branch_options=branch_options)
        messages.append(f"saddle-node: {fold.message}")
    t2 = time.perf_counter()
    hopfs = [b for b in found if b.kind == "secondary-hopf"
             and abs(abs(b.critical) - 1.0) < 1e-3
             and 0.0 < abs(np.angle(b.critical)) < np.pi]
    Nb = branch.info["n_samples"]
    N_b = int(max((Nb[min(int(b.info.get("point", 0)) + k, len(Nb) - 1)]
                   for b in [*flips, *hopfs] for k in (0, 1)),
                  default=Nb[0] if len(Nb) else 32))
    H2, N2 = harmonics_factor * H, harmonics_factor * N_b
    scales = (abs(speed_range[1] - speed_range[0]), abs(range2[1] - range2[0]))
    pd_hb, pd_curves = None, []
    covered = [False] * len(flips)
    for i, b in enumerate(flips):
        if covered[i]:
            continue
        covered[i] = True
        p = branch.point_at(b.s)
        pd_hb, legs = continue_period_doublings(family, p.X, p.lam, range2[0], range2,
                                                H2=H2, N=N2, scales=scales,
                                                options=options, both_ways=False,
                                                limit_max=limit_max)
        leg = at_limit(legs[0], pd_hb, system, limit_max)
        pd_curves.append(leg)
        messages.append(f"period doubling at {b.lam:.6g} rad/s{noted.get(id(b), '')}: "
                        f"{leg.message}")
        if not leg.cusps:
            continue
        try:
            back = [pd_hb.from_z(leg.system.embed(z))[1]
                    for z in leg.solve_at(range2[0] / scales[1])]
        except ConvergenceError:
            back = []
        for j, q in enumerate(flips):
            if not covered[j] and any(abs(w - q.lam) <= 1e-4 * q.lam for w in back):
                covered[j] = True
    ns_hb, ns_curves = None, []
    for b in hopfs:
        p = branch.point_at(b.s)
        theta = abs(float(np.angle(b.critical))) / (2 * np.pi)
        try:
            ns_hb, leg = continue_neimark_sacker(family, p.X, p.lam, range2[0], theta,
                                                 range2, H=H, N=N_b, K=H2 // 2,
                                                 scales=scales, options=options,
                                                 limit_max=limit_max)
            leg = at_limit(leg, ns_hb, system, limit_max)
        except ConvergenceError as exc:
            messages.append(f"secondary Hopf at {b.lam:.6g} rad/s not continued: {exc}")
            continue
        at_half = np.flatnonzero(leg.z[:, -2] > 0.5 - THETA_END)
        if leg.ended_at is None and at_half.size:   # no located event: cut at the step
            k = int(at_half[0])
            leg = dataclasses.replace(
                leg, z=leg.z[: k + 1], tangents=leg.tangents[: k + 1], s=leg.s[: k + 1],
                segment=leg.segment[: k + 1], cusps=[c for c in leg.cusps if c.index <= k],
                success=True, message="ended where the multipliers meet at -1 (theta = "
                "1/2, a 1:2 resonance, located to the continuation step)")
        elif leg.ended_at is not None:
            leg.message = ("ended where the multipliers meet at " + ("+1 (theta = 0, a 1:1"
                           if leg.ended_at == 0 else "-1 (theta = 1/2, a 1:2") +
                           " resonance, located)")
        ns_curves.append(leg)
        messages.append(f"secondary Hopf at {b.lam:.6g} rad/s{noted.get(id(b), '')}: "
                        f"{leg.message}")
    t3 = time.perf_counter()
    col = f"{column_slug(param)}_{column_slug(PARAMETER_UNITS[param])}"
    rows = _curve_rows("period-doubling", pd_hb, pd_curves, system, ref, out_nodes, col)
    table = _merge(fold, _curve_rows("Neimark-Sacker", ns_hb, ns_curves, system, ref,
                                     out_nodes, col, rows))
    turns = [TurningPoint("saddle-node", c.speed_rad_s, c.speed_ratio, c.value)
             for c in (fold.cusps if fold else [])]
    for c in pd_curves:
        for cp in c.cusps:
            _, speed, value = pd_hb.from_z(c.system.embed(cp.z))
            turns.append(TurningPoint("period-doubling", speed, speed / ref, value))
    for c in ns_curves:
        for cp in c.cusps:
            assert ns_hb is not None
            _, speed, value = ns_hb.from_z(c.system.embed(cp.z))
            turns.append(TurningPoint("Neimark-Sacker", speed, speed / ref, value))
    points, codim2_messages = codim2_records(
        family, ref, [("saddle-node", fold.hb if fold else None, fold.curves if fold else []),
                      ("period-doubling", pd_hb, pd_curves),
                      ("Neimark-Sacker", ns_hb, ns_curves)], stability_options,
        multipliers=codim2)
    messages += codim2_messages
    t4 = time.perf_counter()
    success = (fold.success if fold else True) and all(c.success for c in
                                                       pd_curves + ns_curves)
    timings = {"speed_branch_and_stability": t1 - t0, "fold_curves": t2 - t1,
               "period_doubling_and_neimark_sacker_curves": t3 - t2,
               "codimension_2_points": t4 - t3, "total": time.perf_counter() - t0}
    return BifurcationCurves(param, (float(range2[0]), float(range2[1])), ref, H, H2, N2,
                             fold.start_folds if fold else [],
                             [float(b.lam) for b in flips], table, turns, fold, pd_hb,
                             pd_curves, ns_hb, ns_curves, [float(b.lam) for b in hopfs],
                             points, success, "; ".join(messages), timings)


def run_bifurcation_curves(config_or_system: Config | RotorSystem, parameter: str,
                           start: Any, stop: Any, settings: ResponseAnalysis | None = None,
                           *, context: RunContext | None = None,
                           search_path: Path | None = None, harmonics: int | None = None,
                           harmonics_factor: int = 4,
                           options: FoldOptions | None = None) -> BifurcationCurves:
    """:func:`bifurcation_curves` with the speed range, H (``start_harmonics``), output
    nodes of ``[analysis.response]`` and Omega_ref, title of the context; ``parameter``
    a config path or parameter name and ``start, stop`` its range (SI numbers or strings
    with units). From a :class:`RotorSystem` with ``settings`` and ``context`` (defaults:
    an empty configuration's) or from a Config (its system, section and context), through
    the same :meth:`TwoParameterInputs.from_system`."""
    inputs = TwoParameterInputs.resolve(config_or_system, parameter, start, stop, settings,
                                        context, "the bifurcation curves need", search_path)
    result = bifurcation_curves(inputs.system, inputs.speed_range, inputs.param,
                                inputs.range2, harmonics or inputs.response.start_harmonics,
                                harmonics_factor=harmonics_factor,
                                reference_speed=inputs.reference_speed, nodes=inputs.nodes,
                                options=options, stability_options=stability_settings(
                                    inputs.stability, True),
                                branch_options={"limit_max": inputs.response.max_eccentricity})
    result.title = inputs.title
    return result
