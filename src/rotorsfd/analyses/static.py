"""Static deflection of the linear rotor under constant base motion (issue 3, item 5).

    (K + K_base(Omega)) q = F_base(Omega)

with F_base the base-acceleration load (gravity included), the gyroscopic moments
Ip (Omega + w_bx) w_by and Ip (Omega + w_bx) w_bz of pitching and yawing, and the
centripetal terms. The squeeze film carries no static load (its force needs a velocity),
so the centring spring does. This is the static offset the paper describes: pitching
w_by gives a moment about z, an offset along y; yawing w_bz a moment about y, an offset
along z. It grows with the speed (gyroscopic moment), so it is given over a list of
speeds.

``run_static(system, settings, context=...)`` with the ``[analysis.modal]`` section (the
speeds) and a :class:`~rotorsfd.analyses.context.RunContext` (reference speed, title);
``run_static(config)`` is that call with the config's section and context.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.context import RunContext, build, config_context
from rotorsfd.analyses.modal import modal_speeds
from rotorsfd.errors import ConfigError
from rotorsfd.io import atomic
from rotorsfd.io.schema import Config, ModalAnalysis
from rotorsfd.linear.static import static_deflection

if TYPE_CHECKING:
    from rotorsfd.model.system import RotorSystem

COLUMNS = ("speed_rad_s", "speed_ratio", "node", "x_m", "y_m", "z_m", "ty_rad", "tz_rad")


def base_static_offset(system: RotorSystem, speed: float) -> NDArray[np.float64]:
    """q (n_dof,) solving (K + K_base) q = F_base at ``speed`` [rad/s]; ConfigError for a
    time-varying base, ConvergenceError for a singular stiffness."""
    return static_deflection(system, system.static_force(speed), speed)


@dataclass(frozen=True)
class StaticResult:
    """Static deflection at each speed: ``q`` (n_speeds, n_dof)."""

    speeds: NDArray[np.float64]
    q: NDArray[np.float64]
    node_x: NDArray[np.float64]
    reference_speed: float
    title: str = ""

    def rows(self) -> list[tuple[Any, ...]]:
        """One row per (speed, node), columns :data:`COLUMNS`."""
        out = []
        for s, q in zip(self.speeds, self.q, strict=True):
            for i, x in enumerate(self.node_x):
                y, z, ty, tz = (float(v) for v in q[4 * i: 4 * i + 4])
                out.append((float(s), float(s / self.reference_speed), i + 1, float(x),
                            y, z, ty, tz))
        return out

    def to_dataset(self) -> Any:
        """``q`` over ``(speed, dof)`` [m, rad] with the node positions and DOF names."""
        import xarray as xr  # deferred: xarray

        n_nodes = self.node_x.size
        return xr.Dataset(
            {"q": (("speed", "dof"), self.q,
                   {"long_name": "static deflection", "units": "m or rad"}),
             "node_x": ("node", self.node_x, {"units": "m", "long_name": "axial position"})},
            coords={"speed": ("speed", self.speeds, {"units": "rad/s"}),
                    "speed_ratio": ("speed", self.speeds / self.reference_speed,
                                    {"units": "1"}),
                    "node": ("node", np.arange(1, n_nodes + 1, dtype=np.int32)),
                    "dof_name": ("dof", [f"{d}{i}" for i in range(1, n_nodes + 1)
                                         for d in ("y", "z", "ty", "tz")])},
            attrs={"reference_speed_rad_s": self.reference_speed, "title": self.title})

    def plot(self) -> dict[str, Any]:
        """``static_deflection.png``: y and z along the shaft at the speeds
        (:func:`rotorsfd.plots.static.static_figure`)."""
        from rotorsfd.plots.static import static_figure  # deferred: matplotlib

        return {"static_deflection.png": static_figure(
            self.node_x, self.speeds, self.q[:, :4 * self.node_x.size],
            reference_speed=self.reference_speed, title=self.title)}

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """``static_deflection.csv`` (long format, :data:`COLUMNS`) and (``plots``)
        ``static_deflection.png``, written atomically."""
        out = Path(directory)
        paths = {"static_deflection.csv": atomic.write_csv(
            out / "static_deflection.csv", COLUMNS, self.rows())}
        if plots:
            paths.update(atomic.save_figures(self.plot(), out))
        return paths

    def summary(self) -> str:
        """The largest lateral static deflection and where."""
        r = np.hypot(self.q[:, 0::4], self.q[:, 1::4])
        i, j = np.unravel_index(int(np.argmax(r)), r.shape)
        return (f"largest static deflection {r[i, j]:.4g} m at node {j + 1}, speed "
                f"{self.speeds[i]:.6g} rad/s (y = {self.q[i, 4 * j]:.4g} m, "
                f"z = {self.q[i, 4 * j + 1]:.4g} m)")


def check_supports(system: RotorSystem) -> None:
    """ConfigError unless the linear rotor has a support (or there is no nonlinear element
    to carry it)."""
    if not system.rotor.supports and len(system.elements):
        raise ConfigError("rotor.supports", [], "the static offset is that of the linear "
                          "rotor, which has no support here: its nonlinear elements "
                          "(" + ", ".join(e.describe() for e in system.elements) + ") "
                          "are excluded; a journal bearing carries its load only at "
                          "speed: its equilibrium is the static part (0X, static_* "
                          "columns) of `rotorsfd response`")


def run_static(config_or_system: Config | RotorSystem, settings: ModalAnalysis | None = None,
               *, context: RunContext | None = None, speeds: Sequence[float] | None = None,
               reference_speed: float | None = None, search_path: Path | None = None
               ) -> StaticResult:
    """Static deflection over ``speeds`` [rad/s], default the ``[analysis.modal]`` speeds.

    ``run_static(system, settings, context=...)``: ``settings`` the ``[analysis.modal]``
    section (its speeds or speed range on Omega_ref; default: its defaults), ``context``
    the reference speed (the ``speed_ratio`` column) and the title (default: an empty
    configuration's, Omega_ref the first forward critical speed). ``run_static(config)``
    is that call with ``build(config)``, ``config.analysis.modal`` and
    :func:`~rotorsfd.analyses.context.config_context`: the two paths cannot disagree.
    ``reference_speed`` [rad/s] overrides the context's."""
    if isinstance(config_or_system, Config):
        config = config_or_system
        system = build(config, search_path)
        check_supports(system)          # before Omega_ref: a free rotor has none
        return run_static(system, config.analysis.modal if settings is None else settings,
                          context=config_context(config, system, "modal",
                                                 search_path=search_path,
                                                 reference_speed=reference_speed),
                          speeds=speeds)
    system = config_or_system
    m = settings if settings is not None else ModalAnalysis()
    ctx = context if context is not None else RunContext(search_path=search_path)
    check_supports(system)
    ref = float(reference_speed) if reference_speed is not None else ctx.reference(system)
    s = np.asarray(modal_speeds(m, ref) if speeds is None else speeds, dtype=float)
    q = np.array([base_static_offset(system, float(w)) for w in s])
    return StaticResult(s, q, np.asarray(system.rotor.node_x, float), float(ref), ctx.title)
