"""The linear analyses of a configuration: its linear system, the reference speed
Omega_ref, the Campbell diagram and the critical speeds (``rotorsfd modal``).

``linear_system(config)`` is the rotor with its supports and the elements' linear parts
(the film excluded) plus the base terms of constant base rates; ``reference_speed(config)``
is ``reference.speed`` or the first forward critical speed, the Omega~ = Omega / Omega_ref
of every analysis.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.io import atomic
from rotorsfd.io.schema import Config
from rotorsfd.linear import CampbellResult, CriticalSpeed, campbell, critical_speeds
from rotorsfd.model.build import Model, build_model
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.time_terms import linear_part

__all__ = ["ModalRunResult", "first_critical", "linear_system", "modal_speeds",
           "reference_speed", "run_modal"]


def linear_system(config: Config, model: Model | RotorSystem | None = None) -> RotorSystem:
    """The linear rotor for modal analysis (``LinearDynamics``): the linear part of the
    configuration's system (:func:`~rotorsfd.model.time_terms.linear_part`: the rotor with
    its supports and the elements' linear parts, an SFD's centring spring, no film, on
    the constant base rates), whose ``matrices(speed)`` are the ``(M, D, K)`` of the
    model's record ``second_order(speed)``. ``model``: the configuration's system or
    :class:`~rotorsfd.model.build.Model` when already built. ConfigError if a base rate
    varies in time (no eigenvalues then)."""
    if model is None:
        model = build_model(config)
    if isinstance(model, Model):
        model = RotorSystem(model.rotor, base=model.base_motion)
    if not model.base.rates_constant:
        for name in ("rolling", "pitching", "yawing"):
            if getattr(config.base, name).law not in ("off", "constant"):
                raise ConfigError(f"base.{name}.law", getattr(config.base, name).law,
                                  "modal analysis needs constant base rates ('off' or "
                                  "'constant'); time-varying rates: use a stability chart")
    return linear_part(model)


def first_critical(system: Any, speed_max: float = 2e4) -> float:
    """The first forward critical speed of a linear ``system`` below ``speed_max`` [rad/s]
    (the reference speed of an analysis given a system, not a config)."""
    found = critical_speeds(system, n=1, whirl="forward", speed_range=(0.0, speed_max))
    if not found:
        raise ConfigError("reference_speed", None, f"no forward critical speed below "
                          f"{speed_max:g} rad/s: give the reference speed")
    return float(found[0].speed_rad_s)


def reference_speed(config: Config, system: Any | None = None,
                    forward_critical: Sequence[CriticalSpeed] | None = None) -> float:
    """Omega_ref [rad/s]: ``reference.speed``, or the first forward critical speed
    (``forward_critical``: the forward critical speeds of ``system`` below
    ``analysis.modal.critical_speed_max`` when already computed; the first is reused)."""
    if isinstance(config.reference.speed, float):
        return config.reference.speed
    top = config.analysis.modal.critical_speed_max
    if forward_critical is not None:
        found = list(forward_critical)
    else:
        system = linear_system(config) if system is None else system
        found = critical_speeds(system, n=1, whirl="forward", speed_range=(0.0, top))
    if not found:
        raise ConfigError("reference.speed", "first_critical",
                          f"no forward critical speed below analysis.modal.critical_speed_max"
                          f" = {top:g} rad/s; give reference.speed in rad/s")
    return found[0].speed_rad_s


@dataclass(frozen=True)
class ModalRunResult:
    """Campbell diagram and critical speeds of a configuration."""

    config: Config
    campbell: CampbellResult
    critical_speeds: list[CriticalSpeed]
    reference_speed: float

    FILES = ("critical_speeds.csv", "campbell.csv", "campbell.png")

    def critical_speeds_rows(self) -> list[tuple[int, str, float]]:
        """Rows ``(mode, whirl, speed_rad_s)``."""
        return [(c.mode, c.whirl, float(c.speed_rad_s)) for c in self.critical_speeds]

    def method_words(self) -> str:
        """How the modes were computed (``CampbellResult.info``) and, for the reduced model,
        its measured relative eigenvalue error max |lambda_red - lambda| / |lambda|."""
        info = self.campbell.info
        method = info.get("method", "")
        err = info.get("reduced_error")
        if method == "reduced":
            return (f"reduced model on exact modes at {len(info.get('snapshots_rad_s', []))} "
                    f"speeds (basis {info.get('basis_size')}), measured relative eigenvalue "
                    f"error {err:.1e}")
        if method == "sparse" and err is not None:
            return (f"sparse eigensolver at every speed (the reduced model's measured error "
                    f"{err:.1e} was above its tolerance)")
        if method:
            return f"{method} eigensolver at every speed"
        return ""

    def plot(self, ax: Any = None) -> Any:
        """Campbell diagram (:func:`rotorsfd.plots.campbell.campbell_axes`) with the
        critical speeds marked, the title wrapped (never cut); returns the Axes."""
        from rotorsfd.plots.campbell import campbell_axes, campbell_figure

        c = self.campbell
        crit = [s.speed_rad_s for s in self.critical_speeds]
        title = self.config.title or "Campbell diagram"
        if ax is None:
            return campbell_figure(c.speeds, c.frequencies, c.whirl, critical=crit,
                                   title=title).axes[0]
        return campbell_axes(ax, c.speeds, c.frequencies, c.whirl, critical=crit,
                             title=title)

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """Write ``critical_speeds.csv`` (mode, whirl, speed_rad_s), ``campbell.csv`` and
        (if ``plots``) ``campbell.png`` atomically into ``directory`` (created if
        missing)."""
        out = Path(directory)
        paths = {name: out / name for name in self.FILES}
        atomic.write_csv(paths["critical_speeds.csv"], ("mode", "whirl", "speed_rad_s"),
                         self.critical_speeds_rows())
        with atomic.atomic_path(paths["campbell.csv"]) as tmp:
            self.campbell.to_csv(tmp)
        if not plots:
            return {k: v for k, v in paths.items() if k != "campbell.png"}
        fig = self.plot().figure
        atomic.save_figure(fig, paths["campbell.png"], dpi=120)
        return paths

    def summary(self) -> str:
        """Human-readable lines: the Campbell method (and its measured error when known),
        the critical speeds (rad/s, rpm, Omega/Omega_ref)."""
        lines = [f"reference speed: {self.reference_speed:.6g} rad/s"]
        method = self.method_words()
        if method:
            lines.append(f"Campbell diagram: {self.campbell.speeds.size} speeds, {method}")
        for c in self.critical_speeds:
            lines.append(f"critical speed {c.mode} ({c.whirl}): {c.speed_rad_s:.6g} rad/s = "
                         f"{c.speed_rad_s * 30 / np.pi:.6g} rpm = "
                         f"{c.speed_rad_s / self.reference_speed:.4f} x reference")
        return "\n".join(lines)


def modal_speeds(config: Config, ref: float) -> np.ndarray:
    """The speeds of the Campbell diagram [rad/s]."""
    m = config.analysis.modal
    if m.speeds is not None:
        return np.asarray(m.speeds, dtype=float)
    start, stop = m.speed_range.bounds(ref)
    return np.linspace(start, stop, m.speed_range.n)


def run_modal(config: Config, search_path: Path | None = None,
              progress: bool = False) -> ModalRunResult:
    """Campbell diagram over ``analysis.modal`` speeds and the first ``n_critical``
    critical speeds (film excluded, centring spring included, constant base rates).
    ``progress``: a tqdm bar on stderr over the stages."""
    import sys

    from tqdm import tqdm

    m = config.analysis.modal
    if len({s.speed_ratio for s in config.rotor.shafts}) > 1:   # shafts at several speeds
        from rotorsfd.analyses.spool_modal import run_spool_modal

        system = linear_system(config, build_model(config, search_path))
        ref = reference_speed(config, system)
        return run_spool_modal(config, system, ref, modal_speeds(config, ref))
    with tqdm(total=3, desc="modal", disable=not progress, file=sys.stderr,
              leave=False) as bar:
        system = linear_system(config, build_model(config, search_path))
        bar.set_postfix_str("critical speeds")
        crit = critical_speeds(system, n=m.n_critical, whirl=m.whirl,
                               speed_range=(0.0, m.critical_speed_max))
        bar.update()
        bar.set_postfix_str("reference speed")   # the first forward one, not searched again
        ref = reference_speed(config, system, crit if m.whirl == "forward" else None)
        bar.update()
        bar.set_postfix_str("Campbell diagram")
        camp = campbell(system, modal_speeds(config, ref), m.n_modes)
        bar.update()
    return ModalRunResult(config, camp, crit, ref)
