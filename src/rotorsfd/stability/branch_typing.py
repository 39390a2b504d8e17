"""Branch points among a branch's located bifurcations: found by the bordered HB
determinant, located on the HB equations and typed.

:func:`branch_point_scan` takes the sign of ``tau_BP = det [J; t^T]``
(:mod:`~rotorsfd.stability.branch_points`) at every computed point (as the continuation
took it there, where it could) and keeps the
intervals where it changes sign while dlam/ds does not (a turn is a fold, where tau_BP
keeps its sign). :func:`type_branch_points` then, for each such interval,

- locates the branch point on the HB equations (Brent on tau_BP in the arc length) and
  types it (``pitchfork``: symmetry-breaking, the second branch tangent to lam = const;
  ``transcritical``: it crosses);
- attaches it to the Floquet crossing of +1 without a turn in (or next to) that interval:
  the bifurcation's ``lam`` and ``s`` become the HB branch point's (as a fold's are the
  turning point's), the Floquet one is kept in ``info['floquet_lam']``; without such a
  crossing (the HB Jacobian singular, the multipliers not resolving it) a new branch
  point is added with the multipliers there;
- a +1 crossing without a turn and without a sign change of tau_BP next to it is no
  branch point of the HB equations: it stays an untyped ``branch-point`` and a message
  says so.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.branch import Branch
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.hb_system import HBSystem
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.bifurcations import Bifurcation, BranchSample
from rotorsfd.stability.branch_options import StabilityOptions
from rotorsfd.stability.branch_points import (
    branch_system,
    harmonics_of,
    locate_branch_point,
    point_test,
    samples_of,
    stored_signs,
)
from rotorsfd.stability.branch_result import reported_kind

#: The short type names of :func:`~rotorsfd.stability.branch_result.reported_kind`.
SHORT = {"symmetry-breaking pitchfork": "pitchfork", "transcritical": "transcritical"}


@dataclass
class BranchPointScan:
    """The sign of the bordered test at every point (``tests``: as the continuation took
    it, else in a system of the point's H), the intervals i (points i, i+1) where it
    changes sign without a turn, and the HB systems it was re-evaluated in, by (H, N_f)."""

    tests: NDArray[np.float64]
    intervals: list[int]
    systems: dict[tuple[int, int], HBSystem] = field(repr=False)


def branch_point_scan(branch: Branch, problem: PeriodicProblem) -> BranchPointScan | None:
    """:class:`BranchPointScan` of a condensed branch with tangents; None where the test
    does not apply (a full-HB branch, fewer than 2 points) or cannot be evaluated. Two
    neighbours the continuation took the sign at in one HB system
    (:func:`~rotorsfd.stability.branch_points.stored_signs`) are compared as stored, with
    no re-evaluation; the others are evaluated in a system of the branch's scaling
    (:func:`~rotorsfd.stability.branch_points.branch_system`): an interval whose ends
    have different H or N_f (adaptive harmonics or samples) with both ends in the system
    of the second's H and N_f (the first padded or cut: near a solution, the sign is that
    of the solution's)."""
    if branch.n_points < 2 or branch.tangents.size == 0 or not branch.condensed:
        return None
    Hs, Ns = harmonics_of(branch), samples_of(branch)
    systems: dict[tuple[int, int], HBSystem] = {}
    cache: dict[tuple[int, int, int], float] = {}
    stored = stored_signs(branch)

    def test(i: int, j: int) -> float:   # point i in the system of point j's H and N_f
        key = (int(Hs[j]), int(Ns[j]))
        if (i, *key) not in cache:
            if key not in systems:
                systems[key] = branch_system(problem, branch, j)
            cache[(i, *key)] = point_test(systems[key], problem, branch, i)
        return cache[(i, *key)]

    def pair(i: int) -> tuple[float, float]:
        if stored is not None:
            sign, system = stored
            if system[i] == system[i + 1] and np.isfinite(sign[i] * sign[i + 1]):
                return float(sign[i]), float(sign[i + 1])
        return test(i, i + 1), test(i + 1, i + 1)

    def own(i: int) -> float:
        if stored is not None and np.isfinite(stored[0][i]):
            return float(stored[0][i])
        return test(i, i)

    try:
        pairs = [pair(i) for i in range(branch.n_points - 1)]
        tests = np.array([own(i) for i in range(branch.n_points)])
    except (ValueError, ArithmeticError, ConvergenceError, np.linalg.LinAlgError):
        return None
    if not np.all(np.isfinite(tests)):
        return None
    turn = np.sign(branch.tangents[:, -1])
    intervals = [i for i, (a, b) in enumerate(pairs)
                 if a * b < 0 and turn[i] * turn[i + 1] > 0]
    return BranchPointScan(tests, intervals, systems)


def _critical_plus_one(mu: NDArray[np.complex128]) -> complex:
    mu = np.asarray(mu, dtype=complex)
    return complex(mu[int(np.argmin(np.abs(mu - 1.0)))]) if mu.size else complex(np.nan)


def type_branch_points(bifs: list[Bifurcation], scan: BranchPointScan, branch: Branch,
                       problem: PeriodicProblem, samples: list[BranchSample],
                       multipliers: Callable[[float, NDArray], NDArray],
                       options: StabilityOptions, messages: list[str]
                       ) -> list[Bifurcation]:
    """The bifurcations with the branch points located, typed and attached (module
    docstring), in arc-length order; ``multipliers(lam, X)`` gives the Floquet multipliers
    of a point (for a branch point that no multiplier crossing announced)."""
    plus_one = [b for b in bifs if reported_kind(b) == "branch-point"]
    out = list(bifs)
    used: set[int] = set()
    for i in scan.intervals:
        try:
            bp = locate_branch_point(problem, branch, i, scan.systems.get(
                (int(harmonics_of(branch)[i + 1]), int(samples_of(branch)[i + 1]))))
        except (ConvergenceError, ArithmeticError, ValueError, np.linalg.LinAlgError) as exc:
            messages.append(f"branch point between lam = {branch.lam[i]:.9g} and "
                            f"{branch.lam[i + 1]:.9g} (the bordered HB determinant changes "
                            f"sign) not located: {' '.join(str(exc).split())}")
            continue
        near = [b for b in plus_one if id(b) not in used
                and abs(int(b.info.get("bracket", (-9, -9))[0]) - i) <= 1]
        info = {"branch_point": bp, "branch_type": SHORT[bp.kind],
                "second_slope": bp.second_slope}
        if near:
            b = min(near, key=lambda x: abs(x.lam - bp.lam))
            used.add(id(b))
            gap = abs(b.lam - bp.lam) / max(abs(bp.lam), np.finfo(float).tiny)
            info["floquet_lam"] = b.lam
            b.lam, b.s = bp.lam, bp.s
            b.info.update(info)
            if gap > 10 * options.rtol:
                messages.append(f"{SHORT[bp.kind]} at lam = {bp.lam:.9g} (HB branch point): "
                                f"the multiplier crosses +1 at lam = {info['floquet_lam']:.9g}"
                                f", {gap:.1e} (relative) away: the HB truncation and Floquet "
                                "discretisation error; raise H and the intervals")
            continue
        try:
            mu = np.asarray(multipliers(bp.lam, bp.X), dtype=complex)
        except (ConvergenceError, ArithmeticError, ValueError):
            mu = np.asarray(samples[i + 1].multipliers, dtype=complex)
        j = i if abs(samples[i].s - bp.s) <= abs(samples[i + 1].s - bp.s) else i + 1
        crit = _critical_plus_one(mu)
        info.update(point=j, reported=_critical_plus_one(samples[j].multipliers),
                    bracket=(i, i + 1))
        out.append(Bifurcation("saddle-node", bp.s, bp.lam, mu, crit, "determinant", 0,
                               (float(branch.lam[i]), float(branch.lam[i + 1])), info))
        messages.append(f"{SHORT[bp.kind]} at lam = {bp.lam:.9g}: the HB Jacobian is "
                        "singular there (the bordered determinant changes sign) without a "
                        "Floquet multiplier crossing +1 between the computed points "
                        f"(nearest +1: {crit.real:.5f}{crit.imag:+.5f}i)")
    for b in plus_one:
        if id(b) not in used:
            b.info["branch_type"] = ""
            messages.append(f"branch-point at lam = {b.lam:.9g}: a multiplier crosses +1 "
                            "without a turn but the bordered HB determinant keeps its sign "
                            "there: no branch point of the HB equations (the truncated "
                            "orbit's multiplier: raise H and the intervals)")
    return sorted(out, key=lambda x: x.s)
