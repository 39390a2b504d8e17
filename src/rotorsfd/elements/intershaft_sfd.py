"""The intershaft squeeze film damper: a short film between a node of one shaft (the
journal, ``node``) and a node of another (the housing, ``outer_node``) of a multi-shaft
rotor (:mod:`rotorsfd.model.multishaft`).

The film acts on the relative motion of the two nodes. With ``T = [I, -I]`` on the DOFs
``(y_a, z_a, y_b, z_b)`` and the housing offset ``o``::

    d = T q - o,   F = T^T f(d, T q'),   dF/dq = T^T (df/dd) T,   dF/dq' = T^T (df/dd') T

(``f`` the SFD's short-bearing film, ``docs/sfd.md``): ``+f`` on the journal, ``-f`` on the
housing, so the pair exerts no net force on the system. The film does not depend on the
spins of either shaft (a squeeze film: no journal rotation in the Reynolds equation), so
the law is the same whatever the speed ratio. Validity: ``eps = |d| / C < 1``. A centring
spring becomes an intershaft bearing between the two nodes
(:meth:`IntershaftSFDConfig.intershaft_bearings`). Short film only.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
from pydantic import Field, model_validator

from rotorsfd.elements.base import FloatArray, NonlinearElement
from rotorsfd.elements.registry import register
from rotorsfd.elements.sfd import SFDConfig, SFDElement
from rotorsfd.io.fields import NODE, fail
from rotorsfd.model.dofs import dof_index
from rotorsfd.model.multishaft import IntershaftBearing
from rotorsfd.model.supports import LinearSupport

__all__ = ["IntershaftSFDConfig", "IntershaftSFDElement", "relative"]


def relative(x: FloatArray) -> FloatArray:
    """``T x = x_a - x_b`` of samples ``(..., 4)`` -> ``(..., 2)``."""
    x = np.asarray(x, dtype=np.float64)
    return x[..., :2] - x[..., 2:]


def _spread(f: FloatArray) -> FloatArray:
    """``T^T f``: ``(..., 2)`` -> ``(..., 4)``."""
    return np.concatenate([f, -f], axis=-1)


def _spread_jacobian(j: FloatArray) -> FloatArray:
    """``T^T j T``: ``(..., 2, 2)`` -> ``(..., 4, 4)``."""
    top = np.concatenate([j, -j], axis=-1)
    return np.concatenate([top, -top], axis=-2)


class IntershaftSFDElement(NonlinearElement):
    """Short film between the journal ``node`` and the housing ``outer_node`` (module doc);
    the film law is the :class:`~rotorsfd.elements.sfd.SFDElement` ``film`` on the relative
    state."""

    kind = "intershaft_sfd"
    limit_label = "eps"
    parameters = SFDElement.parameters

    def __init__(self, name: str, node: int, outer_node: int, film: SFDElement) -> None:
        super().__init__(name, [dof_index(node, "y"), dof_index(node, "z"),
                                dof_index(outer_node, "y"), dof_index(outer_node, "z")],
                         film.clearance, nodes=(node, outer_node))
        self.node, self.outer_node = int(node), int(outer_node)
        #: the film on the relative state (an SFD element at the journal node)
        self.film = film
        self.diagnostic_info = film.diagnostic_info

    @property
    def clearance(self) -> float:
        return self.film.clearance

    def force_and_jacobian(self, q: FloatArray, v: FloatArray
                           ) -> tuple[FloatArray, FloatArray, FloatArray]:
        f, jq, jv = self.film.force_and_jacobian(relative(q), relative(v))
        return _spread(f), _spread_jacobian(jq), _spread_jacobian(jv)

    def force(self, q: FloatArray, v: FloatArray) -> FloatArray:
        return _spread(self.film.force(relative(q), relative(v)))

    @property
    def kernel(self):
        """:func:`rotorsfd.elements.intershaft_sfd_kernel.intershaft_sfd_kernel`."""
        from rotorsfd.elements.intershaft_sfd_kernel import (  # deferred: numba
            intershaft_sfd_kernel,
        )

        return intershaft_sfd_kernel

    @property
    def kernel_params(self) -> FloatArray:
        """The SFD element's vector ``[mu, R, L, C, eps_max, film code, o_y, o_z]``."""
        return self.film.kernel_params

    def limit(self, q: FloatArray) -> float:
        """The largest relative eccentricity ratio ``|T q - o| / C`` of the samples."""
        return self.film.limit(relative(q))

    def diagnostics(self, q: FloatArray, v: FloatArray) -> dict[str, float]:
        return self.film.diagnostics(relative(q), relative(v))

    def contact_error(self, q: FloatArray, v: FloatArray, where: str = "") -> Exception:
        return self.film.contact_error(relative(q), relative(v), where=(
            f"intershaft, nodes {self.node} and {self.outer_node}" + (
                f", {where}" if where else "")))

    def with_parameter(self, name: str, value: float) -> IntershaftSFDElement:
        """The element with the film's field ``name`` at ``value`` (as the SFD's: the
        film's table is this element's, so its copy is an intershaft SFD)."""
        return self.film.with_parameter(name, value)

    def dforce(self, q: FloatArray, v: FloatArray, name: str) -> FloatArray:
        """``T^T df/dp`` at the relative state."""
        return _spread(self.film.dforce(relative(q), relative(v), name))

    def describe(self) -> str:
        return (f"intershaft SFD {self.name!r} between nodes {self.node} and "
                f"{self.outer_node} ({self.film.film.cavitation} film, C = "
                f"{self.clearance:.4g} m)")


class IntershaftSFDConfig(SFDConfig):
    """Squeeze film damper between two shafts: the journal at ``node`` (the inner shaft),
    the housing at ``outer_node`` (the outer shaft); the SFD's fields (short film only)."""

    kind: Literal["intershaft_sfd"] = Field(
        "intershaft_sfd", description="element kind: 'intershaft_sfd' (squeeze film "
        "damper between a node of one shaft and a node of another, on their relative "
        "motion)")
    outer_node: NODE

    @model_validator(mode="after")
    def _two_nodes(self):
        if self.outer_node == self.node:
            raise fail("outer_node", self.outer_node, "must differ from node (a node of "
                       "another shaft)")
        if self.film_length != "short":
            raise fail("film_length", self.film_length, "the intershaft SFD has the short "
                       "film only: 'short'")
        if self.fluid_inertia:
            raise fail("fluid_inertia", True, "the intershaft SFD has no fluid inertia "
                       "force yet (false)")
        return self

    @property
    def nodes(self) -> tuple[int, ...]:
        return (self.node, self.outer_node)

    def linear_supports(self) -> list[LinearSupport]:
        """None to ground: the centring spring joins the two nodes
        (:meth:`intershaft_bearings`)."""
        return []

    def intershaft_bearings(self) -> list:
        """The centring spring as an intershaft bearing between the two nodes."""
        k, c = self.centring_stiffness, self.centring_damping
        if k > 0 or c > 0:
            return [IntershaftBearing(self.node, self.outer_node, k, k, cyy=c, czz=c)]
        return []

    def build(self, name: str) -> IntershaftSFDElement:
        """The element of this table, named ``name``."""
        film = super().build(name)
        return IntershaftSFDElement(name, self.node, self.outer_node, film)


register(IntershaftSFDConfig)
