"""The second branch at a branch point of a response: ``rotorsfd response CONFIG
--switch-at bp:N``.

N counts the branch's branch points from 1, in the order of the branch (the summary lines
and the ``pitchfork`` / ``transcritical`` / ``branch-point`` rows of
``bifurcations.csv``). At the N-th one, located on the HB equations
(:class:`~rotorsfd.stability.branch_points.LocatedBranchPoint`: ``z*``, the followed
tangent ``t1`` and the second tangent ``t2`` of the branching equation
``a11 a^2 + 2 a12 a b + a22 b^2 = 0``),
:func:`~rotorsfd.stability.branch_points.switch_branch_point` continues the second branch
both ways, from ``z* +- delta t2`` along ``+-t2`` (the two halves: mirror images under the
broken symmetry at a pitchfork), within the main branch's parameter range, with the same
H (the located point's), N_f scaling and element limit; Floquet stability of every point
as on the main branch. An untyped ``branch-point`` (no sign change of the bordered HB
determinant next to the +1 crossing) has no second branch of the HB equations: refused.

Written next to the main branch as ``branch_bp<N>.nc`` / ``branch_bp<N>.csv`` (a ``leg``
0 along +t2, 1 along -t2, then the columns of ``branch.csv``) and drawn over its response
figures by :class:`~rotorsfd.analyses.response_second_branch.SecondBranchResult`
(``at = "bp"``; the layout of both switches is in
:mod:`rotorsfd.analyses.response_second_branch`).
"""

from __future__ import annotations

import time
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.response_second_branch import (
    OPTION,
    SecondBranchResult,
    needs_stability,
    second_branch_problem,
    where_words,
)
from rotorsfd.errors import ConfigError
from rotorsfd.stability.branch_result import BRANCH_POINT_KINDS

if TYPE_CHECKING:
    from rotorsfd.analyses.response_result import ResponseResult

__all__ = ["ClosureStop", "check_branch_switch", "run_branch_switch",
           "second_branch_problem", "switch_kwargs"]

#: Distance of each leg's first point from the branch point along +-t2 (scaled units:
#: clearances), and the longest step along the legs.
DELTA, STEP_MAX = 0.01, 0.05
#: A leg closes on itself (the second branch of a tongue between two branch points is a
#: loop through both) when, after going further than ``CLOSURE_AWAY`` delta from its
#: first point, it crosses that point's parameter again within ``CLOSURE_NEAR`` of it
#: (the largest coefficient difference over the clearance; ~ the longest step).
CLOSURE_AWAY, CLOSURE_NEAR = 4.0, 2 * STEP_MAX
CLOSED = "closes on itself"


def branch_points(result: ResponseResult) -> list[int]:
    """Indices into ``result.bifurcations`` (and the stability's located bifurcations) of
    the branch points (typed or not), in the branch's order."""
    return [i for i, row in enumerate(result.bifurcations or ())
            if row["type"] in BRANCH_POINT_KINDS]


def check_branch_switch(result: ResponseResult, number: int, value: str = "") -> int:
    """The bifurcation index of the ``number``-th branch point (from 1); ConfigError
    naming ``--switch-at`` and ``value`` (default ``bp:<number>``) when the branch has
    none, fewer than ``number``, or that one is untyped (not located on the HB
    equations)."""
    value = value or f"bp:{number}"
    needs_stability(result, value)
    bps = branch_points(result)
    if not bps:
        raise ConfigError(OPTION, value, "the branch has no branch point (no Floquet "
                          "multiplier crosses +1 without a turn, no sign change of the "
                          "bordered HB determinant over its range); pd:N switches at a "
                          "period doubling")
    if not 1 <= number <= len(bps):
        where = ", ".join(f"{k + 1}: {result.bifurcations[i]['type']} at "
                          f"{where_words(result, result.bifurcations[i])}"
                          for k, i in enumerate(bps))
        raise ConfigError(OPTION, value, f"must be bp:1..bp:{len(bps)}, the branch's "
                          f"branch points ({where})")
    i = bps[number - 1]
    bif = result.info["stability"].bifurcations[i]
    if bif.info.get("branch_point") is None:
        raise ConfigError(OPTION, value, "that +1 crossing is an untyped branch-point: the "
                          "bordered HB determinant keeps its sign there, so the HB "
                          "equations have no second branch to switch to (raise H and the "
                          "intervals)")
    return i


class ClosureStop:
    """The event hook of the legs: stops a leg that closes on itself (see
    :data:`CLOSURE_AWAY`); a leg starts again at point index 0. ``closed`` holds the
    parameter of each leg's stop (None: it did not close)."""

    def __init__(self, clearance: float, delta: float) -> None:
        self.c, self.away = clearance, CLOSURE_AWAY * delta
        self.X0: NDArray[np.complex128] | None = None
        self.lam0 = self.lam_prev = 0.0
        self.left = False
        self.closed: list[float | None] = []

    def __call__(self, point: Any) -> bool:
        if point.index == 0 or self.X0 is None:
            self.X0, self.lam0, self.lam_prev = point.X, point.lam, point.lam
            self.left = False
            self.closed.append(None)
            return False
        h = min(point.X.shape[0], self.X0.shape[0])
        d = float(np.abs(point.X[:h] - self.X0[:h]).max()) / self.c
        crossed = (point.lam - self.lam0) * (self.lam_prev - self.lam0) <= 0
        self.lam_prev = point.lam
        if d > self.away:
            self.left = True
        elif self.left and crossed and d < CLOSURE_NEAR:
            self.closed[-1] = float(point.lam)
            return True
        return False


def switch_kwargs(result: ResponseResult, **continue_kw: Any) -> dict[str, Any]:
    """The keywords of :func:`~rotorsfd.stability.branch_points.switch_branch_point` the
    CLI uses: ``delta``, ``ds_max`` and the main branch's element limit."""
    return {"delta": DELTA, "ds_max": STEP_MAX,
            "limit_max": result.info.get("limit_max", 1.0), **continue_kw}


def run_branch_switch(result: ResponseResult, number: int, *, stability: bool = True,
                      value: str = "", **continue_kw: Any) -> SecondBranchResult:
    """The second branch at the ``number``-th branch point of ``result`` (module
    docstring); ``continue_kw`` override :func:`switch_kwargs`. ConfigError (the option
    named) when there is no such branch point."""
    # deferred: rotorsfd.stability loads numba (only when switching)
    from rotorsfd.stability.branch_points import switch_branch_point
    from rotorsfd.stability.branch_stability import branch_stability

    i = check_branch_switch(result, number, value)
    t0 = time.perf_counter()
    point = result.info["stability"].bifurcations[i].info["branch_point"]
    problem = second_branch_problem(result)
    lam = result.branch.lam
    kw = switch_kwargs(result, **continue_kw)
    stop = ClosureStop(result.clearance, kw["delta"])
    kw.setdefault("callback", stop)
    sw = switch_branch_point(problem, point, (float(lam.min()), float(lam.max())), **kw)
    sw.message = sw.message.replace("stopped by the callback", CLOSED)
    p = sw.point
    attrs = {"branch_point_kind": p.kind, "branch_point_parameter": p.lam,
             "branch_point_second_slope": p.second_slope,
             "branch_coefficients": np.asarray(p.coefficients, float),
             "delta": float(sw.delta)}
    out = SecondBranchResult(result, "bp", number, sw, result.bifurcations[i], float(p.lam),
                             attrs=attrs)
    out.info["closed"] = stop.closed
    if stability:
        options = result.info.get("stability_options")
        out.with_stability([branch_stability(leg, problem, options) for leg in sw.legs])
    out.elapsed = time.perf_counter() - t0
    return out
