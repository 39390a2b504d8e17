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
from typing import TYPE_CHECKING, Any

from rotorsfd.errors import ConfigError
from rotorsfd.lazy import lazy_getattr

if TYPE_CHECKING:
    from rotorsfd.analyses.modal import (
        ModalRunResult,
        linear_system,
        modal_speeds,
        reference_speed,
        run_modal,
    )
    from rotorsfd.io.config import dump_config, load_config, show_config, with_values
    from rotorsfd.io.schema import Config
    from rotorsfd.model.build import build_elements, build_model, build_rotor, build_system

#: the names this module re-exports, by the module that defines them: imported on first
#: use (PEP 562; deferred: pydantic, pint, numpy, scipy, numba), so that ``import
#: rotorsfd.api`` costs a few milliseconds
LAZY: dict[str, str] = {
    **dict.fromkeys(("ModalRunResult", "linear_system", "modal_speeds", "reference_speed",
                     "run_modal"), "rotorsfd.analyses.modal"),
    **dict.fromkeys(("dump_config", "load_config", "show_config", "with_values"),
                    "rotorsfd.io.config"),
    "Config": "rotorsfd.io.schema",
    **dict.fromkeys(("build_elements", "build_model", "build_rotor", "build_system"),
                    "rotorsfd.model.build"),
}

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
    "modal_speeds",
    "reference_speed",
    "run_bifurcation_curves",
    "run_bifurcation_diagram",
    "run_fit_supports",
    "run_fold_curve",
    "run_modal",
    "run_paper",
    "run_response",
    "run_second_branch",
    "run_simulation",
    "run_stability_chart",
    "run_static",
    "second_branch_switch",
    "show_config",
    "with_values",
]


#: the names of :data:`LAZY`, imported on first use and kept
__getattr__ = lazy_getattr(__name__, LAZY, globals())


def __dir__() -> list[str]:
    return sorted({*globals(), *LAZY})


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
        from rotorsfd.io import atomic  # deferred: numpy

        f = self.fit
        return atomic.write_json(Path(directory) / "fit.json", {
            "fields": list(self.fields), "stiffnesses_N_per_m": list(f.stiffnesses),
            "critical_speeds_rad_s": list(f.critical_speeds), "targets_rad_s": list(f.targets),
            "relative_errors": list(f.relative_errors), "exact": f.exact,
            "message": f.message, "overrides": self.overrides()})


def announce_compilation(analysis: str, kwargs: dict[str, Any]) -> None:
    """The progress line of a first run (``compiling the numerical kernels once ...`` on
    stderr, :func:`rotorsfd.kernel_cache.compile_notice`) unless ``progress=False``."""
    if kwargs.get("progress", True):
        from rotorsfd.kernel_cache import compile_notice  # deferred: numba

        compile_notice(analysis)


def run_fit_supports(config: Config, fields: Sequence[str], targets: Sequence[float],
                     whirl: str = "forward") -> FitRunResult:
    """Fit the stiffness fields at dotted paths ``fields`` (e.g.
    ``elements.sfd.centring_stiffness``, ``rotor.supports[0].stiffness``) so that the lowest
    ``whirl`` critical speeds of the linear rotor are ``targets`` [rad/s] (as many fields as
    targets); the starting values are the configuration's."""
    # deferred: analyses.modal, io.config, io.schema (loads numba, scipy, pydantic)
    from rotorsfd.analyses.modal import linear_system
    from rotorsfd.io.config import get_path, with_values
    from rotorsfd.io.schema import resolve_kind

    # deferred: linear.fit (loads scipy)
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
    # deferred: analyses.response (loads numba, scipy, pydantic)
    from rotorsfd.analyses.response import run_response as _run

    announce_compilation("response", kwargs)
    return _run(config, **kwargs)


def second_branch_switch(at: str) -> tuple[Any, Any]:
    """The check and the run of ``rotorsfd response --switch-at <at>:N``: ``"pd"``
    (:mod:`rotorsfd.analyses.response_switch`) or ``"bp"``
    (:mod:`rotorsfd.analyses.response_branch_switch`)."""
    # deferred: analyses.response_switch, analyses.response_branch_switch (load numba,
    # scipy, pydantic)
    from rotorsfd.analyses import response_branch_switch, response_switch

    if at == "pd":
        return response_switch.check_switch, response_switch.run_switch
    if at == "bp":
        return response_branch_switch.check_branch_switch, response_branch_switch.run_branch_switch
    raise ValueError(f"switch at 'pd' or 'bp', got {at!r}")


def run_second_branch(result: Any, at: str, number: int, **kwargs: Any) -> Any:
    """The second branch of a response ``result`` at its ``number``-th period doubling
    (``at = "pd"``: the period-2 branch) or branch point (``"bp"``), as ``rotorsfd
    response --switch-at pd:N | bp:N``: a
    :class:`~rotorsfd.analyses.response_second_branch.SecondBranchResult` (``write(dir)``,
    ``table()``, ``summary()``); ``kwargs`` go to the switch's run function."""
    return second_branch_switch(at)[1](result, number, **kwargs)


def run_static(config: Any, **kwargs: Any) -> Any:
    """Static deflection of the linear rotor under constant base motion: see
    :func:`rotorsfd.analyses.static.run_static`."""
    # deferred: analyses.static (loads numba, scipy, pydantic)
    from rotorsfd.analyses.static import run_static as _run

    return _run(config, **kwargs)


def run_simulation(config: Any, speed: float | None = None, **kwargs: Any) -> Any:
    """Time integration at one speed (``[analysis.simulate]``): see
    :func:`rotorsfd.analyses.simulate.run_simulation`."""
    # deferred: analyses.simulate (loads numba, scipy, pydantic)
    from rotorsfd.analyses.simulate import run_simulation as _run

    announce_compilation("simulate", kwargs)
    return _run(config, speed, **kwargs)


def run_bifurcation_diagram(config: Any, **kwargs: Any) -> Any:
    """Speed swept up and down in the time domain (``[analysis.bifurcation_diagram]``): see
    :func:`rotorsfd.analyses.bifurcation_diagram.run_bifurcation_diagram`."""
    # deferred: analyses.bifurcation_diagram (loads numba, scipy, pydantic)
    from rotorsfd.analyses.bifurcation_diagram import run_bifurcation_diagram as _run

    announce_compilation("bifurcation_diagram", kwargs)
    return _run(config, **kwargs)


def run_stability_chart(config: Any, **kwargs: Any) -> Any:
    """Stability chart of the linear rotor under harmonic base rotation
    (``[analysis.stability_chart]``): see
    :func:`rotorsfd.analyses.stability_chart.run_stability_chart`."""
    # deferred: analyses.stability_chart (loads numba, scipy, pydantic)
    from rotorsfd.analyses.stability_chart import run_stability_chart as _run

    return _run(config, **kwargs)


def run_fold_curve(config: Any, parameter: str, start: Any, stop: Any, **kwargs: Any) -> Any:
    """Saddle-nodes of the speed response continued in a second parameter (the boundary
    of the bistable region and its cusp): see
    :func:`rotorsfd.analyses.fold_curve.run_fold_curve`."""
    # deferred: analyses.fold_curve (loads numba, scipy, pydantic)
    from rotorsfd.analyses.fold_curve import run_fold_curve as _run

    return _run(config, parameter, start, stop, **kwargs)


def run_bifurcation_curves(config: Any, parameter: str, start: Any, stop: Any,
                           **kwargs: Any) -> Any:
    """Saddle-nodes and period doublings of the speed response continued together in a
    second parameter (fold and period-doubling curves, their turning points): see
    :func:`rotorsfd.analyses.bifurcation_curves.run_bifurcation_curves`."""
    # deferred: analyses.bifurcation_curves (loads numba, scipy, pydantic)
    from rotorsfd.analyses.bifurcation_curves import run_bifurcation_curves as _run

    return _run(config, parameter, start, stop, **kwargs)


def run_paper(output: Any, figures: Sequence[str] | None = None, **kwargs: Any) -> Any:
    """Reproduce the paper's case studies and write the comparison report: see
    :func:`rotorsfd.paper.run.run_paper`."""
    # deferred: paper.cases, paper.run (loads multiprocessing)
    from rotorsfd.paper.cases import select
    from rotorsfd.paper.run import run_paper as _run

    select(list(figures or []), bool(kwargs.get("quick")))   # unknown figures: before work
    announce_compilation("response" if kwargs.get("quick") else "paper", kwargs)
    return _run(output, figures, **kwargs)
