"""Finite-element rotor model: shaft elements, disks, supports, damping, assembly."""

from rotorsfd.model.damping import ModalDamping, RayleighDamping
from rotorsfd.model.disk import Disk, PointMass
from rotorsfd.model.dofs import dof_index
from rotorsfd.model.materials import Material
from rotorsfd.model.rotor import Rotor
from rotorsfd.model.shaft import ShaftElement, hollow_circle_shear_coefficient, uniform_shaft
from rotorsfd.model.supports import LinearSupport

__all__ = [
    "Disk",
    "LinearSupport",
    "Material",
    "ModalDamping",
    "PointMass",
    "RayleighDamping",
    "Rotor",
    "ShaftElement",
    "dof_index",
    "hollow_circle_shear_coefficient",
    "uniform_shaft",
]
