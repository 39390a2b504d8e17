"""Configuration -> model objects: the only place where config tables become physics.

``build_rotor(config)`` is the linear rotor of every analysis: shaft, disks, point masses,
supports, structural damping and the SFD's centring spring (a linear support at the SFD
node). The squeeze film itself is nonlinear and is built separately by ``build_sfd``.
"""

from __future__ import annotations

import importlib
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

from rotorsfd.errors import ConfigError
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
    from rotorsfd.model.base_motion import BaseMotion, TimeLaw
    from rotorsfd.model.gravity import Gravity
    from rotorsfd.model.sfd import SFD
    from rotorsfd.model.unbalance import Unbalance


def build_material(config: Config, name: str) -> Material:
    """The named material of ``[materials.<name>]``."""
    m = config.materials[name]
    return Material(m.density, m.young_modulus, m.resolved_shear_modulus, name=name)


def build_supports(config: Config) -> list[LinearSupport]:
    """``[[rotor.supports]]`` plus the SFD centring spring (if it has stiffness or damping)."""
    out = [LinearSupport(s.node, **s.coefficients()) for s in config.rotor.supports]
    sfd = config.sfd
    if sfd is not None and (sfd.centring_stiffness > 0 or sfd.centring_damping > 0):
        out.append(LinearSupport.isotropic(sfd.node, sfd.centring_stiffness,
                                           sfd.centring_damping))
    return out


def build_rotor(config: Config) -> Rotor:
    """The linear finite-element rotor (with the SFD centring spring, without the film)."""
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
        damping = ModalDamping(r.damping.ratio)
    return Rotor(elements, disks=disks,
                 point_masses=[PointMass(p.node, p.mass) for p in r.point_masses],
                 supports=build_supports(config), damping=damping, x_start=r.x_start)


def build_sfd(config: Config) -> SFD | None:
    """The squeeze film of ``[sfd]`` (None without one); its node is ``config.sfd.node``."""
    from rotorsfd.sfd import SFD

    s = config.sfd
    if s is None:
        return None
    return SFD(s.viscosity, s.resolved_radius, s.resolved_length, s.resolved_clearance,
               cavitation=s.cavitation)


def build_unbalances(config: Config) -> list[Unbalance]:
    """The ``[[unbalance]]`` entries."""
    from rotorsfd.model.unbalance import Unbalance

    return [Unbalance(u.node, u.magnitude, u.phase) for u in config.unbalance]


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
    f = resolve_callable(c.callable, f"{where}.callable", search_path)
    df = (resolve_callable(c.derivative, f"{where}.derivative", search_path)
          if c.derivative is not None else None)
    return bm.CallableLaw(f, df)


def build_gravity(config: Config) -> Gravity | None:
    """Gravity of ``[gravity]`` (None when disabled)."""
    from rotorsfd.model.gravity import Gravity

    g = config.gravity
    if not g.enabled:
        return None
    return Gravity(g.magnitude, tuple(g.direction), frame=g.frame)


def build_base_motion(config: Config, search_path: Path | None = None) -> BaseMotion:
    """The six base-motion laws of ``[base]`` and gravity; callables are imported with the
    config file's folder ``search_path`` first on the module path."""
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
    sfd: SFD | None
    sfd_node: int | None
    unbalances: list[Unbalance] = field(default_factory=list)
    base_motion: BaseMotion | None = None


def build_model(config: Config, search_path: Path | None = None) -> Model:
    """Rotor, SFD (and its node), unbalances and base motion of ``config``."""
    return Model(config=config, rotor=build_rotor(config), sfd=build_sfd(config),
                 sfd_node=config.sfd.node if config.sfd is not None else None,
                 unbalances=build_unbalances(config),
                 base_motion=build_base_motion(config, search_path))
