"""The two entry paths of an analysis made one: ``run_x(system, settings, context=...)``
and ``run_x(config)``.

An analysis takes the :class:`~rotorsfd.model.system.RotorSystem`, its own settings
section (the pydantic model, e.g. ``SimulateAnalysis``) and a :class:`RunContext`: what it
needs from outside its section (the reference speed Omega_ref, the HB settings of an HB
start, ``[analysis.stability]``, the output nodes, the title). :func:`config_context`
builds the context of a configuration and :func:`build` its system, so the config path is
``run_x(build(config), config.analysis.x, config_context(config, system, "x"))``; given a
system only, the context's defaults are those of an empty configuration (the sections'
defaults: ``ResponseAnalysis()``, ``StabilityAnalysis()``, the critical-speed search up to
``ModalAnalysis().critical_speed_max``), so the two paths cannot disagree
(:func:`system_context`: that dispatch, for simulate and bifurcation_diagram). Written so:
simulate, bifurcation_diagram, response (its system path), modal, static,
attractors_config (the census), torus_response, dual_spool_response (docs/INTERFACES.md
lists their sections).
"""

from __future__ import annotations

from dataclasses import dataclass, field, replace
from pathlib import Path
from typing import TYPE_CHECKING

from rotorsfd.analyses.linear_model import first_critical
from rotorsfd.analyses.linear_model import reference_speed as config_reference_speed
from rotorsfd.errors import ConfigError
from rotorsfd.io.config import show_config
from rotorsfd.io.schema import Config, ModalAnalysis, ResponseAnalysis, StabilityAnalysis
from rotorsfd.model.build import build_system

if TYPE_CHECKING:
    from rotorsfd.model.system import RotorSystem

__all__ = ["RunContext", "build", "config_context", "system_context"]


@dataclass(frozen=True)
class RunContext:
    """What an analysis takes besides the system and its settings: ``reference_speed``
    [rad/s] (None: the first forward critical speed when needed), ``response`` (H and N_f
    of an HB start), ``modal`` (the critical-speed search bound), output ``nodes`` (None:
    the system's), ``title``, the resolved configuration text, the folder relative
    paths of the config are read from, and ``stability`` (``[analysis.stability]``: whether
    an analysis that computes it by default does)."""

    reference_speed: float | None = None
    response: ResponseAnalysis = field(default_factory=ResponseAnalysis)
    modal: ModalAnalysis = field(default_factory=ModalAnalysis)
    nodes: tuple[int, ...] | None = None
    title: str = ""
    config_toml: str = ""
    search_path: Path | None = None
    stability: StabilityAnalysis = field(default_factory=StabilityAnalysis)

    @property
    def harmonics(self) -> int:
        """H of an HB start: ``[analysis.response]``'s first H."""
        return self.response.start_harmonics

    def reference(self, system: RotorSystem) -> float:
        """Omega_ref: the given one, else the first forward critical speed of ``system``
        below ``modal.critical_speed_max`` (as ``reference.speed = 'first_critical'``)."""
        if self.reference_speed is not None:
            return float(self.reference_speed)
        return first_critical(system, self.modal.critical_speed_max)

    def output_nodes(self, system: RotorSystem) -> tuple[int, ...]:
        """The output nodes: the given ones, else the disks' and the elements'."""
        nodes = tuple(self.nodes) if self.nodes else system.output_nodes
        for n in nodes:
            if not 1 <= n <= system.rotor.n_nodes:
                raise ConfigError("nodes", n, f"must be 1..{system.rotor.n_nodes}")
        return nodes


def build(config: Config, search_path: Path | None = None) -> RotorSystem:
    """The :class:`RotorSystem` of a configuration (the one builder every analysis uses)."""
    return build_system(config, search_path)


def config_context(config: Config, system: RotorSystem, section: str, *,
                   search_path: Path | None = None,
                   reference_speed: float | None = None,
                   resolve_reference: bool = True) -> RunContext:
    """The context of ``config`` for the analysis ``analysis.<section>``: Omega_ref of
    ``[reference]`` (``reference_speed`` overrides it; with ``resolve_reference`` False a
    'first_critical' is left None, for an analysis that locates the critical speeds
    itself: ``modal``), ``[analysis.response]``, ``[analysis.modal]``,
    ``[analysis.stability]``, the section's output nodes (sections without nodes: None,
    the system's), the title and the resolved configuration."""
    if reference_speed is not None:
        ref: float | None = float(reference_speed)
    elif resolve_reference or isinstance(config.reference.speed, float):
        ref = float(config_reference_speed(config, system))
    else:
        ref = None
    has_nodes = hasattr(getattr(config.analysis, section, None), "nodes")
    return RunContext(ref, config.analysis.response, config.analysis.modal,
                      tuple(config.output_nodes(section)) if has_nodes else None,
                      config.title, show_config(config), search_path,
                      config.analysis.stability)


def system_context(config_or_system: Config | RotorSystem, section: str, *,
                   context: RunContext | None = None, search_path: Path | None = None,
                   reference_speed: float | None = None
                   ) -> tuple[RotorSystem, RunContext, Config | None]:
    """The system, the context and the Config (None for a system) of an analysis called
    as ``run_x(system, context=...)`` (default: an empty configuration's context with
    ``search_path``) or ``run_x(config)`` (:func:`build`, :func:`config_context` of
    ``analysis.<section>``); ``reference_speed`` overrides Omega_ref on both paths."""
    if isinstance(config_or_system, Config):
        system = build(config_or_system, search_path)
        return system, config_context(config_or_system, system, section,
                                      search_path=search_path,
                                      reference_speed=reference_speed), config_or_system
    ctx = context if context is not None else RunContext(search_path=search_path)
    if reference_speed is not None:
        ctx = replace(ctx, reference_speed=float(reference_speed))
    return config_or_system, ctx, None
