"""Isotropic linear-elastic materials of the shaft and disks."""

from __future__ import annotations

from dataclasses import dataclass

from rotorsfd.errors import ConfigError


@dataclass(frozen=True)
class Material:
    """Isotropic material: density rho [kg/m^3], Young's modulus E [Pa], shear modulus G [Pa].

    Poisson's ratio follows from ``nu = E / (2 G) - 1``.
    """

    density: float
    young_modulus: float
    shear_modulus: float
    name: str = "steel"

    def __post_init__(self) -> None:
        for field in ("density", "young_modulus", "shear_modulus"):
            value = getattr(self, field)
            if not value > 0.0:
                raise ConfigError(f"material.{field}", value, "must be a positive number")
        nu = self.poisson_ratio
        if not -1.0 < nu <= 0.5:
            raise ConfigError(
                "material.shear_modulus", self.shear_modulus,
                f"E/(2G) - 1 = {nu:.4g} must lie in (-1, 0.5]",
            )

    @property
    def poisson_ratio(self) -> float:
        """nu = E / (2 G) - 1."""
        return self.young_modulus / (2.0 * self.shear_modulus) - 1.0
