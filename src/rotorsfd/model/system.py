"""The rotor with its nonlinear elements on a moving base, assembled into the solvers' inputs.

    M q'' + (C + Omega G + C_base) q' + (K + K_base) q = F_mu(t) + F_base + F_nl(q_n, q_n')

(paper eq. 1) with the linear rotor (shaft, disks, supports, the linear parts of the
elements such as an SFD's centring spring), the nonlinear elements acting on their DOFs
``q_n`` (:class:`~rotorsfd.elements.ElementSet`: squeeze films, rubs, ...), the unbalances
and the base motion (with gravity). This module is the only place where the
physics meets the solvers: it hands time stepping, Lyapunov and Floquet the
:class:`~rotorsfd.second_order.SecondOrderSystem` at a speed (:meth:`second_order`), the
harmonic-balance solver the same equation as a family in a continuation parameter, a
:class:`~rotorsfd.harmonic.problem.PeriodicProblem` (:meth:`periodic_problem`), and the
linear analyses the ``LinearDynamics`` protocol (``n_dof``, ``matrices(speed)``).
"""

from __future__ import annotations

import functools
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp

from rotorsfd.elements.base import NonlinearElement
from rotorsfd.elements.composite import ElementSet
from rotorsfd.errors import ConfigError
from rotorsfd.harmonic.fold_curve import TwoParameterProblem
from rotorsfd.harmonic.problem import NonlinearLaw, PeriodicProblem
from rotorsfd.model.base_motion import BaseMotion, BaseState, Constant
from rotorsfd.model.base_polynomial import PolynomialTerms, StoredTerms
from rotorsfd.model.base_terms import (
    BaseBasis,
    BaseCoefficients,
    base_basis,
    base_coefficient_derivatives,
    base_coefficients,
    base_rate_derivative,
)
from rotorsfd.model.multishaft_loads import check_one_frequency
from rotorsfd.model.parameters import PARAMETERS, find_parameter
from rotorsfd.model.rotor import Rotor
from rotorsfd.model.time_terms import second_order_system
from rotorsfd.model.unbalance import (
    Unbalance,
    unbalance_harmonics,
    unbalance_harmonics_derivatives,
)
from rotorsfd.second_order import SecondOrderSystem


@dataclass
class RotorSystem:
    """Linear rotor + nonlinear elements + unbalances + base motion.

    ``rotor`` already carries the elements' linear parts (an SFD's centring spring is a
    linear support at its node). ``elements``: an :class:`ElementSet` or a sequence of
    elements. ``base`` None means a fixed base without gravity.
    """

    rotor: Rotor
    elements: ElementSet | Sequence[NonlinearElement] = ()
    unbalances: Sequence[Unbalance] = ()
    base: BaseMotion = field(default_factory=BaseMotion)
    _basis: BaseBasis | None = field(default=None, init=False, repr=False)
    _speed_terms: tuple | None = field(default=None, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        self.unbalances = tuple(self.unbalances)
        if self.base is None:
            self.base = BaseMotion()
        if not isinstance(self.elements, ElementSet):
            self.elements = ElementSet(self.elements)
        for e in self.elements:
            if any(not 1 <= node <= self.rotor.n_nodes for node in e.nodes) or (
                    e.m and int(e.dofs.max()) >= self.n_dof):
                raise ConfigError(f"elements.{e.name}.node", e.nodes,
                                  f"must be a node of the rotor, 1..{self.rotor.n_nodes}")
        for u in self.unbalances:
            if u.node > self.rotor.n_nodes:
                raise ConfigError("unbalance.node", u.node,
                                  f"must be a node of the rotor, 1..{self.rotor.n_nodes}")

    # ---- structure ---------------------------------------------------------------------
    @property
    def n_dof(self) -> int:
        return self.rotor.n_dof

    @property
    def nl_dofs(self) -> np.ndarray:
        """Global indices of the DOFs the nonlinear elements act on (their union)."""
        return self.elements.nl_dofs

    @property
    def length_scale(self) -> float | None:
        """The smallest length scale of the elements (a clearance) [m]: displacements in
        results and plots are shown in it; None without elements."""
        return self.elements.scale

    @property
    def output_nodes(self) -> tuple[int, ...]:
        """The nodes results show by default: the disks' and the elements' (node 1 if
        neither)."""
        nodes = {d.node for d in self.rotor.disks} | set(self.element_nodes)
        return tuple(sorted(nodes)) or (1,)

    @property
    def primary_node(self) -> int | None:
        """The node of the first element (the one shown in the clearance unit C by default
        and checked first); None without elements."""
        nodes = self.element_nodes
        return nodes[0] if nodes else None

    @property
    def element_nodes(self) -> list[int]:
        """The nodes the elements sit at, in the elements' order, each once."""
        out: list[int] = []
        for e in self.elements:
            out += [n for n in e.nodes if n not in out]
        return out

    @property
    def basis(self) -> BaseBasis:
        """Constant base-motion basis of the rotor (built once, on first use)."""
        if self._basis is None:
            self._basis = base_basis(self.rotor)
        return self._basis

    def constant_base_state(self) -> BaseState:
        """The base state of a time-invariant base motion (harmonic balance, modal, statics).

        ConfigError if the base motion varies in time.
        """
        if not self.base.is_constant:
            field, value = _time_varying(self.base)
            raise ConfigError(field, value, "this analysis needs a base motion constant in "
                              "time ('off' or 'constant' laws); for harmonic or callable "
                              "laws use `rotorsfd simulate` or `rotorsfd stability-chart`")
        return self.base.state(0.0)

    # ---- LinearDynamics ----------------------------------------------------------------
    def linear_terms(self, parameter: str = "speed", speed: float | None = None,
                     state: BaseState | None = None) -> PolynomialTerms:
        """The linear part as polynomials in a continuation parameter (assembled once):
        damping ``C + Omega G + C_base``, stiffness ``K + K_base`` and load ``F_base``
        (film off, no unbalance) in the speed, or in a constant base rate
        (``base.rolling|pitching|yawing``) at the fixed ``speed``; ``state`` (default: the
        constant base state) with the parameter's own value ignored (in a rate, its
        origin acceleration follows it: a0 = v0' + w x v0, so a0 must be that of the
        state's own rates, as ``BaseMotion.state`` gives). See
        :class:`~rotorsfd.model.base_polynomial.PolynomialTerms`."""
        st = self.constant_base_state() if state is None else state
        r = self.rotor
        par = find_parameter(parameter)
        lowrank = getattr(r, "damping_lowrank", None)  # modal damping of a few modes
        C = r.C_csr if lowrank is None else r.C_band_csr
        if par.kind == "speed":
            if self.base.is_fixed and state is None:
                return PolynomialTerms(self.n_dof, D=(C, r.G_csr), K=(r.K_csr,),
                                       lowrank=lowrank)
            return PolynomialTerms.of_base(self.basis, st, 0.0, "speed").plus(
                D=(C, r.G_csr), K=(r.K_csr,), lowrank=lowrank)
        if par.kind != "base_rate":
            raise ConfigError("parameter", parameter,
                              "linear terms are polynomial in the speed or a base rate")
        om = float(speed)
        return PolynomialTerms.of_base(self.basis, st, om, par.rate_name).plus(
            D=(C + om * r.G_csr,), K=(r.K_csr,), lowrank=lowrank)

    def _speed_polynomial(self) -> PolynomialTerms:
        """linear_terms("speed") of the current base state, cached by that state."""
        st = self.constant_base_state()
        key = b"".join(np.asarray(v, dtype=float).tobytes()
                       for v in (st.w, st.dw, st.a_eff)) + bytes([self.base.is_fixed])
        key += id(self.rotor).to_bytes(8, "little")
        if self._speed_terms is None or self._speed_terms[0] != key:
            self._speed_terms = (key, self.linear_terms("speed"))
        return self._speed_terms[1]

    def _base_terms(self, state: BaseState, speed: float
                    ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(C_base, K_base, F_base) by the direct combination of the basis (reference)."""
        if self.base.is_fixed:
            n = self.n_dof
            return np.zeros((n, n)), np.zeros((n, n)), np.zeros(n)
        return self.basis.combine(base_coefficients(state, speed))

    def matrices(self, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(M, C + speed G + C_base, K + K_base) under the constant base motion, film off
        (read-only: a matrix free of the speed is the same array at every call)."""
        lin = self._speed_polynomial()
        return self.rotor.M, lin.damping(speed), lin.stiffness(speed)

    def sparse_matrices(self, speed: float) -> tuple[sp.csr_matrix, sp.csr_matrix,
                                                      sp.csr_matrix]:
        """:meth:`matrices` as CSR (scipy.sparse), without a dense n x n array."""
        lin = self._speed_polynomial()
        return self.rotor.M_csr, lin.sparse_damping(speed), lin.sparse_stiffness(speed)

    def split_matrices(self, speed: float) -> tuple[sp.csr_matrix, Any, sp.csr_matrix]:
        """:meth:`matrices` without a dense n x n array: CSR, the damping a
        :class:`~rotorsfd.model.lowrank.BandedLowRank` (CSR + ``U diag(c) U^T``) when the
        rotor has modal damping of a few modes (``rotor.damping.modes``)."""
        lin = self._speed_polynomial()
        return self.rotor.M_csr, lin.split_damping(speed), lin.sparse_stiffness(speed)

    def static_force(self, speed: float) -> np.ndarray:
        """Constant load F_base (base acceleration, gravity, gyroscopic moments) [N, N m]."""
        return self._speed_polynomial().load(speed).copy()

    def unbalance_harmonics(self, speed: float) -> tuple[np.ndarray, np.ndarray]:
        """(F_c, F_s): F_mu = F_c cos(Omega t) + F_s sin(Omega t) (paper eq. 5-6)."""
        return unbalance_harmonics(self.unbalances, self.rotor, speed,
                                   self.constant_base_state())

    # ---- harmonic balance --------------------------------------------------------------
    def periodic_problem(self, parameter: str = "speed", speed: float | None = None,
                         assembly: str = "polynomial", stored: StoredTerms | None = None
                         ) -> PeriodicProblem:
        """The HB problem with continuation parameter ``parameter`` (see PARAMETERS).

        For parameters other than the speed, ``speed`` fixes the rotor speed. Every
        derivative with respect to the parameter is exact.

        ``assembly="polynomial"`` (default): the linear part (damping, stiffness, base
        load) is assembled once as a polynomial in the parameter (:meth:`linear_terms`;
        affine in the speed, quadratic in a base rate) and evaluated per call with a
        scaled add or two; parameter-free matrices are the same objects at every call.
        ``"direct"``: the base terms recombined from the basis at every call (the
        reference, for tests and benchmarks); equal to round-off.

        ``stored``: this rotor's matrices and base patterns stored once in band storage
        or dense (:class:`~rotorsfd.model.base_polynomial.StoredTerms`, e.g. shared by the
        problems of :meth:`two_parameter_problem`): the polynomial linear part summed
        from them, the same numbers without the sparse sums and conversions (ignored for
        another rotor, and where nothing is stored).
        """
        return self._periodic_problem(parameter, speed, assembly, stored)

    def _periodic_problem(self, parameter: str, speed: float | None, assembly: str,
                          stored: StoredTerms | None, state0: BaseState | None = None
                          ) -> PeriodicProblem:
        """:meth:`periodic_problem` with ``state0`` the constant base state if known
        (that of this system's base: a two-parameter family builds it once)."""
        if assembly not in ("polynomial", "direct"):
            raise ConfigError("assembly", assembly, "must be 'polynomial' or 'direct'")
        if not len(self.elements):
            raise ConfigError("elements", None, "the nonlinear response needs at least one "
                              "nonlinear element (an [elements.<name>] table)")
        check_one_frequency(self.rotor, self.unbalances, "the harmonic balance")  # 2 spools
        par = find_parameter(parameter)
        if par.kind != "speed" and (speed is None or speed <= 0):
            raise ConfigError("speed", speed,
                              f"continuing in {parameter} needs a fixed speed > 0 [rad/s]")
        if state0 is None:
            state0 = self.constant_base_state()
        if par.kind == "base_rate":
            self._check_base_rate(par)
        r = self.rotor
        fixed_base = self.base.is_fixed and par.kind != "base_rate"
        U_ref = self.unbalances[0].magnitude if self.unbalances else 0.0
        if par.kind == "unbalance" and U_ref == 0.0:
            raise ConfigError("unbalance", None,
                              "continuing in the unbalance needs a nonzero first unbalance")

        def at(lam: float) -> tuple[float, BaseState, float]:
            """(speed, base state, unbalance scale) at parameter value lam."""
            if par.kind == "speed":
                return lam, state0, 1.0
            if par.kind == "element":
                return float(speed), state0, 1.0
            if par.kind == "base_rate":   # a0 = v0' + w x v0 follows the rate
                return float(speed), state0.with_rate(par.axis, lam), 1.0
            return float(speed), state0, lam / U_ref

        def coefficient_derivative(om: float, st: BaseState) -> BaseCoefficients:
            if par.kind == "speed":
                return base_coefficient_derivatives(st, om)["speed"]
            if par.kind == "base_rate":   # with d a0 / d w_i = e_i x v0
                return base_rate_derivative(st, om, par.rate_name)
            return BaseCoefficients(np.zeros(12), np.zeros(12), np.zeros(8))

        if assembly == "polynomial":
            frozen = par.kind in ("unbalance", "element")  # the linear part is free of lam
            summed = None
            if stored is not None and stored.rotor is r:
                summed = stored.linear_part(
                    par.rate_name if par.kind == "base_rate" else "speed",
                    None if fixed_base else state0,
                    float(speed) if par.kind != "speed" else 0.0,
                    float(speed) if frozen else None)
            if summed is not None:
                matrices, lin = summed
            else:
                if par.kind == "base_rate":
                    lin = self.linear_terms(par.name, speed, state0)
                else:
                    lin = self.linear_terms("speed", state=None if fixed_base else state0)
                if frozen:
                    lin = lin.constant(float(speed))
                # band storage of (M, D, K): the condensation reads it directly; dense
                # arrays for the other callers are built on request (dense storage for a
                # wide band)
                matrices = lin.linear_part(r.M_csr)
            dmatrices = matrices.derivatives

            def base_load(lam: float) -> np.ndarray:
                return lin.load(lam)

            def dbase_load(lam: float) -> np.ndarray:
                return lin.dload(lam)
        else:
            def matrices(lam: float):
                om, st, _ = at(lam)
                if fixed_base:
                    return r.M, r.C + om * r.G, r.K
                C_b, K_b, _ = self.basis.combine(base_coefficients(st, om))
                return r.M, r.C + om * r.G + C_b, r.K + K_b

            def dmatrices(lam: float):
                om, st, _ = at(lam)
                zero = np.zeros_like(r.M)
                dG = r.G if par.kind == "speed" else zero
                if fixed_base:
                    return zero, dG, zero
                dC_b, dK_b, _ = self.basis.combine(coefficient_derivative(om, st))
                return zero, dG + dC_b, dK_b

            def base_load(lam: float) -> np.ndarray:
                om, st, _ = at(lam)
                return self.basis.combine(base_coefficients(st, om))[2]

            def dbase_load(lam: float) -> np.ndarray:
                om, st, _ = at(lam)
                return self.basis.combine(coefficient_derivative(om, st))[2]

        def forcing(lam: float, H: int) -> np.ndarray:
            om, st, scale = at(lam)
            F = np.zeros((H + 1, self.n_dof), dtype=complex)
            if not fixed_base:
                F[0] = base_load(lam)
            if H >= 1 and self.unbalances:
                Fc, Fs = unbalance_harmonics(self.unbalances, r, om, st)
                F[1] = scale * (Fc - 1j * Fs)
            return F

        def dforcing(lam: float, H: int) -> np.ndarray:
            om, st, scale = at(lam)
            dF = np.zeros((H + 1, self.n_dof), dtype=complex)
            if not fixed_base:
                dF[0] = dbase_load(lam)
            if H >= 1 and self.unbalances and par.kind != "element":
                if par.kind == "unbalance":
                    Fc, Fs = unbalance_harmonics(self.unbalances, r, om, st)
                    dF[1] = (Fc - 1j * Fs) / U_ref
                else:
                    key = "speed" if par.kind == "speed" else par.rate_name
                    dFc, dFs = unbalance_harmonics_derivatives(self.unbalances, r, om, st,
                                                                 only=key)[key]
                    dF[1] = scale * (dFc - 1j * dFs)
            return dF

        def frequency(lam: float) -> float:
            return float(lam) if par.kind == "speed" else float(speed)

        def dfrequency(lam: float) -> float:
            return 1.0 if par.kind == "speed" else 0.0

        el = self.elements
        limited = any(e.limit_label is not None for e in el)
        nl_at = None
        if par.kind == "element":   # the element's law at each lam, with dF/dlam
            el = el.at_speed(float(speed))
            self._check_element_parameter(par)
            nl_at = functools.partial(_law_at, el, par.field, par.element)
        elif par.kind != "speed":
            el = el.at_speed(float(speed))
        elif el.depends_on("speed"):   # a law of the speed itself: the law at each lam
            nl_at = functools.partial(_law_at, el, "speed", None)
            el = el.at_speed(float("nan"))   # the fixed fields must not be used
        return PeriodicProblem(
            n_dof=self.n_dof, nl_dofs=self.nl_dofs, matrices=matrices, dmatrices=dmatrices,
            forcing=forcing, dforcing=dforcing, frequency=frequency, dfrequency=dfrequency,
            nl_force=el.force, nl_jacobian=el.jacobian, nl_force_jacobian=el.force_and_jacobian,
            nl_kernel=el.kernel, nl_kernel_params=el.kernel_params, scaling=self.dof_scale(),
            nl_limit=el.limit if limited else None,
            name=f"rotor response in {parameter}", nl_at=nl_at,
            nl_force_jacobians=el.force_and_jacobians if el.inertial else None,
            nl_inertial_kernel=el.inertial_kernel,
            frequency_line=(0.0, 1.0) if par.kind == "speed" else (float(speed), 0.0))

    def _check_element_parameter(self, par) -> None:
        """ConfigError unless the element of an ``"element"`` parameter exists and has the
        field as an input."""
        names = [e.name for e in self.elements]
        if par.element not in names:
            raise ConfigError("parameter", par.name, "names no element; the elements are "
                              + ", ".join(names))
        e = self.elements[par.element]
        if par.field not in e.parameters:
            raise ConfigError("parameter", par.name, f"{e.describe()} has no field "
                              f"{par.field!r} to continue in (it has: "
                              + (", ".join(e.parameters) or "none") + ")")

    def _check_base_rate(self, par) -> None:
        """ConfigError unless the base stays constant in time at every value of the base
        rate ``par`` (the rest of the base motion held; the base's own state is constant).

        Inertial gravity is constant in the base frame only while w is parallel to it
        (dg/dt = -w x g in base components, :mod:`~rotorsfd.model.gravity`): at a
        constant w off its axis g(t) turns about w with period 2 pi / |w|, a load and
        (through a_eff) no periodic response at the speed alone. With w parallel to g at
        the start, w = w_start + (lam - w_start_i) e_i stays parallel to g for every lam
        only if e_i is: any rate about another axis is refused, unless gravity is fixed
        to the base. A uniform acceleration of the origin makes a0 = v0' + w x v0 grow
        in time once the base rotates (``BaseMotion.is_constant``): refused too."""
        base, axis = self.base, par.axis
        now = float(base.rates(0.0)[axis])
        g = base.gravity
        if (g is not None and g.enabled and g.frame == "inertial"
                and np.any(np.cross(np.eye(3)[axis], g.vector) != 0.0)):
            along = [p.name for p in PARAMETERS.values() if p.kind == "base_rate"
                     and not np.any(np.cross(np.eye(3)[p.axis], g.vector) != 0.0)]
            raise ConfigError("parameter", par.name, (
                f"a rate about {'xyz'[axis]} other than its value here ({now:g} rad/s) "
                "turns the base off inertial gravity g = "
                f"({', '.join(f'{v:g}' for v in g.vector)}) m/s^2, which then rotates in "
                "the base frame (dg/dt = -w x g): no periodic response; continue a rate "
                "about the gravity axis only ("
                + (", ".join(along) or "gravity is along no base axis")
                + "), or fix gravity to the base (gravity.frame = 'base')"))
        for name, law in zip(("x", "y", "z"), base.translation, strict=True):
            if law.kind == "uniform_acceleration" and law.acceleration != 0.0:
                raise ConfigError("parameter", par.name, (
                    f"a rate about {'xyz'[axis]} other than its value here ({now:g} rad/s) "
                    f"with the uniform acceleration of base.{name} makes the origin "
                    "acceleration a0 = v0' + w x v0 grow in time: no periodic response; "
                    "continue a base rate with translations of constant velocity only"))

    # ---- the solvers' record ---------------------------------------------------------------
    def second_order(self, speed: float, *, horizon: float | None = None
                     ) -> SecondOrderSystem:
        """The system at rotor speed ``speed`` [rad/s] as the solvers' record
        (:class:`~rotorsfd.second_order.SecondOrderSystem`: M, D, K, the time-varying base
        terms as bases x coefficients, the forcing and the elements' force law at that
        speed), what time stepping, Lyapunov and Floquet take
        (:func:`~rotorsfd.model.time_terms.second_order_system`; ``horizon`` [s]: the
        interval on which a base coefficient must be constant to be folded into D, K)."""
        return second_order_system(self, speed, horizon=horizon)

    def elements_at(self, speed: float) -> ElementSet:
        """The nonlinear elements at rotor speed ``speed`` [rad/s] (a journal bearing's law
        depends on it): what a run at one speed must use."""
        return self.elements.at_speed(float(speed))

    def dof_scale(self) -> np.ndarray:
        """Per-DOF scale: the elements' length scale c (the smallest clearance; 1e-4 m
        without elements) for displacements, c / rotor length for rotations, so that a
        tolerance on scaled unknowns means the same in any units."""
        c = self.length_scale or 1e-4
        length = float(np.ptp(self.rotor.node_x))   # the axial extent (several shafts too)
        scale = np.full(self.n_dof, c)
        scale[2::4] = scale[3::4] = c / length
        return scale

    def with_base_rate(self, parameter: str, value: float) -> RotorSystem:
        """A copy with the constant base rate ``parameter`` (base.rolling|pitching|yawing)
        set to ``value`` [rad/s]."""
        laws = list(self.base.rotation)
        laws[find_parameter(parameter).axis] = Constant(value)
        base = BaseMotion(*self.base.translation, *laws, gravity=self.base.gravity)
        return RotorSystem(self.rotor, self.elements, self.unbalances, base)


    def with_parameter(self, parameter: str, value: float) -> RotorSystem:
        """A copy with a continuation parameter (not the speed) set: a constant base rate
        [rad/s], or the first unbalance's magnitude [kg m] (the others scaled with it, as
        in :meth:`periodic_problem`). The copy shares the base-motion basis."""
        par = find_parameter(parameter)
        if par.kind == "element":
            self._check_element_parameter(par)
            out = RotorSystem(self.rotor, self.elements.with_parameter(
                par.field, value, element=par.element), self.unbalances, self.base)
        elif par.kind == "base_rate":
            out = self.with_base_rate(par.name, value)
        elif par.kind == "unbalance":
            if not self.unbalances or self.unbalances[0].magnitude == 0.0:
                raise ConfigError("unbalance", None,
                                  "continuing in the unbalance needs a nonzero first unbalance")
            scale = value / self.unbalances[0].magnitude
            ub = [Unbalance(u.node, u.magnitude * scale, u.phase) for u in self.unbalances]
            out = RotorSystem(self.rotor, self.elements, ub, self.base)
        else:
            raise ConfigError("parameter", parameter, "must be one of " + ", ".join(
                p for p in PARAMETERS if PARAMETERS[p].kind != "speed"))
        out._basis = self._basis
        return out

    def two_parameter_problem(self, second: str):
        """The HB problem in (speed, ``second``) as a
        :class:`~rotorsfd.harmonic.fold_curve.TwoParameterProblem`: ``first(value)`` is
        ``periodic_problem("speed")`` of :meth:`with_parameter` (second = value), and
        ``second(speed)`` is ``periodic_problem(second, speed)``; both exact in their
        parameter, so ``dR/dspeed`` and ``dR/dsecond`` are exact at every (speed, value).
        The problems are built from the rotor's terms stored once here
        (:class:`~rotorsfd.model.base_polynomial.StoredTerms`): the same numbers as built
        from scratch, at a fraction of the cost (the fold-curve Newton builds two per
        evaluation)."""
        state0 = self.constant_base_state()
        par = find_parameter(second)
        if par.kind == "speed":
            raise ConfigError("parameter", second, "must be one of " + ", ".join(
                p for p in PARAMETERS if PARAMETERS[p].kind != "speed")
                + ", elements.<name>.<field>")
        if par.kind == "base_rate":
            self._check_base_rate(par)
        moving = par.kind == "base_rate" or not self.base.is_fixed
        # the rotor's matrices and base patterns stored once (band storage, or dense for a
        # full modal damping), for every problem of the family (the basis built once,
        # shared by every copy)
        stored = StoredTerms(self.rotor, self.basis if moving else None)

        # the base state once: this system's, and its copies' but in a base rate (their
        # base is this one)
        copy_state = None if par.kind == "base_rate" else state0

        def first(value: float) -> PeriodicProblem:
            return self.with_parameter(second, value)._periodic_problem(
                "speed", None, "polynomial", stored, copy_state)

        def across(speed: float) -> PeriodicProblem:
            return self._periodic_problem(second, speed, "polynomial", stored, state0)

        return TwoParameterProblem(first, across, ("speed", second))


def _law_at(elements: ElementSet, name: str, element: str | None, value: float
            ) -> NonlinearLaw:
    """The elements' force law with their input ``name`` (``"speed"``, or a field of the
    element named ``element``) at ``value``, with ``dF/dvalue``."""
    el = elements.with_parameter(name, float(value), element=element)
    return NonlinearLaw(el.force, el.jacobian, el.force_and_jacobian, el.kernel_params,
                        functools.partial(el.dforce, name=name, element=element),
                        el.force_and_jacobians if el.inertial else None)


def _time_varying(base: BaseMotion) -> tuple[str, str]:
    """(config field, its value) of the first base-motion setting that makes the base
    state vary in time (see ``BaseMotion.is_constant``)."""
    for name, law in zip(("rolling", "pitching", "yawing"), base.rotation, strict=True):
        if not law.is_constant:
            return f"base.{name}.law", law.kind
    rotating = bool(np.any(base.rates(0.0) != 0.0))
    for name, law in zip(("x", "y", "z"), base.translation, strict=True):
        if law.kind == "uniform_acceleration":
            if rotating and law.acceleration != 0.0:
                return f"base.{name}.law", law.kind
        elif not law.is_constant:
            return f"base.{name}.law", law.kind
    return "gravity.frame", "inertial"
