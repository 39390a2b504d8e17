"""Configuration -> model objects: the only place where config tables become physics.

``build_rotor(config)`` is the linear rotor of every analysis: shaft, disks, point masses,
supports, structural damping and the elements' linear parts (an SFD's centring spring is a
linear support at its node). The nonlinear elements are built by ``build_elements``, and
``build_system(config)`` is the whole :class:`~rotorsfd.model.system.RotorSystem`.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.interop.matrices import matrix_rotor
from rotorsfd.io.schema import Config, RotationComponent, TranslationComponent
from rotorsfd.model import (
    Disk,
    LinearSupport,
    Material,
    ModalDamping,
    PointMass,
    RayleighDamping,
    Rotor,
    uniform_shaft,
)

if TYPE_CHECKING:
    from rotorsfd.elements.base import NonlinearElement
    from rotorsfd.model.base_motion import BaseMotion, TimeLaw
    from rotorsfd.model.gravity import Gravity
    from rotorsfd.model.system import RotorSystem
    from rotorsfd.model.unbalance import Unbalance


def build_material(config: Config, name: str) -> Material:
    """The named material of ``[materials.<name>]``."""
    m = config.materials[name]
    return Material(m.density, m.young_modulus, m.resolved_shear_modulus, name=name)


def build_supports(config: Config) -> list[LinearSupport]:
    """``[[rotor.supports]]`` plus the elements' linear parts (an SFD's centring spring)."""
    out = [LinearSupport(s.node, **s.coefficients()) for s in config.rotor.supports]
    for element in config.elements.values():
        out += element.linear_supports()
    return out


def build_rotor(config: Config, search_path: Path | None = None) -> Rotor:
    """The linear finite-element rotor (with the elements' linear parts); a rotor given by
    ``[rotor.matrices]`` reads them (paths relative to ``search_path``, the config file's
    folder, else the working folder)."""
    r = config.rotor
    elements = []
    for s in r.shaft:
        elements += uniform_shaft(s.length, s.n_elements, s.inner_radius, s.outer_radius,
                                  build_material(config, s.material), s.shear_coefficient)
    disks = []
    for d in r.disks:
        if d.mass is not None:
            disks.append(Disk(d.node, d.mass, d.polar_inertia, d.diametral_inertia))
        else:
            disks.append(Disk.from_geometry(d.node, config.materials[d.material].density,
                                            d.inner_radius or 0.0, d.outer_radius,
                                            d.thickness))
    damping: RayleighDamping | ModalDamping | None = None
    if r.damping.kind == "rayleigh":
        damping = RayleighDamping(r.damping.alpha or 0.0, r.damping.beta or 0.0)
    elif r.damping.kind == "modal":
        damping = ModalDamping(r.damping.ratio, r.damping.modes)
    point_masses = [PointMass(p.node, p.mass) for p in r.point_masses]
    if r.shafts:   # several shafts at their speed ratios, global node numbering
        from rotorsfd.model.multishaft_build import multishaft_rotor

        return multishaft_rotor(config, damping, build_supports(config))
    if r.matrices is not None:
        return matrix_rotor(config, search_path, disks, point_masses, build_supports(config),
                            damping)
    return Rotor(elements, disks=disks,
                 point_masses=point_masses,
                 supports=build_supports(config), damping=damping, x_start=r.x_start)


def build_elements(config: Config) -> list[NonlinearElement]:
    """The nonlinear elements of the ``[elements.<name>]`` tables, in their order."""
    return [table.build(name) for name, table in config.elements.items()]


def build_unbalances(config: Config) -> list[Unbalance]:
    """The ``[[unbalance]]`` entries."""
    # deferred: model.unbalance (loads 3 more rotorsfd modules, needed only here)
    from rotorsfd.model.unbalance import Unbalance

    return [Unbalance(u.node, u.magnitude, u.phase, u.start, u.rise_time)
            for u in config.unbalance]


def resolve_callable(spec: str, field_name: str,
                     search_path: Path | None = None) -> Callable[..., Any]:
    """Import ``"module:function"``; ``search_path`` (the config file's folder) is tried
    first. ConfigError naming ``field_name`` if it cannot be imported or is not callable."""
    module_name, _, attr = spec.partition(":")
    added = search_path is not None and str(search_path) not in sys.path
    if added:
        sys.path.insert(0, str(search_path))
    try:
        module = importlib.import_module(module_name)
        func = getattr(module, attr)
    except Exception as exc:  # ImportError, AttributeError, errors raised by the module
        raise ConfigError(field_name, spec, f"must be an importable 'module:function' "
                          f"({type(exc).__name__}: {exc})") from None
    finally:
        if added:
            sys.path.remove(str(search_path))
    if not callable(func):
        raise ConfigError(field_name, spec, "must name a callable")
    return func


def _law(c: RotationComponent | TranslationComponent, where: str,
         search_path: Path | None) -> TimeLaw | None:
    # deferred: model.base_motion (loads 2 more rotorsfd modules, for a [base] law only)
    from rotorsfd.model import base_motion as bm

    if c.law == "off":
        return None
    if c.law == "constant":
        return bm.Constant(c.value)
    if c.law == "uniform_acceleration":
        return bm.UniformAcceleration(c.acceleration, c.velocity or 0.0, c.value or 0.0)
    if c.law == "harmonic":
        if isinstance(c, RotationComponent):
            amplitude, phase = c.rate_amplitude(), c.phase or 0.0
        else:
            amplitude, phase = c.displacement_amplitude()
        return bm.Harmonic(amplitude, c.frequency, phase, c.value or 0.0)
    if c.law in ("table", "pulse"):
        return _recorded_law(c, where, search_path)
    f = resolve_callable(c.callable, f"{where}.callable", search_path)
    df = (resolve_callable(c.derivative, f"{where}.derivative", search_path)
          if c.derivative is not None else None)
    return bm.CallableLaw(f, df)


ORDER = {"rate": 0, "angle": -1, "displacement": 0, "velocity": 1, "acceleration": 2}
"""The derivative of the law a recorded quantity is (model/recorded_motion.py)."""


def _recorded_law(c: RotationComponent | TranslationComponent, where: str,
                  search_path: Path | None) -> TimeLaw:
    """A recorded history or a shock pulse (:mod:`rotorsfd.model.recorded_motion`)."""
    # deferred: model.recorded_motion (loads 3 more rotorsfd modules, for a record only)
    from rotorsfd.model import recorded_motion as rm

    rotation = isinstance(c, RotationComponent)
    if c.law == "pulse":
        amplitude = c.amplitude if rotation else c.acceleration_amplitude
        return rm.PulseLaw(c.shape, amplitude, c.duration, c.start or 0.0,
                           order=0 if rotation else 2)
    if c.file is not None:
        path = Path(c.file)
        if not path.is_absolute() and search_path is not None:
            path = search_path / path
        times, values = rm.read_record(path, f"{where}.file")
    else:
        times, values = np.asarray(c.times, float), np.asarray(c.values, float)
    return rm.RecordedLaw(times, values, order=ORDER[c.quantity], cutoff=c.filter,
                          where=where)


def build_gravity(config: Config) -> Gravity | None:
    """Gravity of ``[gravity]`` (None when disabled)."""
    # deferred: model.gravity (loads 1 more rotorsfd module, needed only here)
    from rotorsfd.model.gravity import Gravity

    g = config.gravity
    if not g.enabled:
        return None
    return Gravity(g.magnitude, tuple(g.direction), frame=g.frame)


def build_base_motion(config: Config, search_path: Path | None = None) -> BaseMotion:
    """The six base-motion laws of ``[base]`` and gravity; callables are imported with the
    config file's folder ``search_path`` first on the module path."""
    # deferred: model.base_motion (loads 2 more rotorsfd modules, needed only here)
    from rotorsfd.model.base_motion import BaseMotion

    b = config.base
    laws = {key: _law(getattr(b, name), f"base.{name}", search_path)
            for key, name in (("x0", "x"), ("y0", "y"), ("z0", "z"),
                              ("wx", "rolling"), ("wy", "pitching"), ("wz", "yawing"))}
    return BaseMotion(**laws, gravity=build_gravity(config))


@dataclass
class Model:
    """Everything the solvers need from a configuration."""

    config: Config
    rotor: Rotor
    elements: list[NonlinearElement] = field(default_factory=list)
    unbalances: list[Unbalance] = field(default_factory=list)
    base_motion: BaseMotion | None = None


def build_model(config: Config, search_path: Path | None = None) -> Model:
    """Rotor, nonlinear elements, unbalances and base motion of ``config``."""
    return Model(config=config, rotor=build_rotor(config, search_path),
                 elements=build_elements(config),
                 unbalances=build_unbalances(config),
                 base_motion=build_base_motion(config, search_path))


def build_system(config: Config, search_path: Path | None = None) -> RotorSystem:
    """The :class:`~rotorsfd.model.system.RotorSystem` of ``config``: the one way from a
    configuration to what the solvers take."""
    from rotorsfd.model.system import RotorSystem  # deferred: numba (the HB problem)

    m = build_model(config, search_path)
    return RotorSystem(m.rotor, m.elements, m.unbalances, m.base_motion)
