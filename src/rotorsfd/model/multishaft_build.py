"""Configuration -> :class:`~rotorsfd.model.multishaft.MultiShaftRotor`: the
``[[rotor.shafts]]`` tables (each with its sections, disks, point masses and supports at
global nodes), ``[[rotor.intershaft]]`` bearings and the intershaft elements' centring
springs. Called by :func:`rotorsfd.model.build.build_rotor` when the rotor has shafts."""

from __future__ import annotations

from collections.abc import Sequence

from rotorsfd.io.schema import Config, DiskConfig
from rotorsfd.model.damping import ModalDamping, RayleighDamping
from rotorsfd.model.disk import Disk, PointMass
from rotorsfd.model.materials import Material
from rotorsfd.model.multishaft import IntershaftBearing, MultiShaftRotor, Shaft
from rotorsfd.model.shaft import uniform_shaft
from rotorsfd.model.supports import LinearSupport

__all__ = ["multishaft_rotor"]


def _disk(config: Config, d: DiskConfig) -> Disk:
    if d.mass is not None:
        return Disk(d.node, d.mass, d.polar_inertia, d.diametral_inertia)
    return Disk.from_geometry(d.node, config.materials[d.material].density,
                              d.inner_radius or 0.0, d.outer_radius, d.thickness)


def _material(config: Config, name: str) -> Material:
    m = config.materials[name]
    return Material(m.density, m.young_modulus, m.resolved_shear_modulus, name=name)


def multishaft_rotor(config: Config, damping: RayleighDamping | ModalDamping | None,
                     extra_supports: Sequence[LinearSupport]) -> MultiShaftRotor:
    """The multi-shaft rotor of ``config.rotor.shafts``; ``extra_supports`` are the grounded
    supports of ``[[rotor.supports]]`` and the elements' linear parts (global nodes), the
    rotor table's own disks and point masses are added as well."""
    r = config.rotor
    shafts = []
    for s in r.shafts:
        elements = []
        for sec in s.sections:
            elements += uniform_shaft(sec.length, sec.n_elements, sec.inner_radius,
                                      sec.outer_radius, _material(config, sec.material),
                                      sec.shear_coefficient)
        shafts.append(Shaft(
            s.name, tuple(elements), s.speed_ratio, s.x_start,
            disks=tuple(_disk(config, d) for d in s.disks),
            point_masses=tuple(PointMass(p.node, p.mass) for p in s.point_masses),
            supports=tuple(LinearSupport(b.node, **b.coefficients()) for b in s.supports)))
    bearings = [IntershaftBearing(b.node, b.outer_node, **b.coefficients())
                for b in r.intershaft]
    for table in config.elements.values():
        bearings += getattr(table, "intershaft_bearings", list)()
    return MultiShaftRotor(shafts, bearings, damping, extra_supports,
                           [_disk(config, d) for d in r.disks],
                           [PointMass(p.node, p.mass) for p in r.point_masses])
