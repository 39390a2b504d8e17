"""The second branch of a response, switched at one of its bifurcations: ``rotorsfd
response CONFIG --switch-at pd:N | bp:N | N``. One result type for both switches
(:class:`SecondBranchResult`, ``at`` says which), one writer, one summary, one drawing;
the switches themselves are :mod:`rotorsfd.analyses.response_switch` (``pd:N``, or plain
``N``: the period-2 branch at the N-th period doubling) and
:mod:`rotorsfd.analyses.response_branch_switch` (``bp:N``: the second branch at the N-th
branch point).

Written next to the main branch, in one layout for both (:meth:`SecondBranchResult.write`):
``branch_period2.nc`` / ``branch_period2.csv`` (``pd``) or ``branch_bp<N>.nc`` /
``branch_bp<N>.csv`` (``bp``). The CSV is a ``leg`` column, then the columns of
``branch.csv`` (:meth:`ResponseResult.table`) of the branch as a response of period
``p`` T (``p`` = 2 for ``pd``, 1 for ``bp``), whose harmonic k has the frequency
``k Omega / p``::

    amp_<n>_<d>_h<j>     = |X_{jp}|  [m]   (the speed's harmonics)
    amp_<n>_<d>_h<k>_2   = |X_k|, k odd   (pd only: the k/2 x speed subharmonics)
    sub_<n>              = sqrt(sum_k odd |X_k,y|^2 + |X_k,z|^2) / C   (pd only)

The netCDF is ``branch.nc``'s layout (:mod:`rotorsfd.io.branch_files`; ``frequency_rad_s``
is Omega / p) with a ``leg`` variable and the attributes ``branch`` (what it is and where it
starts), ``switch`` (``period-doubling`` / ``branch-point``), ``switched_at`` (``pd:N`` /
``bp:N``), ``period``, ``bifurcation_parameter``, ``outcome``, ``elapsed_s`` and the
switch's own (:attr:`SecondBranchResult.attrs`).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any, Literal

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.response_words import system_parameter
from rotorsfd.continuation.branch import Branch
from rotorsfd.errors import ConfigError

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from rotorsfd.analyses.response_result import ResponseResult

OPTION = "--switch-at"
OMEGA_TEX = r"$\tilde\Omega$"
#: The two switches: the period of the second branch's orbits (in T), the name of the
#: branch, what its legs are.
PERIOD = {"pd": 2, "bp": 1}
NAME = {"pd": "period-2 branch", "bp": "second branch"}
LEGS = {"pd": "leg of the period-2 branch: 0 the first continued, 1 from where it turned "
              "back",
        "bp": "leg of the second branch: 0 along +t2, 1 along -t2"}
SWITCH = {"pd": "period-doubling", "bp": "branch-point"}


def where_words(result: ResponseResult, row: dict[str, Any], tex: bool = False) -> str:
    """Where a bifurcation row is, in user terms (``Omega~ = ...`` or the parameter)."""
    if result.is_speed:
        return f"{OMEGA_TEX if tex else 'Omega~'} = {row['speed_ratio']:.5g}"
    return f"{result.parameter} = {row['parameter']:.6g} {result.parameter_units}"


def needs_stability(result: ResponseResult, value: Any) -> None:
    """ConfigError naming ``--switch-at`` and ``value`` when the branch has no Floquet
    stability (no bifurcations to switch at)."""
    if result.bifurcations is None or "stability" not in result.info:
        raise ConfigError(OPTION, value, "needs the branch's Floquet stability: set "
                          "[analysis.stability] enabled = true")


def joined(legs: Sequence[Branch], message: str) -> Branch:
    """The legs as one Branch (points of leg 0, then leg 1)."""
    first = legs[0]
    cat = {name: np.concatenate([getattr(b, name) for b in legs])
           for name in ("lam", "X", "frequency", "tangents", "iterations", "ds", "s",
                        "aliasing")}
    return dataclasses.replace(first, **cat, jacobians=None,
                               success=all(b.success for b in legs), message=message,
                               info={}, resolver=None)


def second_branch_problem(result: ResponseResult) -> Any:
    """The periodic problem the main branch was continued on (speed or a system
    parameter at the fixed speed)."""
    sys_param = system_parameter(result.parameter)
    return result.system.periodic_problem(sys_param, None if sys_param == "speed"
                                          else result.speed)


def files(at: str, number: int) -> tuple[str, str]:
    """The names of the second branch's files: ``branch_period2.*`` at a period doubling,
    ``branch_bp<N>.*`` at branch point N."""
    stem = "branch_period2" if at == "pd" else f"branch_{at}{number}"
    return f"{stem}.nc", f"{stem}.csv"


@dataclass
class SecondBranchResult:
    """The second branch switched at the ``number``-th bifurcation of kind ``at`` of
    ``main`` (``"pd"``: the period-2 branch at a period doubling, ``"bp"``: at a branch
    point). ``switch``: the switch's own outcome
    (:class:`~rotorsfd.harmonic.branch_switching.PeriodDoublingSwitch` /
    :class:`~rotorsfd.stability.branch_points.BranchPointSwitch`; ``legs`` and ``message``
    are read here), ``row`` the bifurcation row switched at, ``bifurcation_parameter`` the
    parameter it was switched at, ``attrs`` the switch's own netCDF attributes, ``notes``
    its own summary lines; ``stable`` / ``max_multiplier`` per point over ``period`` T."""

    main: ResponseResult
    at: Literal["pd", "bp"]
    number: int
    switch: Any
    row: dict[str, Any]
    bifurcation_parameter: float
    stable: NDArray[np.bool_] | None = None
    max_multiplier: NDArray[np.float64] | None = None
    elapsed: float = 0.0
    attrs: dict[str, Any] = field(default_factory=dict)
    notes: list[str] = field(default_factory=list)
    info: dict[str, Any] = field(default_factory=dict)

    # ---- what it is -----------------------------------------------------------------------
    @property
    def period(self) -> int:
        """The period of its orbits in T (2 at a period doubling)."""
        return PERIOD[self.at]

    @property
    def switched_at(self) -> str:
        """The ``--switch-at`` value in its full form, ``pd:N`` / ``bp:N``."""
        return f"{self.at}:{self.number}"

    @property
    def files(self) -> tuple[str, str]:
        return files(self.at, self.number)

    @property
    def branch(self) -> Branch:
        """The legs as one Branch (harmonics of Omega / ``period``)."""
        return joined(self.switch.legs, self.switch.message)

    @property
    def leg(self) -> NDArray[np.int64]:
        """The leg of every point (:data:`LEGS`)."""
        return np.concatenate([np.full(b.n_points, i, dtype=np.int64)
                               for i, b in enumerate(self.switch.legs)])

    @property
    def as_response(self) -> ResponseResult:
        """The second branch as a ResponseResult of period ``period`` T of the main one's
        system and outputs (its table and dataset are those of ``branch.csv`` /
        ``branch.nc``)."""
        return dataclasses.replace(self.main, branch=self.branch, stable=self.stable,
                                   max_multiplier=self.max_multiplier, multipliers=None,
                                   bifurcations=None, elapsed=self.elapsed, info={},
                                   period=self.period)

    @property
    def speeds(self) -> NDArray[np.float64]:
        """The rotor speed of every point [rad/s]."""
        return self.as_response.speeds

    def origin(self, tex: bool = False) -> str:
        """Where it starts: ``the period doubling at Omega~ = ...`` (or the branch point's
        type)."""
        what = "period doubling" if self.at == "pd" else str(self.row["type"])
        return f"the {what} at {where_words(self.main, self.row, tex)}"

    @property
    def label(self) -> str:
        """The legend entry / netCDF attribute: the branch and where it starts."""
        return f"{NAME[self.at]} (from {self.origin()})"

    def with_stability(self, legs: Sequence[Any]) -> None:
        """Take the stability of every leg (``stable``, ``max_multiplier`` of each)."""
        self.stable = np.concatenate([s.stable for s in legs])
        self.max_multiplier = np.concatenate([s.max_multiplier for s in legs])

    # ---- files ----------------------------------------------------------------------------
    def table(self) -> dict[str, NDArray[Any]]:
        """The CSV's columns: ``leg``, then those of ``branch.csv`` (module docstring)."""
        return {"leg": self.leg, **self.as_response.table()}

    def to_dataset(self) -> xr.Dataset:
        """``branch.nc``'s layout with ``leg`` and the switch's attributes."""
        sw = self.switch
        ds = self.as_response.to_dataset()
        ds["leg"] = ("point", self.leg, {"long_name": LEGS[self.at], "units": "1"})
        period = "T" if self.period == 1 else (f"{self.period} T (harmonic k is "
                                               f"k Omega / {self.period})")
        ds.attrs.update({"branch": self.label, "switch": SWITCH[self.at],
                         "switched_at": self.switched_at, "period": period,
                         "bifurcation_parameter": float(self.bifurcation_parameter),
                         "outcome": sw.message, "elapsed_s": float(self.elapsed),
                         **self.attrs})
        return ds

    def write(self, directory: str | Path) -> dict[str, Path]:
        """Write the netCDF and the CSV (:attr:`files`) atomically."""
        # deferred: io.branch_files loads xarray (only when writing)
        from rotorsfd.io.branch_files import write_netcdf, write_table

        out = Path(directory)
        nc, csv = self.files
        return {nc: write_netcdf(self.to_dataset(), out / nc),
                csv: write_table(out / csv, self.table())}

    # ---- figures and text -----------------------------------------------------------------
    def draw(self, figures: dict[str, Figure]) -> None:
        """Draw it over the main branch's response figures: r~ in
        ``response_deflection.png``, its first harmonic |X_1|/C (the Omega/2 subharmonic
        of a period-2 branch) in each ``response_node<n>.png`` panel, each leg its own
        line, dashed where unstable, and the legends redone."""
        from rotorsfd.plots.second_branch import draw_second_branch  # deferred: matplotlib

        m, r = self.main, self.as_response
        tab = self.table()
        x = tab["speed_ratio"] if m.is_speed else tab[m.parameter_column]
        first = r.harmonic_name(1)
        legend = f"{NAME[self.at]}, from {self.origin(True)}"
        words = "1X" if self.period == 1 else f"1/{self.period}X"
        draw_second_branch(
            figures, x, tab.get("stable"), {n: tab[f"defl_{n}"] for n in m.nodes},
            {(n, d): tab[f"amp_{n}_{d}_{first}"] / m.clearance for n in m.nodes
             for d in m.directions},
            nodes=m.nodes, directions=m.directions, legend=legend,
            amplitude_legend=legend.replace(NAME[self.at], f"{NAME[self.at]}: its {words}"),
            main_stable=m.stable, bifurcations=m.bifurcations or (),
            pieces=[tab["leg"] == k for k in range(len(self.switch.legs))])

    def summary(self) -> str:
        """A few lines: where it starts, its points and range, the legs' outcome, the
        switch's notes, its unstable points."""
        m, b = self.main, self.branch
        x = self.speeds / m.reference_speed if m.is_speed else b.lam
        name = "Omega~" if m.is_speed else m.parameter
        of = "" if self.period == 1 else f" harmonics of Omega/{self.period}"
        lines = [f"{NAME[self.at]} (H = {b.H}{of}) from {self.switched_at}, "
                 f"{self.origin()}: {b.n_points} points in {len(self.switch.legs)} leg(s), "
                 f"{name} {x.min():.5g} .. {x.max():.5g}, {self.elapsed:.2f} s",
                 m.in_user_terms(self.switch.message), *self.notes]
        if self.stable is not None:
            lines.append(f"{NAME[self.at]}: unstable points {int(np.sum(~self.stable))} of "
                         f"{self.stable.size}")
        return "\n".join(lines)
