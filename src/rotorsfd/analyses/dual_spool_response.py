"""``rotorsfd response`` of a dual-spool rotor with unbalances on both spools: the branch of
two-frequency responses (tori, lines ``k1 Omega_LP + k2 Omega_HP``) along the speed line
``Omega_HP = r Omega_LP``, its stability, files and plots (issue 20 item 3).

The problem is :func:`~rotorsfd.quasiperiodic.dual_frequency.dual_spool_problem` (the linear
part time-invariant, each harmonic its own block), continued in Omega_LP by the torus arc
length (:func:`~rotorsfd.quasiperiodic.continue_torus`) over ``[analysis.response]``'s
speed range on the box ``|k1|, |k2| <= H`` (H = ``start_harmonics``). With
``[analysis.stability].enabled`` the largest Lyapunov exponent of the motion started on
the torus (:func:`~rotorsfd.quasiperiodic.torus_stability.torus_lyapunov`: the time
integration runs each shaft's unbalance at its own speed) at
:data:`~rotorsfd.analyses.torus_response.LYAPUNOV_POINTS` points spread along the branch.

Files: ``torus.nc`` and ``torus.csv`` as for a torus under a harmonic base law (there the
base frequency column ``base_frequency_rad_s`` is Omega_HP; ``torus.csv`` has
``hp_speed_rad_s`` as well), ``dual_spool_response.png`` (the strongest lines in the
spools' words, "1X LP", "1X HP", "2X LP - 1X HP", and the Lyapunov exponents).
"""

from __future__ import annotations

import dataclasses
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rotorsfd.analyses.context import RunContext, build, config_context
from rotorsfd.analyses.torus_response import (
    LYAPUNOV_POINTS,
    TorusPoint,
    TorusResponseResult,
    branch_lyapunov,
    continue_torus_section,
)
from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import Config

if TYPE_CHECKING:
    from rotorsfd.io.schema import ResponseAnalysis
    from rotorsfd.model.system import RotorSystem
    from rotorsfd.quasiperiodic import TorusLattice

FIELD = "analysis.response"
__all__ = ["DualSpoolResponseResult", "dual_spool", "run_dual_spool_response"]


def dual_spool(config: Config) -> bool:
    """True when an unbalance of ``config`` is on a shaft at a speed ratio other than 1
    (the response then has two base frequencies)."""
    shafts = config.rotor.shafts
    if not shafts:
        return False
    for u in config.unbalance:
        k = config.rotor.shaft_of(u.node)
        if k is not None and shafts[k].speed_ratio != 1.0 and u.magnitude != 0.0:
            return True
    return False


@dataclasses.dataclass
class DualSpoolResponseResult(TorusResponseResult):
    """A torus branch along the speed line Omega_HP = r Omega_LP (``speeds``: Omega_LP)."""

    FILES = ("torus.nc", "torus.csv", "dual_spool_response.png")
    #: no Floquet data per point (the Lyapunov exponents are at a few points: ``lyapunov``)
    stable = None
    max_multiplier = None
    bifurcations = None

    @property
    def ratio(self) -> float:
        return float(self.info["speed_ratio"])

    def table(self) -> dict[str, Any]:
        cols = super().table()
        out = {k: cols[k] for k in ("point", "speed_rad_s")}
        out["hp_speed_rad_s"] = np.asarray(self.branch.wb, dtype=float)
        out.update(cols)
        return out

    def summary(self) -> str:
        lines = super().summary().splitlines()
        b = self.branch
        lines[0] = (f"dual-spool response (torus, lines k1 Omega_LP + k2 Omega_HP, Omega_HP = "
                    f"{self.ratio:g} Omega_LP): {b.n_points} points, Omega_LP~ from "
                    f"{b.omega.min() / self.reference_speed:.5g} to "
                    f"{b.omega.max() / self.reference_speed:.5g}, box |k1|, |k2| <= "
                    f"{b.lattice.H1}, grid {b.grid[0]} x {b.grid[1]}, {self.elapsed:.2f} s")
        return "\n".join(lines)

    def to_dataset(self) -> Any:
        """The torus branch's Dataset with ``speed_ratio_hp_lp`` = r."""
        ds = super().to_dataset()
        ds.attrs["speed_ratio_hp_lp"] = self.ratio
        return ds

    def plot(self, multipliers_at: float | None = None) -> dict[str, Any]:
        """``dual_spool_response.png`` (none for an empty branch)."""
        if not self.branch.n_points:
            return {}
        # deferred: plots.dual_spool (loads matplotlib)
        from rotorsfd.plots.dual_spool import plot_dual_spool_response

        return {"dual_spool_response.png": plot_dual_spool_response(self)}


def run_dual_spool_response(config_or_system: Config | RotorSystem,
                            settings: ResponseAnalysis | None = None, *,
                            context: RunContext | None = None,
                            search_path: Path | None = None,
                            lattice: TorusLattice | None = None, progress: bool = True,
                            stability: bool | None = None, from_orbit: Any = None,
                            callback: Callable[[Any], bool | None] | None = None,
                            lyapunov_points: int = LYAPUNOV_POINTS
                            ) -> DualSpoolResponseResult:
    """The two-frequency branch of a dual-spool system over its speed range (module doc).

    ``run_dual_spool_response(system, settings, context=...)``: ``settings`` the
    ``[analysis.response]`` section (default: the context's, an empty section's; a fixed
    H, the speed range in Omega~ on the context's reference speed), ``context`` the
    reference speed, ``[analysis.stability]`` and title. ``run_dual_spool_response(config)``
    is that call with ``build(config)``, ``config.analysis.response`` and
    :func:`~rotorsfd.analyses.context.config_context`: the two paths cannot disagree.
    ``stability`` None: the context's ``[analysis.stability].enabled``;
    ``callback(point)`` returning True stops the branch."""
    from rotorsfd.quasiperiodic import TorusLattice  # deferred: numba
    from rotorsfd.quasiperiodic.dual_frequency import dual_spool_problem

    if from_orbit is not None:
        raise ConfigError("--from-orbit", str(from_orbit), "a dual-spool branch (unbalances "
                          "on two spools) starts from the linear response, not an orbit")
    if isinstance(config_or_system, Config):
        config = config_or_system
        r = config.analysis.response if settings is None else settings
        _check_settings(r)
        if not config.elements:
            raise ConfigError("elements", None, "the nonlinear response needs at least one "
                              "nonlinear element (an [elements.<name>] table)")
        system = build(config, search_path)
        return run_dual_spool_response(
            system, r, context=config_context(config, system, "response",
                                              search_path=search_path),
            lattice=lattice, progress=progress, stability=stability, callback=callback,
            lyapunov_points=lyapunov_points)
    system = config_or_system
    ctx = context if context is not None else RunContext(search_path=search_path)
    r = settings if settings is not None else ctx.response
    _check_settings(r)
    if not len(system.elements):
        raise ConfigError("elements", None, "the nonlinear response needs at least one "
                          "nonlinear element")
    problem = dual_spool_problem(system)      # ConfigError: base law, ratios
    ref = float(ctx.reference(system))
    lo, hi = r.speed_range.bounds(ref)
    if not (lo > 0 and hi > 0) or lo == hi:
        raise ConfigError(f"{FIELD}.speed_range", r.speed_range.model_dump(
            exclude_none=True), "the dual-spool branch needs two different speeds > 0")
    nodes = tuple(r.nodes) or system.output_nodes
    for n in nodes:
        if not 1 <= n <= system.rotor.n_nodes:
            raise ConfigError(f"{FIELD}.nodes", n, f"must be 1..{system.rotor.n_nodes}")
    lattice = lattice or TorusLattice(r.start_harmonics, r.start_harmonics)

    def hook(index: int, lam: float, X: Any) -> bool:
        if progress:
            print(f"\rdual-spool torus: {index + 1} points, at Omega_LP~ = {lam / ref:.4g}",
                  end="", file=sys.stderr, flush=True)
        return bool(callback(TorusPoint(index, lam, X))) if callback else False

    t0 = time.perf_counter()
    branch = continue_torus_section(problem, lo, hi, lattice, r, hook, progress=progress,
                                    start=f"the speed range (Omega~ = {lo / ref:.4g})")
    enabled = ctx.stability.enabled if stability is None else stability
    lyap = (branch_lyapunov(branch, lattice, lambda lam: system, lyapunov_points)
            if enabled else {})
    return DualSpoolResponseResult(
        branch, system, ref, tuple(nodes), tuple(r.directions), ctx.title,
        time.perf_counter() - t0, lyap,
        {"config_toml": ctx.config_toml, "limit_max": float(r.max_eccentricity),
         "speed_ratio": float(problem.info["speed_ratio"])})


def _check_settings(r: ResponseAnalysis) -> None:
    """ConfigError unless ``[analysis.response]`` continues in the speed with a fixed H."""
    if r.parameter.strip() != "speed":
        raise ConfigError(f"{FIELD}.parameter", r.parameter, "with unbalances on two spools "
                          "the branch is continued in 'speed' (Omega_LP) only")
    if r.adaptive_harmonics:
        raise ConfigError(f"{FIELD}.harmonics", "auto", "the dual-spool torus takes a fixed "
                          "number of harmonics (start_harmonics)")
