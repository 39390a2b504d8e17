"""The Python API behind the command line: everything ``rotorsfd`` does, a script can do.

>>> from rotorsfd import api
>>> config = api.load_config("examples/paper_rotor.toml", ["elements.sfd.clearance_ratio=0.61 %"])
>>> result = api.run_modal(config)
>>> result.critical_speeds[0].speed_rad_s, result.write("out")

Each ``run_*`` takes a validated :class:`~rotorsfd.io.schema.Config` and returns a result
object with its data, ``write(directory)`` (atomic files) and plot methods.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.io import atomic
from rotorsfd.io.config import dump_config, get_path, load_config, show_config, with_values
from rotorsfd.io.schema import Config
from rotorsfd.linear import CampbellResult, CriticalSpeed, campbell, critical_speeds
from rotorsfd.model.build import Model, build_elements, build_model, build_rotor, build_system

__all__ = [
    "FitRunResult",
    "ModalRunResult",
    "build_elements",
    "build_model",
    "build_rotor",
    "build_system",
    "dump_config",
    "linear_system",
    "load_config",
    "reference_speed",
    "run_bifurcation_diagram",
    "run_fit_supports",
    "run_fold_curve",
    "run_modal",
    "run_paper",
    "run_response",
    "run_simulation",
    "run_stability_chart",
    "run_static",
    "show_config",
    "with_values",
]


def linear_system(config: Config, model: Model | None = None) -> Any:
    """The linear rotor for modal analysis (``LinearDynamics``): the rotor with its supports
    and the elements' linear parts (an SFD's centring spring; no film), plus the base terms
    of constant base rotation rates. ConfigError if a base rate varies in time (no
    eigenvalues then)."""
    model = build_model(config) if model is None else model
    base = model.base_motion
    if base is None or not base.rates_constant:
        for name in ("rolling", "pitching", "yawing"):
            if getattr(config.base, name).law not in ("off", "constant"):
                raise ConfigError(f"base.{name}.law", getattr(config.base, name).law,
                                  "modal analysis needs constant base rates ('off' or "
                                  "'constant'); time-varying rates: use a stability chart")
    if base is None or not np.any(base.rates(0.0) != 0.0):
        return model.rotor
    from rotorsfd.model.base_terms import MovingBaseRotor

    return MovingBaseRotor(model.rotor, base.state(0.0))


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

    def write(self, directory: str | Path) -> dict[str, Path]:
        """Write ``critical_speeds.csv`` (mode, whirl, speed_rad_s), ``campbell.csv`` and
        ``campbell.png`` atomically into ``directory`` (created if missing)."""
        out = Path(directory)
        paths = {name: out / name for name in self.FILES}
        atomic.write_csv(paths["critical_speeds.csv"], ("mode", "whirl", "speed_rad_s"),
                         self.critical_speeds_rows())
        with atomic.atomic_path(paths["campbell.csv"]) as tmp:
            self.campbell.to_csv(tmp)
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


@dataclass(frozen=True)
class FitRunResult:
    """Stiffness fields fitted so that the lowest critical speeds meet targets."""

    fields: tuple[str, ...]
    fit: Any                      # rotorsfd.linear.fit.SupportFit
    config: Config                # the configuration with the fitted values

    def overrides(self) -> list[str]:
        """``KEY=VALUE`` strings that reproduce the fit with ``--set``."""
        return [f"{f}={k:.10g}" for f, k in zip(self.fields, self.fit.stiffnesses, strict=True)]

    def summary(self) -> str:
        """Fitted values, resulting critical speeds against the targets, and ``--set`` lines."""
        lines = [f"{f} = {k:.8g} N/m"
                 for f, k in zip(self.fields, self.fit.stiffnesses, strict=True)]
        for i, (c, t) in enumerate(zip(self.fit.critical_speeds, self.fit.targets,
                                       strict=True)):
            lines.append(f"critical speed {i + 1}: {c:.6f} rad/s (target {t:g}, "
                         f"relative error {c / t - 1:+.1e})")
        lines.append(self.fit.message)
        lines.append("reproduce: " + " ".join(f"--set '{o}'" for o in self.overrides()))
        return "\n".join(lines)

    def write(self, directory: str | Path) -> Path:
        """``fit.json``: fields, stiffnesses, critical speeds, targets, errors."""
        f = self.fit
        return atomic.write_json(Path(directory) / "fit.json", {
            "fields": list(self.fields), "stiffnesses_N_per_m": list(f.stiffnesses),
            "critical_speeds_rad_s": list(f.critical_speeds), "targets_rad_s": list(f.targets),
            "relative_errors": list(f.relative_errors), "exact": f.exact,
            "message": f.message, "overrides": self.overrides()})


def run_fit_supports(config: Config, fields: Sequence[str], targets: Sequence[float],
                     whirl: str = "forward") -> FitRunResult:
    """Fit the stiffness fields at dotted paths ``fields`` (e.g.
    ``elements.sfd.centring_stiffness``, ``rotor.supports[0].stiffness``) so that the lowest
    ``whirl`` critical speeds of the linear rotor are ``targets`` [rad/s] (as many fields as
    targets); the starting values are the configuration's."""
    from rotorsfd.io.schema import resolve_kind
    from rotorsfd.linear.fit import fit_support_stiffness

    if len(fields) != len(targets) or not fields:
        raise ConfigError("--field/--target", f"{len(fields)} fields, {len(targets)} targets",
                          "give as many stiffness fields as target critical speeds (>= 1)")
    start = []
    for path in fields:
        try:
            kind = resolve_kind(config, path)
        except KeyError as exc:
            raise ConfigError("--field", path, exc.args[0]) from None
        if kind != "stiffness":
            raise ConfigError("--field", path, f"must be a stiffness field (N/m), not {kind}")
        start.append(get_path(config, path) or 1e7)

    def build(*k: float) -> Any:
        return linear_system(with_values(config, dict(zip(fields, k, strict=True))))

    fit = fit_support_stiffness(build, targets, x0=start, whirl=whirl,
                                speed_range=(0.0, config.analysis.modal.critical_speed_max))
    fitted = with_values(config, dict(zip(fields, fit.stiffnesses, strict=True)))
    return FitRunResult(tuple(fields), fit, fitted)


def run_response(config: Any, **kwargs: Any) -> Any:
    """Periodic response branch (``[analysis.response]``): see
    :func:`rotorsfd.analyses.response.run_response`."""
    from rotorsfd.analyses.response import run_response as _run

    return _run(config, **kwargs)


def run_static(config: Any, **kwargs: Any) -> Any:
    """Static deflection of the linear rotor under constant base motion: see
    :func:`rotorsfd.analyses.static.run_static`."""
    from rotorsfd.analyses.static import run_static as _run

    return _run(config, **kwargs)


def run_simulation(config: Any, speed: float | None = None, **kwargs: Any) -> Any:
    """Time integration at one speed (``[analysis.simulate]``): see
    :func:`rotorsfd.analyses.simulate.run_simulation`."""
    from rotorsfd.analyses.simulate import run_simulation as _run

    return _run(config, speed, **kwargs)


def run_bifurcation_diagram(config: Any, **kwargs: Any) -> Any:
    """Speed swept up and down in the time domain (``[analysis.bifurcation_diagram]``): see
    :func:`rotorsfd.analyses.bifurcation_diagram.run_bifurcation_diagram`."""
    from rotorsfd.analyses.bifurcation_diagram import run_bifurcation_diagram as _run

    return _run(config, **kwargs)


def run_stability_chart(config: Any, **kwargs: Any) -> Any:
    """Stability chart of the linear rotor under harmonic base rotation
    (``[analysis.stability_chart]``): see
    :func:`rotorsfd.analyses.stability_chart.run_stability_chart`."""
    from rotorsfd.analyses.stability_chart import run_stability_chart as _run

    return _run(config, **kwargs)


def run_fold_curve(config: Any, parameter: str, start: Any, stop: Any, **kwargs: Any) -> Any:
    """Saddle-nodes of the speed response continued in a second parameter (the boundary
    of the bistable region and its cusp): see
    :func:`rotorsfd.analyses.fold_curve.run_fold_curve`."""
    from rotorsfd.analyses.fold_curve import run_fold_curve as _run

    return _run(config, parameter, start, stop, **kwargs)


def run_paper(output: Any, figures: Sequence[str] | None = None, **kwargs: Any) -> Any:
    """Reproduce the paper's case studies and write the comparison report: see
    :func:`rotorsfd.paper.run.run_paper`."""
    from rotorsfd.paper.run import run_paper as _run

    return _run(output, figures, **kwargs)
