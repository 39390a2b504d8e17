"""Timoshenko beam element of a hollow circular shaft, 4 DOFs per node.

Local DOF order ``[y1, z1, ty1, tz1, y2, z2, ty2, tz2]`` (see ``rotorsfd.model.dofs``):
``tz`` is the section rotation in the x-y plane (``tz ~ +dy/dx``), ``ty`` the one in the
x-z plane with the opposite sign (``ty ~ -dz/dx``).

Each bending plane uses the interdependent Timoshenko interpolation (cubic deflection
``v = N_v q``, quadratic section rotation ``psi = N_psi q``, the exact static solution of
a Timoshenko beam loaded at its ends) with the shear parameter
``Phi = 12 E I / (kappa G A L^2)``. In the planar DOFs ``[v1, psi1, v2, psi2]``:

    M_t = rho A   int N_v^T N_v dx        translational (consistent) mass
    M_r = rho I   int N_psi^T N_psi dx    rotary inertia
    K   = E I int N_psi'^T N_psi' dx + kappa G A int (N_v' - N_psi)^T (N_v' - N_psi) dx

whose closed forms (Przemieniecki; Nelson, J. Mech. Des. 102, 1980) are coded below and
re-derived from the shape functions with sympy in ``tests/model/test_shaft_sympy.py``.
The x-y plane is ``[y, tz]``, the x-z plane is ``[z, -ty]``. The gyroscopic matrix follows
from the kinetic energy ``1/2 rho Ip (Omega - tz' ty)^2`` per unit length with
``Ip = 2 I`` (thin slice, polar = twice diametral):

    G = 2 rho I int (N_ty^T N_tz - N_tz^T N_ty) dx,   N_tz = N_psi P_y,  N_ty = -N_psi P_z

so that ``G[ty, tz] > 0`` as for a rigid disk (docs/INTERFACES.md).
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model.materials import Material

# Planar -> local maps: rows are planar DOFs [v1, psi1, v2, psi2], columns the 8 local DOFs.
_P_Y = np.zeros((4, 8))
_P_Y[[0, 1, 2, 3], [0, 3, 4, 7]] = 1.0  # x-y plane: v = y, psi = tz
_P_Z = np.zeros((4, 8))
_P_Z[[0, 1, 2, 3], [1, 2, 5, 6]] = [1.0, -1.0, 1.0, -1.0]  # x-z plane: v = z, psi = -ty


def hollow_circle_shear_coefficient(inner_radius: float, outer_radius: float, nu: float) -> float:
    """Shear coefficient of a hollow circular section, Hutchinson's formula.

    J. R. Hutchinson, "Shear coefficients for Timoshenko beam theory", J. Appl. Mech. 68
    (2001) 87-92, hollow circle with ``m = r_i / r_o``::

        kappa = 6 (1 + nu)^2 (1 + m^2)^2
                / [ (7 + 12 nu + 4 nu^2) (1 + m^2)^2 + 4 m^2 (5 + 6 nu + 2 nu^2) ]

    Limits: solid (m = 0) ``6 (1+nu)^2 / (7 + 12 nu + 4 nu^2)``; thin tube (m -> 1)
    ``(1 + nu) / (2 + nu)``.
    """
    m2 = (inner_radius / outer_radius) ** 2
    s = (1.0 + m2) ** 2
    return (6.0 * (1.0 + nu) ** 2 * s) / (
        (7.0 + 12.0 * nu + 4.0 * nu**2) * s + 4.0 * m2 * (5.0 + 6.0 * nu + 2.0 * nu**2)
    )


def _planar_to_local(a4: np.ndarray) -> np.ndarray:
    """8x8 local matrix of a planar 4x4 matrix applied identically in both planes."""
    return _P_Y.T @ a4 @ _P_Y + _P_Z.T @ a4 @ _P_Z


@dataclass(frozen=True)
class ShaftElement:
    """Hollow circular Timoshenko shaft element of length L [m].

    ``shear_coefficient=None`` uses :func:`hollow_circle_shear_coefficient` (Hutchinson).
    """

    length: float
    inner_radius: float
    outer_radius: float
    material: Material
    shear_coefficient: float | None = None
    _kappa: float = field(init=False, repr=False)

    def __post_init__(self) -> None:
        if not self.length > 0.0:
            raise ConfigError("shaft.length", self.length, "must be positive")
        if not 0.0 <= self.inner_radius < self.outer_radius:
            raise ConfigError(
                "shaft.inner_radius", self.inner_radius,
                f"must satisfy 0 <= inner_radius < outer_radius = {self.outer_radius}",
            )
        kappa = self.shear_coefficient
        if kappa is None:
            kappa = hollow_circle_shear_coefficient(
                self.inner_radius, self.outer_radius, self.material.poisson_ratio
            )
        elif not kappa > 0.0:
            raise ConfigError("shaft.shear_coefficient", kappa, "must be positive")
        object.__setattr__(self, "_kappa", float(kappa))

    # ---- section and element quantities -------------------------------------------
    @property
    def kappa(self) -> float:
        """Shear coefficient used (given or Hutchinson's)."""
        return self._kappa

    @property
    def area(self) -> float:
        """A = pi (ro^2 - ri^2) [m^2]."""
        return math.pi * (self.outer_radius**2 - self.inner_radius**2)

    @property
    def second_moment(self) -> float:
        """I = pi (ro^4 - ri^4) / 4 [m^4] (diametral second moment of area)."""
        return math.pi * (self.outer_radius**4 - self.inner_radius**4) / 4.0

    @property
    def mass(self) -> float:
        """rho A L [kg]."""
        return self.material.density * self.area * self.length

    @property
    def polar_moment_mass_per_length(self) -> float:
        """rho Ip = 2 rho I [kg m] (polar mass moment of inertia per unit length)."""
        return 2.0 * self.material.density * self.second_moment

    @property
    def polar_inertia(self) -> float:
        """Polar mass moment of inertia of the element, 2 rho I L [kg m^2]."""
        return self.polar_moment_mass_per_length * self.length

    @property
    def diametral_inertia(self) -> float:
        """Rotary (diametral) inertia about the element's centre, rho I L + m L^2 / 12."""
        rho_i_l = self.material.density * self.second_moment * self.length
        return rho_i_l + self.mass * self.length**2 / 12.0

    @property
    def shear_parameter(self) -> float:
        """Phi = 12 E I / (kappa G A L^2)."""
        mat = self.material
        return 12.0 * mat.young_modulus * self.second_moment / (
            self.kappa * mat.shear_modulus * self.area * self.length**2
        )

    # ---- planar 4x4 closed forms --------------------------------------------------
    def _planar_translational(self) -> np.ndarray:
        L, p = self.length, self.shear_parameter
        a = 4.0 * (70 * p**2 + 147 * p + 78)
        b = L * (35 * p**2 + 77 * p + 44)
        c = 4.0 * (35 * p**2 + 63 * p + 27)
        d = L * (35 * p**2 + 63 * p + 26)
        e = L**2 * (7 * p**2 + 14 * p + 8)
        f = L**2 * (7 * p**2 + 14 * p + 6)
        m = np.array([[a, b, c, -d], [b, e, d, -f], [c, d, a, -b], [-d, -f, -b, e]])
        return self.mass / (840.0 * (1.0 + p) ** 2) * m

    def _planar_rotational_shape(self) -> np.ndarray:
        """int N_psi^T N_psi dx (no rho I factor)."""
        L, p = self.length, self.shear_parameter
        g = 3.0 * L * (1.0 - 5.0 * p)
        h = L**2 * (10 * p**2 + 5 * p + 4)
        k = L**2 * (5 * p**2 - 5 * p - 1)
        m = np.array([[36.0, g, -36.0, g], [g, h, -g, k], [-36.0, -g, 36.0, -g], [g, k, -g, h]])
        return m / (30.0 * (1.0 + p) ** 2 * L)

    def _planar_stiffness(self) -> np.ndarray:
        L, p = self.length, self.shear_parameter
        ei = self.material.young_modulus * self.second_moment
        k = np.array(
            [
                [12.0, 6 * L, -12.0, 6 * L],
                [6 * L, (4 + p) * L**2, -6 * L, (2 - p) * L**2],
                [-12.0, -6 * L, 12.0, -6 * L],
                [6 * L, (2 - p) * L**2, -6 * L, (4 + p) * L**2],
            ]
        )
        return ei / ((1.0 + p) * L**3) * k

    # ---- local 8x8 matrices ---------------------------------------------------------
    def translational_mass_matrix(self) -> np.ndarray:
        """rho A int N_t^T N_t dx in both planes, 8x8 local."""
        return _planar_to_local(self._planar_translational())

    def rotational_mass_matrix(self) -> np.ndarray:
        """rho I int N_r^T N_r dx in both planes, 8x8 local."""
        rho_i = self.material.density * self.second_moment
        return _planar_to_local(rho_i * self._planar_rotational_shape())

    def mass_matrix(self) -> np.ndarray:
        """M_e = M_t + M_r, 8x8 local."""
        return self.translational_mass_matrix() + self.rotational_mass_matrix()

    def stiffness_matrix(self) -> np.ndarray:
        """Bending + shear Timoshenko stiffness, 8x8 local."""
        return _planar_to_local(self._planar_stiffness())

    def gyroscopic_matrix(self) -> np.ndarray:
        """G_e = 2 rho I int (N_ty^T N_tz - N_tz^T N_ty) dx, skew, multiplies Omega."""
        r = self.polar_moment_mass_per_length * self._planar_rotational_shape()
        a = -_P_Z.T @ r @ _P_Y  # int N_ty^T N_tz with N_ty = -N_psi P_z, N_tz = N_psi P_y
        return a - a.T


def uniform_shaft(
    length: float, n_elements: int, inner_radius: float, outer_radius: float,
    material: Material, shear_coefficient: float | None = None,
) -> list[ShaftElement]:
    """``n_elements`` equal elements of a uniform shaft of total ``length``."""
    if n_elements < 1:
        raise ConfigError("shaft.n_elements", n_elements, "must be >= 1")
    le = length / n_elements
    return [
        ShaftElement(le, inner_radius, outer_radius, material, shear_coefficient)
        for _ in range(n_elements)
    ]
