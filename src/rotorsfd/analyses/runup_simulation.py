"""``simulate`` under a speed law (run-up, coast-down): the run of
:func:`rotorsfd.analyses.runup.run_speed_law` from the displaced state, its result and its
files.

``timeseries.nc``: ``displacement`` [m] over (time, node, direction), with the coordinates
``speed`` [rad/s] and ``rotor_angle`` [rad] along time (the orbit against time and against
speed), ``radius`` [m] = sqrt(y^2 + z^2) per node and, at an element with a clearance,
``eccentricity`` = radius / C; the waterfall ``waterfall`` [m] over (window, frequency, node)
(:mod:`rotorsfd.timedomain.waterfall`: the two-sided short-time spectrum of y + i z, forward
whirl at positive frequencies) with the window's ``window_time`` and ``window_speed``, and
the natural frequencies ``natural_frequency`` [rad/s] of the linear rotor (forward modes)
over ``campbell_speed``; the law in the attributes (``speed_law``). ``summary.json``: the
law, the step, per node the peak radius with the time and the speed where it occurs, and
around each unbalance event the peaks before and after it. Figures: ``envelope.png``
(radius against speed, with a steady branch file's orbit over it when given, and against
time) and ``waterfall_<node>.png``.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd import __version__
from rotorsfd.analyses.runup import SpeedLawRun, run_speed_law, speed_law_inputs
from rotorsfd.analyses.runup_step import controlled_run
from rotorsfd.analyses.td_integration import (
    DIRECTIONS,
    FIELD,
    refuse_large_full_step,
    scheme_options,
)
from rotorsfd.errors import ConfigError
from rotorsfd.io import atomic
from rotorsfd.io.provenance import netcdf_attrs
from rotorsfd.model import dofs
from rotorsfd.model.node_names import NodeNames, node_words, with_shaft_coords
from rotorsfd.model.system import RotorSystem
from rotorsfd.timedomain.speed_law import RampSpeed, SpeedLaw, TableSpeed
from rotorsfd.timedomain.speed_law_config import parse_speed_law_text, speed_law_from_config
from rotorsfd.timedomain.waterfall import Waterfall, default_window, waterfall


def law_end(law: SpeedLaw, periods: int) -> float:
    """The run's length: a ramp's end, a table's last time, else ``periods`` periods of
    the (first) speed."""
    if isinstance(law, RampSpeed):
        return law.t_start + law.duration
    if isinstance(law, TableSpeed):
        return float(law.times[-1])
    return periods * 2.0 * np.pi / float(law.omega(np.array(0.0)))


@dataclass
class RunUpResult:
    """A run under a speed law at the output ``nodes``."""

    run: SpeedLawRun
    nodes: tuple[int, ...]
    settings: dict[str, Any]
    title: str = ""
    clearances: dict[int, float] = field(default_factory=dict)
    events: tuple[float, ...] = ()
    natural: tuple[np.ndarray, np.ndarray] | None = None
    #: the steady branch drawn over the envelope: node -> (speed, radius, stable)
    branch: dict[int, tuple[np.ndarray, ...]] | None = None
    config_toml: str = ""       # the resolved configuration it was run from, if any
    #: shaft-wise node names of a multi-shaft rotor (None: one shaft)
    node_names: NodeNames | None = None
    _waterfalls: dict[int, Waterfall] = field(default_factory=dict, repr=False)

    def radius(self, node: int) -> np.ndarray:
        return self.run.radius(node)

    def waterfall(self, node: int) -> Waterfall:
        """The waterfall of ``node`` on windows of 16 periods of the slowest speed (at most a
        quarter of the run); computed once (the files and the figures both use it)."""
        if node not in self._waterfalls:
            run = self.run
            window = min(default_window(float(np.min(run.omega))), 0.25 * float(run.t[-1]))
            self._waterfalls[node] = waterfall(run.t, run.q[:, self._col(node, "y")],
                                               run.q[:, self._col(node, "z")], window)
        return self._waterfalls[node]

    def event_peaks(self) -> list[dict[str, Any]]:
        """Around each unbalance event: per node the peak radius before and after it."""
        out = []
        for te in self.events:
            before = self.run.t < te
            row: dict[str, Any] = {"time_s": float(te), "nodes": {}}
            for n in self.nodes:
                r = self.radius(n)
                after = r[~before]
                i = int(np.argmax(after)) + int(np.count_nonzero(before)) if after.size else 0
                row["nodes"][str(n)] = {
                    "radius_max_before_m": float(r[before].max()) if before.any() else 0.0,
                    "radius_max_after_m": float(r[i]), "time_of_max_after_s":
                    float(self.run.t[i])}
            out.append(row)
        return out

    def peaks(self) -> dict[str, dict[str, float]]:
        """Per node: the largest radius [m], the time [s] and the speed [rad/s] there."""
        out = {}
        for n in self.nodes:
            r = self.radius(n)
            i = int(np.argmax(r))
            out[str(n)] = {"radius_max_m": float(r[i]), "time_s": float(self.run.t[i]),
                           "speed_rad_s": float(self.run.omega[i])}
            if n in self.clearances:
                out[str(n)]["eccentricity_max"] = float(r[i] / self.clearances[n])
        return out

    def to_dataset(self):
        """``timeseries.nc`` (module docstring)."""
        # deferred: xarray is heavy (loaded only when this runs)
        import xarray as xr

        run = self.run
        q = np.stack([np.stack([run.q[:, self._col(n, d)] for d in DIRECTIONS], axis=-1)
                      for n in self.nodes], axis=1)
        radius = np.hypot(q[..., 0], q[..., 1])
        coords = {"time": ("time", run.t, {"units": "s"}),
                  "speed": ("time", run.omega, {"units": "rad/s"}),
                  "rotor_angle": ("time", run.theta, {"units": "rad"}),
                  "node": ("node", np.asarray(self.nodes, dtype=np.int32),
                           {"long_name": "node number (1-based)", "units": "1"}),
                  "direction": ("direction", list(DIRECTIONS),
                                {"long_name": "lateral direction of the base frame"})}
        data = {"displacement": (("time", "node", "direction"), q, {"units": "m"}),
                "radius": (("time", "node"), radius, {"units": "m"})}
        if self.clearances:
            c = np.array([self.clearances.get(n, np.inf) for n in self.nodes])
            data["eccentricity"] = (("time", "node"), radius / c, {
                "units": "1", "description": "radius / clearance (0 at nodes without one)"})
        falls = [self.waterfall(n) for n in self.nodes]
        coords.update({"window_time": ("window", falls[0].time, {"units": "s",
                                                                  "long_name": "window centre"}),
                       "window_speed": ("window", np.interp(falls[0].time, run.t, run.omega),
                                        {"units": "rad/s",
                                         "long_name": "speed at the window centre"}),
                       "frequency": ("frequency", falls[0].frequency, {
                           "units": "Hz", "long_name": "whirl frequency (> 0 forward, "
                                                       "< 0 backward)"})})
        data["waterfall"] = (("window", "frequency", "node"),
                             np.stack([f.amplitude for f in falls], axis=-1),
                             {"units": "m", "long_name": "short-time whirl amplitude of "
                                                         "y + i z (Hann window)"})
        if self.natural is not None:
            coords["campbell_speed"] = ("campbell_speed", self.natural[0], {"units": "rad/s"})
            data["natural_frequency"] = (("campbell_speed", "mode"), self.natural[1], {
                "units": "rad/s", "long_name": "natural frequency of the linear rotor "
                                               "(forward whirl)"})
        attrs = {**netcdf_attrs(), "title": self.title, "speed_law": self.settings["speed_law"],
                 "rotorsfd_version": __version__,
                 "steps_per_period": self.settings["steps_per_period"],
                 "t_final_s": float(run.t[-1])}
        if self.config_toml:
            attrs["config_toml"] = self.config_toml
        return with_shaft_coords(xr.Dataset(data, coords=coords, attrs=attrs),
                                 self.node_names)

    def _col(self, node: int, direction: str) -> int:
        return int(np.flatnonzero(self.run.dofs == dofs.dof_index(node, direction))[0])

    def summary_dict(self) -> dict[str, Any]:
        return {"analysis": "simulate (speed law)", "title": self.title, **self.settings,
                "peaks": self.peaks(), "events": self.event_peaks(),
                "max_eccentricity_run": self.run.max_eccentricity_run}

    def summary(self) -> str:
        lines = [f"speed law: {self.settings['speed_law']}",
                 f"  {self.run.t.size - 1} steps of T/{self.settings['steps_per_period']} "
                 f"at {self.settings['speed_max_rad_s']:.6g} rad/s"]
        step = self.settings.get("time_step") or {}
        if step.get("halvings"):
            ladder = ", ".join(f"T/{h['steps_per_period'][0]} -> T/{h['steps_per_period'][1]}"
                               f" {h['difference']:.2g}" for h in step["halvings"])
            lines.append(f"  time step ({step['mode']}): change of the orbit radius at node "
                         f"{step['node']} per halving ({step['unit']}): {ladder} "
                         f"(tolerance {step['tolerance']:g})")
        for n, p in self.peaks().items():
            lines.append(f"  {node_words(self.node_names, int(n))}: peak radius "
                         f"{p['radius_max_m']:.4g} m at "
                         f"t = {p['time_s']:.4g} s, {p['speed_rad_s']:.6g} rad/s")
        for ev in self.event_peaks():
            for n, p in ev["nodes"].items():
                lines.append(f"  unbalance event at t = {ev['time_s']:.4g} s, "
                             f"{node_words(self.node_names, int(n))}: peak "
                             f"radius {p['radius_max_before_m']:.4g} m before, "
                             f"{p['radius_max_after_m']:.4g} m after (t = "
                             f"{p['time_of_max_after_s']:.4g} s)")
        if step.get("warning"):
            lines.append(f"warning: {step['warning']}")
        return "\n".join(lines)

    def plot(self) -> dict[str, Any]:
        """``envelope.png`` and ``waterfall_<node>.png`` (:mod:`rotorsfd.plots.transient`)."""
        # deferred: plots.transient (loads matplotlib)
        from rotorsfd.plots.transient import envelope_figure, waterfall_figure

        run = self.run
        branch = self.branch
        figs = {"envelope.png": envelope_figure(
            t=run.t, speed=run.omega, radius={n: self.radius(n) for n in self.nodes},
            clearances=self.clearances, events=self.events, branch=branch,
            title=f"{self.title}: {self.settings['speed_law']}".strip(": "))}
        for n in self.nodes:
            f = self.waterfall(n)
            c = self.clearances.get(n)
            figs[f"waterfall_{n}.png"] = waterfall_figure(
                time=f.time, frequency_hz=f.frequency, amplitude=f.amplitude, node=n,
                t=run.t, speed=run.omega, natural=self.natural,
                unit_scale=1.0 / c if c else 1e6, unit="C" if c else "µm",
                title=f"node {n}: waterfall, {self.settings['speed_law']}")
        return figs

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """``timeseries.nc``, ``summary.json`` and (``plots``) the figures in ``directory``."""
        out = Path(directory)
        out.mkdir(parents=True, exist_ok=True)
        ds = self.to_dataset()
        for name, var in ds.data_vars.items():
            if not np.all(np.isfinite(var.values)):
                raise ValueError(f"{name}: non-finite values")
        paths = {"timeseries.nc": atomic.write_netcdf(ds, out / "timeseries.nc"),
                 "summary.json": atomic.write_json(out / "summary.json", self.summary_dict())}
        if plots:
            paths.update(atomic.save_figures(self.plot(), out))
        return paths


def branch_envelope(path: Path, nodes: Sequence[int]) -> dict[int, tuple[np.ndarray, ...]]:
    """Per node of ``nodes`` in the branch file ``path`` (``rotorsfd response``'s
    branch.nc): (speed [rad/s], largest orbit radius over the period [m], stable (1/0)),
    the radius from the harmonics ``q(t) = Re sum_k X_k exp(i k w t)`` on 128 samples."""
    # deferred: xarray is heavy (loaded only when this runs)
    import xarray as xr

    try:
        ds = xr.open_dataset(path)
    except (OSError, ValueError):
        raise ConfigError(f"{FIELD}.overlay", str(path), "a netCDF branch.nc written by "
                          "rotorsfd response") from None
    with ds:
        if "X_real" not in ds or "speed_rad_s" not in ds.coords:
            raise ConfigError(f"{FIELD}.overlay", str(path), "a branch.nc written by "
                              "rotorsfd response (a periodic branch in speed)")
        X = ds["X_real"].values + 1j * ds["X_imag"].values        # (point, harmonic, dof)
        k = ds["harmonic"].values
        node_of, direction = ds["node"].values, ds["direction"].values
        speed = ds["speed_rad_s"].values
        stable = ds["stable"].values if "stable" in ds else np.ones(speed.size)
    phase = np.exp(1j * np.outer(k, np.linspace(0.0, 2 * np.pi, 128, endpoint=False)))
    out = {}
    for n in nodes:
        iy = np.flatnonzero((node_of == n) & (direction == "y"))
        iz = np.flatnonzero((node_of == n) & (direction == "z"))
        if iy.size == 0 or iz.size == 0:
            continue
        y = np.real(np.einsum("ph,hs->ps", X[:, :, iy[0]], phase))
        z = np.real(np.einsum("ph,hs->ps", X[:, :, iz[0]], phase))
        out[int(n)] = (speed, np.hypot(y, z).max(axis=1), np.asarray(stable, float))
    return out


def law_of(law: Any, search_path: Path | None = None) -> SpeedLaw:
    """A law object as given, or the law of a config table / CLI text."""
    if isinstance(law, str):
        law = parse_speed_law_text(law)
    if isinstance(law, dict):
        return speed_law_from_config(law, search_path)
    if not callable(getattr(law, "omega", None)):
        raise ConfigError(f"{FIELD}.speed_law", law, "a speed law (config table or object)")
    return law


def run_speed_law_simulation(system: RotorSystem, law: SpeedLaw, *, sim: Any,
                             nodes: Sequence[int], title: str = "",
                             steps_per_period: int | str | None = None,
                             periods: int | None = None, scheme: str | None = None,
                             alpha: float | None = None,
                             initial_displacement: float | None = None,
                             overlay: str | Path | None = None,
                             natural_modes: int = 6, config_toml: str = "") -> RunUpResult:
    """Integrate ``system`` under ``law`` from the displaced state of ``sim``
    (``[analysis.simulate]``; ``initial_displacement`` in y and z at every node)."""
    spp = steps_per_period if steps_per_period is not None else sim.steps_per_period
    if spp != "auto" and not (isinstance(spp, int | np.integer) and spp >= 8):
        raise ConfigError(f"{FIELD}.steps_per_period", spp, '"auto" or an integer >= 8')
    for n in nodes:
        if not 1 <= n <= system.rotor.n_nodes:
            raise ConfigError(f"{FIELD}.nodes", n, f"must be 1..{system.rotor.n_nodes}")
    overlay = overlay if overlay is not None else getattr(sim, "overlay", None)
    branch = None
    if overlay is not None:                  # read (and so checked) before the run
        overlay = Path(overlay)
        if not overlay.is_file():
            raise ConfigError(f"{FIELD}.overlay", str(overlay), "an existing branch.nc "
                              "of rotorsfd response")
        branch = branch_envelope(overlay, nodes)
    opts = scheme_options(scheme or sim.scheme, sim.alpha if alpha is None else alpha)
    t_end = law_end(law, periods or sim.periods)
    disp = sim.initial_displacement if initial_displacement is None \
        else initial_displacement
    q0 = np.zeros(system.n_dof)
    q0[0::4] = q0[1::4] = disp
    rec = [dofs.dof_index(n, d) for n in nodes for d in DIRECTIONS]
    clear = {}
    for e in system.elements:
        c = getattr(e, "clearance", None)
        node = getattr(e, "node", None)
        if c and node in nodes:
            clear[int(node)] = float(c)
    inputs = speed_law_inputs(system, law, t_end)
    reduction = getattr(sim, "reduction", "none")
    if reduction == "none":           # the config's full step: refused on large models
        refuse_large_full_step(inputs.n_dof)

    def run_at(n: int) -> SpeedLawRun:
        return run_speed_law(None, law, t_end, steps_per_period=n, record_dofs=rec, q0=q0,
                             v0=0.0, inputs=inputs, method_options=opts, reduction=reduction)

    node = next(iter(clear), nodes[0])
    run, step = controlled_run(run_at, spp, node=node, clearance=clear.get(node),
                               tolerance=sim.step_tolerance,
                               max_steps=sim.max_steps_per_period,
                               check=sim.step_check_periods > 0)
    settings = {"speed_law": law.describe() if hasattr(law, "describe") else str(law),
                "steps_per_period": step.steps_per_period, "time_step": step.as_dict(),
                "reduction": reduction, "scheme": scheme or sim.scheme,
                "t_end_s": float(run.t[-1]),
                "speed_max_rad_s": float(np.max(run.omega)),
                "speed_min_rad_s": float(np.min(run.omega)),
                "initial_displacement_m": float(disp)}
    events = tuple(sorted({float(u.start) for u in system.unbalances if u.start > 0.0}))
    natural = _natural_frequencies(system, run.omega, natural_modes)
    if overlay is not None:
        settings["overlay"] = str(overlay)
    return RunUpResult(run, tuple(int(n) for n in nodes), settings, title, clear, events,
                       natural, branch, config_toml, NodeNames.of(system.rotor))


def _natural_frequencies(system: RotorSystem, omega: np.ndarray, n_modes: int
                         ) -> tuple[np.ndarray, np.ndarray] | None:
    """Forward-whirl natural frequencies of the linear rotor (supports and the elements'
    linear parts, no film) at 9 speeds over the run (None without modes)."""
    if n_modes <= 0:
        return None
    # deferred: linear.campbell (loads 7 more rotorsfd modules, needed only here)
    from rotorsfd.linear.campbell import campbell

    lo, hi = float(np.min(omega)), float(np.max(omega))
    speeds = np.linspace(lo, hi if hi > lo else lo * 1.0001, 9)
    res = campbell(system.rotor, speeds, n_modes=2 * n_modes)
    forward = np.all(res.whirl == "forward", axis=0)
    return speeds, np.asarray(res.frequencies)[:, forward][:, :n_modes]

