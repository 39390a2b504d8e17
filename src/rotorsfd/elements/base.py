"""The interface of a nonlinear element: a local force on a few DOFs of the rotor.

An element acts on the DOFs ``dofs`` (global indices, ``m`` of them) and gives

    F = f(q_e, v_e),   q_e = q[dofs],  v_e = q'[dofs]

with its exact Jacobians ``dF/dq_e`` and ``dF/dv_e`` in two forms that must agree: numpy,
vectorised over samples (:meth:`NonlinearElement.force_and_jacobian`, the reference and
the form of the Python paths), and a compiled kernel of the contract of
:mod:`rotorsfd.kernels` with its parameter vector (the form of every compiled loop: HB-AFT,
the condensation, time stepping). A law that depends on the acceleration too (a film's
fluid inertia) says so with :attr:`NonlinearElement.inertial` and gives
``F = f(q_e, v_e, a_e)`` with ``dF/da_e`` (an added mass on its DOFs) by
:meth:`NonlinearElement.force_and_jacobians` and :attr:`NonlinearElement.inertial_kernel`;
the solvers take that path only when an element is inertial. An element may have a
validity limit (a film's eccentricity ratio, which must stay below 1; a contact law has
none), a length scale for the Newton test and the plots, and per-orbit diagnostics for the
results files.

A new kind is two modules: ``<kind>.py`` with a subclass of :class:`NonlinearElement`, its
config model and one :func:`rotorsfd.elements.registry.register` call (no numba), and
``<kind>_kernel.py`` with its compiled law (``docs/elements.md``). The solvers only ever see the
composite of all elements (:class:`rotorsfd.elements.composite.ElementSet`).
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from typing import Any, ClassVar

import numpy as np
from numpy.typing import NDArray

from rotorsfd.errors import ElementDomainError

FloatArray = NDArray[np.float64]


class NonlinearElement(ABC):
    """A nonlinear force on the DOFs ``dofs`` of the rotor.

    Attributes
    ----------
    kind : the registered kind name (``"sfd"``, ``"rub"``, ...).
    name : the element's name in the config and in results (``eps_<name>``).
    dofs : (m,) int64 global DOF indices, in the order of the force components.
    nodes : the rotor nodes the element sits at (1-based), for results and plots.
    scale : length scale [m] of the element's displacements (a clearance): Newton tests
        and plots measure displacements in it.
    limit_label : name of the validity measure (``"eps"``), None if the element has none.
    """

    kind: ClassVar[str]
    limit_label: ClassVar[str | None] = None
    #: inputs of the law that are not states and that an analysis may set or vary
    #: (``"speed"``: the rotor speed of a journal bearing), see :meth:`with_parameter`
    parameters: ClassVar[tuple[str, ...]] = ()
    #: key of :meth:`diagnostics` -> (long name, SI unit), for the results files
    diagnostic_info: ClassVar[dict[str, tuple[str, str]]] = {}
    #: the force depends on the acceleration too (set per instance by such a law)
    inertial: bool = False

    def __init__(self, name: str, dofs: Any, scale: float, nodes: tuple[int, ...] = ()
                 ) -> None:
        self.name = str(name)
        self.dofs = np.atleast_1d(np.asarray(dofs, dtype=np.int64))
        self.scale = float(scale)
        self.nodes = tuple(int(n) for n in nodes)

    @property
    def m(self) -> int:
        """Number of DOFs the element acts on."""
        return int(self.dofs.size)

    # ---- the force law -----------------------------------------------------------------
    @abstractmethod
    def force_and_jacobian(self, q: FloatArray, v: FloatArray
                           ) -> tuple[FloatArray, FloatArray, FloatArray]:
        """``(F, dF/dq, dF/dv)`` of samples ``q, v`` of shape ``(..., m)``: ``F (..., m)``,
        the Jacobians ``(..., m, m)`` (row: force component, column: DOF). Raises the
        element's :class:`~rotorsfd.errors.ElementDomainError` (an SFD's
        :class:`~rotorsfd.errors.JournalContactError`)
        where the state is outside the law's domain."""

    def force(self, q: FloatArray, v: FloatArray) -> FloatArray:
        """``F (..., m)`` alone (the Jacobians skipped where the law can)."""
        return self.force_and_jacobian(q, v)[0]

    def force_and_jacobians(self, q: FloatArray, v: FloatArray, a: FloatArray
                            ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
        """``(F, dF/dq, dF/dv, dF/da)`` at samples ``q, v, a (..., m)``; an element whose
        force does not depend on the acceleration gives ``dF/da = 0`` (an inertial one
        overrides this; its :meth:`force_and_jacobian` is then the force at ``a = 0``)."""
        F, Jq, Jv = self.force_and_jacobian(q, v)
        return F, Jq, Jv, np.zeros_like(Jq)

    @property
    def inertial_kernel(self) -> Any:
        """The compiled law with the acceleration, ``kernel(q, v, a, params, F, dFdq,
        dFdv, dFda) -> int`` (:mod:`rotorsfd.kernels`), None when :attr:`inertial` is
        False."""
        return None

    @property
    @abstractmethod
    def kernel(self) -> Any:
        """The compiled law of one sample, ``kernel(q, v, params, F, dFdq, dFdv) -> int``
        (an ``@njit`` function, :mod:`rotorsfd.kernels`): returns 0, or nonzero outside the
        law's domain (outputs then untouched)."""

    @property
    @abstractmethod
    def kernel_params(self) -> FloatArray:
        """The kernel's float64 parameter vector (a fresh contiguous copy)."""

    # ---- inputs that are not states ---------------------------------------------------
    def with_parameter(self, name: str, value: float) -> NonlinearElement:
        """A copy of the element with its input ``name`` (one of :attr:`parameters`) set to
        ``value`` (SI); the same kernel, another parameter vector."""
        raise KeyError(f"element {self.name!r} ({self.kind}) has no input {name!r}")

    def dforce(self, q: FloatArray, v: FloatArray, name: str) -> FloatArray:
        """``dF/dp (..., m)`` at fixed samples ``q, v (..., m)`` for the input ``p = name``
        (exact)."""
        raise KeyError(f"element {self.name!r} ({self.kind}) has no input {name!r}")

    # ---- validity, results --------------------------------------------------------------
    def limit(self, q: FloatArray) -> float:
        """The validity measure over samples ``q (..., m)`` (largest value; it must stay
        below 1, e.g. the eccentricity ratio of a film); 0 for an element without one."""
        return 0.0

    def diagnostics(self, q: FloatArray, v: FloatArray) -> dict[str, float]:
        """Scalars of one orbit (samples ``q, v (N, m)``) for the results, keyed by short
        names (``eps_max``); the writers name them ``<key>_<element name>``."""
        return {}

    def contact_error(self, q: FloatArray, v: FloatArray, where: str = "") -> Exception:
        """The error to raise when the kernel reported the state ``(q, v) (m,)`` outside
        the law's domain."""
        return ElementDomainError(f"element {self.name!r} ({self.kind}): state outside the "
                                  f"force law's domain at q={q}, v={v}" + (
                                      f" ({where})" if where else ""))

    def describe(self) -> str:
        """One line for messages and reports."""
        return f"{self.kind} {self.name!r} on DOFs {self.dofs.tolist()}"

    def __repr__(self) -> str:
        return f"<{type(self).__name__} {self.name!r} dofs={self.dofs.tolist()}>"
