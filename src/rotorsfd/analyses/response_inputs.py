"""The one resolution of what a response analysis runs with (issue 16 item 3).

A response branch in the speed or another continuation parameter lam is continued over
``[start, stop]`` (SI; for the speed ``start = Omega~_0 Omega_ref``, ``stop = Omega~_1
Omega_ref`` from ``speed_range``), at H harmonics, with the continuation options of
``[analysis.response]``. :meth:`ResponseInputs.from_system` resolves every input from a
:class:`~rotorsfd.model.system.RotorSystem`, its settings section (a
:class:`~rotorsfd.io.schema.ResponseAnalysis`) and a
:class:`~rotorsfd.analyses.context.RunContext`; :meth:`ResponseInputs.from_config` builds
the system once (:func:`~rotorsfd.analyses.context.build`) and its context
(:func:`~rotorsfd.analyses.context.config_context`) and calls ``from_system``: the two
entry paths run the same code, so they cannot disagree. A system given alone gets an
empty configuration's defaults: ``ResponseAnalysis()``, ``StabilityAnalysis()``
(stability on) and Omega_ref the first forward critical speed below
``ModalAnalysis().critical_speed_max``.

:class:`TwoParameterInputs` does the same for the (speed, lam2) analyses, the fold and
bifurcation curves.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rotorsfd.analyses.context import RunContext, build, config_context
from rotorsfd.analyses.response_words import FIELD, PARAMETER_UNITS, system_parameter
from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import Config, ResponseAnalysis, StabilityAnalysis
from rotorsfd.io.units import KINDS, UnitError, to_si

if TYPE_CHECKING:
    from rotorsfd.model.system import RotorSystem
    from rotorsfd.stability.branch_options import StabilityOptions

__all__ = ["ResponseInputs", "TwoParameterInputs", "continuation_options", "parameter_si",
           "stability_settings"]


def continuation_options(r: ResponseAnalysis) -> dict[str, Any]:
    """:func:`~rotorsfd.harmonic.periodic.continue_periodic` keyword arguments from
    ``[analysis.response]``."""
    return {"n_samples": r.n_samples, "condensed": r.condensed, "tol": r.tolerance,
            "ds": r.step_initial, "ds_min": r.step_min, "ds_max": r.step_max,
            "max_iter": r.max_iterations, "max_points": r.max_points,
            "max_angle_deg": math.degrees(r.max_tangent_angle),
            "limit_max": r.max_eccentricity, "harmonics_tol": r.harmonics_tolerance,
            "adaptive_harmonics": r.adaptive_harmonics, "H_min": r.harmonics_min,
            "H_max": r.harmonics_max}


def parameter_si(parameter: str, values: Sequence[Any], field_name: str) -> list[float]:
    """``values`` (SI numbers or strings with units) of the continuation parameter
    ``parameter`` (a name or config path) in SI: the unit of the parameter registry
    (:data:`~rotorsfd.model.parameters.PARAMETERS`) names the quantity's kind (rad/s an
    angular velocity, kg*m an unbalance, ...). ConfigError naming ``field_name``."""
    name = system_parameter(parameter)
    unit = PARAMETER_UNITS[name]
    kind = next(k.name for k in KINDS.values() if k.unit == unit)
    out = []
    for v in values:
        try:
            out.append(to_si(v, kind))
        except UnitError as exc:
            raise ConfigError(field_name, v, str(exc)) from None
    return out


def stability_settings(section: StabilityAnalysis,
                       given: StabilityOptions | bool | None = None
                       ) -> StabilityOptions | None:
    """Options of the after-branch Floquet stability (None: off): ``given`` options as
    they are; False off; None as ``section.enabled``; True on. On: the options of the
    ``[analysis.stability]`` section."""
    # deferred: rotorsfd.stability imports numba (a response without stability never needs it)
    from rotorsfd.stability.branch_options import StabilityOptions

    if isinstance(given, StabilityOptions):
        return given
    if given is False or (given is None and not section.enabled):
        return None
    return StabilityOptions.from_section(section)


@dataclass(frozen=True)
class ResponseInputs:
    """Everything a response branch runs with, resolved (module docstring).

    ``path`` the continuation parameter as given (a config path or name), ``parameter``
    its system parameter; ``start, stop`` its range in SI; ``speed`` the fixed speed
    [rad/s] of a parameter other than the speed; ``harmonics`` H of the first point;
    ``options`` the keyword arguments of ``continue_periodic``; ``stability`` the options
    of the after-branch Floquet stability (None: off); ``config_toml`` the resolved
    configuration ("" for a system given alone)."""

    system: RotorSystem
    path: str
    parameter: str
    reference_speed: float
    harmonics: int
    start: float
    stop: float
    speed: float | None
    nodes: tuple[int, ...]
    directions: tuple[str, ...]
    title: str
    stability: StabilityOptions | None
    options: dict[str, Any] = field(default_factory=dict)
    config_toml: str = ""

    @classmethod
    def from_system(cls, system: RotorSystem, settings: ResponseAnalysis | None = None,
                    context: RunContext | None = None, *, parameter: str | None = None,
                    start: float | None = None, stop: float | None = None,
                    speed: float | None = None, reference_speed: float | None = None,
                    harmonics: int | None = None, nodes: Sequence[int] | None = None,
                    directions: Sequence[str] | None = None, title: str | None = None,
                    stability_options: StabilityOptions | bool | None = None
                    ) -> ResponseInputs:
        """The inputs of ``system`` with ``settings`` (default: the context's
        ``[analysis.response]``, by default ``ResponseAnalysis()``) and ``context``
        (default ``RunContext()``: an empty configuration's); keyword arguments override
        the section (``start, stop`` in SI, a given H fixed, ``stability_options`` see
        :func:`stability_settings`)."""
        ctx = context if context is not None else RunContext()
        if reference_speed is not None:
            ctx = dataclasses.replace(ctx, reference_speed=float(reference_speed))
        ref = float(ctx.reference(system))
        r = settings if settings is not None else ctx.response
        path = (parameter or r.parameter).strip()
        name = system_parameter(path)
        opts = continuation_options(r)
        if harmonics:       # a given H is fixed
            opts["adaptive_harmonics"] = False
        lo: float | None = None
        hi: float | None = None
        if name == "speed":
            lo, hi = r.speed_range.bounds(ref)
            if not (lo > 0 and hi > 0):
                raise ConfigError(f"{FIELD}.speed_range", r.speed_range.model_dump(
                    exclude_none=True), "the response needs speeds > 0")
            where = f"{FIELD}.speed_range"
        else:
            if r.parameter_range is not None:
                lo, hi = parameter_si(path, r.parameter_range, f"{FIELD}.parameter_range")
            if speed is None and (r.speed is not None or r.speed_ratio is not None):
                speed = r.fixed_speed(ref)
            where = f"{FIELD}.parameter_range"
            if not (speed is not None and speed > 0):
                raise ConfigError(f"{FIELD}.speed", speed,
                                  f"continuing in {path} needs a fixed speed > 0 rad/s")
        lo = lo if start is None else start
        hi = hi if stop is None else stop
        if lo is None or hi is None:
            raise ConfigError(where, (lo, hi), "give the parameter range (start, stop)")
        if lo == hi:
            raise ConfigError(where, (lo, hi), "start and stop must differ")
        out_nodes = tuple(nodes or r.nodes) or system.output_nodes
        for n in out_nodes:
            if not 1 <= n <= system.rotor.n_nodes:
                raise ConfigError(f"{FIELD}.nodes", n, f"must be 1..{system.rotor.n_nodes}")
        return cls(system, path, name, ref, int(harmonics or r.start_harmonics), float(lo),
                   float(hi), None if name == "speed" else float(speed), out_nodes,
                   tuple(directions or r.directions), ctx.title if title is None else title,
                   stability_settings(ctx.stability, stability_options), opts,
                   ctx.config_toml)

    @classmethod
    def from_config(cls, config: Config, search_path: Path | None = None, *,
                    reference_speed: float | None = None, **overrides: Any
                    ) -> ResponseInputs:
        """The inputs of ``config``: its system (one :func:`build`), its
        ``[analysis.response]`` and context (``reference_speed`` overrides
        ``[reference]``), through :meth:`from_system` with the same ``overrides``."""
        if not config.elements:
            raise ConfigError("elements", None, "the nonlinear response needs at least one "
                              "nonlinear element (an [elements.<name>] table)")
        system = build(config, search_path)
        ctx = config_context(config, system, "response", search_path=search_path,
                             reference_speed=reference_speed)
        return cls.from_system(system, config.analysis.response, ctx, **overrides)


@dataclass(frozen=True)
class TwoParameterInputs:
    """What a (speed, lam2) analysis runs with: the system, the second parameter ``param``
    (a system parameter, not the speed), Omega_ref, the speed range of
    ``[analysis.response]`` [rad/s], lam2's range ``range2`` (SI), the settings section,
    the output nodes (None: the system's), the title and the ``[analysis.stability]``
    section (the start branch's Floquet stability and bifurcation checks, as ``rotorsfd
    response`` runs them)."""

    system: RotorSystem
    param: str
    reference_speed: float
    speed_range: tuple[float, float]
    range2: tuple[float, float]
    response: ResponseAnalysis
    nodes: tuple[int, ...] | None
    title: str = ""
    stability: StabilityAnalysis = field(default_factory=StabilityAnalysis)

    @classmethod
    def from_system(cls, system: RotorSystem, parameter: str, start: Any, stop: Any,
                    settings: ResponseAnalysis | None = None,
                    context: RunContext | None = None) -> TwoParameterInputs:
        """``parameter`` a config path or parameter name (not the speed), ``start, stop``
        its range (SI numbers or strings with units); the speed range, H and nodes of
        ``settings`` (default: the context's ``[analysis.response]``), Omega_ref and the
        title of ``context`` (default ``RunContext()``)."""
        ctx = context if context is not None else RunContext()
        param = system_parameter(parameter)
        if param == "speed":
            raise ConfigError("--parameter", parameter, "must differ from the speed")
        r = settings if settings is not None else ctx.response
        ref = float(ctx.reference(system))
        lo, hi = r.speed_range.bounds(ref)
        v0, v1 = parameter_si(parameter, [start, stop], "--from/--to")
        return cls(system, param, ref, (float(lo), float(hi)), (v0, v1), r,
                   tuple(r.nodes) or None, ctx.title, ctx.stability)

    @classmethod
    def from_config(cls, config: Config, parameter: str, start: Any, stop: Any,
                    what: str, search_path: Path | None = None) -> TwoParameterInputs:
        """The inputs of ``config`` (one :func:`build`, its context) through
        :meth:`from_system`; ConfigError before any work if the config has no nonlinear
        element (``what`` its subject, e.g. "the fold curve needs")."""
        if not config.elements:
            raise ConfigError("elements", None, f"{what} at least one nonlinear "
                              "element (an [elements.<name>] table)")
        if system_parameter(parameter) == "speed":
            raise ConfigError("--parameter", parameter, "must differ from the speed")
        system = build(config, search_path)
        ctx = config_context(config, system, "response", search_path=search_path)
        return cls.from_system(system, parameter, start, stop, config.analysis.response,
                               ctx)

    @classmethod
    def resolve(cls, config_or_system: Any, parameter: str, start: Any, stop: Any,
                settings: Any, context: Any, what: str,
                search_path: Path | None = None) -> TwoParameterInputs:
        """:meth:`from_system` for a :class:`RotorSystem` (with ``settings`` and
        ``context``), :meth:`from_config` for a Config: the one dispatch of the
        (speed, lam2) analyses."""
        if isinstance(config_or_system, Config):
            return cls.from_config(config_or_system, parameter, start, stop, what,
                                   search_path)
        return cls.from_system(config_or_system, parameter, start, stop, settings, context)
