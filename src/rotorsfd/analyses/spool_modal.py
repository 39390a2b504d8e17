"""``rotorsfd modal`` of a rotor with several shafts at different speeds (a dual-spool
engine): the Campbell diagram against the speed of one spool (``analysis.modal.spool``,
default the first shaft) with the excitation line of every spool's unbalance, and the
critical speeds on each line (issue 20 item 2).

Against spool ``s`` (speed ``Omega_s``) every shaft ``k`` turns at ``(r_k / r_s)
Omega_s``: the linear system is ``rotor.matrices(Omega_s / r_s)``
(:class:`~rotorsfd.model.multishaft.SpoolSpeed`), and shaft k's unbalance excites
``w = (r_k / r_s) Omega_s``: the line "1X <k>". A critical speed of shaft k's unbalance is
a root of ``w_i(Omega_s) = (r_k / r_s) Omega_s`` (:func:`~rotorsfd.linear.critical.
line_critical_speeds`). The speeds of the diagram: ``analysis.modal.speeds`` as the
spool's speeds, or the speed range (in Omega_LP / Omega_ref) times ``r_s``, so that either
spool's diagram covers the same operating range. ``critical_speeds.csv`` gains the columns
``line`` (the shaft whose unbalance) and ``spool_speed_rad_s``; ``speed_rad_s`` there is the
first shaft's speed (Omega_LP, the speed of every other analysis).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.analyses.modal_files import modal_dataset, write_modal
from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import ModalAnalysis
from rotorsfd.linear import CampbellResult, campbell
from rotorsfd.linear.critical import CriticalSpeed, line_critical_speeds

__all__ = ["SpoolModalResult", "run_spool_modal"]


class _SpoolView:
    """``matrices(Omega_s) = system.matrices(Omega_s / r_s)`` (the LinearDynamics view of
    ``system`` against a spool at ratio ``r_s``)."""

    def __init__(self, system: Any, ratio: float) -> None:
        self.system, self.ratio, self.n_dof = system, float(ratio), system.n_dof

    def matrices(self, speed: float):
        return self.system.matrices(float(speed) / self.ratio)


@dataclass(frozen=True)
class SpoolModalResult:
    """The modal result against one spool (the interface of
    :class:`~rotorsfd.analyses.modal.ModalRunResult`): ``spool`` (name), ``ratio`` (its
    r_s), ``lines`` (shaft name -> slope r_k / r_s) and ``line_critical`` ((shaft,
    CriticalSpeed) against the spool's speed; ``critical_speeds`` the same without names)."""

    campbell: CampbellResult
    critical_speeds: list[CriticalSpeed]
    reference_speed: float
    title: str = ""
    spool: str = ""
    ratio: float = 1.0
    lines: dict[str, float] = field(default_factory=dict)
    line_critical: list[tuple[str, CriticalSpeed]] = field(default_factory=list)

    def method_words(self) -> str:
        """How the modes were computed (``CampbellResult.info``)."""
        info = self.campbell.info
        err = info.get("reduced_error")
        return f"{info.get('method', '')} eigensolver" + (
            f", measured relative eigenvalue error {err:.1e}" if err is not None else "")

    def critical_speeds_rows(self) -> list[tuple[Any, ...]]:
        """Rows ``(mode, whirl, speed_rad_s, line, spool_speed_rad_s)``: speed_rad_s the
        first shaft's speed, spool_speed_rad_s the speed of ``spool``."""
        return [(c.mode, c.whirl, float(c.speed_rad_s) / self.ratio, name,
                 float(c.speed_rad_s)) for name, c in self.line_critical]

    def _campbell_words(self) -> dict[str, Any]:
        """The Campbell plot's keywords: each shaft's 1X line, the critical speeds marked
        on their line, the axis and title against the spool."""
        return dict(lines=[(h, rf"1X {name} ($\omega = "
                               + ("" if h == 1.0 else rf"{h:.4g}\,")
                               + rf"\Omega_{{{self.spool}}}$)")
                           for name, h in self.lines.items()],
                    marks=[(cs.speed_rad_s, self.lines[name] * cs.speed_rad_s)
                           for name, cs in self.line_critical],
                    xlabel=rf"speed of spool {self.spool} $\Omega_{{{self.spool}}}$ [rad/s]",
                    title=(self.title or "Campbell diagram")
                    + f" (against spool {self.spool})")

    def plot_on(self, ax: Any) -> Any:
        """The Campbell diagram against the spool on ``ax``; returns ``ax``."""
        # deferred: plots.campbell (loads matplotlib)
        from rotorsfd.plots.campbell import campbell_axes

        c = self.campbell
        return campbell_axes(ax, c.speeds, c.frequencies, c.whirl, **self._campbell_words())

    def plot(self) -> dict[str, Any]:
        """``campbell.png``: the Campbell diagram against the spool."""
        # deferred: plots.campbell (loads matplotlib)
        from rotorsfd.plots.campbell import campbell_figure

        c = self.campbell
        return {"campbell.png": campbell_figure(c.speeds, c.frequencies, c.whirl,
                                                **self._campbell_words())}

    def to_dataset(self) -> Any:
        """The Campbell diagram against the spool, its critical speeds and Omega_ref."""
        ds = modal_dataset(self.campbell, self.critical_speeds_rows(), self.reference_speed,
                           self.title)
        ds["critical_line"] = ("critical", np.array([r[3] for r in
                                                     self.critical_speeds_rows()]))
        ds.attrs.update(spool=self.spool, spool_ratio=self.ratio)
        return ds

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """``critical_speeds.csv``, ``campbell.csv`` and ``campbell.png``."""
        return write_modal(self, Path(directory),
                           ("mode", "whirl", "speed_rad_s", "line", "spool_speed_rad_s"),
                           plots)

    def summary(self) -> str:
        lines = [f"reference speed: {self.reference_speed:.6g} rad/s (of the first shaft)",
                 f"Campbell diagram against spool {self.spool!r}: {self.campbell.speeds.size} "
                 f"speeds, {self.method_words()}"]
        for name, c in self.line_critical:
            lines.append(f"critical speed of the {name} unbalance, mode {c.mode} ({c.whirl}): "
                         f"Omega_{self.spool} = {c.speed_rad_s:.6g} rad/s = "
                         f"{c.speed_rad_s * 30 / np.pi:.6g} rpm (first shaft "
                         f"{c.speed_rad_s / self.ratio:.6g} rad/s = "
                         f"{c.speed_rad_s / self.ratio / self.reference_speed:.4f} x reference)")
        return "\n".join(lines)


def run_spool_modal(system: Any, shafts: Sequence[Any], settings: ModalAnalysis, ref: float,
                    speeds: np.ndarray, title: str = "") -> SpoolModalResult:
    """Campbell diagram and critical speeds of each shaft's unbalance against the speed of
    ``settings.spool`` (module docstring), for the linear ``system``
    (:func:`~rotorsfd.analyses.modal.linear_system`) of a rotor with these ``shafts``
    (``MultiShaftRotor.shafts``: name, speed ratio), its reference speed ``ref`` and the
    diagram's speeds of the first shaft (``modal_speeds``)."""
    m = settings
    names = [s.name for s in shafts]
    spool = m.spool or names[0]
    if spool not in names:
        raise ConfigError("analysis.modal.spool", spool, "must name a shaft: " +
                          ", ".join(names))
    ratios = {s.name: float(s.speed_ratio) for s in shafts}
    r_s = ratios[spool]
    view = _SpoolView(system, r_s)
    lines: dict[str, float] = {}
    for name, r in ratios.items():        # one line per distinct speed (shafts may share)
        same = [k for k, h in lines.items() if h == r / r_s]
        if same:
            lines[f"{same[0]}/{name}"] = lines.pop(same[0])
        else:
            lines[name] = r / r_s
    crit = line_critical_speeds(view, lines, n=m.n_critical, whirl=m.whirl,
                                speed_range=(0.0, m.critical_speed_max * r_s))
    speeds = np.asarray(speeds, dtype=float) * (1.0 if m.speeds is not None else r_s)
    camp = campbell(view, speeds, m.n_modes)
    return SpoolModalResult(camp, [c for _, c in crit], ref, title, spool, r_s, lines, crit)
