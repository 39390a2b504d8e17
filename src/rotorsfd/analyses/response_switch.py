"""The period-2 branch of a response: ``rotorsfd response CONFIG --switch-at pd:N`` (or
plain ``N``; ``bp:N``, the second branch at a branch point, is
:mod:`rotorsfd.analyses.response_branch_switch`).

N counts the branch's period-doubling points from 1, in the order of the branch (the
order of the summary lines and of ``bifurcations.csv``'s ``period-doubling`` rows). At that
point :func:`~rotorsfd.harmonic.branch_switching.switch_period_doubling` continues the
2T-periodic branch in harmonics of ``Omega/2`` (default ``4 H``: the subharmonics k/2 of
the speed), within the main branch's parameter range, with the same element limit; its
legs' Floquet multipliers over 2T when the main branch has them.

Written next to the main branch: ``branch_period2.nc`` (:mod:`rotorsfd.io.branch_files`
layout; ``harmonic`` k is the frequency ``k Omega / 2``, ``frequency_rad_s`` is Omega/2)
and ``branch_period2.csv``, per point::

    leg, speed_rad_s, speed_ratio (, <parameter>)
    static_<n>_<d>           = X_0                    [m]
    amp_<n>_<d>_h<k>_2       = |X_k|, k odd           [m]  (the k/2 x speed subharmonics)
    amp_<n>_<d>_h<j>         = |X_2j|                 [m]  (the speed's harmonics)
    defl_<n>                 = max_t r / C over 2T
    sub_<n>                  = sqrt(sum_k odd |X_k,y|^2 + |X_k,z|^2) / C  (0 on period 1)
    stable, max_multiplier   (multipliers over 2T)

and drawn in ``response_deflection.png`` and ``response_node<n>.png`` over the main branch
(labelled by the period doubling it starts from).
"""

from __future__ import annotations

import dataclasses
import time
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.response_words import PARAMETER_UNITS, system_parameter
from rotorsfd.continuation.branch import Branch
from rotorsfd.errors import ConfigError
from rotorsfd.harmonic.synthesis import max_radius
from rotorsfd.model import dofs

if TYPE_CHECKING:
    from matplotlib.figure import Figure

    from rotorsfd.analyses.response_result import ResponseResult
    from rotorsfd.harmonic.branch_switching import PeriodDoublingSwitch

OPTION = "--switch-at"
FILES = ("branch_period2.nc", "branch_period2.csv")
#: Odd amplitude of the period-2 branch's first point (scaled units: clearances), and the
#: longest step along it: the first point near the period doubling (lam - lam_pd ~ c a^2),
#: steps short of jumping back onto the period-1 branch (the paper case's subharmonic
#: part reaches ~0.05 C).
DELTA, STEP_MAX = 0.005, 0.02
OMEGA_TEX = r"$\tilde\Omega$"


def period_doublings(result: ResponseResult) -> list[int]:
    """Indices into ``result.bifurcations`` (and the stability's located bifurcations) of
    the period-doubling points, in the branch's order."""
    return [i for i, row in enumerate(result.bifurcations or ())
            if row["type"] == "period-doubling"]


def check_switch(result: ResponseResult, n: int, value: str = "") -> int:
    """The bifurcation index of the n-th period doubling (from 1); ConfigError naming
    ``--switch-at`` and ``value`` (default n) when the branch has none or fewer than n."""
    pds = period_doublings(result)
    shown: Any = value or n
    if result.bifurcations is None or "stability" not in result.info:
        raise ConfigError(OPTION, shown, "needs the branch's Floquet stability: set "
                          "[analysis.stability] enabled = true")
    if not pds:
        raise ConfigError(OPTION, shown, "the branch has no period-doubling point (no "
                          "Floquet multiplier crosses -1 over its range)")
    if not 1 <= n <= len(pds):
        where = ", ".join(f"{k + 1}: {where_words(result, result.bifurcations[i])}"
                          for k, i in enumerate(pds))
        raise ConfigError(OPTION, shown, f"must be 1..{len(pds)}, the branch's "
                          f"period-doubling points ({where})")
    return pds[n - 1]


def where_words(result: ResponseResult, row: dict[str, Any], tex: bool = False) -> str:
    """Where a bifurcation row is, in user terms (``Omega~ = ...`` or the parameter)."""
    if result.is_speed:
        return f"{OMEGA_TEX if tex else 'Omega~'} = {row['speed_ratio']:.5g}"
    return f"{result.parameter} = {row['parameter']:.6g} {result.parameter_units}"


@dataclass
class Period2Result:
    """The period-2 branch switched at the ``number``-th period doubling of ``main``."""

    main: ResponseResult
    number: int
    switch: PeriodDoublingSwitch
    stable: NDArray[np.bool_] | None = None
    max_multiplier: NDArray[np.float64] | None = None
    elapsed: float = 0.0
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def branch(self) -> Branch:
        """The legs as one Branch (harmonics of Omega/2; ``frequency`` = Omega/2)."""
        legs = self.switch.legs
        first = legs[0]
        return dataclasses.replace(
            first, lam=self.switch.lam, X=self.switch.X,
            frequency=np.concatenate([b.frequency for b in legs]),
            tangents=np.concatenate([b.tangents for b in legs]),
            iterations=np.concatenate([b.iterations for b in legs]),
            ds=np.concatenate([b.ds for b in legs]),
            s=np.concatenate([b.s for b in legs]), jacobians=None,
            aliasing=np.concatenate([b.aliasing for b in legs]),
            success=all(b.success for b in legs), message=self.switch.message,
            info={}, resolver=None)

    @property
    def leg(self) -> NDArray[np.int64]:
        return np.concatenate([np.full(b.n_points, i, dtype=np.int64)
                               for i, b in enumerate(self.switch.legs)])

    @property
    def speeds(self) -> NDArray[np.float64]:
        """The rotor speed of every point [rad/s] (twice the fundamental Omega/2)."""
        return 2.0 * np.concatenate([b.frequency for b in self.switch.legs])

    @property
    def label(self) -> str:
        """The legend entry: the period-2 branch and where it starts, in user terms."""
        row = self.main.bifurcations[check_switch(self.main, self.number)]
        return f"period-2 branch (from the period doubling at {where_words(self.main, row)})"

    @property
    def legend(self) -> str:
        """:attr:`label` for a figure (mathtext)."""
        row = self.main.bifurcations[check_switch(self.main, self.number)]
        return f"period-2 branch, from the period doubling at {where_words(self.main, row, True)}"

    def table(self) -> dict[str, NDArray[Any]]:
        """The columns of ``branch_period2.csv`` (module docstring)."""
        m, X = self.main, self.switch.X
        C = m.clearance
        cols: dict[str, NDArray[Any]] = {"leg": self.leg}
        if not m.is_speed:
            cols[m.parameter_column] = np.asarray(self.switch.lam, float)
        cols["speed_rad_s"] = self.speeds
        cols["speed_ratio"] = self.speeds / m.reference_speed
        H2 = X.shape[1] - 1
        for n in m.nodes:
            for d in m.directions:
                j = dofs.dof_index(n, d)
                cols[f"static_{n}_{d}"] = X[:, 0, j].real.copy()
                for k in range(1, H2 + 1):
                    name = f"h{k}_2" if k % 2 else f"h{k // 2}"
                    cols[f"amp_{n}_{d}_{name}"] = np.abs(X[:, k, j])
        for n in m.nodes:
            Xy, Xz = X[:, :, dofs.dof_index(n, "y")], X[:, :, dofs.dof_index(n, "z")]
            cols[f"defl_{n}"] = max_radius(Xy, Xz) / C
            odd = np.abs(Xy[:, 1::2]) ** 2 + np.abs(Xz[:, 1::2]) ** 2
            cols[f"sub_{n}"] = np.sqrt(odd.sum(axis=1)) / C
        if self.stable is not None:
            cols["stable"] = np.asarray(self.stable, bool)
            cols["max_multiplier"] = np.asarray(self.max_multiplier, float)
        return cols

    def write(self, directory: str | Path) -> dict[str, Path]:
        """Write ``branch_period2.nc`` and ``branch_period2.csv`` atomically."""
        # deferred: io.branch_files loads xarray (only when writing)
        from rotorsfd.io.branch_files import branch_dataset, write_netcdf, write_table
        from rotorsfd.io.provenance import netcdf_attrs

        out, m, sw = Path(directory), self.main, self.switch
        attrs = {"run_title": m.title, "clearance_m": m.clearance, **netcdf_attrs(),
                 "branch": self.label, "period": "2 T (harmonic k is k Omega / 2)",
                 "switched_at": self.number, "pd_parameter_given": sw.lam_given,
                 "pd_parameter_hb": sw.lam_bifurcation, "closed": int(sw.closed),
                 "outcome": sw.message, "elapsed_s": float(self.elapsed)}
        if sw.lam_rejoin is not None:
            attrs["rejoin_parameter"] = float(sw.lam_rejoin)
        ds = branch_dataset(self.branch, parameter=m.parameter,
                            parameter_units=m.parameter_units, speeds=self.speeds,
                            reference_speed=m.reference_speed, stable=self.stable,
                            max_multiplier=self.max_multiplier, attrs=attrs)
        return {"branch_period2.nc": write_netcdf(ds, out / "branch_period2.nc"),
                "branch_period2.csv": write_table(out / "branch_period2.csv", self.table())}

    def draw(self, figures: dict[str, Figure]) -> None:
        """Draw the period-2 branch over the main branch's response figures: r~ in
        ``response_deflection.png``, the Omega/2 subharmonic |X_1|/C in each
        ``response_node<n>.png`` panel (dashed where unstable), and the legends redone."""
        from rotorsfd.plots.second_branch import draw_second_branch  # deferred: matplotlib

        m = self.main
        tab = self.table()
        x = tab["speed_ratio"] if m.is_speed else tab[m.parameter_column]
        draw_second_branch(
            figures, x, tab.get("stable"), {n: tab[f"defl_{n}"] for n in m.nodes},
            {(n, d): tab[f"amp_{n}_{d}_h1_2"] / m.clearance for n in m.nodes
             for d in m.directions},
            nodes=m.nodes, directions=m.directions, legend=self.legend,
            amplitude_legend=self.legend.replace("period-2 branch",
                                                 "period-2 branch: its 1/2X"),
            main_stable=m.stable, bifurcations=m.bifurcations or ())

    def summary(self) -> str:
        sw, m = self.switch, self.main
        x = self.speeds / m.reference_speed if m.is_speed else sw.lam
        name = "Omega~" if m.is_speed else m.parameter
        lines = [f"period-2 branch (H = {sw.legs[0].H} harmonics of Omega/2) from period "
                 f"doubling {self.number}: {x.size} points in {len(sw.legs)} leg(s), "
                 f"{name} {x.min():.5g} .. {x.max():.5g}, {self.elapsed:.2f} s",
                 m.in_user_terms(sw.message)]
        gap = abs(sw.lam_bifurcation - sw.lam_given) / abs(sw.lam_given)
        if gap > 1e-3:
            lines.append(f"the period doubling of the period-2 HB equations is "
                         f"{gap:.1e} (relative) from the branch's ({name} "
                         f"{_ratio(m, sw.lam_bifurcation):.5g} against "
                         f"{_ratio(m, sw.lam_given):.5g}): the branch's H does not resolve "
                         "it; raise H (the check of the period doubling says by how much)")
        if self.stable is not None:
            lines.append(f"period-2 unstable points: {int(np.sum(~self.stable))} of "
                         f"{self.stable.size}")
        return "\n".join(lines)


def _ratio(result: ResponseResult, lam: float) -> float:
    return lam / result.reference_speed if result.is_speed else lam


def run_switch(result: ResponseResult, number: int, *, harmonics: int | None = None,
               delta: float = DELTA, stability: bool = True, value: str = "",
               **continue_kw: Any) -> Period2Result:
    """The period-2 branch at the ``number``-th period doubling of ``result`` (module
    docstring); ``harmonics`` of Omega/2 (default 4 H); ``continue_kw`` go to
    :func:`~rotorsfd.harmonic.branch_switching.switch_period_doubling`. ConfigError (the
    option named) when there is no such period doubling."""
    # deferred: harmonic.branch_switching (the HB switching machinery, only when switching)
    from rotorsfd.harmonic.branch_switching import switch_period_doubling

    i = check_switch(result, number, value)
    t0 = time.perf_counter()
    st = result.info["stability"]
    bif = st.bifurcations[i]
    located = bif.info.get("located")
    b = result.branch
    if located is not None:
        lam, X = float(located[0].lam), located[0].X
    else:
        lam = float(bif.lam)
        X = b.X[int(np.argmin(np.abs(b.lam - lam)))]
    sys_param = system_parameter(result.parameter)
    problem = result.system.periodic_problem(sys_param, None if sys_param == "speed"
                                             else result.speed)
    kw = {"limit_max": result.info.get("limit_max", 1.0), "ds_max": STEP_MAX,
          **continue_kw}
    sw = switch_period_doubling(problem, lam, X, (float(b.lam.min()), float(b.lam.max())),
                                H=harmonics, delta=delta, **kw)
    out = Period2Result(result, number, sw)
    options = result.info.get("stability_options")
    if stability:
        sts = sw.stability(options)
        out.stable = np.concatenate([s.stable for s in sts])
        out.max_multiplier = np.concatenate([s.max_multiplier for s in sts])
    out.elapsed = time.perf_counter() - t0
    out.info["units"] = PARAMETER_UNITS[sys_param]
    return out
