"""The parameters of a torus branch (``rotorsfd response`` under a harmonic base law): the
config path of ``[analysis.response] parameter`` in the quasiperiodic API's words
(:class:`TorusParameter`: ``speed``, ``unbalance``, ``base.frequency`` with the amplitude
form it holds, ``base.<law>.<amplitude form>``), the problem continued in it and the
system at one of its values. See :mod:`~rotorsfd.analyses.torus_response`.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, NamedTuple

from rotorsfd.errors import ConfigError

if TYPE_CHECKING:
    from rotorsfd.io.schema import Config
    from rotorsfd.model.system import RotorSystem

__all__ = ["ALLOWED", "AMPLITUDES", "LAWS", "SPEED", "TorusParameter", "harmonic_base",
           "parameter_problem", "system_at", "torus_parameter"]

FIELD = "analysis.response"
LAWS = ("rolling", "pitching", "yawing", "x", "y", "z")


def harmonic_base(config: Config) -> bool:
    """True when a base law of the config is harmonic (the response is then a torus)."""
    return any(getattr(config.base, name).law == "harmonic" for name in LAWS)


#: amplitude forms of a base law that a torus branch may be continued in
AMPLITUDES = ("amplitude", "angle_amplitude", "acceleration_amplitude")
ALLOWED = ("speed, base.<law>.frequency (w_b), base.<law>.amplitude (or angle_amplitude, "
           "acceleration_amplitude) of a harmonic law, or unbalance[0].magnitude")


class TorusParameter(NamedTuple):
    """A torus branch's parameter: the config ``path``, the quasiperiodic API's ``name``
    (``speed``, ``unbalance``, ``base.frequency``, ``base.<law>.<amplitude form>``), its SI
    ``unit`` and, for the base frequency, which rotation amplitude is held (``hold``)."""

    path: str
    name: str
    unit: str
    hold: str = "angle"


SPEED = TorusParameter("speed", "speed", "rad/s")
"""The rotor speed as the parameter (the default of a branch)."""


def torus_parameter(config: Config, path: str) -> TorusParameter:
    """The torus parameter of ``analysis.response.parameter`` = ``path`` (module
    docstring); ConfigError naming that field for anything else."""
    # deferred: io.schema, io.units (loads scipy, pydantic)
    from rotorsfd.io.schema import resolve_kind
    from rotorsfd.io.units import KINDS

    path = path.strip()
    if path == "speed":
        return SPEED
    field = f"{FIELD}.parameter"
    if path in ("unbalance[0].magnitude", "unbalance.0.magnitude"):
        if not config.unbalance:
            raise ConfigError(field, path, "needs an [[unbalance]] to continue in")
        return TorusParameter(path, "unbalance", KINDS[resolve_kind(config, path)].unit)
    parts = path.split(".")
    if len(parts) != 3 or parts[0] != "base" or parts[1] not in LAWS \
            or parts[2] not in ("frequency", *AMPLITUDES):
        raise ConfigError(field, path, "under a harmonic base law the torus branch is "
                          f"continued in {ALLOWED}")
    law = getattr(config.base, parts[1])
    if law.law != "harmonic":
        raise ConfigError(field, path, f"base.{parts[1]} has law = {law.law!r}: continue "
                          "in a field of a harmonic law")
    try:
        unit = KINDS[resolve_kind(config, path)].unit
    except KeyError:
        raise ConfigError(field, path, f"base.{parts[1]} has no field {parts[2]!r}; "
                          f"allowed: {ALLOWED}") from None
    if parts[2] != "frequency":
        return TorusParameter(path, path, unit)
    forms = {"angle" if getattr(config.base, n).angle_amplitude is not None else "rate"
             for n in LAWS[:3] if getattr(config.base, n).law == "harmonic"}
    if len(forms) > 1:
        raise ConfigError(field, path, "the base frequency moves every harmonic law: give "
                          "the rotation laws' amplitudes in one form (all angle_amplitude "
                          "or all amplitude)")
    return TorusParameter(path, "base.frequency", unit, forms.pop() if forms else "angle")


def parameter_problem(system: RotorSystem, par: TorusParameter, speed: float | None):
    """The TorusProblem of ``system`` continued in ``par`` (at the fixed ``speed``)."""
    # deferred: quasiperiodic (loads numba, scipy, pydantic)
    from rotorsfd.quasiperiodic import base_parameter_problem, torus_problem

    if par.name in ("speed", "unbalance"):
        return torus_problem(system, par.name, speed=speed)
    return base_parameter_problem(system, par.name, float(speed), hold=par.hold)


def system_at(system: RotorSystem, par: TorusParameter, lam: float) -> RotorSystem:
    """``system`` with the parameter at ``lam`` (for the time integration of a point)."""
    if par.name == "speed":
        return system
    if par.name == "unbalance":
        return system.with_parameter("unbalance.magnitude", lam)
    # deferred: quasiperiodic.torus_base_parameters (loads numba, scipy, pydantic)
    from rotorsfd.quasiperiodic.torus_base_parameters import with_base_value

    return with_base_value(system, par.name, lam, par.hold)
