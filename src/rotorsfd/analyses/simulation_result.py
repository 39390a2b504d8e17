"""The result of a time-domain simulation at one speed (:func:`rotorsfd.analyses.simulate.
run_simulation`): the recorded motion, its class and evidence, the Lyapunov exponent and the
step record; its files (``timeseries.nc``, ``poincare.csv``, ``summary.json``, the plots)
and the summary text."""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rotorsfd.analyses.step_control import StepControl
from rotorsfd.analyses.td_integration import DIRECTIONS
from rotorsfd.analyses.td_lyapunov import uncertainty_per_period
from rotorsfd.io import atomic
from rotorsfd.io.provenance import netcdf_attrs
from rotorsfd.model.node_names import NodeNames, node_words, with_shaft_coords
from rotorsfd.timedomain import LyapunovResult, MotionClass, amplitude_spectrum

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

FILE_SAMPLES_PER_PERIOD = 400
"""At most this many samples a period in ``timeseries.nc`` (a fine accepted step, e.g.
T/3200, is thinned by a whole factor: the file stays the size of a T/400 run)."""


def file_stride(steps_per_period: int) -> int:
    """The largest divisor k of ``steps_per_period`` with ``steps_per_period / k >=``
    :data:`FILE_SAMPLES_PER_PERIOD` (1 up to that many steps a period)."""
    n = int(steps_per_period)
    k = max(1, n // FILE_SAMPLES_PER_PERIOD)
    while n % k:
        k -= 1
    return k


@dataclass
class SimulationResult:
    """A simulation at one speed: recorded motion of ``nodes`` (``q, v``: (n_t, n_nodes,
    2) with directions y, z, every step of the last max(record, Poincare) periods), the
    Poincare points, the motion class and its evidence. ``clearance`` and ``element_node``:
    the elements' length scale and the first element's node (the journal shown in C);
    ``element_diagnostics``: every element's orbit diagnostics over the recorded periods
    (``eps_max_<name>``)."""

    speed: float
    reference_speed: float | None
    nodes: tuple[int, ...]
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    poincare_t: np.ndarray
    poincare_q: np.ndarray
    poincare_v: np.ndarray
    motion: MotionClass | None
    lyapunov: LyapunovResult | None
    clearance: float | None
    element_node: int | None
    settings: dict[str, Any]
    max_eccentricity: float | None
    max_eccentricity_run: float | None
    q_final: np.ndarray
    v_final: np.ndarray
    t_final: float
    elapsed: float
    title: str = ""
    notes: list[str] = field(default_factory=list)
    step_check: StepControl | None = None
    lyapunov_full: LyapunovResult | None = None
    element_diagnostics: dict[str, float] = field(default_factory=dict)
    config_toml: str = ""       # the resolved configuration it was run from, if any
    ended: str = "range"        #: "range" (every period run) or "limit" (contact)
    end_reason: str = ""        #: the element's contact report when ``ended == "limit"``
    #: shaft-wise node names of a multi-shaft rotor (None: one shaft)
    node_names: NodeNames | None = None

    FILES = ("timeseries.nc", "poincare.csv", "summary.json", "simulation.png", "orbit.png",
             "phase.png", "poincare.png", "spectrum.png")

    @property
    def period(self) -> float:
        """Rotor period T [s]."""
        return 2.0 * math.pi / self.speed

    @property
    def speed_ratio(self) -> float | None:
        return None if not self.reference_speed else self.speed / self.reference_speed

    @property
    def message(self) -> str:
        """The outcome in the user's terms: every period run, or where and why the run
        ended at an element's validity limit (the response's vocabulary, ``ended``)."""
        if self.ended == "limit":
            return (f"simulation ended after {self.settings.get('periods_run', 0)} of "
                    f"{self.settings.get('periods')} periods (t = {self.t_final:.6g} s; the "
                    f"files hold the periods before it): {self.end_reason}")
        return f"ran {self.settings.get('periods_run', self.settings.get('periods'))} periods"

    @property
    def motion_name(self) -> str:
        if self.motion is None:
            return "contact" if self.ended == "limit" else "unclassified"
        return self.motion.motion

    @property
    def plot_node(self) -> int:
        """The SFD journal if recorded, else the first output node."""
        return self.element_node if self.element_node in self.nodes else self.nodes[0]

    def column(self, node: int) -> int:
        return self.nodes.index(node)

    def spectrum(self, node: int | None = None, direction: str = "y"
                 ) -> tuple[np.ndarray, np.ndarray]:
        """(frequency / Omega, amplitude [m]) of the recorded ``node, direction`` over a
        whole number of periods (Blackman-Harris window, mean removed)."""
        j = self.column(self.plot_node if node is None else node)
        x = self.q[:, j, DIRECTIONS.index(direction)]
        if x.size < 4:                # a run that ended before its recorded periods
            return np.zeros(0), np.zeros(0)
        spp = int(self.settings["steps_per_period"])
        n = (x.size - 1) // spp * spp if x.size > spp else x.size
        freq, amp = amplitude_spectrum(x[:n], self.period / spp, detrend=True)
        return freq / self.speed, amp

    # ---- files ---------------------------------------------------------------------------
    def to_dataset(self) -> xr.Dataset:
        """``timeseries.nc`` layout: ``displacement`` [m], ``velocity`` [m/s] over
        (time, node, direction) for the last ``record_periods`` (both ends), every step up
        to :data:`FILE_SAMPLES_PER_PERIOD` samples a period, else every k-th step (attrs
        ``steps_per_period``, ``samples_per_period``); ``period`` = t / T along time."""
        # deferred: xarray is heavy (loaded only when this runs)
        import xarray as xr

        spp = int(self.settings["steps_per_period"])
        stride = file_stride(spp)
        keep = int(self.settings["record_periods"]) * spp
        sl = slice(max(0, self.t.size - keep - 1) + (keep % stride), None, stride)
        t = self.t[sl]
        coords = {"time": ("time", t, {"long_name": "time", "units": "s"}),
                  "node": ("node", np.asarray(self.nodes, dtype=np.int32),
                           {"long_name": "rotor node (from 1)", "units": "1"}),
                  "direction": ("direction", list(DIRECTIONS),
                                {"long_name": "direction (y, z, ty, tz)", "units": ""}),
                  "period": ("time", t / self.period,
                             {"long_name": "time in rotor periods t / T",
                              "units": "rotor periods"})}
        attrs = {"title": self.title, "speed_rad_s": self.speed, "motion": self.motion_name,
                 **netcdf_attrs(), "steps_per_period": spp,
                 "samples_per_period": spp // stride}
        if self.speed_ratio is not None:
            attrs["speed_ratio"] = self.speed_ratio
        if self.clearance is not None:
            attrs["clearance_m"] = self.clearance
            attrs["element_node"] = int(self.element_node)
        attrs["t_final_s"] = float(self.t_final)
        attrs["final_phase_rad"] = float(math.fmod(self.speed * self.t_final, 2 * math.pi))
        attrs["initial_state"] = str(self.settings.get("initial_state", ""))
        attrs["ended"] = self.ended
        attrs["outcome"] = self.message
        if self.config_toml:
            attrs["config_toml"] = self.config_toml
        coords["dof"] = ("dof", np.arange(self.q_final.size, dtype=np.int32),
                         {"description": "global DOF index: 4 (node - 1) + (y, z, ty, tz)",
                          "long_name": "global DOF index", "units": "1"})
        return with_shaft_coords(xr.Dataset(
            {"displacement": (("time", "node", "direction"), self.q[sl],
                              {"long_name": "displacement of the node", "units": "m"}),
             "velocity": (("time", "node", "direction"), self.v[sl],
                          {"long_name": "velocity of the node", "units": "m/s"}),
             "final_displacement": ("dof", self.q_final, {
                 "long_name": "displacement of every DOF at t_final_s",
                 "units": "m or rad", "description": "every DOF at t_final_s (a start "
                 "state for rotorsfd simulate --initial-state)"}),
             "final_velocity": ("dof", self.v_final,
                                {"long_name": "velocity of every DOF at t_final_s",
                                 "units": "m/s or rad/s"})},
            coords=coords, attrs=attrs), self.node_names)

    def poincare_table(self) -> dict[str, np.ndarray]:
        """Columns of ``poincare.csv``: ``node, period, y, z, vy, vz`` (one row per node and
        rotor period; ``period`` = t / T, an integer; SI: m, m/s), and for a multi-shaft
        rotor ``shaft, shaft_node`` (:mod:`rotorsfd.model.node_names`)."""
        n_p, n_n = self.poincare_t.size, len(self.nodes)
        per = np.rint(self.poincare_t / self.period).astype(np.int64)
        cols = {"node": np.repeat(np.asarray(self.nodes, dtype=np.int64)[None, :], n_p,
                                  axis=0).T.ravel(),
                "period": np.tile(per, n_n),
                "y": self.poincare_q[:, :, 0].T.ravel(),
                "z": self.poincare_q[:, :, 1].T.ravel(),
                "vy": self.poincare_v[:, :, 0].T.ravel(),
                "vz": self.poincare_v[:, :, 1].T.ravel()}
        if self.node_names is not None:     # a multi-shaft rotor: the node's shaft
            cols["shaft"], cols["shaft_node"] = self.node_names.arrays(cols["node"])
        return cols

    def summary_dict(self) -> dict[str, Any]:
        """Content of ``summary.json``."""
        ev = dict(self.motion.evidence) if self.motion is not None else {}
        lines = ev.pop("spectral_lines", None)
        if lines is not None:
            ev["spectral_lines"] = [{"frequency_rad_s": f, "amplitude_m": a, "ratio": r}
                                    for f, a, r in lines]
        ly = self.lyapunov
        return atomic.json_safe({
            "motion": self.motion_name, "ended": self.ended, "outcome": self.message,
            "speed_rad_s": self.speed, "speed_ratio": self.speed_ratio,
            "evidence": ev,
            "lyapunov": None if ly is None else {
                "exponent_per_s": ly.exponent, "per_period": ly.per_period,
                "half_spread_per_s": ly.half_spread,
                "uncertainty_per_period": uncertainty_per_period(ly, self.period),
                "d0": ly.d0, "renorm_every_steps": ly.renorm_every,
                "periods": self.settings.get("lyapunov_periods"),
                "high_modes_excluded": self.lyapunov_full is not None
                and self.lyapunov_full is not ly,
                "modes_kept": self.settings.get("lyapunov_modes_kept"),
                "omega_max_rad_s": self.settings.get("lyapunov_omega_max_rad_s")},
            "lyapunov_whole_state": None if self.lyapunov_full is None else {
                "exponent_per_s": self.lyapunov_full.exponent,
                "per_period": self.lyapunov_full.per_period,
                "half_spread_per_s": self.lyapunov_full.half_spread,
                "uncertainty_per_period": uncertainty_per_period(self.lyapunov_full,
                                                                 self.period)},
            "max_eccentricity": self.max_eccentricity,
            "max_eccentricity_whole_run": self.max_eccentricity_run,
            "clearance_m": self.clearance, "element_node": self.element_node,
            "elements": dict(self.element_diagnostics),
            "nodes": list(self.nodes), "settings": self.settings,
            "elapsed_s": self.elapsed, "t_final_s": self.t_final, "notes": self.notes,
            "step_check": None if self.step_check is None else self.step_check.as_dict(),
            "title": self.title})

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """Write ``timeseries.nc``, ``poincare.csv``, ``summary.json`` and the plots
        atomically (nothing is written if a value is not finite)."""
        # deferred: io.branch_files (loads xarray, pandas, multiprocessing)
        from rotorsfd.io.branch_files import check_finite, write_table

        ds = self.to_dataset()
        check_finite(ds)
        out = Path(directory)
        paths = {"timeseries.nc": atomic.write_netcdf(ds, out / "timeseries.nc"),
                 "poincare.csv": write_table(out / "poincare.csv", self.poincare_table()),
                 "summary.json": atomic.write_json(out / "summary.json", self.summary_dict())}
        if plots:
            paths.update(atomic.save_figures(self.plot(), out))
        return paths

    # ---- plots and text ----------------------------------------------------------------------
    def plot(self, node: int | None = None) -> dict[str, Figure]:
        """Figures by file name: ``simulation.png`` (four panels like the paper's Fig. 23)
        and ``orbit.png``, ``phase.png``, ``poincare.png``, ``spectrum.png``."""
        # deferred: plots.timedomain (loads matplotlib)
        from rotorsfd.plots.timedomain import simulation_figures

        node = self.plot_node if node is None else node
        j = self.column(node)
        ratio, amp = self.spectrum(node, "y")
        scale = self.clearance if self.clearance else 1.0
        title = (f"{node_words(self.node_names, node)}, Omega = {self.speed:.5g} rad/s"
                 + (f" (Omega~ = {self.speed_ratio:.4g})" if self.speed_ratio else "")
                 + (f": {self.motion_name}" if self.ended == "range" else
                    f": ended at the validity limit (contact) at t = {self.t_final:.4g} s")
                 + (f" -- {self.title}" if self.title else ""))
        return simulation_figures(
            y=self.q[:, j, 0] / scale, z=self.q[:, j, 1] / scale,
            vy=self.v[:, j, 0] / (scale * self.speed),
            py=self.poincare_q[:, j, 0] / scale, pz=self.poincare_q[:, j, 1] / scale,
            pvy=self.poincare_v[:, j, 0] / (scale * self.speed),
            frequency_ratio=ratio, amplitude=amp / scale,
            clearance_circle=self.clearance is not None and node == self.element_node,
            unit="C" if self.clearance else "m", title=title)

    def summary(self) -> str:
        """A few lines: motion, evidence, eccentricity, time."""
        ev = self.motion.evidence if self.motion is not None else {}
        sr = f" (Omega~ = {self.speed_ratio:.5g})" if self.speed_ratio else ""
        lines = [f"speed {self.speed:.6g} rad/s{sr}: {self.motion_name}"
                 + (f" ({ev.get('basis')})" if ev.get("basis") else "")]
        if ev:
            ratios = ", ".join(f"{r:.4g}" for r in ev.get("frequency_ratios", [])[:8])
            lines.append(f"distinct Poincare points: {ev.get('n_distinct_poincare')} of "
                         f"{ev.get('n_poincare')}; spectral lines / Omega: {ratios}")
        if self.lyapunov is not None:
            ly, T = self.lyapunov, self.period
            text = (f"largest Lyapunov exponent: {ly.per_period:.3g} +/- "
                    f"{uncertainty_per_period(ly, T):.2g} per period ({ly.exponent:.4g} "
                    f"+/- {ly.half_spread:.2g} 1/s)")
            full = self.lyapunov_full
            if full is not None and full is not ly:
                text += (f", neutral high modes excluded; whole state: {full.per_period:.3g}"
                         f" +/- {uncertainty_per_period(full, T):.2g} per period")
            lines.append(text)
        if self.max_eccentricity is not None:
            lines.append(f"max eccentricity ratio: {self.max_eccentricity:.4f} (recorded "
                         f"periods), {self.max_eccentricity_run:.4f} (whole run)")
        if len(self.element_diagnostics) > 1:
            lines.append("elements over the recorded periods: " + ", ".join(
                f"{k} = {v:.4g}" for k, v in self.element_diagnostics.items()))
        lines.append(f"{self.settings['periods']} periods, {self.settings['steps_per_period']}"
                     f" steps per period ({self.settings['step_control']}, "
                     f"{self.settings['scheme']}) in {self.elapsed:.2f} s")
        if self.step_check is not None:
            lines.append(self.step_check.line())
        if ev.get("note"):
            lines.append(f"note: {ev['note']}")
        lines += [f"note: {n}" for n in self.notes]
        warning = self.step_check.warning() if self.step_check is not None else None
        if warning:
            lines.append(f"warning: {warning}")
        if self.ended != "range":
            lines.append(f"ended at a validity limit: {self.message}")
        return "\n".join(lines)
