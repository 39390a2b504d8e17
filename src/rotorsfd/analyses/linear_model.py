"""The linear view of a rotor system and the reference speed Omega_ref.

``linear_system(system)`` is the rotor with its supports and the elements' linear parts
(the film excluded) plus the base terms of constant base rates (the ``LinearDynamics`` of
``rotorsfd modal``); ``first_critical(system)`` its first forward critical speed, and
``reference_speed(config)`` ``reference.speed`` or that speed, the Omega~ = Omega /
Omega_ref of every analysis. Below :mod:`~rotorsfd.analyses.context` (which uses them) and
:mod:`~rotorsfd.analyses.modal` (which re-exports them).
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import Config
from rotorsfd.linear import CriticalSpeed, critical_speeds
from rotorsfd.model.build import build_system
from rotorsfd.model.time_terms import linear_part

if TYPE_CHECKING:
    from rotorsfd.model.system import RotorSystem

__all__ = ["first_critical", "forward_reference", "linear_system", "reference_speed"]

RATES = ("rolling", "pitching", "yawing")
"""The ``[base]`` tables of the rotation rates w_x, w_y, w_z."""


def linear_system(source: Config | RotorSystem, search_path: Path | None = None) -> Any:
    """The linear rotor for modal analysis (``LinearDynamics``) of a
    :class:`~rotorsfd.model.system.RotorSystem` (or of a Config, built first): its linear
    part (:func:`~rotorsfd.model.time_terms.linear_part`: the rotor with its supports and
    the elements' linear parts, an SFD's centring spring, no film, on the constant base
    rates), whose ``matrices(speed)`` are the ``(M, D, K)`` of the model's record
    ``second_order(speed)``. ConfigError naming the ``[base]`` law if a base rate varies
    in time (no eigenvalues then)."""
    system = build_system(source, search_path) if isinstance(source, Config) else source
    base = system.base
    if not base.rates_constant:
        for name, law in zip(RATES, base.rotation, strict=True):
            if not law.is_constant:
                raise ConfigError(f"base.{name}.law", law.kind,
                                  "modal analysis needs constant base rates ('off' or "
                                  "'constant'); time-varying rates: use a stability chart")
    return linear_part(system)


def first_critical(system: Any, speed_max: float = 2e4) -> float:
    """The first forward critical speed of a linear ``system`` below ``speed_max`` [rad/s]
    (the reference speed of an analysis given a system, not a config)."""
    found = critical_speeds(system, n=1, whirl="forward", speed_range=(0.0, speed_max))
    if not found:
        raise ConfigError("reference_speed", None, f"no forward critical speed below "
                          f"{speed_max:g} rad/s: give the reference speed")
    return float(found[0].speed_rad_s)


def forward_reference(found: Sequence[CriticalSpeed], speed_max: float) -> float:
    """Omega_ref = the first of the forward critical speeds ``found`` below ``speed_max``;
    ConfigError (naming ``reference.speed``) if there is none."""
    if not found:
        raise ConfigError("reference.speed", "first_critical",
                          f"no forward critical speed below analysis.modal.critical_speed_max"
                          f" = {speed_max:g} rad/s; give reference.speed in rad/s")
    return found[0].speed_rad_s


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
    return forward_reference(found, top)
