"""Floquet multipliers of the HB solutions of one problem, point by point, with the
Craig-Bampton basis reused while M and K stay the same and the Newmark step controlled.

Per point: the multipliers of the perturbation equation along the HB orbit (paper eq. 30)
by :mod:`rotorsfd.stability` (default ``'newmark-cb'``: Newmark, N = 400, on a
Craig-Bampton model that keeps the nonlinear DOFs and the fixed-interface modes with
``omega h <= 1/4``). The reduction basis depends on M and K only, so it is computed once
per branch and again only when K (or M) changes along it (base-rate continuation); D
(gyroscopic, base Coriolis) is projected at every point, ``D_r = Psi^T D Psi``. The basis
is :class:`~rotorsfd.stability.reduction.FixedInterfaceBasis`: on the CSR matrices
(``problem.matrices.sparse``) for a banded model above ``DENSE_MAX_DOF``, else on the
dense ones (every mode by LAPACK). Each result's ``info`` carries ``n_modes``,
``omega_cut`` and ``max_multiplier_outside``, the modes above the cut-off
(:mod:`rotorsfd.stability.outside`).

Step control (``StabilityOptions.interval_tol``): the monodromy at M and M/2 intervals,
the error of the M result ``|mu(M) - mu(M/2)| / 3`` (second-order scheme), M doubled
until it meets the tolerance (:class:`FloquetEvaluator`).
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.stability.branch_options import REDUCED_METHODS, StabilityOptions
from rotorsfd.stability.floquet import FloquetResult
from rotorsfd.stability.hill import (
    fourier_coefficients,
    hill_floquet,
    sampled_first_order_coefficients,
)
from rotorsfd.stability.monodromy import floquet_multipliers
from rotorsfd.stability.orbit import inertial_jacobians, orbit_floquet, orbit_samples
from rotorsfd.stability.outside import averaged_eigenvalues, exact_multipliers, largest_modulus
from rotorsfd.stability.reduction import FixedInterfaceBasis, ReducedModel

#: The step control starts the next point at M/2 when the error estimate at M is below
#: this fraction of the tolerance: the scheme is second order, so the estimate at M/2 is
#: about 4x, a quarter of the tolerance. (1/8 saves 16-28 % of the monodromy work on the
#: convergence cases, multipliers within 5e-5, but moves the weak secondary Hopf of the
#: U = 360.04 g mm case, |mu| - 1 <= 3.4e-4, from Omega~ 1.2881 to 1.2885.)
HALVE_FRACTION = 1 / 16

#: Large (sparse) models: the modes above the cut-off are the Ritz values of the averaged
#: model on the Craig-Bampton basis extended to this multiple of the cut-off.
OUTSIDE_FACTOR = 2.0

#: Multipliers compared by the step control: the largest ones (the critical multipliers
#: of every crossing type lie among them wherever a bifurcation is near).
N_COMPARED = 4


def multiplier_change(a: NDArray, b: NDArray, k: int = N_COMPARED) -> float:
    """Largest change of the moduli of the k largest-modulus multipliers between two
    computations of one spectrum (sorted by modulus): what decides stability and locates
    the crossings. Phases are not compared: an undamped structural mode has ``|mu| = 1``
    at any step (the trapezoidal rule conserves its energy) while its phase error grows
    with the step, irrelevant to stability."""
    a, b = np.sort(np.abs(np.asarray(a, complex)))[::-1], np.sort(np.abs(np.asarray(
        b, complex)))[::-1]
    j = min(k, a.size, b.size)
    return float(np.max(np.abs(a[:j] - b[:j]))) if j else 0.0


class FloquetEvaluator:
    """Multipliers of HB solutions of one problem, reusing the reduction basis while M
    and K stay the same. ``evaluator(lam, X) -> FloquetResult``; ``n_bases`` counts the
    bases computed.

    Step control (``options.interval_tol``, Newmark methods): the monodromy is computed
    at M and M/2 intervals; the scheme is second order, so the error of the M result is
    about ``|mu(M) - mu(M/2)| / 3`` (:func:`multiplier_change` over the largest
    multipliers). Above the tolerance M is doubled (M/2 becomes the old M) until it is met
    or ``max_intervals`` is reached; the M that met it starts the next point, halved when
    the estimate is below :data:`HALVE_FRACTION` of the tolerance (the halved M then
    meets it with a margin of 4). The
    result's ``info`` holds ``n_intervals`` and ``multiplier_error``. The Craig-Bampton
    basis stays the one of ``options.basis_intervals`` or ``n_intervals`` (modes with
    ``omega <= M_b / (4 T)``): the control refines the step on one reduced model."""

    def __init__(self, problem: PeriodicProblem, options: StabilityOptions | None = None
                 ) -> None:
        self.problem = problem
        self.options = options or StabilityOptions()
        self.nl = np.asarray(problem.nl_dofs, dtype=np.intp)
        self._basis: FixedInterfaceBasis | None = None
        self._lin: tuple[object, object, object] = (None, None, None)
        self._cut = 0.0
        self.n_bases = 0
        self.n_intervals = int(self.options.n_intervals)
        #: compute the modes above the cut-off (``max_multiplier_outside``) per result
        self.with_outside = bool(self.options.outside)

    @property
    def step_controlled(self) -> bool:
        o = self.options
        return o.interval_tol is not None and not o.method.startswith("hill")

    def linear_part(self, lam: float) -> tuple[object, object, object]:
        """(M, D, K) at lam for the basis: CSR (``problem.matrices.split``, D a
        :class:`~rotorsfd.model.lowrank.BandedLowRank` with a low-rank modal damping) when
        the problem's linear part is banded and larger than ``DENSE_MAX_DOF`` (the switch
        of the linear solvers), else the dense arrays."""
        part = self.problem.matrices
        if hasattr(part, "split") and self.problem.n_dof > DENSE_MAX_DOF:
            return part.split(lam)     # a low-rank modal damping kept as its factors
        if hasattr(part, "sparse") and self.problem.n_dof > DENSE_MAX_DOF:
            return part.sparse(lam)
        M, D, K = part(lam)
        return np.asarray(M, float), np.asarray(D, float), np.asarray(K, float)

    def reduced(self, lam: float, period: float) -> ReducedModel:
        """Craig-Bampton model at lam (modes with ``omega <= M_b / (4 T)``, ``M_b`` the
        options' ``basis_intervals`` or ``n_intervals``, unless ``n_modes``/``omega_max``
        are given). The basis: :class:`FixedInterfaceBasis` on the matrices of
        :meth:`linear_part` (dense: every mode by LAPACK; sparse: only the lowest)."""
        o = self.options
        M, D, K = self.linear_part(lam)
        if self._basis is None or not self._basis.matches(M, K):
            dense = isinstance(M, np.ndarray)
            self._basis = FixedInterfaceBasis(M.copy() if dense else M,
                                              K.copy() if dense else K, self.nl)
            self.n_bases += 1
        om = o.omega_max
        if o.n_modes is None and om is None:
            om = 0.25 * (o.basis_intervals or o.n_intervals) / period
        red = self._basis.reduce(D, o.n_modes, om)
        self._lin = (M, D, K)
        self._cut = float(om) if om is not None else (
            float(red.omegas[-1]) if red.omegas.size else 0.0)
        return red

    def outside(self, red: ReducedModel, period: float, Jq: NDArray, Jv: NDArray,
                endpoint: bool = True, Ja: NDArray | None = None) -> dict[str, float | int]:
        """The modes above the cut-off of the last :meth:`reduced` model, from the averaged
        model (:mod:`rotorsfd.stability.outside`; ``Jq, Jv`` the Jacobian samples of one
        period, ``t = T`` included unless ``endpoint=False``): ``max_multiplier_outside`` (largest
        ``|exp(lambda_j T)|``, 0 if none is found), ``n_modes`` (fixed-interface modes
        kept) and ``omega_cut`` (the cut-off [rad/s]). Dense basis: every mode of the
        averaged model; sparse: its Ritz values on the Craig-Bampton basis extended to
        :data:`OUTSIDE_FACTOR` x the cut-off (the constraint modes carry the elements'
        coupling; fixed-interface modes found by the same Lanczos run), modes in
        ``(omega_cut, ~OUTSIDE_FACTOR omega_cut)``; an added mass ``Ja`` (fluid inertia)
        averaged into M."""
        M, D, K = self._lin
        Jq, Jv = np.asarray(Jq), np.asarray(Jv)
        if endpoint:      # t = 0 and t = T: one sample of the period
            Jq, Jv = Jq[:-1], Jv[:-1]
        Jq, Jv = Jq.mean(axis=0), Jv.mean(axis=0)
        if self._basis.sparse:   # Ritz: the basis extended to OUTSIDE_FACTOR x the cut-off
            ext = self._basis.reduce(D, None, OUTSIDE_FACTOR * self._cut)
            M, D, K = ext.M, ext.D, ext.K
            nl = ext.nl_dofs
        else:
            nl = self.nl
        if Ja is not None:
            Ja = np.asarray(Ja)
            Ja = (Ja[:-1] if endpoint else Ja).mean(axis=0)
            M = M.copy()
            M[np.ix_(nl, nl)] = M[np.ix_(nl, nl)] - Ja
        lam = averaged_eigenvalues(M, D, K, nl, Jq, Jv, omega_max=self._cut)
        return {"max_multiplier_outside": largest_modulus(exact_multipliers(lam, period)),
                "n_modes": int(red.omegas.size), "omega_cut": float(self._cut)}

    def __call__(self, lam: float, X: NDArray) -> FloquetResult:
        if not self.step_controlled:
            res = self.at(lam, X, self.options.n_intervals)
            res.info.setdefault("n_intervals", self.options.n_intervals)
            return res
        o = self.options
        tol, M = float(o.interval_tol), self.n_intervals
        if o.method in REDUCED_METHODS:   # one reduced model and one sampling for M and M/2
            run = self._stepper(lam, X)
            res, coarse = run(M), run(max(M // 2, 1))
        else:
            res, coarse = self.at(lam, X, M), self.at(lam, X, max(M // 2, 1))
            run = None
        err = multiplier_change(res.multipliers, coarse.multipliers) / 3.0
        while err > tol and 2 * M <= o.max_intervals:
            M *= 2
            coarse, res = res, (run(M) if run is not None else self.at(lam, X, M))
            err = multiplier_change(res.multipliers, coarse.multipliers) / 3.0
        halve = err < tol * HALVE_FRACTION and M // 2 >= o.min_intervals
        self.n_intervals = M // 2 if halve else M
        res.info.update(n_intervals=M, multiplier_error=err)
        return res

    def _stepper(self, lam: float, X: NDArray) -> Callable[[int], FloquetResult]:
        """``run(n)``: the multipliers at (lam, X) with n intervals (a reduced Newmark
        method), the reduced model built once; the orbit's Jacobian samples at n are
        reused for n/2 (every other one: the same ``t_j``)."""
        p = self.problem
        w = float(p.frequency(lam))
        T = 2 * np.pi / w
        X = np.asarray(X, dtype=complex)
        Xnl = X[:, self.nl] if X.shape[1] == p.n_dof else X
        red = self.reduced(lam, T)
        extra: dict[str, float | int] = {}
        cache: dict[int, tuple[NDArray, NDArray, NDArray | None]] = {}

        def run(n: int) -> FloquetResult:
            if n not in cache:
                if 2 * n in cache:
                    cache[n] = tuple(None if J is None else J[::2] for J in cache[2 * n])
                else:
                    cache[n] = self._jacobians(lam, Xnl, w, n)
            Jq, Jv, Ja = cache[n]
            res = self._reduced_newmark(red, T, Jq, Jv, n, p.n_dof, Ja)
            if not extra and self.with_outside:
                extra.update(self.outside(red, T, Jq, Jv, Ja=Ja))
            res.info.update(extra)
            return res

        return run

    def _jacobians(self, lam: float, Xnl: NDArray, w: float, n: int
                   ) -> tuple[NDArray, NDArray, NDArray | None]:
        """``(dF/dq, dF/dv, dF/da or None)`` on the orbit's n + 1 samples: the added mass
        ``dF/da`` of a force of the acceleration (fluid inertia), None without."""
        law = self.problem.law(lam)
        if law.force_jacobians is not None:
            return inertial_jacobians(law.force_jacobians, Xnl, w, n)
        Jq, Jv = law.jacobian(*orbit_samples(Xnl, w, n))
        return Jq, Jv, None

    def _reduced_newmark(self, red: ReducedModel, T: float, Jq: NDArray, Jv: NDArray,
                         n_intervals: int, n_dof: int, Ja: NDArray | None = None
                         ) -> FloquetResult:
        o = self.options
        res = floquet_multipliers(red.M, red.D, red.K, T, nl_dofs=red.nl_dofs, dFdq=Jq,
                                  dFdv=Jv, dFda=Ja, n_intervals=n_intervals, reduction=None,
                                  scheme=o.method.removesuffix("-cb"),
                                  rho_inf=o.rho_inf, tol=o.tol)
        res.method += "-cb"
        res.info.update(n_dof_full=n_dof, n_modes=red.omegas.size)
        return res

    def at(self, lam: float, X: NDArray, n_intervals: int) -> FloquetResult:
        """Multipliers at (lam, X) with ``n_intervals`` Newmark intervals (the options'
        method; Hill ignores it)."""
        o, p = self.options, self.problem
        w = float(p.frequency(lam))
        T = 2 * np.pi / w
        X = np.asarray(X, dtype=complex)
        Xnl = X[:, self.nl] if X.shape[1] == p.n_dof else X
        if o.method not in REDUCED_METHODS:
            M, D, K = p.matrices(lam)
            res = orbit_floquet(M, D, K, Xnl, w, self.nl, p.law(lam).jacobian,
                                method=o.method,
                                n_intervals=n_intervals, rho_inf=o.rho_inf, tol=o.tol,
                                nl_jacobians=p.law(lam).force_jacobians)
            # the full basis: every interior DOF in it, nothing outside
            res.info.update(n_modes=p.n_dof - self.nl.size, max_multiplier_outside=0.0)
            return res
        red = self.reduced(lam, T)    # the basis of the options' M, whatever the step
        if not o.method.startswith("hill"):
            Jq, Jv, Ja = self._jacobians(lam, Xnl, w, n_intervals)
            res = self._reduced_newmark(red, T, Jq, Jv, n_intervals, p.n_dof, Ja)
            if self.with_outside:
                res.info.update(self.outside(red, T, Jq, Jv, Ja=Ja))
            return res
        H = o.n_harmonics if o.n_harmonics is not None else max(8, X.shape[0] - 1)
        L = 2 * H
        law = p.law(lam)
        hill_method = "koopman" if o.method == "hill-koopman" else "symmetric"
        if law.force_jacobians is not None:   # the added mass: A(t) from its samples
            Jq, Jv, Ja = inertial_jacobians(law.force_jacobians, Xnl, w, 4 * (2 * L + 1),
                                            endpoint=False)
            res = hill_floquet(red.M, red.D, red.K, w, n_harmonics=H, method=hill_method,
                               tol=o.tol, A_hat=sampled_first_order_coefficients(
                                   red.M, red.D, red.K, red.nl_dofs, Jq, Jv, Ja, L))
            res.info.update(n_dof_full=p.n_dof, **self.outside(red, T, Jq, Jv,
                                                               endpoint=False, Ja=Ja))
            return res
        q, v = orbit_samples(Xnl, w, 4 * (2 * L + 1), endpoint=False)
        Jq, Jv = law.jacobian(q, v)
        res = hill_floquet(red.M, red.D, red.K, w, nl_dofs=red.nl_dofs,
                           dFdq_hat=fourier_coefficients(Jq, L),
                           dFdv_hat=fourier_coefficients(Jv, L), n_harmonics=H,
                           method=hill_method, tol=o.tol)
        res.info.update(n_dof_full=p.n_dof, **self.outside(red, T, Jq, Jv, endpoint=False))
        return res

