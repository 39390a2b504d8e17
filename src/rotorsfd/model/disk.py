"""Rigid disks and point masses attached to rotor nodes."""

from __future__ import annotations

import math
from dataclasses import dataclass

from rotorsfd.errors import ConfigError


@dataclass(frozen=True)
class Disk:
    """Rigid disk at 1-based ``node``: mass m [kg], polar Ip and diametral Id inertia [kg m^2].

    Adds ``m`` to the y, z mass, ``Id`` to the ty, tz mass and the gyroscopic terms
    ``G[ty, tz] = +Ip``, ``G[tz, ty] = -Ip``.
    """

    node: int
    mass: float
    polar_inertia: float
    diametral_inertia: float

    def __post_init__(self) -> None:
        if self.node < 1:
            raise ConfigError("disk.node", self.node, "node numbers start at 1")
        for name in ("mass", "polar_inertia", "diametral_inertia"):
            if getattr(self, name) < 0.0:
                raise ConfigError(f"disk.{name}", getattr(self, name), "must be >= 0")

    @classmethod
    def from_geometry(
        cls, node: int, density: float, inner_radius: float, outer_radius: float,
        thickness: float,
    ) -> Disk:
        """Annular disk of uniform density.

        m = rho pi (ro^2 - ri^2) h,  Ip = m (ro^2 + ri^2) / 2,
        Id = m (3 (ro^2 + ri^2) + h^2) / 12.
        """
        if not 0.0 <= inner_radius < outer_radius or not thickness > 0.0 or not density > 0.0:
            raise ConfigError(
                "disk geometry", (density, inner_radius, outer_radius, thickness),
                "need density > 0, 0 <= inner_radius < outer_radius, thickness > 0",
            )
        r2 = outer_radius**2 + inner_radius**2
        m = density * math.pi * (outer_radius**2 - inner_radius**2) * thickness
        return cls(node, m, m * r2 / 2.0, m * (3.0 * r2 + thickness**2) / 12.0)


@dataclass(frozen=True)
class PointMass:
    """Lumped mass m [kg] on the y and z DOFs of 1-based ``node`` (no rotary inertia)."""

    node: int
    mass: float

    def __post_init__(self) -> None:
        if self.node < 1:
            raise ConfigError("point_mass.node", self.node, "node numbers start at 1")
        if self.mass < 0.0:
            raise ConfigError("point_mass.mass", self.mass, "must be >= 0")
