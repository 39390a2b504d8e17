"""Floquet stability of every point of a branch of periodic solutions, and its bifurcations
located and classified (paper section 3.2, Tables 1 and 3).

Per point: the multipliers of the perturbation equation along the HB orbit (paper eq. 30),
by :class:`~rotorsfd.stability.floquet_evaluator.FloquetEvaluator` (Craig-Bampton basis once
per (M, K), the Newmark step controlled per point).

Bifurcations, detected between consecutive points by the test functions of
:mod:`rotorsfd.stability.bifurcations` and located along the arc length (``Branch.point_at``)
to a relative parameter tolerance ``rtol`` (default 1e-6):

* saddle-node: a real multiplier through +1 and/or a sign change of dlam/ds. When the
  branch turns, the located point is the turning point ``dlam/ds = 0`` (exact for the
  HB equations; the Newmark multiplier there is ``1 + O(1e-4)``, its discretisation
  error); without a turn it is a branch point (below), not a saddle-node.
  A multiplier crossing +1 within ``fold_merge_rtol`` (1e-3) of a turning point is that
  fold: for a truncated HB orbit they differ by the truncation error (paper rotor under
  pitching, U = 144.02 g mm: 2.6e-4 at H = 3, < 1e-5 at H = 8); the gap is reported.
  So is a crossing farther away when no multiplier crosses +1 across the nearest turning
  point (and no other turn lies between): the isola of the C/R = 0.728 % case has, at
  H = 16 and N = 400, its only +1 crossing at Omega~ 1.0904 and |mu| = 1.037 at the turn
  1.0939; at H = 24, N = 1600 the crossing is in the turning interval.
* branch point: a real multiplier through +1 where the branch does not turn, or a sign
  change of the bordered HB determinant ``det [J; t^T]`` there
  (:mod:`~rotorsfd.stability.branch_points`): located on the HB equations, typed
  ``pitchfork`` (symmetry-breaking) or ``transcritical`` by its second tangent
  (:mod:`~rotorsfd.stability.branch_typing`); a +1 crossing without that sign change stays
  an untyped ``branch-point`` with a message (no branch point of the HB equations).
* period-doubling: a real multiplier through -1 (``det(Phi + I)`` changes sign).
* secondary-hopf: a complex pair leaves the unit circle (``|mu|^2 - 1`` of the pair).

The options come from :mod:`~rotorsfd.stability.branch_options`, the result and what each
bifurcation is reported as from :mod:`~rotorsfd.stability.branch_result`.
"""

from __future__ import annotations

import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.branch import Branch
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.bifurcations import (
    IMAG_TOL,
    Bifurcation,
    Bracket,
    BranchSample,
    critical_value,
    crossing_signs,
    detect,
    find_bifurcations,
    locate,
)
from rotorsfd.stability.branch_options import (
    FOLD_MULTIPLIER_TOL,
    METHODS,
    REDUCED_METHODS,
    StabilityOptions,
)
from rotorsfd.stability.branch_result import BranchStability, located_critical, reported_kind
from rotorsfd.stability.branch_typing import branch_point_scan, type_branch_points
from rotorsfd.stability.floquet import STABILITY_TOL, FloquetResult
from rotorsfd.stability.floquet_evaluator import (
    HALVE_FRACTION,
    N_COMPARED,
    FloquetEvaluator,
    multiplier_change,
)
from rotorsfd.stability.hill import LADDER_TOL

#: Names defined in the split-out modules, importable from here as before the split.
__all__ = ["FOLD_MULTIPLIER_TOL", "HALVE_FRACTION", "METHODS", "N_COMPARED",
           "REDUCED_METHODS", "BranchStability", "FloquetEvaluator", "StabilityOptions",
           "branch_stability", "located_critical", "multiplier_change", "reported_kind"]


def _pad(rows: list[NDArray]) -> tuple[NDArray[np.complex128], NDArray[np.int64]]:
    counts = np.array([r.size for r in rows], dtype=np.int64)
    out = np.zeros((len(rows), int(counts.max()) if rows else 0), dtype=complex)
    for i, r in enumerate(rows):
        out[i, : r.size] = r
    return out, counts


def _merge_folds(brackets: list[Bracket], samples: list[BranchSample], rtol: float,
                 dead_band: float = STABILITY_TOL, branch_points: Sequence[int] = ()
                 ) -> tuple[list[Bracket], dict[int, Bracket]]:
    """One bracket per fold. A multiplier-only saddle-node bracket is the same fold as the
    nearest tangent (turning-point) bracket when it is next to it (within one interval:
    the method's lag), its parameter is within ``rtol`` (relative) of it, or no real
    multiplier crosses +1 across that turning point itself and no other turning point
    lies between them: at a turning point of the exact orbit a multiplier is +1, so a
    turn without a crossing and a crossing without a turn are one fold displaced by the
    numerical error (HB truncation, Floquet discretisation; isola of the C/R 0.728 % case
    at H = 16, N = 400: 3.2e-3 apart, one interval apart at H = 24, N = 1600). Returns the
    kept brackets and, by id of a kept tangent bracket, the merged multiplier one. A
    crossing next to (within one interval of) a sign change of the bordered HB
    determinant without a turn (``branch_points``: their intervals) is a branch point,
    never merged."""
    index = {id(p): i for i, p in enumerate(samples)}
    tang = [b for b in brackets if b.kind == "saddle-node" and b.via == "tangent"]
    turns = sorted(index[id(t.a)] for t in tang)

    def crossless(t: Bracket) -> bool:
        return (crossing_signs(t.a.multipliers, dead_band)["saddle-node"]
                == crossing_signs(t.b.multipliers, dead_band)["saddle-node"])

    out, merged = [], {}
    for b in brackets:
        i = index[id(b.a)]
        if any(abs(i - j) <= 1 for j in branch_points):
            out.append(b)
            continue
        if b.kind == "saddle-node" and b.via == "multiplier" and tang:
            t = min(tang, key=lambda x: abs(index[id(x.a)] - i))
            it = index[id(t.a)]
            lam_b = 0.5 * (b.a.lam + b.b.lam)
            lam_t = 0.5 * (t.a.lam + t.b.lam)
            alone = not any(min(i, it) < j < max(i, it) for j in turns)
            if (abs(it - i) <= 1 or abs(lam_b - lam_t) <= rtol * abs(lam_t)
                    or (alone and crossless(t))) and id(t) not in merged:
                merged[id(t)] = b
                continue
        out.append(b)
    return out, merged


def _largest(kind: str, mu: NDArray) -> complex:
    """The multiplier of the crossing type (real > 0, real < 0, complex Im > 0) of
    largest modulus (NaN if none)."""
    mu = np.asarray(mu, dtype=complex)
    real = np.abs(mu.imag) <= IMAG_TOL * np.maximum(1.0, np.abs(mu))
    if kind == "secondary-hopf":
        c = mu[~real & (mu.imag > 0)]
    else:
        c = mu[real & ((mu.real > 0) if kind == "saddle-node" else (mu.real < 0))]
    return complex(c[np.argmax(np.abs(c))]) if c.size else complex(np.nan, np.nan)


def _reported(kind: str, samples: list[BranchSample], ia: int, ib: int, tol: float,
              s_star: float) -> tuple[int, complex]:
    """The computed point nearest to the bifurcation (arc length s*) with a multiplier of
    the crossing type outside the unit circle (|mu| > 1 + tol): its index and that
    multiplier; if there is none, the nearer bracket end."""
    order = sorted(range(len(samples)), key=lambda j: abs(samples[j].s - s_star))
    for j in order:
        c = _largest(kind, samples[j].multipliers)
        if np.isfinite(c) and abs(c) > 1.0 + tol:
            return j, c
    j = ia if abs(samples[ia].s - s_star) <= abs(samples[ib].s - s_star) else ib
    return j, _largest(kind, samples[j].multipliers)


def _floquet_crossing(fold: Bifurcation, bracket: Bracket, solve_at: Callable,
                      o: StabilityOptions, messages: list[str]) -> None:
    """Locate the multiplier crossing merged into ``fold``; store it in
    ``fold.info['floquet_lam']`` and say how far it is from the HB turning point when that
    exceeds ``rtol`` (an estimate of the HB truncation error: raise H)."""
    try:
        c = locate(bracket, solve_at, rtol=o.rtol)
    except (ConvergenceError, ArithmeticError, ValueError):
        return
    fold.info["floquet_lam"] = c.lam
    gap = abs(c.lam - fold.lam) / abs(fold.lam)
    if gap > 10 * o.rtol:
        messages.append(f"saddle-node at lam = {fold.lam:.9g} (turning point): a multiplier "
                        f"crosses +1 at lam = {c.lam:.9g}, {gap:.1e} (relative) away; the "
                        "gap measures the HB truncation and Floquet discretisation error: "
                        "raise H and the Floquet intervals to shrink it")


def _hill_resolution(results: list[FloquetResult]) -> list[str]:
    """A message when Hill's largest multiplier is not resolved by the truncation (its
    ladder defect, :func:`rotorsfd.stability.hill.ladder_defect`, above ``LADDER_TOL``) at
    some points: its value and crossing type are then unreliable."""
    d = np.array([r.info.get("critical_defect", 0.0) for r in results], dtype=float)
    bad = ~(d <= LADDER_TOL)
    if not results or not bad.any():
        return []
    H = results[0].info.get("n_harmonics")
    return [f"hill (H = {H}): the largest multiplier is not resolved by the truncation at "
            f"{int(bad.sum())} of {len(results)} points (ladder defect up to "
            f"{np.nanmax(np.where(bad, d, np.nan)):.1e} > {LADDER_TOL:g}): its value and "
            "crossing type are unreliable there; raise n_harmonics or use newmark-cb"]


#: interior points sampled when a located secondary Hopf is off the unit circle
REFINE_POINTS = 8


def _refined(br: Bracket, solve_at: Callable, o: StabilityOptions) -> list[Bifurcation]:
    """The crossings of a bracket re-detected on ``REFINE_POINTS`` interior points and
    located: a complex pair whose modulus passes 1 between two points may have met the
    real axis in between (a narrow locking range: the crossing there is a period doubling
    or a real multiplier through +1), which the endpoints alone cannot tell."""
    ss = np.linspace(br.a.s, br.b.s, REFINE_POINTS + 2)[1:-1]
    try:
        inner = [BranchSample.from_solve(float(x), solve_at(float(x))) for x in ss]
        out = []
        for sub in detect([br.a, *inner, br.b], o.tol):
            out.append(locate(sub, solve_at, rtol=o.rtol))
    except (ConvergenceError, ArithmeticError, ValueError):
        return []
    if all(f.kind == "secondary-hopf" and abs(abs(f.critical) - 1.0) > 0.05 for f in out):
        return []      # nothing better than the endpoints' picture
    return out


def branch_stability(branch: Branch, problem: PeriodicProblem,
                     options: StabilityOptions | None = None, *,
                     progress: Callable[[int, int], None] | None = None) -> BranchStability:
    """Floquet multipliers of every point of ``branch`` (a branch of ``problem``) and its
    bifurcations located to ``options.rtol`` (module docstring).

    ``progress(i, n)`` is called after each point (and with ``i = n`` when locating).
    Bifurcations that cannot be located (re-solve fails, e.g. at journal contact) are
    kept with their interpolated position and a message in ``messages``.
    """
    o = options or StabilityOptions()
    ev = FloquetEvaluator(problem, o)
    t0 = time.perf_counter()
    results = []
    n = branch.n_points
    for i in range(n):
        results.append(ev(float(branch.lam[i]), branch.X[i]))
        if progress is not None:
            progress(i + 1, n)
    t_points = time.perf_counter() - t0
    ev.with_outside = False     # the located re-solves report no max_multiplier_outside
    dlam = branch.dlam_ds if branch.tangents.size else np.full(n, np.nan)
    s = branch.s if branch.s.size == n else np.arange(n, dtype=float)
    samples = [BranchSample(float(s[i]), float(branch.lam[i]), r.multipliers,
                            float(dlam[i]) if np.isfinite(dlam[i]) else None)
               for i, r in enumerate(results)]
    scan = branch_point_scan(branch, problem) if o.locate else None
    brackets, merged = _merge_folds(detect(samples, o.tol), samples, o.fold_merge_rtol,
                                    o.tol, scan.intervals if scan is not None else ())
    index = {id(p): i for i, p in enumerate(samples)}

    located: dict[float, tuple[Any, FloquetResult]] = {}   # this bracket's re-solves

    def solve_at(s_: float) -> tuple[float, NDArray, float]:
        p = branch.point_at(s_)
        res = ev(p.lam, p.X)
        located[float(s_)] = (p, res)
        return p.lam, res.multipliers, p.dlam_ds

    bifs: list[Bifurcation] = []
    messages: list[str] = _hill_resolution(results)
    can_locate = o.locate and branch.resolver is not None
    for br in brackets:
        ia, ib = index[id(br.a)], index[id(br.b)]
        b = None
        if can_locate:
            located.clear()
            try:
                b = locate(br, solve_at, rtol=o.rtol)
                if float(b.s) in located:   # the point and multipliers there, for reuse
                    b.info["located"] = located[float(b.s)]
            except (ConvergenceError, ArithmeticError, ValueError) as err:
                messages.append(f"{br.kind} between lam = {br.a.lam:.9g} and "
                                f"{br.b.lam:.9g} not located: {err}")
        if b is None:  # interpolated position, multipliers of the nearer end
            est = [x for x in find_bifurcations([br.a, br.b], None, dead_band=o.tol)
                   if x.kind == br.kind]
            b = est[0] if est else Bifurcation(br.kind, br.b.s, br.b.lam, br.b.multipliers,
                                               critical_value(br.kind, br.b.multipliers)[1],
                                               br.via)
        if id(br) in merged:
            b.info["merged"] = True
            if can_locate:
                _floquet_crossing(b, merged[id(br)], solve_at, o, messages)
        if (b.via == "tangent" and b.kind == "saddle-node" and can_locate
                and not abs(b.critical - 1.0) <= FOLD_MULTIPLIER_TOL):
            messages.append(f"saddle-node at lam = {b.lam:.9g} (turning point): the "
                            f"multiplier nearest +1 there is {located_critical(b):.5f}, "
                            "not +1: "
                            "the orbit's truncation (H) or the Floquet step does not "
                            "resolve the exchange of stability at this fold, so the "
                            "stability flags next to it are unreliable; raise H (or use "
                            "harmonics = 'auto') and the intervals")
        if (can_locate and b.kind == "secondary-hopf"
                and abs(abs(b.critical) - 1.0) > 0.05):
            finer = _refined(br, solve_at, o)
            if finer:   # e.g. a pair that meets the real axis: period doublings inside
                for f in finer:   # the nearest computed points carry the complex pair:
                    j = ia if abs(br.a.s - f.s) <= abs(br.b.s - f.s) else ib   # report it
                    mu = np.asarray(samples[j].multipliers, dtype=complex)
                    rep = complex(mu[np.argmax(np.abs(mu))]) if mu.size else 0j
                    f.info.update(point=j, reported=rep, bracket=(ia, ib), refined=True)
                    bifs.append(f)
                messages.append(f"secondary-hopf between lam = {br.a.lam:.9g} and "
                                f"{br.b.lam:.9g} not on the unit circle at its located "
                                f"point: {len(finer)} crossing(s) found on a finer sampling "
                                "of the interval (" + ", ".join(
                                    f"{f.kind} at {f.lam:.9g}" for f in finer) + ")")
                continue
        if b.via != "tangent" and abs(abs(b.critical) - 1.0) > 0.05:
            messages.append(f"{b.kind} at lam = {b.lam:.9g}: the multiplier at the located "
                            f"point is {b.critical:.4f}, far from the unit circle (a pair "
                            "meeting the real axis, or an unresolved stiff mode): check "
                            "with more intervals or method='hill'")
        j, rep = _reported(br.kind, samples, ia, ib, o.tol, b.s)
        b.info.update(point=j, reported=rep, bracket=(ia, ib))
        bifs.append(b)
    if scan is not None and can_locate:
        bifs = type_branch_points(bifs, scan, branch, problem, samples,
                                  lambda lam, X: ev(lam, X).multipliers, o, messages)
    if progress is not None:
        progress(n, n)
    mu, counts = _pad([r.multipliers for r in results])
    le = np.array([r.liouville_error or 0.0 for r in results], dtype=float)
    return BranchStability(
        lam=np.asarray(branch.lam, float).copy(),
        frequency=np.asarray(branch.frequency, float).copy(),
        stable=np.array([r.stable for r in results], dtype=bool),
        max_multiplier=np.array([r.max_abs for r in results], dtype=float),
        critical=np.array([r.critical for r in results], dtype=complex),
        multipliers=mu, n_multipliers=counts,
        liouville_error=np.where(np.isfinite(le), le, 0.0), bifurcations=bifs,
        method=results[0].method if results else o.method, tol=o.tol,
        elapsed=time.perf_counter() - t0, elapsed_points=t_points, n_bases=ev.n_bases,
        messages=messages,
        n_intervals=np.array([r.info.get("n_intervals", o.n_intervals) for r in results],
                             dtype=np.int64),
        multiplier_error=np.array([r.info["multiplier_error"] for r in results], float)
        if results and all("multiplier_error" in r.info for r in results) else None,
        basis=o.basis_label,
        max_multiplier_outside=np.array([r.info["max_multiplier_outside"] for r in results],
                                        dtype=float)
        if results and all("max_multiplier_outside" in r.info for r in results) else None,
        n_modes=np.array([r.info.get("n_modes", 0) for r in results], dtype=np.int64))

