"""Run the paper's cases (:mod:`rotorsfd.paper.cases`) and collect their numbers.

:func:`run_case` runs one case and returns an :class:`Outcome`: ``numbers`` (what the
report compares with the paper) and ``data`` (plain arrays for the figures); it never
raises for a numerical failure (the outcome says ``failed`` and why). :func:`run_cases`
runs several in a process pool with a progress bar.
"""

from __future__ import annotations

import os
import re
import sys
import time
import traceback
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor, as_completed
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.paper.cases import (
    READINGS,
    Case,
    Outcome,
    calibration_overrides,
    examples_dir,
    literal_name,
)
from rotorsfd.plots.labels import mathtext, setting

# ---- response -------------------------------------------------------------------------------


#: A disk peak stands out from the troughs on both sides by this fraction of the largest
#: value (2 %: Figure 15's second peak at 9 rad/s, Omega~ 1.392, rises 3 % of the main
#: peak above its trough, plainly a local maximum in the figure; the earlier 5 % missed it,
#: and a smooth branch has no wiggles at that level).
PEAK_PROMINENCE = 0.02


def local_peaks(x: np.ndarray, y: np.ndarray, rel: float = PEAK_PROMINENCE) -> list[float]:
    """x of the local maxima of y(x) along the branch (arc order) that stand out by ``rel``
    of the largest value from the lowest point on both sides up to a higher value."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    out = []
    top = float(np.max(y)) if y.size else 0.0
    for i in range(1, y.size - 1):
        if y[i] >= y[i - 1] and y[i] > y[i + 1]:
            left = y[:i][::-1]
            right = y[i + 1:]
            lmin = min(left[: np.argmax(left > y[i])].min(initial=y[i]) if np.any(left > y[i])
                       else left.min(), y[i])
            rmin = min(right[: np.argmax(right > y[i])].min(initial=y[i])
                       if np.any(right > y[i]) else right.min(), y[i])
            if y[i] - max(lmin, rmin) > rel * top:
                out.append(float(x[i]))
    return out


def _wave(X: np.ndarray, n: int = 256) -> np.ndarray:
    """y(theta) on n phases from coefficients X_k (k = 0..H)."""
    k = np.arange(X.shape[-1])
    th = 2 * np.pi * np.arange(n + 1) / n
    return (X @ np.exp(1j * np.outer(k, th))).real


def response_numbers(result: Any, orbits: Sequence[float] = ()) -> tuple[dict, dict]:
    """Numbers and plot data of a :class:`~rotorsfd.analyses.response.ResponseResult`."""
    from rotorsfd.model import dofs

    table = result.table()
    s = np.asarray(table["speed_ratio"], float)
    C = result.clearance
    rows = [{k: (float(v) if isinstance(v, (int, float, np.number))
                 and not isinstance(v, bool) else v) for k, v in b.items()}
            for b in (result.bifurcations or [])]
    sn = sorted((b for b in rows if b["type"] == "saddle-node"), key=lambda b: b["speed_ratio"])
    n: dict[str, Any] = {"bifurcations": [(b["type"], b["speed_ratio"], b["max_multiplier"],
                                           b["multiplier_re"], b["multiplier_im"])
                                          for b in rows],
                         "success": result.success, "n_points": int(s.size),
                         "H": int(result.branch.H)}
    if sn:
        n.update(sn_hi=sn[-1]["speed_ratio"], sn_hi_mu=sn[-1]["max_multiplier"],
                 sn_lo=sn[0]["speed_ratio"], sn_lo_mu=sn[0]["max_multiplier"])
    if len(sn) >= 2:
        n["width"] = sn[-1]["speed_ratio"] - sn[0]["speed_ratio"]
    ecc = np.asarray(table[f"defl_{result.system.primary_node}"], float)
    n["ended"] = getattr(result, "ended", "range" if result.success else "failed")
    n["end"] = (f"reached Omega~ = {s[-1]:.4f}" if result.success else
                f"ended at Omega~ = {s[-1]:.4f} where the journal reached eps = "
                f"{ecc[-1]:.3f} (the film's limit, max_eccentricity)" if n["ended"] == "limit"
                else f"stopped at Omega~ = {s[-1]:.4f}, eps = {ecc[-1]:.3f}")
    n["message"] = result.message
    sfd = result.system.primary_node
    d1 = np.asarray(table[f"defl_{sfd}"])
    i = int(np.argmax(d1))
    n["peak_ratio"], n["peak_defl"] = float(s[i]), float(d1[i])
    h = [np.asarray(table[f"amp_{sfd}_y_h{k}"])[i] for k in range(1, result.branch.H + 1)]
    n["dominant"] = ("1X" if h[0] > 5 * max(h[1:], default=0.0)
                     else f"mixed (h1/h2 = {h[0] / max(h[1], 1e-30):.2f})")
    disk = [d.node for d in result.system.rotor.disks]
    if disk and f"amp_{disk[0]}_y_h1" in table:
        n["disk_peaks"] = local_peaks(s, np.asarray(table[f"amp_{disk[0]}_y_h1"]))
    data: dict[str, Any] = {k: np.asarray(v) for k, v in table.items()}
    data["bifurcations"] = rows
    data["nodes"] = list(result.nodes)
    data["H"] = int(result.branch.H)
    data["clearance"] = C
    X = result.branch.X
    for node in result.nodes:
        for d in ("y", "z"):
            w = _wave(X[:, :, dofs.dof_index(node, d)], 128) / C
            data[f"max_{node}_{d}"] = w.max(axis=1)
            data[f"min_{node}_{d}"] = w.min(axis=1)
    orb = []
    for target in orbits:
        j = int(np.argmin(np.abs(s - target)))
        orb.append((float(s[j]), _wave(X[j, :, dofs.dof_index(sfd, "y")]) / C,
                    _wave(X[j, :, dofs.dof_index(sfd, "z")]) / C))
    data["orbits"] = orb
    return n, data


# ---- the kinds -------------------------------------------------------------------------------


def case_title(case: Case, config_title: str) -> str:
    """The title of a case's own result figures: its config's title with the list of every
    variant ("U = 72.008 / 144.02 / 360.04 g mm") and the settings the case changes
    replaced by the case's settings in words ("U = 144.02 g mm"), its note after; the
    config's title as it is when the case sets nothing."""
    words = [w for w in (setting(o) for o in case.overrides) if w]
    if not words:
        return config_title + (f"; {case.note}" if case.reading != "literal" else "")
    head, sep, rest = config_title.partition(":")
    if not sep:
        head, rest = "", config_title
    m = re.search(r"\s*(\([^()]*\))\s*$", rest)        # "(Zhang et al. 2025)" kept last
    source = m.group(1) if m else ""
    rest = rest[:m.start()] if m else rest
    names = {w.split(" = ")[0] for w in words}
    kept = [p.strip() for p in rest.split(",") if p.strip() and " / " not in p
            and mathtext(p.split(" = ")[0].strip()) not in names]
    text = ", ".join([*kept, *words])
    note = f"; {case.note}" if case.note else ""
    return (f"{head.strip()}: " if head else "") + text + note + \
        (f" {source}" if source else "")


def load_case_config(case: Case, examples: Path | None = None, quick: bool = False,
                     extra: Sequence[str] = ()) -> Any:
    """The validated config of ``case`` (a calibrated case: :func:`calibration_overrides`
    first; then its overrides, ``--quick`` ones, ``extra``), titled by :func:`case_title`."""
    from rotorsfd.io.config import load_config

    folder = examples or examples_dir()
    reading = calibration_overrides(folder) if case.reading == "calibrated" else ()
    config = load_config(folder / case.config,
                         [*reading, *case.overrides, *(case.quick if quick else ()), *extra])
    return config.model_copy(update={"title": case_title(case, config.title)})


def _modal(case: Case, config: Any, out: Path | None,
           plots: bool = False) -> tuple[dict, dict]:
    from rotorsfd.analyses.modal import run_modal

    r = run_modal(config)
    if out is not None:
        r.write(out, plots=plots)
    n = {f"crit{c.mode}": float(c.speed_rad_s) for c in r.critical_speeds}
    return n, {}


def _response(case: Case, config: Any, out: Path | None,
              plots: bool = False) -> tuple[dict, dict]:
    from rotorsfd.analyses.response import run_response

    r = run_response(config, progress=False)
    if out is not None:
        r.write(out, plots=plots)
    return response_numbers(r, case.options.get("orbits", ()))


def _simulate(case: Case, config: Any, out: Path | None,
              plots: bool = False) -> tuple[dict, dict]:
    from rotorsfd.analyses.simulate import run_simulation

    r = run_simulation(config, speed_ratio=case.options.get("speed_ratio"), progress=False,
                       lyapunov_periods=0)
    if out is not None:
        r.write(out, plots=plots)
    ev = r.motion.evidence if r.motion is not None else {}
    n = {"motion": r.motion_name, "n_distinct_poincare": ev.get("n_distinct_poincare"),
         "max_eccentricity": r.max_eccentricity, **_td_numbers(r)}
    return n, _td_data(r)


def _td_numbers(r: Any, prefix: str = "") -> dict[str, Any]:
    """Step, journal Poincare point (last, in C), the eccentricity there and the orbit's
    maximum, and the step check of a SimulationResult (keys ``prefix + ...``)."""
    j = r.column(r.element_node if r.element_node in r.nodes else r.plot_node)
    scale = r.clearance or 1.0
    y, z = (float(r.poincare_q[-1, j, k] / scale) for k in (0, 1))
    chk = r.step_check.as_dict() if r.step_check is not None else {}
    return {prefix + k: v for k, v in {
        "steps_per_period": int(r.settings["steps_per_period"]), "poincare_y": y,
        "poincare_z": z, "eps_poincare": float(np.hypot(y, z)),
        "eps_max": r.max_eccentricity, "step_check": chk.get("difference")}.items()}


def _td_data(r: Any, keep_periods: int = 20) -> dict[str, Any]:
    """Orbit, phase and Poincare arrays of a SimulationResult at its journal, in C."""
    c = r.column(r.plot_node)
    scale = r.clearance or 1.0
    keep = keep_periods * int(r.settings["steps_per_period"])
    return {"y": r.q[-keep:, c, 0] / scale, "z": r.q[-keep:, c, 1] / scale,
            "vy": r.v[-keep:, c, 0] / (scale * r.speed),
            "py": r.poincare_q[:, c, 0] / scale, "pz": r.poincare_q[:, c, 1] / scale,
            "pvy": r.poincare_v[:, c, 0] / (scale * r.speed),
            "speed_ratio": r.speed_ratio, "motion": r.motion_name,
            "steps": int(r.settings["steps_per_period"])}


def _isola(case: Case, config: Any, out: Path | None,
           plots: bool = False) -> tuple[dict, dict]:
    """A coexisting attractor and its isola (Figure 23 / Table 3 diagnosis):
    (a) the time domain at ``find_steps`` steps per period (the paper's T/200) from the HB
    orbit shifted by ``hb_phase`` of the period, which at that step lands near a second
    attractor; (b) the branch through that orbit (``harmonics``; HB-corrected, so it
    does not depend on the step of (a)), continued until it closes, with its
    bifurcations; (c) the time domain at the config's step started on the isola's HB
    orbit at the case's speed: the second attractor at a converged step, and how far the
    HB orbit is from it; (d) the time domain at ``speeds``, each from the previous run's
    final state, at the config's step; (e) the same at ``find_steps`` from (a) at
    ``paper_speeds`` (what the paper's step shows); (d) and (e) with the Lyapunov
    exponent (``lyapunov_periods``)."""
    from rotorsfd.analyses.response import run_response
    from rotorsfd.analyses.simulate import SavedState, hb_state, run_simulation
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.io.config import with_values
    from rotorsfd.model import dofs

    o = case.options
    H = int(o.get("harmonics", 16))
    n_ly = int(o.get("lyapunov_periods", 200))
    coarse = int(o.get("find_steps", 200))
    cfg = with_values(config, {"analysis.response.harmonics": H})
    a = run_simulation(cfg, progress=False, from_hb=True, hb_phase=float(o["hb_phase"]),
                       steps_per_period=coarse, lyapunov_periods=0)
    if out is not None:
        a.write(out / "a-find", plots=False)
    n: dict[str, Any] = {"find_motion": a.motion_name, **_td_numbers(a, "find_")}
    iso = run_response(cfg, from_orbit=a, progress=False)
    if out is not None:
        iso.write(out / "b-isola", plots=False)
    num, data = response_numbers(iso)
    ref = iso.reference_speed
    rows = sorted(data["bifurcations"], key=lambda b: b["speed_ratio"])
    lam = iso.branch.lam / ref
    folds = sorted(float(lam[i]) for i in iso.branch.folds())
    sh = [b for b in rows if b["type"] == "secondary-hopf"]
    n.update({"iso_closed": iso.info.get("closed"), "iso_orbit_difference":
              iso.info.get("orbit_difference"), "bifurcations": num["bifurcations"],
              "success": iso.success, "end": iso.message,
              "iso_fold_lo": folds[0] if folds else None,
              "iso_fold_hi": folds[-1] if folds else None,
              "iso_range": [float(lam.min()), float(lam.max())],
              "iso_pd": [b["speed_ratio"] for b in rows if b["type"] == "period-doubling"]})
    if sh:
        n["iso_sh"] = sh[0]["speed_ratio"]
        n["iso_sh_mu"] = [sh[0]["multiplier_re"], sh[0]["multiplier_im"]]
    if iso.stable is not None:
        st = lam[iso.stable]
        n["iso_stable"] = [float(st.min()), float(st.max())] if st.size else None
    # (c) on the isola's HB orbit at the case's speed (nearest stable point, re-solved)
    speed = a.speed
    pick = np.flatnonzero(iso.stable) if iso.stable is not None and iso.stable.any() \
        else np.arange(lam.size)
    k = int(pick[np.argmin(np.abs(iso.branch.lam[pick] - speed))])
    X = solve_periodic(iso.system.periodic_problem(), speed, H, iso.branch.X[k]).X
    q0, v0 = hb_state(X, speed)
    b = run_simulation(cfg, progress=False, q0=q0, v0=v0, lyapunov_periods=0)
    if out is not None:
        b.write(out / "c-second-attractor", plots=False)
    n.update({"second_motion": b.motion_name, **_td_numbers(b, "second_")})
    j = b.column(b.element_node)
    w = np.exp(1j * np.outer(b.t[-int(b.settings["steps_per_period"]):] * speed,
                             np.arange(X.shape[0])))
    hb = np.stack([(w @ X[:, dofs.dof_index(b.element_node, d)]).real for d in ("y", "z")], -1)
    n["second_hb_difference"] = float(np.max(np.hypot(*(
        hb - b.q[-hb.shape[0]:, j, :]).T)) / b.clearance)
    runs, t200 = [], []
    for seq, start, steps, speeds, ly in (
            (runs, b, None, o.get("speeds", ()), n_ly),
            (t200, a, coarse, o.get("paper_speeds", ()), n_ly)):
        state: Any = start
        for s_ in speeds:
            saved = SavedState(state.q_final, state.v_final, state.t_final, state.speed)
            r = run_simulation(config, speed_ratio=float(s_), progress=False,
                               initial_state=saved, steps_per_period=steps,
                               lyapunov_periods=ly)
            tag = f"{s_:g}" if steps is None else f"{s_:g}_T{steps}"
            if out is not None:
                r.write(out / f"d-{tag}", plots=False)
            n[f"motion_{tag}"] = r.motion_name
            n[f"n_distinct_{tag}"] = (r.motion.evidence.get("n_distinct_poincare")
                                      if r.motion is not None else None)
            if ly:
                n[f"lyapunov_{tag}"] = r.lyapunov.per_period if r.lyapunov else None
            n.update(_td_numbers(r, f"td_{tag}_"))
            seq.append(_td_data(r))
            state = r
    data.update(second=_td_data(b), find=_td_data(a), runs=runs, runs_t200=t200)
    return n, data


def _fold_curve(case: Case, config: Any, out: Path | None,
                plots: bool = False) -> tuple[dict, dict]:
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


def turning_points(result: Any) -> list[float]:
    """Omega~ of the turning points of a response branch (``dlam/ds = 0``, located on the
    HB equations alone, relative 1e-6 of the bracket in s, as the response's stability
    locates its tangent saddle-nodes), in increasing order."""
    from rotorsfd.continuation.folds import locate_branch_fold

    b = result.branch
    return sorted(locate_branch_fold(b, int(i), rtol=1e-6).lam / result.reference_speed
                  for i in b.folds())


def _width_sweep(case: Case, config: Any, out: Path | None,
                 plots: bool = False) -> tuple[dict, dict]:
    """The unstable width (upper minus lower fold) per pitching rate: one branch per rate,
    its folds its turning points (no Floquet: a fold is a turning point of the branch, the
    width needs nothing else; the response with stability costs 3-4x)."""
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
    "isola": _isola}


def run_case(case: Case, examples: Path | None = None, quick: bool = False,
             out: Path | None = None, plots: bool = False) -> Outcome:
    """Run one case; results files into ``out/<case>`` when ``out`` is given, with the
    analysis' own figures (``response_*.png``, ...) if ``plots``."""
    from rotorsfd.errors import RotorsfdError

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
              progress: bool = True, plots: bool = False) -> dict[str, Outcome]:
    """Run ``cases`` (longest first) in ``workers`` processes (default: the CPUs, at most
    2; 1: in this process) with a tqdm bar on stderr; ``plots``: see :func:`run_case`."""
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
                results[c.name] = run_case(c, examples, quick, out, plots)
                bar.update()
        else:
            with ProcessPoolExecutor(workers, initializer=_worker_init) as pool:
                futures = {pool.submit(run_case, c, examples, quick, out, plots): c
                           for c in order}
                for f in as_completed(futures):
                    o = f.result()
                    results[o.name] = o
                    bar.set_postfix_str(f"{o.name} {o.status} {o.elapsed:.0f} s")
                    bar.update()
    finally:
        bar.close()
    return {c.name: results[c.name] for c in cases}


#: Rough cost per kind [CPU s] (longest first keeps both workers busy) ...
COST = {"isola": 15, "chart": 7, "width-sweep": 8, "simulate": 1.5, "fold-curve": 3,
        "response": 1.5, "modal": 1.4}
#: ... and of the cases that cost more than their kind [CPU s, measured 2026-12-02]; a
#: calibrated case costs about twice its literal one (dense modal damping).
CASE_COST = {"fig21-cr0.61": 12.5, "fig21-cr0.728": 7, "fig21-cr0.485": 5.3,
             "fig24-u144": 5.2, "fig24-u360": 4.1, "fig19-u252": 5.3, "fig19-u144": 3.4,
             "fig17-u252-w9": 3.9, "fig17-u252-w7": 3.1, "fig17-u360-w9": 3.0,
             "fig17-u360-w7": 2.7, "fig12-w9": 2.3, "fig12-w10": 2.3}


def case_cost(case: Case) -> float:
    """The expected CPU time of a case (:data:`CASE_COST`, else :data:`COST`)."""
    base = CASE_COST.get(literal_name(case.name), COST.get(case.kind, 1.0))
    return base * (2.0 if case.reading == "calibrated" else 1.0)


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


def run_paper(output: str | Path, figures: Sequence[str] | None = None, *,
              quick: bool = False, workers: int | None = None, progress: bool = True,
              examples: Path | None = None, case_plots: bool = False,
              readings: Sequence[str] = READINGS) -> PaperResult:
    """Run the cases of ``figures`` (all by default; ``quick``: Figure 7 only, shorter
    settings) in the ``readings`` (literal and calibrated; see
    :mod:`rotorsfd.paper.cases`), draw the figures and write the report into ``output``;
    the cases' results files go to ``output/cases/<case>``, with each analysis' own
    figures only if ``case_plots``."""
    import io

    from rotorsfd.paper.cases import select
    from rotorsfd.paper.figures import draw
    from rotorsfd.paper.report import DIAGNOSES, write_report

    t0 = time.perf_counter()
    out = Path(output)
    specs, cases = select(list(figures or []), quick, tuple(readings))
    outcomes = run_cases(cases, examples=examples, quick=quick, out=out / "cases",
                         workers=workers, progress=progress, plots=case_plots)
    pngs: dict[str, bytes] = {}
    for spec in specs:
        fig = draw(spec, outcomes)
        if fig is not None:
            buf = io.BytesIO()
            fig.savefig(buf, format="png", dpi=110)
            pngs[spec.number] = buf.getvalue()
    elapsed = time.perf_counter() - t0
    paths = write_report(out, outcomes, pngs, elapsed=elapsed, diagnoses=DIAGNOSES)
    return PaperResult(outcomes, paths, elapsed)
