"""The rub element: contact between the rotor at a node and a stator, with Coulomb friction.

The rotor's lateral DOFs ``q = (y, z)`` at its node are measured against the stator centre
``o = (offset_y, offset_z)``; with ``d = q - o``, ``r = |d|`` and the radial clearance
``delta``, the penetration is ``p = r - delta`` and the force on the rotor is

    F = -F_n(p) (e_r + mu e_t),   e_r = d / r,   e_t = (-d_z, d_y) / r,
    F_n(p) = k_c s(p)

with ``k_c`` the contact stiffness (a rigid stator's local contact stiffness, or that in
series with an elastic stator's) and ``mu`` the Coulomb friction coefficient. Friction
opposes the sliding of the rotor surface on the stator. The rotor spins forward
(``Omega > 0``, from y towards z, the sense of the unbalance force), and its surface
speed ``Omega R`` is taken to dominate the whirl velocity at the contact point, so the
sliding is always along ``+e_t`` and friction is ``-mu F_n e_t`` (the law does not
depend on ``q'``: ``dF/dv = 0``). A backward whirl fast enough to reverse the sliding
(dry whip near its onset) is outside this law.

Smoothed contact (so that the Jacobian exists): the ramp ``max(p, 0)`` is replaced by a
C2 ramp centred on ``p = 0`` with smoothing length ``eps``; with ``x = (p + eps/2) / eps``

    s(p) = 0                        x <= 0     (p <= -eps/2: no contact)
    s(p) = eps (x^3 - x^4 / 2)      0 < x < 1
    s(p) = p                        x >= 1     (p >= eps/2: the linear contact law)

    s'(p) = 3 x^2 - 2 x^3 (0 .. 1),   s''(p) = 6 x (1 - x) / eps

(``s``, ``s'`` and ``s''`` are continuous at ``x = 0`` and ``x = 1``: at ``x = 1``,
``s = eps/2 = p``, ``s' = 1``, ``s'' = 0``). The law is the exact piecewise-linear one
outside the band ``|p| < eps/2``; ``eps -> 0`` recovers the hard ramp. Jacobian: with
``A = I + mu J`` (``J = [[0, -1], [1, 0]]``, so ``e_t = J e_r``) the force is
``F = -k_c s(p) A d / r``, and since ``dr/dq = e_r^T``,

    dF/dq = -k_c A [ (s / r) I + (s' - s / r) e_r e_r^T ],   dF/dv = 0

(finite wherever ``s > 0``, which needs ``r > delta - eps/2 > 0``: ``eps < 2 delta``, the
config asks ``eps < delta``). Full annular rub synchronous whirl of a Jeffcott rotor
(the closed form of the tests, ``docs/elements.md``): in complex notation the force is
``-k_c s(p) (1 + i mu) z / r``, a circular orbit stays circular, and its radius solves a
quadratic (derived in ``docs/elements.md``). References: Choy and Padovan, J. Sound Vib.
113 (1987) (rotor-casing rub with a contact stiffness and Coulomb friction); Black,
J. Mech. Eng. Sci. 10 (1968) (synchronous full annular rub); Muszynska, Rotordynamics
(CRC, 2005), the chapter on rotor-to-stator rub.
"""

from __future__ import annotations

from typing import ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from rotorsfd.elements.base import FloatArray, NonlinearElement
from rotorsfd.elements.registry import register
from rotorsfd.io.fields import NODE, Section, fail, quantity
from rotorsfd.model.dofs import dof_index

__all__ = ["RubConfig", "RubElement", "smooth_ramp"]


def smooth_ramp(p: FloatArray, eps: float) -> tuple[FloatArray, FloatArray]:
    """``(s(p), s'(p))`` of the C2 ramp of smoothing length ``eps`` (module doc)."""
    p = np.asarray(p, dtype=np.float64)
    x = np.clip((p + 0.5 * eps) / eps, 0.0, 1.0)
    s = np.where(x >= 1.0, p, eps * x**3 * (1.0 - 0.5 * x))
    ds = x * x * (3.0 - 2.0 * x)
    return s, ds


class RubElement(NonlinearElement):
    """Rotor-stator rub at ``node`` (DOFs y, z): radial clearance ``clearance`` to a stator
    centred at ``offset``, contact stiffness, Coulomb friction, smoothed ramp (module doc).
    No validity limit; diagnostics: the largest normal force and penetration, the contact
    fraction of the period."""

    kind = "rub"
    limit_label = None
    diagnostic_info: ClassVar[dict[str, tuple[str, str]]] = {
        "force_max": ("largest normal contact force over the period", "N"),
        "penetration_max": ("largest penetration |q - o| - delta over the period "
                            "(negative: the smallest gap)", "m"),
        "contact_fraction": ("fraction of the period in contact (penetration > 0)", "1")}

    def __init__(self, name: str, node: int, clearance: float, contact_stiffness: float,
                 friction: float = 0.0, smoothing: float | None = None,
                 offset: tuple[float, float] = (0.0, 0.0)) -> None:
        super().__init__(name, [dof_index(node, "y"), dof_index(node, "z")], clearance,
                         nodes=(node,))
        eps = 0.01 * clearance if smoothing is None else float(smoothing)
        if not (clearance > 0 and contact_stiffness > 0 and friction >= 0
                and 0 < eps < 2 * clearance):
            raise ValueError("rub: need clearance > 0, contact_stiffness > 0, "
                             "friction >= 0 and 0 < smoothing < 2 clearance")
        self.node = int(node)
        self.clearance = float(clearance)
        self.contact_stiffness = float(contact_stiffness)
        self.friction = float(friction)
        self.smoothing = eps
        self.offset = np.array([float(offset[0]), float(offset[1])])
        self._params = np.array([self.clearance, self.contact_stiffness, self.friction,
                                 eps, *self.offset])

    def _geometry(self, q: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``d = q - o``, ``r = |d|`` and ``p = r - delta`` of samples ``q (..., 2)``."""
        d = np.asarray(q, dtype=np.float64) - self.offset
        r = np.hypot(d[..., 0], d[..., 1])
        return d, r, r - self.clearance

    def normal_force(self, q: FloatArray) -> FloatArray:
        """``F_n = k_c s(p)`` [N] of samples ``q (..., 2)``."""
        return self.contact_stiffness * smooth_ramp(self._geometry(q)[2], self.smoothing)[0]

    def force_and_jacobian(self, q: FloatArray, v: FloatArray
                           ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``F = -k_c s A d / r`` and ``dF/dq = -k_c A [(s/r) I + (s' - s/r) e_r e_r^T]``,
        ``dF/dv = 0`` (module doc), vectorised over samples ``(..., 2)``."""
        d, r, p = self._geometry(q)
        s, ds = smooth_ramp(p, self.smoothing)
        touching = s > 0.0
        r_safe = np.where(touching, r, 1.0)
        g = np.where(touching, self.contact_stiffness * s / r_safe, 0.0)
        h = np.where(touching, self.contact_stiffness * ds, 0.0) - g
        A = np.array([[1.0, -self.friction], [self.friction, 1.0]])
        e = d / r_safe[..., None]
        B = g[..., None, None] * np.eye(2) + h[..., None, None] * e[..., :, None] \
            * e[..., None, :]
        F = -g[..., None] * (d @ A.T)
        Jq = -np.einsum("ij,...jk->...ik", A, B)
        return F, Jq, np.zeros_like(Jq)

    @property
    def kernel(self):
        """The compiled law, :func:`rotorsfd.elements.rub_kernel.rub_kernel`."""
        from rotorsfd.elements.rub_kernel import rub_kernel  # deferred: numba

        return rub_kernel

    @property
    def kernel_params(self) -> FloatArray:
        """``[delta, k_c, mu, eps, o_y, o_z]``."""
        return self._params.copy()

    def diagnostics(self, q: FloatArray, v: FloatArray) -> dict[str, float]:
        """Over one orbit (samples uniform in time): ``force_max`` the largest normal force
        [N], ``penetration_max`` the largest ``p = r - delta`` [m] (negative: the smallest
        gap, no contact), ``contact_fraction`` the fraction of the period with ``p > 0``
        (the hard law's contact arc; the smoothed force starts at ``p = -eps/2``, which
        would add O(eps) to the fraction)."""
        p = self._geometry(q)[2]
        return {"force_max": float(np.max(self.normal_force(q), initial=0.0)),
                "penetration_max": float(np.max(p)) if p.size else float("nan"),
                "contact_fraction": float(np.mean(p > 0.0)) if p.size else 0.0}

    def describe(self) -> str:
        return (f"rub {self.name!r} at node {self.node} (clearance {self.clearance:.4g} m, "
                f"k_c = {self.contact_stiffness:.4g} N/m, mu = {self.friction:g})")


class RubConfig(Section):
    """Rotor-stator rub at a node: radial clearance to a (rigid or elastic) stator, its
    contact stiffness, Coulomb friction against forward spin, and the smoothing length of
    the contact law."""

    kind: Literal["rub"] = Field("rub", description="element kind: 'rub' (rotor-stator "
                                 "contact with Coulomb friction)")
    node: NODE
    clearance: quantity("length", "radial clearance delta between rotor and stator", gt=0)
    contact_stiffness: quantity("stiffness", "contact stiffness k_c (a rigid stator's "
                                "local stiffness, or in series with an elastic stator's)",
                                gt=0)
    friction: quantity("ratio", "Coulomb friction coefficient mu (friction opposes forward "
                       "spin, Omega > 0)", ge=0, le=2) = 0.0
    smoothing: quantity("length", "smoothing length eps of the contact ramp (C2 ramp on "
                        "|penetration| < eps/2); default 1 % of the clearance", gt=0,
                        optional=True) = None
    offset_y: quantity("length", "static offset of the stator centre, y") = 0.0
    offset_z: quantity("length", "static offset of the stator centre, z") = 0.0

    @model_validator(mode="after")
    def _smoothing_below_clearance(self):
        if self.smoothing is not None and self.smoothing >= self.clearance:
            raise fail("smoothing", self.smoothing,
                       f"must be smaller than the clearance ({self.clearance:.6g} m)")
        return self

    @property
    def resolved_smoothing(self) -> float:
        """eps [m], given or 1 % of the clearance."""
        return 0.01 * self.clearance if self.smoothing is None else self.smoothing

    @property
    def nodes(self) -> tuple[int, ...]:
        """The rotor nodes the element sits at."""
        return (self.node,)

    def derived_text(self) -> str:
        """The smoothing length used, for ``config show`` and ``config check``."""
        eps = self.resolved_smoothing
        return (f"smoothing eps = {eps:.6g} m (eps/delta = {eps / self.clearance:.6g}"
                + (", the default)" if self.smoothing is None else ")"))

    def linear_supports(self) -> list:
        """None: a rub has no linear part."""
        return []

    def build(self, name: str) -> RubElement:
        """The element of this table, named ``name``."""
        return RubElement(name, self.node, self.clearance, self.contact_stiffness,
                          self.friction, self.resolved_smoothing,
                          (self.offset_y, self.offset_z))


register(RubConfig)
