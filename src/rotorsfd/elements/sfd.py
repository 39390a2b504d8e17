"""The squeeze film damper element: the short-bearing film at a node, in a housing that may
be offset.

The film acts on the lateral DOFs ``(y, z)`` of its node, measured from the housing centre
``o = (offset_y, offset_z)`` (an eccentric housing, or a centring spring preloaded off
centre; zero by default)::

    F = F_film(q - o, q'),   dF/dq = dF_film/dq (q - o, q'),   eps = |q - o| / C

with ``F_film`` the short-bearing force of :class:`rotorsfd.model.sfd.SFD` (pi, 2 pi or
Guembel film; derivation in ``docs/sfd.md``) or, with ``film_length = "finite"``, the
finite-length Reynolds film of :class:`rotorsfd.model.film_finite.FiniteSFD` (open ends
or end seals of end-flow coefficient ``end_flow``). With ``fluid_inertia`` and an oil
density, the short film adds the fluid inertia force of the short open-ended SFD (San
Andres' averaged-inertia form, :mod:`rotorsfd.model.film_inertia`), which depends on the
journal acceleration: ``F = F_film(q - o, q') + F_in(q - o, q', q'')`` with the added
mass ``-dF/dq''`` on the node's (y, z). Diagnostics per orbit: the
eccentricity, the peak film pressure, the cavitated arc and, with an oil density, the
squeeze Reynolds number (:mod:`rotorsfd.model.film_diagnostics`). The centring spring
is linear and becomes a support of the rotor (:meth:`SFDConfig.linear_supports`). Static
offset: the eccentric SFD of Zhao, Linnett and McLean (J. Vib. Acoust. 116, 1994) is the
classic case.
"""

from __future__ import annotations

import math
from typing import TYPE_CHECKING, ClassVar, Literal

import numpy as np
from pydantic import Field, model_validator

from rotorsfd.elements.base import FloatArray, NonlinearElement
from rotorsfd.elements.registry import register
from rotorsfd.errors import ConfigError, JournalContactError
from rotorsfd.io.fields import (
    NODE,
    Section,
    and_list,
    fail,
    given_fields,
    in_range,
    integer,
    quantity,
    range_text,
)
from rotorsfd.model.dofs import dof_index
from rotorsfd.model.film_diagnostics import film_diagnostics
from rotorsfd.model.supports import LinearSupport

if TYPE_CHECKING:
    from rotorsfd.model.film_finite import FiniteSFD
    from rotorsfd.model.sfd import SFD

__all__ = ["SFD_RATIO_BOUNDS", "SFDConfig", "SFDElement"]


class SFDElement(NonlinearElement):
    """Short-bearing squeeze film at ``node`` (DOFs y, z) in a housing centred at
    ``offset`` [m]; validity measure: the eccentricity ratio ``eps = |q - o| / C``."""

    kind = "sfd"
    limit_label = "eps"
    diagnostic_info: ClassVar[dict[str, tuple[str, str]]] = {
        "eps_max": ("largest eccentricity ratio |q - o| / C over the period", "1")}
    #: The film's quantities (``film_report``), and the squeeze Reynolds number (density).
    FILM_INFO: ClassVar[dict[str, tuple[str, str]]] = {
        "p_max": ("peak film pressure over the period (relative to the cavity pressure)",
                  "Pa"),
        "p_min": ("lowest pressure of the uncavitated film over the period (a supply "
                  "pressure above -p_min keeps the film whole)", "Pa"),
        "cavitated_arc": ("largest arc at mid-land where the uncavitated film pressure is "
                          "below the cavity pressure", "rad")}
    REYNOLDS_INFO: ClassVar[dict[str, tuple[str, str]]] = {
        "squeeze_reynolds": ("squeeze Reynolds number rho omega C^2 / mu of the orbit", "1")}

    def __init__(self, name: str, node: int, film: SFD | FiniteSFD,
                 offset: tuple[float, float] = (0.0, 0.0), density: float | None = None,
                 film_report: bool | None = None, fluid_inertia: bool = False) -> None:
        super().__init__(name, [dof_index(node, "y"), dof_index(node, "z")],
                         film.clearance, nodes=(node,))
        self.node = int(node)
        self.film = film
        self.finite = hasattr(film, "pressure")  # FiniteSFD: its parameters hold o
        self.offset = np.array([float(offset[0]), float(offset[1])])
        self.density = None if density is None else float(density)
        #: the fluid inertia force is included (short film, a density > 0)
        self.inertial = bool(fluid_inertia) and bool(self.density)
        if self.inertial and self.finite:
            raise ConfigError(f"elements.{name}.fluid_inertia", True, "the fluid inertia "
                              "force is implemented for film_length = 'short' only")
        if self.finite:
            # deferred: model.film_finite_kernels (loads numba)
            from rotorsfd.model.film_finite_kernels import P_OFFSET_Y, P_OFFSET_Z

            self._params = film.kernel_params
            self._params[P_OFFSET_Y], self._params[P_OFFSET_Z] = self.offset
        else:
            self._params = np.concatenate([film.kernel_params, self.offset, [
                self.density if self.inertial else 0.0]])
        #: report p_max, p_min, cavitated_arc (default: for the finite film only)
        self.film_report = self.finite if film_report is None else bool(film_report)
        self.diagnostic_info = {**type(self).diagnostic_info,
                                **(self.FILM_INFO if self.film_report else {}),
                                **(self.REYNOLDS_INFO if self.density is not None else {})}

    @property
    def clearance(self) -> float:
        """Radial clearance C [m]."""
        return self.film.clearance

    def force_and_jacobian(self, q: FloatArray, v: FloatArray
                           ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Film force and exact Jacobians at ``q - o`` (module doc); with the fluid
        inertia, the force at zero acceleration (the convective inertia included)."""
        q = np.asarray(q, dtype=np.float64)
        v = np.asarray(v, dtype=np.float64)
        if self.inertial:
            return self.force_and_jacobians(q, v, np.zeros_like(q))[:3]
        return self.film.force_and_jacobian(q[..., 0] - self.offset[0],
                                            q[..., 1] - self.offset[1], v[..., 0], v[..., 1])

    def force(self, q: FloatArray, v: FloatArray) -> FloatArray:
        q = np.asarray(q, dtype=np.float64)
        if self.inertial:
            return self.force_and_jacobian(q, v)[0]
        return self.film.nl_force(q - self.offset, v)

    def force_and_jacobians(self, q: FloatArray, v: FloatArray, a: FloatArray
                            ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """``(F, dF/dq, dF/dv, dF/da)`` with the fluid inertia (module doc), by the
        compiled inertial kernel over the samples; without inertia ``dF/da = 0``."""
        if not self.inertial:
            return super().force_and_jacobians(q, v, a)
        from rotorsfd.elements.sfd_kernel import sfd_inertial_batch  # deferred: numba

        q, v, a = np.broadcast_arrays(*(np.asarray(x, dtype=np.float64) for x in (q, v, a)))
        shape = q.shape[:-1]
        flat = [np.ascontiguousarray(x).reshape(-1, 2) for x in (q, v, a)]
        n = flat[0].shape[0]
        F, Jq, Jv, Ja = np.empty((n, 2)), np.empty((n, 2, 2)), np.empty((n, 2, 2)), \
            np.empty((n, 2, 2))
        bad = sfd_inertial_batch(*flat, self._params, F, Jq, Jv, Ja)
        if bad >= 0:
            raise self.contact_error(flat[0][bad], flat[1][bad])
        return (F.reshape((*shape, 2)), Jq.reshape((*shape, 2, 2)),
                Jv.reshape((*shape, 2, 2)), Ja.reshape((*shape, 2, 2)))

    @property
    def inertial_kernel(self):
        """:func:`rotorsfd.elements.sfd_kernel.sfd_inertial_kernel` when the fluid inertia
        is included, else None."""
        if not self.inertial:
            return None
        from rotorsfd.elements.sfd_kernel import sfd_inertial_kernel  # deferred: numba

        return sfd_inertial_kernel

    @property
    def kernel(self):
        """The compiled law, :func:`rotorsfd.elements.sfd_kernel.sfd_element_kernel` (finite
        film: :func:`rotorsfd.model.film_finite_kernels.finite_kernel`)."""
        if self.finite:
            from rotorsfd.model.film_finite_kernels import finite_kernel  # deferred: numba

            return finite_kernel
        from rotorsfd.elements.sfd_kernel import sfd_element_kernel  # deferred: numba

        return sfd_element_kernel

    @property
    def kernel_params(self) -> FloatArray:
        """``[mu, R, L, C, eps_max, film code, o_y, o_z, rho]`` (rho = 0 without the fluid
        inertia; finite film: the layout of
        :mod:`rotorsfd.model.film_finite_kernels`)."""
        return self._params.copy()

    def eccentricity(self, q: FloatArray) -> FloatArray:
        """``eps = |q - o| / C`` of samples ``q (..., 2)``."""
        q = np.asarray(q, dtype=float)
        return np.hypot(q[..., 0] - self.offset[0], q[..., 1] - self.offset[1]) \
            / self.film.clearance

    def limit(self, q: FloatArray) -> float:
        """The largest eccentricity ratio of the samples."""
        return float(np.max(self.eccentricity(q), initial=0.0))

    def diagnostics(self, q: FloatArray, v: FloatArray) -> dict[str, float]:
        """``eps_max``, the largest eccentricity ratio over the orbit, and the film's
        pressures and squeeze Reynolds number as :attr:`diagnostic_info` lists them
        (:func:`rotorsfd.model.film_diagnostics.film_diagnostics`)."""
        out = {"eps_max": self.limit(q)}
        if len(self.diagnostic_info) > 1:
            q = np.asarray(q, dtype=float).reshape(-1, 2)
            film = film_diagnostics(self.film, q - self.offset,
                                    np.asarray(v, dtype=float).reshape(-1, 2), self.density)
            out.update({k: film[k] for k in self.diagnostic_info if k in film})
        return out

    def contact_error(self, q: FloatArray, v: FloatArray, where: str = "") -> Exception:
        y, z = float(q[0] - self.offset[0]), float(q[1] - self.offset[1])
        return JournalContactError(math.hypot(y, z) / self.clearance, y, z, float(v[0]),
                                   float(v[1]), where=f"SFD {self.name!r}" + (
                                       f", {where}" if where else ""))

    # ---- the table's fields as continuation parameters ---------------------------------
    #: fields of the table a continuation may vary (those the table gives)
    parameters: ClassVar[tuple[str, ...]] = (
        "clearance_ratio", "clearance", "radius", "length", "length_to_diameter",
        "viscosity")

    def with_parameter(self, name: str, value: float) -> SFDElement:
        """The element of the same table with the field ``name`` set to ``value`` (SI),
        the table's other given fields held (C/R at fixed C moves R and, with L/D given,
        L: the paper's section 4.3)."""
        table = self._table(name)
        raw = table.model_dump(exclude_none=True) | {name: float(value)}
        return type(table).model_validate(raw).build(self.name)

    def dforce(self, q: FloatArray, v: FloatArray, name: str) -> FloatArray:
        """``dF/dp`` of a field ``p`` of the table, exact: the short film scales as
        ``F ~ mu R L^3`` and, from ``F(s q, s v; s C) = F / s^2`` (``q`` from the housing
        centre), ``dF/dC = -(2 F + dF/dq (q - o) + dF/dv v) / C``; the chain rule through
        the table's geometry (:meth:`SFDConfig.geometry_derivative`)."""
        table = self._table(name)
        if self.inertial:
            raise ConfigError(f"elements.{self.name}.{name}", None, "continuation in a "
                              "field of an SFD with fluid_inertia is not supported yet")
        if self.finite:
            raise ConfigError(f"elements.{self.name}.{name}", None, "continuation in a "
                              "field of the finite-length film is not supported yet "
                              "(film_length = 'short' only)")
        dR, dL, dC, dmu = table.geometry_derivative(name)
        q = np.asarray(q, dtype=np.float64)
        v = np.asarray(v, dtype=np.float64)
        F, Jq, Jv = self.force_and_jacobian(q, v)
        f = self.film
        dFdC = -(2.0 * F + np.einsum("...ij,...j->...i", Jq, q - self.offset)
                 + np.einsum("...ij,...j->...i", Jv, v)) / f.clearance
        return F * (dR / f.radius + 3.0 * dL / f.length + dmu / f.viscosity) + dFdC * dC

    def _table(self, name: str) -> SFDConfig:
        table = getattr(self, "table", None)
        if table is None or name not in self.parameters:
            return super().with_parameter(name, 0.0)   # raises: no such input
        if name != "viscosity" and getattr(table, name) is None:
            C, R, L = table.resolved_clearance, table.resolved_radius, table.resolved_length
            derived = {"clearance": C, "radius": R, "length": L, "clearance_ratio": C / R,
                       "length_to_diameter": L / (2 * R)}[name]
            raise ConfigError(f"elements.{self.name}.{name}", derived, "is derived from the "
                              "table's other fields: continue in a field the table gives ("
                              + ", ".join(n for n in self.parameters
                                          if getattr(table, n) is not None) + ")")
        return table

    def describe(self) -> str:
        length = "finite-length " if self.finite else ""
        return (f"SFD {self.name!r} at node {self.node} ({length}{self.film.cavitation} "
                f"film, C = {self.clearance:.4g} m)")


#: Ranges of the SFD ratios, also applied when a ratio is derived from the other fields.
SFD_RATIO_BOUNDS: dict[str, dict[str, float]] = {
    "clearance_ratio": {"gt": 0.0, "lt": 1.0},
    "length_to_diameter": {"gt": 0.0, "le": 10.0},
}


class SFDConfig(Section):
    """Short-bearing squeeze film damper at a node, with an optional centring spring and an
    optional static offset of the housing.

    Geometry: give the clearance C with C/R (radius derived, as in the paper, which varies
    C/R at fixed C) or with R, or R with C/R; and L or L/D.
    """

    kind: Literal["sfd"] = Field("sfd", description="element kind: 'sfd' (squeeze film "
                                 "damper)")
    node: NODE
    viscosity: quantity("viscosity", "oil dynamic viscosity mu", gt=0)
    clearance: quantity("length", "radial clearance C", gt=0, optional=True) = None
    clearance_ratio: quantity("ratio", "clearance ratio C/R", optional=True,
                              **SFD_RATIO_BOUNDS["clearance_ratio"]) = None
    radius: quantity("length", "journal radius R", gt=0, optional=True) = None
    length: quantity("length", "land length L", gt=0, optional=True) = None
    length_to_diameter: quantity("ratio", "land length to diameter L/D = L/(2R)",
                                 optional=True,
                                 **SFD_RATIO_BOUNDS["length_to_diameter"]) = None
    cavitation: Literal["pi", "none", "guembel"] = Field(
        "pi", description="film model: 'pi' (half-Sommerfeld, theta in [pi, 2pi]), "
                          "'none' (full 2pi film), 'guembel' (film where pressure > 0)")
    centring_stiffness: quantity("stiffness", "centring spring stiffness (isotropic, in "
                                 "parallel with the film)", ge=0) = 0.0
    centring_damping: quantity("damping", "centring spring damping (isotropic)", ge=0) = 0.0
    offset_y: quantity("length", "static offset of the housing centre from the centring "
                       "spring's neutral position, y") = 0.0
    offset_z: quantity("length", "static offset of the housing centre, z") = 0.0
    film_length: Literal["short", "finite"] = Field(
        "short", description="film model along the land: 'short' (short-bearing closed "
                             "forms, the paper's) or 'finite' (Reynolds equation on a "
                             "(theta, axial) grid, open or sealed ends)")
    end_flow: quantity("ratio", "end-flow coefficient of each end seal, beta = 6 mu L c_e "
                       "/ C^3 with c_e the seal's flow per unit circumference and "
                       "pressure (finite film only; omit for open ends, 0 for a sealed "
                       "land)", ge=0, optional=True) = None
    grid_theta: integer("theta nodes of the finite film's grid (a multiple of 4)", ge=16,
                        le=1024) = 48
    grid_axial: integer("axial intervals of the finite film's half land (even)", ge=2,
                        le=64) = 4
    film_table: bool = Field(
        True, description="finite film: tabulate it over eps when built (256 nodes, cubic "
                          "Hermite, its error against the grid solver measured) instead "
                          "of solving the grid at every sample")
    density: quantity("density", "oil density rho (for the squeeze Reynolds number "
                      "rho omega C^2 / mu in the results, and the fluid inertia force "
                      "with fluid_inertia = true)", gt=0, optional=True) = None
    fluid_inertia: bool = Field(
        False, description="add the fluid inertia force of the short open-ended film (San "
                           "Andres' averaged inertia, temporal and convective; needs "
                           "density; short film only): an added mass pi rho R L^3/(24 C) "
                           "per direction at the centre for the pi film")
    film_report: bool | None = Field(
        None, description="report the peak film pressure p_max, the lowest uncavitated "
                          "pressure p_min and the cavitated arc per orbit in the results "
                          "(default: true for the finite film, false for the short film)")

    @model_validator(mode="after")
    def _geometry(self):
        given = given_fields(self, ("clearance", "clearance_ratio", "radius"))
        if len(given) != 2:
            # one of the three is given too many or too few: the field is the table
            raise fail((), and_list(given) or "none of them",
                       "give exactly two of clearance, clearance_ratio, radius (the "
                       "third is derived)")
        if (self.length is None) == (self.length_to_diameter is None):
            raise fail((), "length and length_to_diameter" if self.length is not None
                       else "neither length nor length_to_diameter",
                       "give exactly one of length, length_to_diameter")
        if self.resolved_clearance >= self.resolved_radius:
            raise fail("clearance", self.clearance,
                       f"gives C = {self.resolved_clearance:.6g} m >= R = "
                       f"{self.resolved_radius:.6g} m; the clearance must be smaller "
                       "than the journal radius")
        self._derivedin_range()
        self._film_fields()
        if self.fluid_inertia and self.density is None:
            raise fail("fluid_inertia", True, "needs the oil density: give density "
                       "(e.g. density = \"850 kg/m^3\")")
        if self.fluid_inertia and self.film_length == "finite":
            raise fail("fluid_inertia", True, "is implemented for film_length = 'short' "
                       "only")
        return self

    def _film_fields(self) -> None:
        """The finite film's fields: only with ``film_length = "finite"``, grid sizes
        the scheme takes."""
        if self.film_length == "short":
            for name in ("end_flow", "grid_theta", "grid_axial", "film_table"):
                if getattr(self, name) != type(self).model_fields[name].default:
                    raise fail(name, getattr(self, name),
                               "is a field of the finite film: set film_length = "
                               "\"finite\" or remove it")
        if self.grid_theta % 4:
            raise fail("grid_theta", self.grid_theta, "must be a multiple of 4")
        if self.grid_axial % 2:
            raise fail("grid_axial", self.grid_axial, "must be even")

    def _derivedin_range(self) -> None:
        """A derived value (the third of C, C/R, R; L or L/D) within the range its own
        field would have: ``length = "3 furlongs"`` must not pass with L/D = 11524."""
        derived = {"clearance_ratio": self.resolved_clearance / self.resolved_radius,
                   "length_to_diameter": self.resolved_length / (2.0 * self.resolved_radius)}
        for name, value in derived.items():
            if getattr(self, name) is not None:
                continue
            bounds = SFD_RATIO_BOUNDS[name]
            if not in_range(value, *(bounds.get(k) for k in ("gt", "ge", "lt", "le"))):
                given = "length" if name == "length_to_diameter" else given_fields(
                    self, ("clearance", "radius"))[-1]
                symbol = "L/D = L / (2R)" if name == "length_to_diameter" else "C/R"
                raise fail(given, getattr(self, given),
                           f"gives {symbol} = {value:.6g} (R = {self.resolved_radius:.6g} m); "
                           f"{name} must be {range_text('1', **bounds)}")

    @property
    def resolved_clearance(self) -> float:
        """C [m]."""
        if self.clearance is not None:
            return self.clearance
        return self.clearance_ratio * self.radius

    @property
    def resolved_radius(self) -> float:
        """R [m], given or C / (C/R)."""
        if self.radius is not None:
            return self.radius
        return self.clearance / self.clearance_ratio

    @property
    def resolved_length(self) -> float:
        """L [m], given or (L/D) * 2R."""
        if self.length is not None:
            return self.length
        return self.length_to_diameter * 2.0 * self.resolved_radius

    @property
    def nodes(self) -> tuple[int, ...]:
        """The rotor nodes the element sits at."""
        return (self.node,)

    def derived_text(self) -> str:
        """The derived geometry, for ``config show`` and ``config check``."""
        c, r, length = self.resolved_clearance, self.resolved_radius, self.resolved_length
        text = (f"C = {c:.6g} m, R = {r:.6g} m, L = {length:.6g} m, C/R = {c / r:.6g}, "
                f"L/D = {length / (2 * r):.6g}")
        if self.film_length == "finite":
            ends = "open ends" if self.end_flow is None else f"end_flow = {self.end_flow:g}"
            text += (f"; finite film, {ends}, grid {self.grid_theta} x {self.grid_axial} "
                     "(theta x half land)" + (", tabulated over eps" if self.film_table
                                              else ""))
        return text

    def linear_supports(self) -> list[LinearSupport]:
        """The centring spring: an isotropic linear support at the SFD node (none if it has
        neither stiffness nor damping)."""
        if self.centring_stiffness > 0 or self.centring_damping > 0:
            return [LinearSupport.isotropic(self.node, self.centring_stiffness,
                                            self.centring_damping)]
        return []

    def build(self, name: str) -> SFDElement:
        """The element of this table, named ``name``."""
        geometry = (self.viscosity, self.resolved_radius, self.resolved_length,
                    self.resolved_clearance)
        if self.film_length == "finite":
            # deferred: model.film_finite (loads 2 more rotorsfd modules, needed only here)
            from rotorsfd.model.film_finite import FiniteSFD

            film = FiniteSFD(*geometry, cavitation=self.cavitation,
                             end_flow=math.inf if self.end_flow is None else self.end_flow,
                             n_theta=self.grid_theta, n_axial=self.grid_axial,
                             table=self.film_table)
        else:
            from rotorsfd.model.sfd import SFD  # deferred: numba (the film's kernels)

            film = SFD(*geometry, cavitation=self.cavitation)
        element = SFDElement(name, self.node, film, (self.offset_y, self.offset_z),
                             density=self.density, film_report=self.film_report,
                             fluid_inertia=self.fluid_inertia)
        element.table = self   # its fields as continuation parameters
        return element

    def geometry_derivative(self, field: str) -> tuple[float, float, float, float]:
        """``d(R, L, C, mu)/d(field)`` with the table's other given fields held: C/R at fixed
        C gives ``R = C / (C/R)``, L/D gives ``L = (L/D) 2 R``, and so on."""
        if field == "viscosity":
            return 0.0, 0.0, 0.0, 1.0
        C, R = self.resolved_clearance, self.resolved_radius
        given = set(given_fields(self, ("clearance", "clearance_ratio", "radius")))
        dC = dR = 0.0
        if given == {"clearance", "clearance_ratio"}:        # R = C / cr
            if field == "clearance":
                dC, dR = 1.0, R / C
            elif field == "clearance_ratio":
                dR = -R / self.clearance_ratio
        elif given == {"clearance", "radius"}:
            dC, dR = (float(field == "clearance"), float(field == "radius"))
        else:                                                 # C = cr R
            if field == "clearance_ratio":
                dC = R
            elif field == "radius":
                dC, dR = C / R, 1.0
        if self.length is not None:
            dL = float(field == "length")
        else:
            dL = 2.0 * self.length_to_diameter * dR + (
                2.0 * R if field == "length_to_diameter" else 0.0)
        return dR, dL, dC, 0.0


register(SFDConfig)
