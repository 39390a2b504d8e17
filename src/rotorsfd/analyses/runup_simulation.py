"""``simulate`` under a speed law (run-up, coast-down): the run of
:func:`rotorsfd.analyses.runup.run_speed_law` from the displaced state, its result and its
files.

``timeseries.nc``: ``displacement`` [m] over (time, node, direction), with the coordinates
``speed`` [rad/s] and ``rotor_angle`` [rad] along time (the orbit against time and against
speed), ``radius`` [m] = sqrt(y^2 + z^2) per node and, at an element with a clearance,
``eccentricity`` = radius / C; the law in the attributes (``speed_law``). ``summary.json``:
the law, the step, and per node the peak radius with the time and the speed where it occurs.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.analyses.runup import SpeedLawRun, run_speed_law
from rotorsfd.analyses.td_integration import DIRECTIONS, FIELD, scheme_options
from rotorsfd.errors import ConfigError
from rotorsfd.model import dofs
from rotorsfd.model.system import RotorSystem
from rotorsfd.timedomain.speed_law import RampSpeed, SpeedLaw, TableSpeed

DEFAULT_STEPS = 200
"""Steps per period of the highest speed with ``steps_per_period = "auto"`` (no halving
control under a speed law yet)."""


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

    def radius(self, node: int) -> np.ndarray:
        return self.run.radius(node)

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
        import xarray as xr

        from rotorsfd import __version__

        run = self.run
        q = np.stack([np.stack([run.q[:, self._col(n, d)] for d in DIRECTIONS], axis=-1)
                      for n in self.nodes], axis=1)
        radius = np.hypot(q[..., 0], q[..., 1])
        coords = {"time": ("time", run.t, {"units": "s"}),
                  "speed": ("time", run.omega, {"units": "rad/s"}),
                  "rotor_angle": ("time", run.theta, {"units": "rad"}),
                  "node": ("node", np.asarray(self.nodes, dtype=np.int32)),
                  "direction": ("direction", list(DIRECTIONS))}
        data = {"displacement": (("time", "node", "direction"), q, {"units": "m"}),
                "radius": (("time", "node"), radius, {"units": "m"})}
        if self.clearances:
            c = np.array([self.clearances.get(n, np.inf) for n in self.nodes])
            data["eccentricity"] = (("time", "node"), radius / c, {
                "units": "1", "description": "radius / clearance (0 at nodes without one)"})
        attrs = {"title": self.title, "speed_law": self.settings["speed_law"],
                 "rotorsfd_version": __version__,
                 "steps_per_period": self.settings["steps_per_period"],
                 "t_final_s": float(run.t[-1])}
        return xr.Dataset(data, coords=coords, attrs=attrs)

    def _col(self, node: int, direction: str) -> int:
        return int(np.flatnonzero(self.run.dofs == dofs.dof_index(node, direction))[0])

    def summary_dict(self) -> dict[str, Any]:
        return {"analysis": "simulate (speed law)", "title": self.title, **self.settings,
                "peaks": self.peaks(),
                "max_eccentricity_run": self.run.max_eccentricity_run}

    def summary(self) -> str:
        lines = [f"speed law: {self.settings['speed_law']}",
                 f"  {self.run.t.size - 1} steps of T/{self.settings['steps_per_period']} "
                 f"at {self.settings['speed_max_rad_s']:.6g} rad/s"]
        for n, p in self.peaks().items():
            lines.append(f"  node {n}: peak radius {p['radius_max_m']:.4g} m at "
                         f"t = {p['time_s']:.4g} s, {p['speed_rad_s']:.6g} rad/s")
        return "\n".join(lines)

    def write(self, directory: str | Path, plots: bool = False) -> dict[str, Path]:
        """``timeseries.nc`` and ``summary.json`` in ``directory``."""
        from rotorsfd.io import atomic

        out = Path(directory)
        out.mkdir(parents=True, exist_ok=True)
        ds = self.to_dataset()
        for name, var in ds.data_vars.items():
            if not np.all(np.isfinite(var.values)):
                raise ValueError(f"{name}: non-finite values")
        return {"timeseries.nc": atomic.write_netcdf(ds, out / "timeseries.nc"),
                "summary.json": atomic.write_json(out / "summary.json", self.summary_dict())}


def law_of(law: Any, search_path: Path | None = None) -> SpeedLaw:
    """A law object as given, or the law of a config table / CLI text."""
    from rotorsfd.timedomain.speed_law_config import parse_speed_law_text, speed_law_from_config

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
                             initial_displacement: float | None = None) -> RunUpResult:
    """Integrate ``system`` under ``law`` from the displaced state of ``sim``
    (``[analysis.simulate]``; ``initial_displacement`` in y and z at every node)."""
    spp = steps_per_period if steps_per_period is not None else sim.steps_per_period
    spp = DEFAULT_STEPS if spp == "auto" else spp
    if not (isinstance(spp, int | np.integer) and spp >= 8):
        raise ConfigError(f"{FIELD}.steps_per_period", spp, '"auto" or an integer >= 8')
    for n in nodes:
        if not 1 <= n <= system.rotor.n_nodes:
            raise ConfigError(f"{FIELD}.nodes", n, f"must be 1..{system.rotor.n_nodes}")
    opts = scheme_options(scheme or sim.scheme, sim.alpha if alpha is None else alpha)
    t_end = law_end(law, periods or sim.periods)
    disp = sim.initial_displacement if initial_displacement is None \
        else initial_displacement
    q0 = np.zeros(system.n_dof)
    q0[0::4] = q0[1::4] = disp
    rec = [dofs.dof_index(n, d) for n in nodes for d in DIRECTIONS]
    run = run_speed_law(system, law, t_end, steps_per_period=int(spp), record_dofs=rec,
                        q0=q0, v0=0.0, method_options=opts)
    clear = {}
    for e in system.elements:
        c = getattr(e, "clearance", None)
        node = getattr(e, "node", None)
        if c and node in nodes:
            clear[int(node)] = float(c)
    settings = {"speed_law": law.describe() if hasattr(law, "describe") else str(law),
                "steps_per_period": int(spp), "scheme": scheme or sim.scheme,
                "t_end_s": float(run.t[-1]),
                "speed_max_rad_s": float(np.max(run.omega)),
                "speed_min_rad_s": float(np.min(run.omega)),
                "initial_displacement_m": float(disp)}
    return RunUpResult(run, tuple(int(n) for n in nodes), settings, title, clear)

