"""Small test rotors for the base-motion tests (built through rotorsfd.model.Rotor)."""

from __future__ import annotations

from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft

STEEL = Material(7810.0, 211e9, 81.783e9)


def make_rotor(n_elements: int = 6, disk_node: int = 3, stiffness: float = 1e7,
               x_start: float = 0.0, damping: float = 0.0) -> Rotor:
    """Hollow shaft 0.6 m on isotropic supports at both ends, one disk (paper's geometry)."""
    shaft = uniform_shaft(0.6, n_elements, 0.02065, 0.03015, STEEL)
    disk = Disk.from_geometry(disk_node, 7810.0, 0.03015, 0.1016, 0.0508)
    supports = [LinearSupport.isotropic(1, stiffness, damping),
                LinearSupport.isotropic(n_elements + 1, stiffness, damping)]
    return Rotor(shaft, disks=[disk], supports=supports, x_start=x_start)
