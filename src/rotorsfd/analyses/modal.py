"""The Campbell diagram and the critical speeds of the linear rotor (``rotorsfd modal``).

``run_modal(system, settings, context=...)``: ``settings`` the ``[analysis.modal]`` section
(speeds, modes, whirl, the critical-speed search bound), ``context`` the reference speed
and title (:class:`~rotorsfd.analyses.context.RunContext`; its reference speed None: the
first forward critical speed, reused from the located ones). ``run_modal(config)`` is that
call with ``build(config)``, ``config.analysis.modal`` and ``config_context``. The linear
system (film excluded, centring spring and constant base rates included) and the reference
speed Omega_ref are :mod:`~rotorsfd.analyses.linear_model`'s (``linear_system``,
``reference_speed``, ``first_critical``, re-exported here).
"""

from __future__ import annotations

import sys
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rotorsfd.analyses.context import RunContext, build, config_context
from rotorsfd.analyses.linear_model import (
    first_critical,
    forward_reference,
    linear_system,
    reference_speed,
)
from rotorsfd.analyses.modal_files import modal_dataset, write_modal
from rotorsfd.io.schema import Config, ModalAnalysis
from rotorsfd.linear import CampbellResult, CriticalSpeed, campbell, critical_speeds

if TYPE_CHECKING:
    from rotorsfd.analyses.spool_modal import SpoolModalResult
    from rotorsfd.model.system import RotorSystem

__all__ = ["ModalRunResult", "first_critical", "linear_system", "modal_speeds",
           "reference_speed", "run_modal"]


@dataclass(frozen=True)
class ModalRunResult:
    """Campbell diagram and critical speeds of the linear rotor, with the reference speed
    and the title of the run."""

    campbell: CampbellResult
    critical_speeds: list[CriticalSpeed]
    reference_speed: float
    title: str = ""

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

    def plot_on(self, ax: Any) -> Any:
        """The Campbell diagram on ``ax`` (:func:`rotorsfd.plots.campbell.campbell_axes`),
        critical speeds marked, the title wrapped (never cut); returns ``ax``."""
        # deferred: plots.campbell loads matplotlib (only when drawing)
        from rotorsfd.plots.campbell import campbell_axes

        c = self.campbell
        return campbell_axes(ax, c.speeds, c.frequencies, c.whirl,
                             critical=[s.speed_rad_s for s in self.critical_speeds],
                             title=self.title or "Campbell diagram")

    def plot(self) -> dict[str, Any]:
        """``campbell.png``: the Campbell diagram (:meth:`plot_on` on a new figure)."""
        # deferred: plots.campbell loads matplotlib (only when drawing)
        from rotorsfd.plots.campbell import campbell_figure

        c = self.campbell
        return {"campbell.png": campbell_figure(
            c.speeds, c.frequencies, c.whirl,
            critical=[s.speed_rad_s for s in self.critical_speeds],
            title=self.title or "Campbell diagram")}

    def to_dataset(self) -> Any:
        """The Campbell diagram (:meth:`CampbellResult.to_dataset`) with the critical
        speeds (dimension ``critical``) and the reference speed."""
        return modal_dataset(self.campbell, self.critical_speeds_rows(),
                             self.reference_speed, self.title)

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """Write ``critical_speeds.csv`` (mode, whirl, speed_rad_s), ``campbell.csv`` and
        (if ``plots``) ``campbell.png`` atomically into ``directory`` (created if
        missing)."""
        return write_modal(self, Path(directory), ("mode", "whirl", "speed_rad_s"), plots)

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


def modal_speeds(settings: ModalAnalysis | Config, ref: float) -> np.ndarray:
    """The speeds of the Campbell diagram [rad/s]: ``settings.speeds`` or its speed range
    on Omega_ref = ``ref`` (``settings``: the ``[analysis.modal]`` section or a Config)."""
    m = settings.analysis.modal if isinstance(settings, Config) else settings
    if m.speeds is not None:
        return np.asarray(m.speeds, dtype=float)
    start, stop = m.speed_range.bounds(ref)
    return np.linspace(start, stop, m.speed_range.n)


def run_modal(config_or_system: Config | RotorSystem, settings: ModalAnalysis | None = None,
              *, context: RunContext | None = None, search_path: Path | None = None,
              reference_speed: float | None = None, progress: bool = False
              ) -> ModalRunResult | SpoolModalResult:
    """Campbell diagram over the ``[analysis.modal]`` speeds and the first ``n_critical``
    critical speeds (film excluded, centring spring included, constant base rates).

    ``run_modal(system, settings, context=...)``: ``settings`` the section (default: its
    defaults), ``context`` the reference speed and title (default: an empty
    configuration's; its reference speed None: the first forward critical speed below
    ``settings.critical_speed_max``, the one located when ``whirl = 'forward'``).
    ``run_modal(config)`` is that call with ``build(config)``, ``config.analysis.modal``
    and :func:`~rotorsfd.analyses.context.config_context` (``reference.speed`` of the
    config, 'first_critical' left to this run): the two paths cannot disagree.
    ``reference_speed`` [rad/s] overrides the context's. Shafts at several speeds: the
    diagram against one spool (:func:`~rotorsfd.analyses.spool_modal.run_spool_modal`).
    ``progress``: a tqdm bar on stderr over the stages."""
    # deferred: tqdm (only with a progress bar)
    from tqdm import tqdm

    if isinstance(config_or_system, Config):
        config = config_or_system
        system = build(config, search_path)
        return run_modal(system, config.analysis.modal if settings is None else settings,
                         context=config_context(config, system, "modal",
                                                search_path=search_path,
                                                resolve_reference=False),
                         reference_speed=reference_speed, progress=progress)
    system = config_or_system
    m = settings if settings is not None else ModalAnalysis()
    ctx = context if context is not None else RunContext(search_path=search_path)
    given = ctx.reference_speed if reference_speed is None else float(reference_speed)
    shafts = getattr(system.rotor, "shafts", ())
    if len({s.speed_ratio for s in shafts}) > 1:      # shafts at several speeds
        from rotorsfd.analyses.spool_modal import run_spool_modal

        lin = linear_system(system)
        ref = given if given is not None else forward_reference(critical_speeds(
            lin, n=1, whirl="forward", speed_range=(0.0, m.critical_speed_max)),
            m.critical_speed_max)
        return run_spool_modal(lin, shafts, m, ref, modal_speeds(m, ref), ctx.title)
    with tqdm(total=3, desc="modal", disable=not progress, file=sys.stderr,
              leave=False) as bar:
        lin = linear_system(system)
        bar.set_postfix_str("critical speeds")
        crit = critical_speeds(lin, n=m.n_critical, whirl=m.whirl,
                               speed_range=(0.0, m.critical_speed_max))
        bar.update()
        bar.set_postfix_str("reference speed")   # the first forward one, not searched again
        if given is not None:
            ref = float(given)
        else:
            ref = forward_reference(crit if m.whirl == "forward" else critical_speeds(
                lin, n=1, whirl="forward", speed_range=(0.0, m.critical_speed_max)),
                m.critical_speed_max)
        bar.update()
        bar.set_postfix_str("Campbell diagram")
        camp = campbell(lin, modal_speeds(m, ref), m.n_modes)
        bar.update()
    return ModalRunResult(camp, crit, ref, ctx.title)
