"""``rotorsfd response`` under a harmonic base law: a branch of quasi-periodic responses
(tori, harmonics ``k1 Omega + k2 w_b``) continued in the rotor speed, or at a fixed speed
in the base frequency, a base law's amplitude or the unbalance, its files and plots.

Under a base law ``w(t) = mean + A sin(w_b t + phi)`` the response lies on a 2-torus,
``q(t) = Re sum_k X_k exp(i (k1 Omega + k2 w_b) t)`` over the box ``|k1| <= H1,
|k2| <= H2`` (:mod:`rotorsfd.quasiperiodic`, docs/quasiperiodic.md). From
``[analysis.response]``: H1 = the response's (starting) harmonics, H2 = ``base_harmonics``
(default 2; the base terms couple k2 to k2 +- 1, +- 2 and the loads sit at |k2| <= 2, so
a large base motion needs more: raise H2 until the lines stop changing), the speed range,
step sizes, tolerance and ``max_eccentricity``. ``parameter`` in the vocabulary of the
periodic branches (config paths; :func:`torus_parameter`): ``"speed"`` over
``speed_range``, or, at the fixed ``speed`` / ``speed_ratio`` over ``parameter_range`` (in
the field's units), ``base.<law>.frequency`` (w_b: every harmonic law moves with it, the
rotation laws keeping the amplitude form the config gives them, angle or rate;
translations keep their displacement), ``base.<law>.amplitude`` (or ``angle_amplitude``,
``acceleration_amplitude``) and ``unbalance[0].magnitude`` (the others scaled with it),
each with exact derivatives (:mod:`rotorsfd.quasiperiodic.torus_base_parameters`,
:func:`~rotorsfd.quasiperiodic.torus_system.torus_problem`). With
``[analysis.stability].enabled`` the
largest Lyapunov exponent of the motion started on the torus
(:func:`~rotorsfd.quasiperiodic.torus_stability.torus_lyapunov`, 200 rotor periods at
T/200) is computed at :data:`LYAPUNOV_POINTS` points spread along the branch (the first and
the last among them); a point is stable when ``lambda T + its uncertainty < 0``.

Quantities per point (after ``speed_rad_s``, ``speed_ratio``, ``base_frequency_rad_s``
and, for a parameter other than the speed, its value ``<path>_<unit>``, e.g.
``base_pitching_frequency_rad_s``), for an output node n, direction d and lattice harmonic
(k1, k2)::

    amp_<n>_<d>_<k1>_<k2>  = |X_(k1,k2)| / C     (half peak-to-peak of that line; a
                                                   negative k2 written m2, m1)
    defl_<n>               = max over the torus of sqrt(y^2 + z^2) / C
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import TYPE_CHECKING, Any, NamedTuple

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.context import RunContext, build, config_context
from rotorsfd.analyses.response_words import column_slug
from rotorsfd.analyses.torus_parameters import (
    ALLOWED,
    AMPLITUDES,
    LAWS,
    SPEED,
    TorusParameter,
    harmonic_base,
    parameter_problem,
    system_at,
    torus_parameter,
)
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.io import atomic
from rotorsfd.io.schema import Config, parameter_values
from rotorsfd.model.node_names import (
    NodeNames,
    node_words,
    with_shaft_coords,
    write_node_table,
)
from rotorsfd.model.system import RotorSystem

if TYPE_CHECKING:
    import xarray as xr

    from rotorsfd.io.schema import ResponseAnalysis
    from rotorsfd.quasiperiodic import TorusBranch, TorusLattice
    from rotorsfd.quasiperiodic.torus_stability import TorusLyapunov

__all__ = ["ALLOWED", "AMPLITUDES", "LAWS", "LYAPUNOV_POINTS", "TorusParameter", "TorusPoint",
           "TorusResponseResult", "harmonic_base", "lyapunov_indices", "parameter_problem",
           "run_torus_response", "system_at", "torus_parameter"]

FloatArray = NDArray[np.float64]
FIELD = "analysis.response"
#: points of the branch with a Lyapunov exponent (spread along it; about 2 s each on the
#: 20-DOF test rotor, about 3-6 s on the paper rotor)
LYAPUNOV_POINTS = 5
#: torus samples per direction for the largest radius defl_<n>
RADIUS_GRID = 64


class TorusPoint(NamedTuple):
    """A converged torus as the callback sees it: index, speed [rad/s], coefficients."""

    index: int
    lam: float
    X: Any


def continue_torus_section(problem: Any, lo: float, hi: float, lattice: Any, r: Any,
                           hook: Any, *, start: str = "the range",
                           progress: bool = False) -> Any:
    """:func:`~rotorsfd.quasiperiodic.torus_continuation.continue_torus` over [lo, hi]
    with the continuation settings of the ``[analysis.response]`` section ``r``; a first
    point that does not converge is ConvergenceError "no torus at the start of
    ``start``"; ``progress``: the hook's progress line cleared at the end."""
    from rotorsfd.quasiperiodic import continue_torus  # deferred: numba

    try:
        return continue_torus(problem, float(lo), float(hi), lattice, tol=r.tolerance,
                              ds=r.step_initial, ds_min=r.step_min, ds_max=r.step_max,
                              max_iter=r.max_iterations, max_points=r.max_points,
                              max_angle_deg=math.degrees(r.max_tangent_angle),
                              limit_max=r.max_eccentricity, callback=hook)
    except ConvergenceError as exc:
        raise ConvergenceError(f"no torus at the start of {start}: {exc}") from None
    finally:
        if progress:
            print("\r\033[K", end="", file=sys.stderr, flush=True)


def branch_lyapunov(branch: Any, lattice: Any, system_of: Callable[[float], Any],
                    count: int = LYAPUNOV_POINTS) -> dict[int, Any]:
    """The largest Lyapunov exponent of the motion started on the torus
    (:func:`~rotorsfd.quasiperiodic.torus_stability.torus_lyapunov`) at ``count`` points
    spread along ``branch`` (:func:`lyapunov_indices`), by point index; ``system_of(lam)``
    the system at a point's parameter."""
    from rotorsfd.quasiperiodic.torus_stability import torus_lyapunov  # deferred: numba

    return {i: torus_lyapunov(system_of(float(branch.lam[i])), lattice, branch.X[i],
                              float(branch.omega[i]), float(branch.wb[i]))
            for i in lyapunov_indices(branch.n_points, count)}


def component_slug(k1: int, k2: int) -> str:
    """(k1, k2) in a column name: 1_m2 for (1, -2)."""
    return "_".join(f"m{-k}" if k < 0 else str(k) for k in (k1, k2))


@dataclasses.dataclass
class TorusResponseResult:
    """A torus branch in the speed with its system, output nodes and Lyapunov exponents
    (``lyapunov``: point index -> :class:`TorusLyapunov`)."""

    branch: TorusBranch
    system: RotorSystem
    reference_speed: float
    nodes: tuple[int, ...]
    directions: tuple[str, ...]
    title: str = ""
    elapsed: float = 0.0
    lyapunov: dict[int, TorusLyapunov] = dataclasses.field(default_factory=dict)
    info: dict[str, Any] = dataclasses.field(default_factory=dict)

    parameter: str = "speed"                  # config path
    parameter_units: str = "rad/s"
    speed: float | None = None                # the fixed speed of a non-speed branch

    FILES = ("torus.nc", "torus.csv")

    @property
    def is_speed(self) -> bool:
        return self.parameter == "speed"

    @property
    def parameter_column(self) -> str:
        """The parameter's CSV column (a non-speed branch): ``<path>_<unit>``."""
        return f"{column_slug(self.parameter)}_{column_slug(self.parameter_units)}"

    def at(self, index: int) -> str:
        """Where point ``index`` is, in the parameter's terms."""
        b = self.branch
        if self.is_speed:
            return f"Omega~ = {b.omega[index] / self.reference_speed:.5g}"
        unit = "" if self.parameter_units == "1" else f" {self.parameter_units}"
        return f"{self.parameter} = {b.lam[index]:.6g}{unit}"

    @property
    def clearance(self) -> float:
        """C [m]: the smallest length scale of the nonlinear DOFs (an SFD's clearance)."""
        return float(self.system.length_scale or 1.0)

    @property
    def speeds(self) -> FloatArray:
        return np.asarray(self.branch.omega, dtype=float)

    @property
    def success(self) -> bool:
        return bool(self.branch.success)

    @property
    def ended(self) -> str:
        """"range", "limit" (an element's validity limit), "stopped" or "failed"."""
        msg = str(self.branch.message)
        if msg.startswith("stopped by the callback"):
            return "stopped"
        if self.branch.success:
            return "range"
        return "limit" if "state limit" in msg else "failed"

    @property
    def message(self) -> str:
        b = self.branch
        if not b.n_points:
            return str(b.message)
        last = self.at(-1)
        if self.ended == "stopped":
            return f"torus branch stopped on request after {b.n_points} points at {last}"
        if self.ended == "range":
            return f"reached the end of the range at {last}"
        if self.ended == "limit":
            return (f"the torus branch ends at {last}: an element reached its validity "
                    f"limit (analysis.response.max_eccentricity = "
                    f"{self.info.get('limit_max', 1.0):g}) [{b.message}]")
        return f"the torus branch stopped at {last} [{b.message}]"

    # ---- quantities -----------------------------------------------------------------------
    def dof(self, node: int, direction: str) -> int:
        return 4 * (node - 1) + "yz".index(direction)

    def amplitude(self, node: int, direction: str, k1: int, k2: int) -> FloatArray:
        """|X_(k1,k2)| / C of one node and direction along the branch."""
        return self.branch.amplitude(self.dof(node, direction), k1, k2) / self.clearance

    def deflection(self, node: int) -> FloatArray:
        """max over the torus of sqrt(y^2 + z^2) / C at each point (a 64 x 64 grid)."""
        # deferred: quasiperiodic.torus_fourier (loads 8 more rotorsfd modules, needed only here)
        from rotorsfd.quasiperiodic.torus_fourier import TorusAFT

        aft = TorusAFT(self.branch.lattice, RADIUS_GRID, RADIUS_GRID)
        d = [self.dof(node, "y"), self.dof(node, "z")]
        out = [np.sqrt((aft.sample(to_real(X[:, d])) ** 2).sum(axis=1)).max()
               for X in self.branch.X]
        return np.asarray(out, dtype=float) / self.clearance

    def stability_columns(self) -> dict[str, list[Any]]:
        """Per point: the Lyapunov exponent per rotor period, its uncertainty and 1/0
        stable; empty where it was not computed."""
        cols: dict[str, list[Any]] = {"lyapunov_per_period": [], "lyapunov_uncertainty": [],
                                      "stable": []}
        for i in range(self.branch.n_points):
            ly = self.lyapunov.get(i)
            cols["lyapunov_per_period"].append("" if ly is None else ly.per_period)
            cols["lyapunov_uncertainty"].append("" if ly is None else ly.uncertainty)
            cols["stable"].append("" if ly is None else int(ly.stable))
        return cols

    def table(self) -> dict[str, Any]:
        """The columns of ``torus.csv`` (module docstring)."""
        b = self.branch
        cols: dict[str, Any] = {"point": np.arange(b.n_points), "speed_rad_s": b.omega,
                                "speed_ratio": b.omega / self.reference_speed,
                                "base_frequency_rad_s": b.wb}
        if not self.is_speed:
            cols[self.parameter_column] = np.asarray(b.lam, dtype=float)
        cols.update({"iterations": b.iterations, "aliasing": b.aliasing,
                     "validity_measure": b.limit})
        for n in self.nodes:
            cols[f"defl_{n}"] = self.deflection(n)
            for d in self.directions:
                for k1, k2 in b.lattice.k:
                    cols[f"amp_{n}_{d}_{component_slug(int(k1), int(k2))}"] = \
                        self.amplitude(n, d, int(k1), int(k2))
        if self.lyapunov:
            cols.update(self.stability_columns())
        return cols

    def summary(self) -> str:
        b = self.branch
        lat = b.lattice
        if self.is_speed:
            where = (f"Omega~ from {b.omega.min() / self.reference_speed:.5g} to "
                     f"{b.omega.max() / self.reference_speed:.5g}, w_b = {b.wb[0]:.6g} rad/s")
        else:
            unit = "" if self.parameter_units == "1" else f" {self.parameter_units}"
            where = (f"{self.parameter} from {b.lam.min():.6g} to {b.lam.max():.6g}{unit} "
                     f"at Omega~ = {b.omega[0] / self.reference_speed:.5g}"
                     + ("" if self.parameter.endswith(".frequency")
                        else f", w_b = {b.wb[0]:.6g} rad/s"))
        lines = [f"quasi-periodic response (torus, harmonics of Omega and w_b): {b.n_points} "
                 f"points, {where}, box |k1| <= {lat.H1}, |k2| <= {lat.H2}, grid "
                 f"{b.grid[0]} x {b.grid[1]}, {self.elapsed:.2f} s"]
        for n in self.nodes:
            r = self.deflection(n)
            i = int(np.argmax(r))
            lines.append(f"{node_words(self.node_names, n)}: max r~ = {r[i]:.4g} at "
                         f"{self.at(i)}")
        if self.lyapunov:
            bad = [i for i, ly in self.lyapunov.items() if not ly.stable]
            lines.append(f"Lyapunov exponent at {len(self.lyapunov)} points: "
                         f"{len(bad)} unstable" + (
                             f" (first at {self.at(bad[0])})" if bad else ""))
        lines.append({"range": "ok: ", "limit": "ended at a validity limit: ",
                      "stopped": "stopped: "}.get(self.ended, "FAILED: ") + self.message)
        return "\n".join(lines)

    # ---- files ----------------------------------------------------------------------------
    def to_dataset(self) -> xr.Dataset:
        from rotorsfd.io.provenance import netcdf_attrs
        from rotorsfd.io.torus_files import torus_dataset

        attrs = {"run_title": self.title, "clearance_m": self.clearance,
                 "elements": "; ".join(e.describe() for e in self.system.elements),
                 "output_nodes": np.asarray(self.nodes, dtype=np.int32),
                 "output_directions": " ".join(self.directions),
                 **netcdf_attrs(), "elapsed_s": float(self.elapsed),
                 "ended": self.ended, "outcome": self.message}
        if "config_toml" in self.info:
            attrs["config_toml"] = self.info["config_toml"]
        defl = {n: self.deflection(n) for n in self.nodes}
        ds = torus_dataset(self.branch, reference_speed=self.reference_speed,
                           deflection=defl, lyapunov=self.lyapunov, attrs=attrs,
                           parameter=None if self.is_speed else (
                               self.parameter, self.parameter_units),
                           node_labels={n: node_words(self.node_names, n)
                                        for n in self.nodes})
        return with_shaft_coords(ds, self.node_names)

    @property
    def node_names(self) -> NodeNames | None:
        """Shaft-wise node names of a multi-shaft rotor (None: one shaft)."""
        return NodeNames.of(self.system.rotor)

    def spectrum_index(self, speed_ratio: float | None = None) -> int:
        """The point nearest ``speed_ratio`` (a non-speed branch: the parameter's value in
        SI; default: the largest deflection)."""
        if speed_ratio is None:
            return int(np.argmax(self.deflection(self.nodes[0])))
        x = self.branch.omega / self.reference_speed if self.is_speed else self.branch.lam
        return int(np.argmin(np.abs(x - speed_ratio)))

    def plot(self, multipliers_at: float | None = None) -> dict[str, Any]:
        """``torus_components.png`` and ``torus_spectrum.png`` (at the point nearest
        ``multipliers_at``, a speed ratio; default the largest deflection; a non-speed
        branch: the parameter's value); none for an empty branch."""
        if not self.branch.n_points:
            return {}
        # deferred: plots.torus (loads matplotlib)
        from rotorsfd.plots.torus import plot_torus_components, plot_torus_spectrum

        return {"torus_components.png": plot_torus_components(self),
                "torus_spectrum.png": plot_torus_spectrum(
                    self, self.spectrum_index(multipliers_at))}

    def write(self, directory: str | Path, plots: bool = True,
              multipliers_at: float | None = None) -> dict[str, Path]:
        """Write torus.nc, torus.csv and the plots (:meth:`plot`) atomically."""
        # deferred: io.branch_files, io.torus_files (loads xarray, pandas, multiprocessing)
        from rotorsfd.io.branch_files import write_table
        from rotorsfd.io.torus_files import write_torus_netcdf

        out = Path(directory)
        paths = {"torus.nc": write_torus_netcdf(self.to_dataset(), out / "torus.nc"),
                 "torus.csv": write_table(out / "torus.csv", self.table()),
                 **write_node_table(out, self.node_names, self.nodes)}
        if plots:
            paths.update(atomic.save_figures(self.plot(multipliers_at), out))
        return paths


def lyapunov_indices(n_points: int, count: int = LYAPUNOV_POINTS) -> list[int]:
    """``count`` point indices spread evenly along a branch of n_points (first, last)."""
    if n_points <= 0:
        return []
    return sorted({int(np.rint(v)) for v in np.linspace(0, n_points - 1, min(count, n_points))})


def run_torus_response(config_or_system: Config | RotorSystem,
                       settings: ResponseAnalysis | None = None, *,
                       context: RunContext | None = None,
                       parameter: TorusParameter | None = None,
                       start: float | None = None, stop: float | None = None,
                       search_path: Path | None = None,
                       lattice: TorusLattice | None = None, progress: bool = True,
                       stability: bool | None = None, from_orbit: Any = None,
                       callback: Callable[[Any], bool | None] | None = None,
                       lyapunov_points: int = LYAPUNOV_POINTS) -> TorusResponseResult:
    """The torus branch of a system under a harmonic base law over its speed range, or at
    its fixed speed over a parameter range (module docstring).

    ``run_torus_response(system, settings, context=..., parameter=...)``: ``settings`` the
    ``[analysis.response]`` section (default: the context's, an empty section's), the
    speed range in Omega~ on the context's reference speed, ``parameter`` a
    :class:`~rotorsfd.analyses.torus_parameters.TorusParameter` (default the speed) with
    ``start, stop`` its range in SI. ``run_torus_response(config)`` is that call with
    ``build(config)``, ``config.analysis.response``, :func:`config_context`, the parameter
    of ``analysis.response.parameter`` (:func:`torus_parameter`) and its
    ``parameter_range`` in SI: the two paths cannot disagree. ``stability`` None: the
    context's ``[analysis.stability].enabled``. ``callback(point)`` returning True stops
    the branch (``point.index``, ``point.lam``: the parameter in SI)."""
    from rotorsfd.quasiperiodic import TorusLattice  # deferred: numba

    if from_orbit is not None:
        raise ConfigError("--from-orbit", str(from_orbit), "a torus branch (harmonic base "
                          "law) starts from the linear response, not from an orbit")
    if isinstance(config_or_system, Config):
        config = config_or_system
        r = config.analysis.response if settings is None else settings
        par = torus_parameter(config, r.parameter)
        if not config.elements:
            raise ConfigError("elements", None, "the nonlinear response needs at least one "
                              "nonlinear element (an [elements.<name>] table)")
        system = build(config, search_path)
        if par.name != "speed" and (start is None or stop is None):
            lo, hi = parameter_values(config, par.path, list(r.parameter_range))
            start, stop = (lo if start is None else start), (hi if stop is None else stop)
        return run_torus_response(
            system, r, context=config_context(config, system, "response",
                                              search_path=search_path),
            parameter=par, start=start, stop=stop, lattice=lattice, progress=progress,
            stability=stability, callback=callback, lyapunov_points=lyapunov_points)
    system = config_or_system
    ctx = context if context is not None else RunContext(search_path=search_path)
    r = settings if settings is not None else ctx.response
    par = parameter if parameter is not None else SPEED
    if not len(system.elements):
        raise ConfigError("elements", None, "the nonlinear response needs at least one "
                          "nonlinear element")
    ref = float(ctx.reference(system))
    speed = None
    if par.name == "speed":
        lo, hi = r.speed_range.bounds(ref)
        lo, hi = (lo if start is None else start), (hi if stop is None else stop)
        if not (lo > 0 and hi > 0) or lo == hi:
            raise ConfigError(f"{FIELD}.speed_range", r.speed_range.model_dump(
                exclude_none=True), "the torus branch needs two different speeds > 0")
    else:
        if r.speed is None and r.speed_ratio is None:
            raise ConfigError(f"{FIELD}.speed", None, f"continuing in {par.path} needs a "
                              "fixed speed: speed or speed_ratio")
        speed = float(r.fixed_speed(ref))
        if start is None or stop is None:
            raise ConfigError(f"{FIELD}.parameter_range", (start, stop),
                              f"give the range of {par.path} in SI")
        lo, hi = float(start), float(stop)
        low = 0.0 if par.name.endswith("amplitude") or par.name == "unbalance" else None
        if lo == hi or (low is None and not (lo > 0 and hi > 0)) or \
                (low is not None and not (lo >= 0 and hi >= 0)):
            need = "> 0" if low is None else ">= 0"
            raise ConfigError(f"{FIELD}.parameter_range", list(r.parameter_range or
                                                               (lo, hi)),
                              f"the torus branch in {par.path} needs two different values "
                              f"{need}")
    nodes = tuple(r.nodes) or system.output_nodes
    for n in nodes:
        if not 1 <= n <= system.rotor.n_nodes:
            raise ConfigError(f"{FIELD}.nodes", n, f"must be 1..{system.rotor.n_nodes}")
    lattice = lattice or TorusLattice(r.start_harmonics, r.base_harmonics)
    problem = parameter_problem(system, par, speed)   # ConfigError: unsupported base laws
    unit = "" if par.unit == "1" else f" {par.unit}"

    def where(lam: float) -> str:
        return f"Omega~ = {lam / ref:.4g}" if speed is None else \
            f"{par.path} = {lam:.4g}{unit}"

    def hook(index: int, lam: float, X: Any) -> bool:
        if progress:
            print(f"\rtorus: {index + 1} points, at {where(lam)}", end="",
                  file=sys.stderr, flush=True)
        return bool(callback(TorusPoint(index, lam, X))) if callback else False

    t0 = time.perf_counter()
    where_start = (f"the speed range ({where(lo)})" if speed is None else
                   f"{FIELD}.parameter_range ({where(lo)}, Omega~ = {speed / ref:.4g})")
    branch = continue_torus_section(problem, lo, hi, lattice, r, hook, start=where_start,
                                    progress=progress)
    enabled = ctx.stability.enabled if stability is None else stability
    lyap = (branch_lyapunov(branch, lattice, lambda lam: system_at(system, par, lam),
                            lyapunov_points) if enabled else {})
    return TorusResponseResult(branch, system, ref, tuple(nodes),
                               tuple(r.directions), ctx.title,
                               time.perf_counter() - t0, lyap,
                               {"config_toml": ctx.config_toml,
                                "limit_max": float(r.max_eccentricity)},
                               parameter=par.path, parameter_units=par.unit, speed=speed)
