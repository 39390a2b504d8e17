"""Run the paper's cases (:mod:`rotorsfd.paper.cases`) and collect their numbers.

One runner per kind of case (the isola's in :mod:`rotorsfd.paper.isola`; the numbers from
:mod:`rotorsfd.paper.numbers`, the config from :mod:`rotorsfd.paper.case_config`).
:func:`run_case` runs one case and returns an :class:`Outcome`: ``numbers`` (what the
report compares with the paper) and ``data`` (plain arrays for the figures); it never
raises for a numerical failure (the outcome says ``failed`` and why). :func:`run_cases`
runs several in a process pool with a progress bar.
"""

from __future__ import annotations

import io
import os
import sys
import time
import traceback
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import RotorsfdError
from rotorsfd.paper.case_config import case_title, load_case_config, paper_stability
from rotorsfd.paper.cases import CAL, READINGS, Case, Outcome, examples_dir, select
from rotorsfd.paper.isola import run_isola
from rotorsfd.paper.numbers import (
    local_peaks,
    response_numbers,
    td_data,
    td_numbers,
    turning_points,
)

#: Names of the split-out modules, importable from here as before the split.
__all__ = [
    "CASE_COST",
    "COST",
    "RUNNERS",
    "Outcome",
    "PaperResult",
    "case_cost",
    "case_title",
    "load_case_config",
    "local_peaks",
    "paper_stability",
    "response_numbers",
    "run_case",
    "run_cases",
    "run_paper",
    "turning_points",
]


# ---- the kinds -------------------------------------------------------------------------------


def _modal(case: Case, config: Any, out: Path | None,
           plots: bool = False) -> tuple[dict, dict]:
    # deferred: analyses.modal (loads numba, scipy, pydantic)
    from rotorsfd.analyses.modal import run_modal

    r = run_modal(config)
    if out is not None:
        r.write(out, plots=plots)
    n = {f"crit{c.mode}": float(c.speed_rad_s) for c in r.critical_speeds}
    return n, {}


def _response(case: Case, config: Any, out: Path | None,
              plots: bool = False) -> tuple[dict, dict]:
    # deferred: analyses.response (loads numba, scipy, pydantic)
    from rotorsfd.analyses.response import run_response

    r = run_response(config, progress=False, stability_options=paper_stability(config))
    if out is not None:
        r.write(out, plots=plots)
    return response_numbers(r, case.options.get("orbits", ()))


def _simulate(case: Case, config: Any, out: Path | None,
              plots: bool = False) -> tuple[dict, dict]:
    # deferred: analyses.simulate (loads numba, scipy, pydantic)
    from rotorsfd.analyses.simulate import run_simulation

    r = run_simulation(config, speed_ratio=case.options.get("speed_ratio"), progress=False,
                       lyapunov_periods=0)
    if out is not None:
        r.write(out, plots=plots)
    ev = r.motion.evidence if r.motion is not None else {}
    n = {"motion": r.motion_name, "n_distinct_poincare": ev.get("n_distinct_poincare"),
         "max_eccentricity": r.max_eccentricity, **td_numbers(r)}
    return n, td_data(r)


def _fold_curve(case: Case, config: Any, out: Path | None,
                plots: bool = False) -> tuple[dict, dict]:
    # deferred: analyses.fold_curve (loads numba, scipy, pydantic)
    from rotorsfd.analyses.fold_curve import run_fold_curve

    lo, hi = case.options["range"]
    f = run_fold_curve(config, "base.pitching.value", lo, hi,
                       harmonics=case.options.get("harmonics"))
    if out is not None:                        # the figure titled by the case's settings
        from rotorsfd.io import atomic

        f.write(out, plots=False)
        if plots:
            atomic.save_figure(f.plot()["fold_curve.png"], out / "fold_curve.png", dpi=120)
    grid = np.linspace(lo, hi, 201)
    w = f.unstable_width(grid)
    n = {"end_rate": f.bistability_end, "width0": float(f.unstable_width([lo])[0]),
         "width10": float(f.unstable_width([hi])[0]),
         "start_folds": [x / f.reference_speed for x in f.start_folds],
         "success": f.success, "message": f.message}
    for rate in case.options.get("widths_at", ()):   # widths at the paper's named rates
        n[f"width{rate:g}"] = float(f.unstable_width([rate])[0])
    return n, {"rate": grid, "width": w}


def _width_sweep(case: Case, config: Any, out: Path | None,
                 plots: bool = False) -> tuple[dict, dict]:
    """The unstable width (upper minus lower fold) per pitching rate: one branch per rate,
    its folds its turning points (no Floquet: a fold is a turning point of the branch, the
    width needs nothing else; the response with stability costs 3-4x)."""
    # deferred: analyses.response, io.config (loads numba, scipy, pydantic)
    from rotorsfd.analyses.response import run_response
    from rotorsfd.io.config import with_values

    values = [float(v) for v in case.options["values"]]
    widths, notes = [], []
    for v in values:
        r = run_response(with_values(config, {"base.pitching.value": v}), progress=False,
                         stability_options=False)
        folds = turning_points(r)
        num, _ = response_numbers(r)
        if len(folds) >= 2:
            widths.append(folds[-1] - folds[0])
            notes.append(f"{v:g}: folds {folds[0]:.4f}-{folds[-1]:.4f}")
        elif r.success:
            widths.append(0.0)
            notes.append(f"{v:g}: no fold")
        else:                      # no fold pair before the branch ended: no width
            widths.append(None)
            notes.append(f"{v:g}: {num['end']}")
    zero = [v for v, x in zip(values, widths, strict=True) if x == 0.0]
    n = {"width0": widths[0], "width10": widths[-1], "end_rate": zero[0] if zero else None,
         "notes": notes}
    for key, i in (("width0", 0), ("width10", -1)):
        if widths[i] is None:
            n[f"{key}_why"] = "no fold pair, " + notes[i].split(": ", 1)[1]
    w = np.array([np.nan if x is None else x for x in widths])   # the figure leaves a gap
    return n, {"rate": np.array(values), "width": w}


def _chart(case: Case, config: Any, out: Path | None,
           plots: bool = False) -> tuple[dict, dict]:
    # deferred: analyses.stability_chart (loads numba, scipy, pydantic)
    from rotorsfd.analyses.stability_chart import run_stability_chart

    r = run_stability_chart(config, workers=1, progress=False)
    if out is not None:
        r.write(out, plots=plots)
    n = {"unstable_fraction": float((~r.stable).mean())}
    return n, {"x": r.x.values, "y": r.y.values, "max_abs": r.chart.max_abs,
               "x_label": f"{r.x.path} [{r.x.units}]", "y_label": f"{r.y.path} [{r.y.units}]",
               "tol": float(r.chart.tol), "speed": r.speed}


#: kind -> runner ``(case, config, out, plots)``: the case's results files into ``out``
#: (None: none), with the analysis' own figures only if ``plots`` (the report draws the
#: paper's figures from the numbers; the analyses' figures cost more than their runs)
RUNNERS: dict[str, Callable[..., tuple[dict, dict]]] = {
    "modal": _modal, "response": _response, "simulate": _simulate,
    "fold-curve": _fold_curve, "width-sweep": _width_sweep, "chart": _chart,
    "isola": run_isola}


def run_case(case: Case, examples: Path | None = None, quick: bool = False,
             out: Path | None = None, plots: bool = False) -> Outcome:
    """Run one case; results files into ``out/<case>`` when ``out`` is given, with the
    analysis' own figures (``response_*.png``, ...) if ``plots``."""
    t0 = time.perf_counter()
    examples = examples or examples_dir()
    try:
        config = load_case_config(case, examples, quick)
        numbers, data = RUNNERS[case.kind](case, config, None if out is None
                                           else out / case.name, plots)
    except RotorsfdError as exc:
        return Outcome(case.name, "failed", " ".join(str(exc).split()),
                       time.perf_counter() - t0)
    except Exception as exc:  # a bug: the other cases still run
        return Outcome(case.name, "error", f"{type(exc).__name__}: {exc} "
                       f"{traceback.format_exc(limit=-2)}", time.perf_counter() - t0)
    # a branch that ends at an element's validity limit is a result (issue 22 item 3)
    status = ("ok" if numbers.get("success", True) else
              "limit" if numbers.get("ended") == "limit" else "partial")
    return Outcome(case.name, status, str(numbers.get("end") or numbers.get("message", "")),
                   time.perf_counter() - t0, numbers, data)


def _worker_init() -> None:
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")


def run_cases(cases: Sequence[Case], *, examples: Path | None = None, quick: bool = False,
              out: Path | None = None, workers: int | None = None,
              progress: bool = True, plots: bool = False,
              on_outcome: Callable[[Outcome], None] | None = None) -> dict[str, Outcome]:
    """Run ``cases`` (longest first) in ``workers`` processes (default: the CPUs, at most
    2; 1: in this process) with a tqdm bar on stderr; ``plots``: see :func:`run_case`;
    ``on_outcome(outcome)`` is called in this process as each case ends (the workers
    keep running meanwhile)."""
    # deferred: tqdm is heavy (loaded only when this runs)
    from tqdm import tqdm

    examples = examples or examples_dir()
    workers = workers or min(2, os.cpu_count() or 1)
    order = sorted(cases, key=lambda c: -case_cost(c))
    results: dict[str, Outcome] = {}
    bar = tqdm(total=len(order), desc="paper", disable=not progress, file=sys.stderr,
               dynamic_ncols=True)
    try:
        if workers == 1:
            for c in order:
                bar.set_postfix_str(c.name)
                results[c.name] = o = run_case(c, examples, quick, out, plots)
                bar.update()
                if on_outcome is not None:
                    on_outcome(o)
        else:
            with ProcessPoolExecutor(workers, initializer=_worker_init) as pool:
                futures = {pool.submit(run_case, c, examples, quick, out, plots): c
                           for c in order}
                for f in as_completed(futures):
                    o = f.result()
                    results[o.name] = o
                    bar.set_postfix_str(f"{o.name} {o.status} {o.elapsed:.0f} s")
                    bar.update()
                    if on_outcome is not None:
                        on_outcome(o)
    finally:
        bar.close()
    return {c.name: results[c.name] for c in cases}


#: Rough cost per kind [CPU s] of a case not in :data:`CASE_COST` (a calibrated case about
#: twice its literal one: the dense modal damping takes the dense LU path) ...
COST = {"isola": 15, "chart": 7, "width-sweep": 8, "simulate": 1.5, "fold-curve": 3,
        "response": 1.5, "modal": 1.4}
#: ... and of every case of the full run [CPU s]: each case's wall time in the full run of
#: 2026-12-03 on an idle 2-core AMD EPYC (2 workers, 137 s wall) times that run's CPU /
#: summed case wall (254 s / 264 s), before the dense-path savings of issue 17 item 5
#: (the calibrated branches 5-15 % less since; a run at load 6 keeps the order); only
#: their order matters (longest first keeps both workers busy to the end).
CASE_COST: dict[str, float] = {"fig23-isola": 29.2, "cal-fig24-u360": 19.4,
    "cal-fig21-cr0.728": 14.3, "fig21-cr0.61": 12.4, "cal-fig21-cr0.61": 11.3, "fig6": 10.4,
    "cal-fig19-u252": 7.8, "cal-fig19-u360": 7.3, "cal-fig21-cr0.485": 7.2,
    "cal-fig24-u144": 6.8, "fig19-u360": 6.6, "cal-fig17-u252-w7": 6.3,
    "cal-fig17-u360-w9": 5.7, "cal-fig19-u144": 4.9, "fig21-cr0.728": 4.7,
    "cal-fig17-u252-w6": 4.2, "fig19-u252": 3.9, "fig24-u144": 3.5, "fig21-cr0.485": 3.1,
    "fig19-u252-paper-h": 3.0, "cal-fig7-u360": 2.9, "fig17-u252-w9": 2.8,
    "cal-fig12-w9": 2.8, "fig19-u144": 2.7, "fig23-s1.1": 2.7, "fig17-u252-w7": 2.4,
    "cal-fig12-w10": 2.3, "fig19-u144-paper-h": 2.3, "fig24-u360": 2.3,
    "cal-fig23-s1.025": 2.1, "fig23-s1.075": 2.0, "cal-fig23-s1.04": 2.0,
    "cal-fig7-u144": 2.0, "cal-fig23-s1.1": 1.9, "fig17-u252-w6": 1.9, "modal": 1.9,
    "cal-fig12-w8": 1.9, "cal-fig12-w2": 1.9, "cal-fig23-s1.075": 1.8,
    "cal-fig23-s1.05": 1.7, "fig12-w10": 1.7, "fig23-s1.025": 1.6, "cal-fig12-w4": 1.6,
    "fig23-s1.04": 1.6, "fig23-s1.05": 1.6, "fig10-w5": 1.4, "fig12-w9": 1.3,
    "fig12-w4": 1.2, "fig7-u144": 1.2, "fig16-w9": 1.2, "fig17-u360-w6": 1.1,
    "fig17-u360-w9": 1.1, "fig17-u360-w7": 1.1, "fig16-w2": 1.1, "fig17-u252-w0": 1.1,
    "fig10-w0": 1.1, "fig7-u72": 1.0, "fig16-w6": 1.0, "fig12-w8": 1.0, "fig16-w4": 1.0,
    "fig7-u360": 1.0, "fig23-t200-s1.04": 0.9, "fig12-w2": 0.9, "fig17-u360-w0": 0.9,
    "fig23-t200-s1.075": 0.9, "fig10-w10": 0.9, "fig23-t200-s1.1": 0.8, "sens-sfdp": 0.8,
    "fig12-w0": 0.8, "sens-rightm": 0.8, "sens-rightp": 0.7, "fig23-t200-s1.05": 0.7,
    "fig10-w20": 0.7, "sens-sfdm": 0.6, "fig23-t200-s1.025": 0.6, "fig12-w6": 0.5}


def case_cost(case: Case) -> float:
    """The expected CPU time of a case (:data:`CASE_COST`, else :data:`COST`)."""
    if case.name in CASE_COST:
        return CASE_COST[case.name]
    return COST.get(case.kind, 1.0) * (2.0 if case.reading == "calibrated" else 1.0)


@dataclass
class PaperResult:
    """What ``rotorsfd paper`` produced."""

    outcomes: dict[str, Outcome]
    paths: dict[str, Path]
    elapsed: float

    def summary(self) -> str:
        bad = [o for o in self.outcomes.values() if o.status not in ("ok", "limit")]
        limit = [o for o in self.outcomes.values() if o.status == "limit"]
        part = sum(o.status == "partial" for o in bad)
        lines = [f"{len(self.outcomes)} cases in {self.elapsed:.0f} s: "
                 f"{len(self.outcomes) - len(bad) - len(limit)} ok, {len(limit)} ended at "
                 f"the film's limit (a result, see the report), {part} partial (branch "
                 f"stopped early), {len(bad) - part} failed"]
        lines += [f"  {o.name}: {o.message[:150]}" for o in limit]
        lines += [f"  {o.name}: {o.status}: {o.message[:150]}" for o in bad]
        return "\n".join(lines)


class FigureQueue:
    """The paper's figures drawn as their cases end: :meth:`add` each outcome; a figure
    is drawn (PNG, 110 dpi) once every case it shows that runs has ended, with exactly
    the outcomes it would be drawn from after the run (:func:`rotorsfd.paper.figures.draw`
    reads only its own cases). :meth:`pngs`: the PNGs in the order of ``specs``."""

    def __init__(self, specs: Sequence[Any], names: Sequence[str]) -> None:
        ran = set(names)
        self.specs = list(specs)
        self.needs = {s.number: {n for c in s.cases for n in (c, CAL + c) if n in ran}
                      for s in self.specs}
        self.outcomes: dict[str, Outcome] = {}
        self.done: dict[str, bytes | None] = {}

    def add(self, outcome: Outcome) -> None:
        """Record an outcome; draw the figures it completes."""
        self.outcomes[outcome.name] = outcome
        for spec in self.specs:
            if spec.number not in self.done and self.needs[spec.number] <= set(self.outcomes):
                self.done[spec.number] = self._png(spec)

    def _png(self, spec: Any) -> bytes | None:
        # deferred: paper.figures (loads scipy, matplotlib)
        from rotorsfd.paper.figures import draw

        fig = draw(spec, self.outcomes)
        if fig is None:
            return None
        buf = io.BytesIO()
        fig.savefig(buf, format="png", dpi=110)
        return buf.getvalue()

    def pngs(self) -> dict[str, bytes]:
        """Every figure (those not drawn yet now), in the order of the specs."""
        out: dict[str, bytes] = {}
        for spec in self.specs:
            if spec.number not in self.done:
                self.done[spec.number] = self._png(spec)
            png = self.done[spec.number]
            if png is not None:
                out[spec.number] = png
        return out


def run_paper(output: str | Path, figures: Sequence[str] | None = None, *,
              quick: bool = False, workers: int | None = None, progress: bool = True,
              examples: Path | None = None, case_plots: bool = False,
              readings: Sequence[str] = READINGS) -> PaperResult:
    """Run the cases of ``figures`` (all by default; ``quick``: Figure 7 only, shorter
    settings) in the ``readings`` (literal and calibrated; see
    :mod:`rotorsfd.paper.cases`), draw the figures and write the report into ``output``;
    the cases' results files go to ``output/cases/<case>``, with each analysis' own
    figures only if ``case_plots``. Each figure is drawn as soon as its cases have ended,
    while the workers run the others (:class:`FigureQueue`)."""
    # deferred: paper.report (loads scipy, matplotlib)
    from rotorsfd.paper.report import DIAGNOSES, write_report

    t0 = time.perf_counter()
    out = Path(output)
    specs, cases = select(list(figures or []), quick, tuple(readings))
    queue = FigureQueue(specs, [c.name for c in cases])
    outcomes = run_cases(cases, examples=examples, quick=quick, out=out / "cases",
                         workers=workers, progress=progress, plots=case_plots,
                         on_outcome=queue.add)
    pngs = queue.pngs()
    elapsed = time.perf_counter() - t0
    paths = write_report(out, outcomes, pngs, elapsed=elapsed, diagnoses=DIAGNOSES)
    return PaperResult(outcomes, paths, elapsed)
