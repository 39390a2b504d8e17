"""The solver-level description of the dynamics: the one record the solvers take.

    M q'' + D(t) q' + K(t) q = f(t) + P F_nl(P^T q, P^T q')

with ``D(t) = D + sum_i d_i(t) D_i``, ``K(t) = K + sum_i k_i(t) K_i`` (the time-varying
terms as bases times coefficients, :class:`~rotorsfd.timedomain.forcing.TimeVaryingMatrices`;
None when the matrices are constant), the load ``f(t)`` (a constant, harmonics of the
speed and bases times coefficient series, :class:`~rotorsfd.timedomain.forcing.Forcing`)
and the nonlinear force ``F_nl`` on the DOFs ``nl_dofs`` (``P`` selects them) given by a
force law (:class:`ForceLaw`: its compiled kernel with its parameter vector, and its
numpy form). ``speed`` is the rotor speed Omega; its period ``T = 2 pi / Omega`` is the
period of the forcing, the Poincare section and the Floquet problem.

The model builds it in one place, :meth:`rotorsfd.model.system.RotorSystem.second_order`
(the harmonic-balance problem :meth:`~rotorsfd.model.system.RotorSystem.periodic_problem`
is the same equation as a family in a continuation parameter: at the speed ``Omega`` its
matrices and its first harmonic are this record's, a test keeps the two equal). The
solvers take it with an options record:

- time stepping: :func:`rotorsfd.timedomain.integrate.prepare_system` (the compiled
  loop's arrays packed once) and :func:`~rotorsfd.timedomain.integrate.integrate_system`
  with :class:`~rotorsfd.timedomain.step_records.StepOptions`;
- the reduced step: :func:`rotorsfd.timedomain.reduced.reduce_system` (its
  :meth:`~rotorsfd.timedomain.reduced.ReducedStep.stepped` is again a SecondOrderSystem);
- Lyapunov exponents: :func:`rotorsfd.timedomain.lyapunov.system_lyapunov`;
- Floquet multipliers of an orbit of it: :func:`rotorsfd.stability.monodromy.system_multipliers`
  with :class:`~rotorsfd.stability.monodromy.MonodromyOptions`.

A force law that depends on the journal acceleration (fluid inertia: an SFD with
``fluid_inertia = true``) is ``inertial`` and has an ``inertial_kernel`` ``(q, v, a,
params, F, dFdq, dFdv, dFda)`` (:mod:`rotorsfd.kernels`); the record hands it to the
solvers (:attr:`SecondOrderSystem.inertial_kernel`), whose iteration matrices then hold
the added mass ``M - P (dF/dq'') P^T``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

import numpy as np

if TYPE_CHECKING:
    from rotorsfd.timedomain.forcing import Forcing, TimeVaryingMatrices

__all__ = ["ForceLaw", "SecondOrderSystem"]


@runtime_checkable
class ForceLaw(Protocol):
    """The force-law contract of the nonlinear elements as the solvers see it
    (:class:`~rotorsfd.elements.composite.ElementSet` implements it): the compiled
    ``kernel(q, v, params, F, dFdq, dFdv) -> status`` with ``kernel_params``, the numpy
    ``force``/``jacobian``, the validity measure ``limit`` (largest over samples), the
    error of a rejected state ``located_contact`` and per-orbit ``diagnostics``."""

    @property
    def kernel(self) -> Any: ...

    @property
    def kernel_params(self) -> np.ndarray: ...

    def force(self, q: np.ndarray, v: np.ndarray) -> np.ndarray: ...

    def jacobian(self, q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]: ...

    def limit(self, q: np.ndarray) -> float: ...

    def located_contact(self, q: np.ndarray, v: np.ndarray, where: str = "") -> Exception:
        ...

    def diagnostics(self, q: np.ndarray, v: np.ndarray) -> dict[str, float]: ...


@dataclass
class SecondOrderSystem:
    """``M q'' + D(t) q' + K(t) q = f(t) + P F_nl`` at rotor speed ``speed`` (module
    docstring). ``M, D, K``: the constant parts (n, n), D with ``Omega G`` and the constant
    base terms; ``kernel``/``params``: the compiled force law and its parameters (None: no
    nonlinear force); ``elements``: the law's numpy form (:class:`ForceLaw`), for
    validity, contact reports and diagnostics; ``reduction``: the Craig-Bampton model the
    time step runs on (:class:`~rotorsfd.timedomain.reduced.ReducedStep`), None: the full
    step; ``gyroscopic``: ``G = dD/dOmega`` (None: not given), so that the record at
    another speed has ``D + (Omega' - Omega) G`` (the base terms held)."""

    M: np.ndarray
    D: np.ndarray
    K: np.ndarray
    nl_dofs: np.ndarray
    kernel: Any
    params: np.ndarray | None
    forcing: Forcing
    time_varying: TimeVaryingMatrices | None
    speed: float
    elements: ForceLaw | None = None
    reduction: Any = None
    gyroscopic: np.ndarray | None = None

    def linear(self) -> SecondOrderSystem:
        """The same record without the nonlinear elements (``M q'' + D(t) q' + K(t) q =
        f(t)``)."""
        return replace(self, nl_dofs=np.zeros(0, dtype=np.int64), kernel=None, params=None,
                       elements=None)

    @property
    def period(self) -> float:
        """Rotor period T = 2 pi / Omega [s]."""
        return 2.0 * math.pi / self.speed

    @property
    def n_dof(self) -> int:
        """Physical DOFs."""
        return self.M.shape[0]

    @property
    def n_nl(self) -> int:
        """Nonlinear DOFs m."""
        return int(np.asarray(self.nl_dofs).size)

    @property
    def has_inertia(self) -> bool:
        """True if the force law depends on the acceleration (fluid inertia)."""
        return bool(getattr(self.elements, "inertial", False))

    @property
    def inertial_kernel(self) -> Any:
        """The law's compiled inertial kernel (None without acceleration dependence)."""
        return self.elements.inertial_kernel if self.has_inertia else None

    def matrices_at(self, t: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(M, D(t), K(t))`` (callable coefficients only)."""
        # deferred: model.lowrank (loads scipy)
        from rotorsfd.model.lowrank import dense

        D, K = dense(self.D).copy(), dense(self.K).copy()   # CSR above 400 DOFs
        tv = self.time_varying
        if tv is not None:
            for c, X in tv.damping:
                D += float(np.asarray(c(np.asarray([t])))[0]) * np.asarray(X)
            for c, X in tv.stiffness:
                K += float(np.asarray(c(np.asarray([t])))[0]) * np.asarray(X)
        return dense(self.M), D, K
