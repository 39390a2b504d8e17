"""The hydrodynamic journal bearing element: the short (Ocvirk) bearing with a rotating
journal.

The journal at a node (DOFs y, z) spins at Omega (the rotor speed, forward: from y to z)
in a fixed bush of radius R, length L and radial clearance C, lubricated by oil of
viscosity mu. The short-bearing Reynolds equation with the journal surface moving at
``Omega R`` (the Couette term ``6 mu Omega dh/dphi``) and the squeeze term of the journal
velocity,

    d/dx (h^3 dp/dx) = 12 mu (dh/dt + (Omega/2) dh/dphi),   h = C - q.n(phi),

has ``dh/dt + (Omega/2) dh/dphi = -(v - (Omega/2) J q).n`` with ``J q = (-q_z, q_y)``: it
is the squeeze film of :mod:`rotorsfd.model.sfd` (``docs/sfd.md``) seen in the frame that
turns at Omega/2,

    F(q, v; Omega) = F_film(q, v - (Omega/2) J q),

which in the polar form replaces the precession rate psi' by ``psi' - Omega/2``. The film
models: ``"pi"`` is the half-Sommerfeld film where the pressure is positive (the film of
``cavitation = "guembel"`` of the SFD: its arc follows the squeeze velocity, as the
classical pi film of a journal bearing does), ``"none"`` the full 2 pi (Sommerfeld) film.
For the static journal (``v = 0``) the pi film gives the Ocvirk short-bearing load
``W = (mu Omega R L^3 / (4 C^2)) eps (pi^2 (1 - eps^2) + 16 eps^2)^(1/2) / (1 - eps^2)^2``
at the attitude angle ``tan(phi) = pi (1 - eps^2)^(1/2) / (4 eps)`` (e.g. Childs,
Turbomachinery Rotordynamics, 1993, ch. 3; Friswell et al., Dynamics of Rotating
Machines, 2010, sec. 5.5), tested in ``tests/elements/test_journal_bearing.py``.

The speed is an input of the law (``parameters = ("speed",)``): the system sets it for
a run at one speed and continuation in the speed adds ``dF/dOmega = -(1/2) dF/dv J q``
to ``dR/dlam`` (:class:`~rotorsfd.harmonic.problem.NonlinearLaw`).
"""

from __future__ import annotations

import math
from typing import ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from rotorsfd.elements.base import FloatArray, NonlinearElement
from rotorsfd.elements.registry import register
from rotorsfd.errors import JournalContactError
from rotorsfd.io.fields import NODE, Section, fail, quantity
from rotorsfd.model.dofs import dof_index

__all__ = ["JournalBearingConfig", "JournalBearingElement"]

#: journal bearing film name -> the squeeze-film model that computes it
FILMS = {"pi": "guembel", "none": "none"}


def rotated(q: FloatArray) -> FloatArray:
    """``J q = (-q_z, q_y)``: q turned by +90 degrees (the direction of spin)."""
    q = np.asarray(q, dtype=np.float64)
    return np.stack([-q[..., 1], q[..., 0]], axis=-1)


class JournalBearingElement(NonlinearElement):
    """Short hydrodynamic journal bearing at ``node``; validity measure: the eccentricity
    ratio ``eps = |q| / C``; input: the journal speed (``with_parameter("speed", Omega)``).

    ``film`` is a :class:`rotorsfd.model.sfd.SFD` with the bearing's geometry and film
    model (:data:`FILMS`)."""

    kind = "journal_bearing"
    limit_label = "eps"
    parameters: ClassVar[tuple[str, ...]] = ("speed",)
    diagnostic_info: ClassVar[dict[str, tuple[str, str]]] = {
        "eps_max": ("largest eccentricity ratio |q| / C over the period", "1"),
        "h_min": ("smallest film thickness C (1 - eps) over the period", "m")}

    def __init__(self, name: str, node: int, film, speed: float | None = None) -> None:
        super().__init__(name, [dof_index(node, "y"), dof_index(node, "z")],
                         film.clearance, nodes=(node,))
        self.node = int(node)
        self.film = film
        self.speed = None if speed is None else float(speed)
        self._params = np.append(film.kernel_params,
                                 np.nan if self.speed is None else self.speed)

    @property
    def clearance(self) -> float:
        """Radial clearance C [m]."""
        return self.film.clearance

    def with_parameter(self, name: str, value: float) -> JournalBearingElement:
        if name != "speed":
            return super().with_parameter(name, value)
        return JournalBearingElement(self.name, self.node, self.film, value)

    def _half_speed(self) -> float:
        if self.speed is None or not math.isfinite(self.speed):
            raise ValueError(f"journal bearing {self.name!r}: its speed is not set (an "
                             "analysis at one speed uses RotorSystem.elements_at(speed))")
        return 0.5 * self.speed

    def force_and_jacobian(self, q: FloatArray, v: FloatArray
                           ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``F_film(q, w)`` with ``w = v - (Omega/2) J q`` and the chain rule (module doc)."""
        half = self._half_speed()
        q = np.asarray(q, dtype=np.float64)
        w = np.asarray(v, dtype=np.float64) - half * rotated(q)
        F, dFdq, dFdv = self.film.force_and_jacobian(q[..., 0], q[..., 1], w[..., 0],
                                                     w[..., 1])
        dFdq = dFdq.copy()
        dFdq[..., :, 0] -= half * dFdv[..., :, 1]
        dFdq[..., :, 1] += half * dFdv[..., :, 0]
        return F, dFdq, dFdv

    def force(self, q: FloatArray, v: FloatArray) -> FloatArray:
        q = np.asarray(q, dtype=np.float64)
        return self.film.nl_force(q, np.asarray(v, dtype=np.float64)
                                  - self._half_speed() * rotated(q))

    def dforce(self, q: FloatArray, v: FloatArray, name: str) -> FloatArray:
        """``dF/dOmega = dF_film/dw (-(1/2) J q)``."""
        if name != "speed":
            return super().dforce(q, v, name)
        q = np.asarray(q, dtype=np.float64)
        _, _, dFdv = self.force_and_jacobian(q, v)
        return np.einsum("...ij,...j->...i", dFdv, -0.5 * rotated(q))

    @property
    def kernel(self):
        """The compiled law,
        :func:`rotorsfd.elements.journal_bearing_kernel.journal_bearing_kernel`."""
        from rotorsfd.elements.journal_bearing_kernel import (  # deferred: numba
            journal_bearing_kernel,
        )

        return journal_bearing_kernel

    @property
    def kernel_params(self) -> FloatArray:
        """``[mu, R, L, C, eps_max, film code, Omega]`` (Omega NaN while unset)."""
        return self._params.copy()

    def eccentricity(self, q: FloatArray) -> FloatArray:
        """``eps = |q| / C`` of samples ``q (..., 2)``."""
        q = np.asarray(q, dtype=float)
        return np.hypot(q[..., 0], q[..., 1]) / self.film.clearance

    def limit(self, q: FloatArray) -> float:
        """The largest eccentricity ratio of the samples."""
        return float(np.max(self.eccentricity(q), initial=0.0))

    def diagnostics(self, q: FloatArray, v: FloatArray) -> dict[str, float]:
        """``eps_max`` and the smallest film thickness ``h_min = C (1 - eps_max)``."""
        eps = self.limit(q)
        return {"eps_max": eps, "h_min": self.clearance * (1.0 - eps)}

    def contact_error(self, q: FloatArray, v: FloatArray, where: str = "") -> Exception:
        y, z = float(q[0]), float(q[1])
        return JournalContactError(math.hypot(y, z) / self.clearance, y, z, float(v[0]),
                                   float(v[1]), where=f"journal bearing {self.name!r}" + (
                                       f", {where}" if where else ""))

    def describe(self) -> str:
        film = {"guembel": "pi", "none": "2 pi"}[self.film.cavitation]
        return (f"journal bearing {self.name!r} at node {self.node} ({film} film, "
                f"C = {self.clearance:.4g} m)")


class JournalBearingConfig(Section):
    """Short hydrodynamic journal bearing at a node (rotating journal, fixed bush)."""

    kind: Literal["journal_bearing"] = Field(
        "journal_bearing", description="element kind: 'journal_bearing' (short "
        "hydrodynamic bearing, Ocvirk)")
    node: NODE
    viscosity: quantity("viscosity", "oil dynamic viscosity mu", gt=0)
    radius: quantity("length", "journal radius R", gt=0)
    length: quantity("length", "bearing length L (the short-bearing model wants "
                     "L/D <= 0.5)", gt=0)
    clearance: quantity("length", "radial clearance C", gt=0)
    cavitation: Literal["pi", "none"] = Field(
        "pi", description="film model: 'pi' (half-Sommerfeld: the film where the pressure "
                          "is positive), 'none' (full 2 pi Sommerfeld film)")

    @model_validator(mode="after")
    def _clearance_below_radius(self):
        if self.clearance >= self.radius:
            raise fail("clearance", self.clearance, f"must be smaller than the journal "
                       f"radius R = {self.radius:.6g} m")
        return self

    @property
    def nodes(self) -> tuple[int, ...]:
        """The rotor nodes the element sits at."""
        return (self.node,)

    def derived_text(self) -> str:
        """Derived ratios, for ``config show`` and ``config check``."""
        return (f"C/R = {self.clearance / self.radius:.6g}, "
                f"L/D = {self.length / (2 * self.radius):.6g}")

    def linear_supports(self) -> list:
        """None: the bearing's stiffness and damping are its film's."""
        return []

    def build(self, name: str) -> JournalBearingElement:
        """The element of this table, named ``name`` (speed unset)."""
        from rotorsfd.model.sfd import SFD  # deferred: numba (the film's kernels)

        film = SFD(self.viscosity, self.radius, self.length, self.clearance,
                   cavitation=FILMS[self.cavitation])
        return JournalBearingElement(name, self.node, film)


register(JournalBearingConfig)
