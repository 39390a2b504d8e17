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

Written next to the main branch: ``branch_bp<N>.nc`` (:mod:`rotorsfd.io.branch_files`
layout, harmonics of Omega as in ``branch.nc``, a ``leg`` variable: 0 along +t2, 1 along
-t2) and ``branch_bp<N>.csv`` (the columns of ``branch.csv`` after a ``leg`` column), and
drawn in ``response_deflection.png`` and ``response_node<n>.png`` over the main branch.
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.response_switch import OPTION, where_words
from rotorsfd.analyses.response_words import system_parameter
from rotorsfd.continuation.branch import Branch
from rotorsfd.errors import ConfigError
from rotorsfd.stability.branch_result import BRANCH_POINT_KINDS

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from rotorsfd.analyses.response_result import ResponseResult
    from rotorsfd.stability.branch_points import BranchPointSwitch

#: Distance of each leg's first point from the branch point along +-t2 (scaled units:
#: clearances), and the longest step along the legs.
DELTA, STEP_MAX = 0.01, 0.05
#: A leg closes on itself (the second branch of a tongue between two branch points is a
#: loop through both) when, after going further than ``CLOSURE_AWAY`` delta from its
#: first point, it crosses that point's parameter again within ``CLOSURE_NEAR`` of it
#: (the largest coefficient difference over the clearance; ~ the longest step).
CLOSURE_AWAY, CLOSURE_NEAR = 4.0, 2 * STEP_MAX
CLOSED = "closes on itself"


def files(number: int) -> tuple[str, str]:
    """The names of the second branch's files at branch point ``number``."""
    return f"branch_bp{number}.nc", f"branch_bp{number}.csv"


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
    if result.bifurcations is None or "stability" not in result.info:
        raise ConfigError(OPTION, value, "needs the branch's Floquet stability: set "
                          "[analysis.stability] enabled = true")
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


def joined(legs: list[Branch], message: str) -> Branch:
    """The legs as one Branch (points of leg 0, then leg 1)."""
    first = legs[0]
    cat = {name: np.concatenate([getattr(b, name) for b in legs])
           for name in ("lam", "X", "frequency", "tangents", "iterations", "ds", "s",
                        "aliasing")}
    return dataclasses.replace(first, **cat, jacobians=None,
                               success=all(b.success for b in legs), message=message,
                               info={}, resolver=None)


@dataclass
class SecondBranchResult:
    """The second branch at the ``number``-th branch point of ``main``."""

    main: ResponseResult
    number: int
    switch: BranchPointSwitch
    stable: NDArray[np.bool_] | None = None
    max_multiplier: NDArray[np.float64] | None = None
    elapsed: float = 0.0
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def branch(self) -> Branch:
        """The legs as one Branch (harmonics of Omega, as the main branch)."""
        return joined(self.switch.legs, self.switch.message)

    @property
    def leg(self) -> NDArray[np.int64]:
        """The leg of every point: 0 along +t2, 1 along -t2 (the legs that converged)."""
        return np.concatenate([np.full(b.n_points, i, dtype=np.int64)
                               for i, b in enumerate(self.switch.legs)])

    @property
    def as_response(self) -> ResponseResult:
        """The second branch as a ResponseResult of the main one's system and outputs (its
        table and dataset are those of ``branch.csv`` / ``branch.nc``)."""
        return dataclasses.replace(self.main, branch=self.branch, stable=self.stable,
                                   max_multiplier=self.max_multiplier, multipliers=None,
                                   bifurcations=None, elapsed=self.elapsed, info={})

    @property
    def kind(self) -> str:
        return str(self.main.bifurcations[check_branch_switch(self.main, self.number)]
                   ["type"])

    def where(self, tex: bool = False) -> str:
        row = self.main.bifurcations[check_branch_switch(self.main, self.number)]
        return where_words(self.main, row, tex)

    @property
    def label(self) -> str:
        """The legend entry / netCDF attribute: the second branch and where it starts."""
        return f"second branch (from the {self.kind} at {self.where()})"

    def table(self) -> dict[str, NDArray[Any]]:
        """The columns of ``branch_bp<N>.csv``: ``leg``, then those of ``branch.csv``."""
        return {"leg": self.leg, **self.as_response.table()}

    def write(self, directory: str | Path) -> dict[str, Path]:
        """Write ``branch_bp<N>.nc`` and ``branch_bp<N>.csv`` atomically."""
        # deferred: io.branch_files loads xarray (only when writing)
        from rotorsfd.io.branch_files import write_netcdf, write_table

        out, sw, p = Path(directory), self.switch, self.switch.point
        ds = self.as_response.to_dataset()
        ds["leg"] = ("point", self.leg, {"long_name": "leg of the second branch: 0 along "
                                         "+t2, 1 along -t2", "units": "1"})
        ds.attrs.update({"branch": self.label, "switched_at": f"bp:{self.number}",
                         "branch_point_kind": p.kind, "branch_point_parameter": p.lam,
                         "branch_point_second_slope": p.second_slope,
                         "branch_coefficients": np.asarray(p.coefficients, float),
                         "delta": float(sw.delta), "outcome": sw.message})
        nc, csv = files(self.number)
        return {nc: write_netcdf(ds, out / nc), csv: write_table(out / csv, self.table())}

    def draw(self, figures: dict[str, Figure]) -> None:
        """Draw the second branch over the main branch's response figures (r~ and the
        first harmonic |X_1|/C, each leg on its own line, dashed where unstable)."""
        from rotorsfd.plots.second_branch import draw_second_branch  # deferred: matplotlib

        m = self.main
        tab = self.table()
        x = tab["speed_ratio"] if m.is_speed else tab[m.parameter_column]
        legend = f"second branch, from the {self.kind} at {self.where(True)}"
        pieces = [tab["leg"] == k for k in range(len(self.switch.legs))]
        draw_second_branch(
            figures, x, tab.get("stable"), {n: tab[f"defl_{n}"] for n in m.nodes},
            {(n, d): tab[f"amp_{n}_{d}_h1"] / m.clearance for n in m.nodes
             for d in m.directions},
            nodes=m.nodes, directions=m.directions, legend=legend,
            amplitude_legend=legend.replace("second branch", "second branch: its 1X"),
            main_stable=m.stable, bifurcations=m.bifurcations or (), pieces=pieces)

    def summary(self) -> str:
        """A few lines: where it starts, its points and range, the legs' outcome."""
        m, sw = self.main, self.switch
        b = self.branch
        x = self.as_response.speeds / m.reference_speed if m.is_speed else b.lam
        name = "Omega~" if m.is_speed else m.parameter
        lines = [f"second branch (H = {b.H}) from branch point {self.number}, the "
                 f"{self.kind} at {self.where()}: {b.n_points} points in "
                 f"{len(sw.legs)} leg(s), {name} {x.min():.5g} .. {x.max():.5g}, "
                 f"{self.elapsed:.2f} s", m.in_user_terms(sw.message)]
        if self.stable is not None:
            lines.append(f"second-branch unstable points: {int(np.sum(~self.stable))} of "
                         f"{self.stable.size}")
        return "\n".join(lines)


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


def second_branch_problem(result: ResponseResult) -> Any:
    """The periodic problem the main branch was continued on (speed or a system
    parameter at the fixed speed)."""
    sys_param = system_parameter(result.parameter)
    return result.system.periodic_problem(sys_param, None if sys_param == "speed"
                                          else result.speed)


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
    out = SecondBranchResult(result, number, sw)
    out.info["closed"] = stop.closed
    if stability:
        options = result.info.get("stability_options")
        sts = [branch_stability(leg, problem, options) for leg in sw.legs]
        out.stable = np.concatenate([s.stable for s in sts])
        out.max_multiplier = np.concatenate([s.max_multiplier for s in sts])
    out.elapsed = time.perf_counter() - t0
    return out
