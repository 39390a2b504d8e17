"""Definition of a periodic problem for harmonic balance (generic: knows nothing of rotors).

    M(lam) q'' + D(lam) q' + K(lam) q = f(t; lam) + F_nl(q[nl_dofs], q'[nl_dofs])

periodic with fundamental angular frequency w(lam); lam is the continuation parameter
(a rotor speed, a base rate, an unbalance, a clearance ratio, ...).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
Matrices = tuple[FloatArray, FloatArray, FloatArray]


def _zero_limit(q_nl: FloatArray) -> float:
    return 0.0


@dataclass(frozen=True)
class NonlinearLaw:
    """The nonlinear force law at one parameter value lam.

    force(q_nl, v_nl) -> (..., m); jacobian(q_nl, v_nl) -> (dF/dq, dF/dv) (..., m, m);
    force_jacobian -> all three, or None; kernel_params: the compiled kernel's parameter
    vector at lam (None without a kernel); dforce(q_nl, v_nl) -> dF/dlam (..., m) at fixed
    samples, None when the force does not depend on lam.
    """

    force: Callable[[FloatArray, FloatArray], FloatArray]
    jacobian: Callable[[FloatArray, FloatArray], tuple[FloatArray, FloatArray]]
    force_jacobian: Callable[[FloatArray, FloatArray],
                             tuple[FloatArray, FloatArray, FloatArray]] | None = None
    kernel_params: FloatArray | None = None
    dforce: Callable[[FloatArray, FloatArray], FloatArray] | None = None
    #: ``(q, v, a) -> (F, dF/dq, dF/dv, dF/da)`` of a law that depends on the
    #: acceleration too (fluid inertia); None otherwise
    force_jacobians: Callable[[FloatArray, FloatArray, FloatArray],
                              tuple[FloatArray, FloatArray, FloatArray, FloatArray]] | None = None


@dataclass
class PeriodicProblem:
    """Second-order system with a local nonlinearity, for HB-AFT and continuation.

    Fields
    ------
    n_dof : number of DOFs n.
    nl_dofs : (m,) int indices of the DOFs the nonlinear force acts on (and depends on).
    matrices(lam) -> (M, D, K), each (n, n) float.
    dmatrices(lam) -> (dM, dD, dK), their derivatives with respect to lam.
    forcing(lam, H) -> (H+1, n) complex Fourier coefficients F_k of f(t), with
        ``f(t) = Re(sum_k F_k exp(i k w t))`` (F_0 real).
    dforcing(lam, H) -> (H+1, n) complex, dF_k/dlam.
    frequency(lam) -> w [rad/s];  dfrequency(lam) -> dw/dlam.
    nl_force(q_nl, v_nl) -> (..., m) force, vectorised over leading axes.
    nl_jacobian(q_nl, v_nl) -> (dF/dq, dF/dv), each (..., m, m).
    scaling : length scale c [m] (e.g. the SFD clearance) or an (n,) array of per-DOF
        scales: unknowns are judged as q/c, so the convergence threshold means the same in
        any units.
    nl_limit(q_nl_samples (N, m)) -> float, optional: a measure that must stay < 1 (e.g.
        the largest eccentricity ratio over the period); solvers damp steps to keep it.
    name : label for messages.
    nl_force_jacobian(q_nl, v_nl) -> (F, dF/dq, dF/dv), optional: both in one pass (e.g.
        ``SFD.force_and_jacobian``), used instead of two calls when given.
    nl_kernel, nl_kernel_params : optional compiled form of the same force law, the
        kernel of ``docs/INTERFACES.md`` (``kernel(q, v, params, F, dFdq, dFdv) -> int``,
        one sample, nonzero on contact; e.g. ``SFD.numba_kernel``, ``SFD.kernel_params``).
        When given, the condensed HB evaluates the AFT in compiled loops with it; it must
        agree with nl_force / nl_jacobian (which still serve the other paths).
    nl_at(lam) -> NonlinearLaw, optional: for a force that depends on lam itself (a journal
        bearing's on the speed, a film's on its clearance), the law at lam with its exact
        lam-derivative ``dforce``; solvers then ask :meth:`law` and the fixed fields above
        are not used. ``dR/dlam`` gains ``-S^T dG/dlam|_x`` with ``dG/dlam`` the AFT of
        ``dforce``.
    nl_force_jacobians(q_nl, v_nl, a_nl) -> (F, dF/dq, dF/dv, dF/da), nl_inertial_kernel:
        for a force that depends on the acceleration too (a film's fluid inertia), its
        numpy form and its inertial kernel (``kernel(q, v, a, params, F, dFdq, dFdv,
        dFda)``, :mod:`rotorsfd.kernels`); the AFT then samples ``a = w^2 Edd xs`` and
        ``dG/dx`` gains ``P dF/da w^2 Edd`` (:mod:`rotorsfd.harmonic.aft_inertia`).
    frequency_line : optional ``(w0, w1)`` with ``frequency(lam) = w0 + w1 lam`` exactly;
        with a linear part that states itself as a polynomial in lam
        (``matrices.polynomial() -> (M, (D_0, D_1, D_2), (K_0, K_1, K_2))``, None for zero
        terms) the dense condensation may use one eigendecomposition per harmonic for a
        branch (:mod:`rotorsfd.harmonic.pencil_condensation`).
    """

    n_dof: int
    nl_dofs: NDArray[np.int64]
    matrices: Callable[[float], Matrices]
    dmatrices: Callable[[float], Matrices]
    forcing: Callable[[float, int], ComplexArray]
    dforcing: Callable[[float, int], ComplexArray]
    frequency: Callable[[float], float]
    dfrequency: Callable[[float], float]
    nl_force: Callable[[FloatArray, FloatArray], FloatArray]
    nl_jacobian: Callable[[FloatArray, FloatArray], tuple[FloatArray, FloatArray]]
    scaling: float | FloatArray = 1.0
    nl_limit: Callable[[FloatArray], float] | None = None
    name: str = field(default="periodic problem")
    nl_force_jacobian: Callable[[FloatArray, FloatArray],
                                tuple[FloatArray, FloatArray, FloatArray]] | None = None
    nl_kernel: Any = None
    nl_kernel_params: FloatArray | None = None
    nl_at: Callable[[float], NonlinearLaw] | None = None
    nl_force_jacobians: Callable[..., tuple[FloatArray, FloatArray, FloatArray, FloatArray]
                                 ] | None = None
    nl_inertial_kernel: Any = None
    frequency_line: tuple[float, float] | None = None

    def __post_init__(self) -> None:
        self.nl_dofs = np.atleast_1d(np.asarray(self.nl_dofs, dtype=np.int64))
        if self.nl_dofs.size and (self.nl_dofs.min() < 0 or self.nl_dofs.max() >= self.n_dof):
            raise ValueError(f"nl_dofs {self.nl_dofs} out of range for n_dof={self.n_dof}")
        if len(np.unique(self.nl_dofs)) != len(self.nl_dofs):
            raise ValueError(f"nl_dofs {self.nl_dofs} has repeated entries")
        if self.nl_kernel is not None:
            self.nl_kernel_params = np.ascontiguousarray(
                np.zeros(0) if self.nl_kernel_params is None else self.nl_kernel_params,
                dtype=np.float64)
        c = np.broadcast_to(np.asarray(self.scaling, dtype=float), (self.n_dof,))
        if not np.all(np.isfinite(c)) or np.any(c <= 0):
            raise ValueError(f"scaling must be positive and finite, got {self.scaling!r}")
        self._fixed_law = NonlinearLaw(self.nl_force, self.nl_jacobian,
                                       self.nl_force_jacobian, self.nl_kernel_params,
                                       force_jacobians=self.nl_force_jacobians)
        self._law_at: tuple[float, NonlinearLaw] | None = None

    def law(self, lam: float) -> NonlinearLaw:
        """The nonlinear force law at lam (the fixed fields unless ``nl_at`` is given; the
        last value's law is reused)."""
        if self.nl_at is None:
            return self._fixed_law
        if self._law_at is None or self._law_at[0] != lam:
            self._law_at = (lam, self.nl_at(lam))
        return self._law_at[1]

    @property
    def inertial(self) -> bool:
        """True when the nonlinear force depends on the acceleration too."""
        return self.nl_force_jacobians is not None

    @property
    def parametric(self) -> bool:
        """True when the nonlinear force depends on lam (``nl_at`` given)."""
        return self.nl_at is not None

    @property
    def m(self) -> int:
        """Number of nonlinear DOFs."""
        return int(self.nl_dofs.size)

    @property
    def dof_scale(self) -> FloatArray:
        """Per-DOF length scale (n,)."""
        return np.broadcast_to(np.asarray(self.scaling, dtype=float), (self.n_dof,)).copy()

    def limit(self, q_nl_samples: FloatArray) -> float:
        """nl_limit of the samples, 0 when the problem has none."""
        return float((self.nl_limit or _zero_limit)(q_nl_samples))
