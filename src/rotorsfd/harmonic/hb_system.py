"""The scaled continuation system of one HB residual (:class:`HBSystem`) and its start
(:func:`hb_system`): the unknowns and residual of :mod:`rotorsfd.harmonic.periodic`'s
point solves and branches.

Scaling (so that the threshold ``tol = 1e-6`` means the same in any units): with the
per-DOF length scale c of the problem and ``lam_scale``, the Newton unknowns are ``x/c``
and ``lam/lam_scale``; the condensed residual (units of length) is divided by c; the full
residual (forces) by ``c_i kappa_i`` with ``kappa_i = |K_ii|`` at the first lam (a force
that would move DOF i by c_i).
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import (
    aft_matrices,
    aliasing_error,
    choose_n_samples,
    smallest_n_samples,
    to_real,
)
from rotorsfd.harmonic.full_sparse import full_hb
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.residual import FullHB, nonlinear_coefficients
from rotorsfd.model.lowrank import SparseLowRank

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

__all__ = ["HBSystem", "hb_system", "initial_guess", "stiffness_diagonal"]


def stiffness_diagonal(problem: PeriodicProblem, lam: float) -> FloatArray:
    """``K_ii(lam)`` of the problem's linear part: from band storage when the part has
    ``stiffness_diagonal`` (:class:`~rotorsfd.model.sparse.BandedLinearPart`: no n x n
    array), else the diagonal of its (dense) K."""
    part = problem.matrices
    if hasattr(part, "stiffness_diagonal"):
        return np.asarray(part.stiffness_diagonal(lam), dtype=float)
    K = part(lam)[2]
    return np.asarray(K.diagonal() if sp.issparse(K) else np.diag(K), dtype=float)


class HBSystem:
    """Scaled continuation system ``z = (x/c, lam/lam_scale)`` around an HB residual."""

    def __init__(self, problem: PeriodicProblem, H: int, N: int, condensed: bool,
                 lam_ref: float, lam_scale: float, limit_max: float = 1.0) -> None:
        self.problem, self.H, self.N, self.condensed = problem, H, N, condensed
        self.hb: CondensedHB | FullHB = (CondensedHB if condensed else full_hb)(problem, H, N)
        self.n = self.hb.n_unknowns
        self.lam_scale = float(lam_scale)
        self.limit_max = limit_max
        c = problem.dof_scale
        if condensed:
            self.cx = np.tile(c[problem.nl_dofs], 2 * H + 1)
            self.cr = self.cx
        else:
            kappa = np.abs(stiffness_diagonal(problem, lam_ref))
            pos = kappa[kappa > 0]
            kappa = np.where(kappa > 0, kappa, pos.mean() if pos.size else 1.0)
            self.cx = np.tile(c, 2 * H + 1)
            self.cr = np.tile(c * kappa, 2 * H + 1)
        # arc length measured on the nonlinear DOFs and lam in both paths (same branch)
        self.weights = np.ones(self.n + 1)
        if not condensed:
            nl = np.zeros((2 * H + 1, problem.n_dof))
            nl[:, problem.nl_dofs] = 1.0
            self.weights[:-1] = nl.ravel()

    # scaling -----------------------------------------------------------------------------
    def to_z(self, x: FloatArray, lam: float) -> FloatArray:
        return np.append(np.ravel(x) / self.cx, lam / self.lam_scale)

    def from_z(self, z: FloatArray) -> tuple[FloatArray, float]:
        return z[:-1] * self.cx, float(z[-1]) * self.lam_scale

    # ContinuationSystem protocol ------------------------------------------------------------
    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        x, lam = self.from_z(z)
        R, J, dR = self.hb.residual(x, lam, jac=True)
        if isinstance(J, SparseLowRank):   # the sparse full HB with a low-rank damping
            return R.ravel() / self.cr, J.scaled(1.0 / self.cr, self.cx).with_column(
                dR * (self.lam_scale / self.cr))
        if sp.issparse(J):     # the sparse full HB: CSR [dR/dx, dR/dlam] scaled
            Jx = sp.diags(1.0 / self.cr) @ J @ sp.diags(self.cx)
            col = sp.csr_matrix((dR * (self.lam_scale / self.cr))[:, None])
            return R.ravel() / self.cr, sp.hstack([Jx, col], format="csr")
        Jz = np.empty((self.n, self.n + 1))
        Jz[:, :-1] = J if self.condensed else J * (self.cx[None, :] / self.cr[:, None])
        Jz[:, -1] = dR * (self.lam_scale / self.cr)
        return R.ravel() / self.cr, Jz

    def admissible(self, z: FloatArray) -> bool:
        if self.problem.nl_limit is None:
            return True
        x, _ = self.from_z(z)
        val = self.problem.limit(self.hb.aft.E @ self.hb.nl_part(x))
        return bool(np.isfinite(val) and val < self.limit_max)

    # results -------------------------------------------------------------------------------
    def physical_jacobian(self, z: FloatArray, Jz: FloatArray) -> FloatArray:
        """[dR/dx, dR/dlam] in physical units (condensed: Schur form) at a solution z."""
        if isinstance(Jz, SparseLowRank):
            J, dR = Jz.without_last_column()
            return J.scaled(self.cr, 1.0 / self.cx).with_column(
                dR * (self.cr / self.lam_scale))
        if sp.issparse(Jz):
            Jz = sp.csr_matrix(Jz)
            J = sp.diags(self.cr) @ Jz[:, :-1] @ sp.diags(1.0 / self.cx)
            dR = Jz[:, -1].toarray().ravel() * (self.cr / self.lam_scale)
            return sp.hstack([J, sp.csr_matrix(dR[:, None])], format="csr")
        J = Jz[:, :-1] * (self.cr[:, None] / self.cx[None, :])
        dR = Jz[:, -1] * (self.cr / self.lam_scale)
        if isinstance(self.hb, CondensedHB):
            return self.hb.schur_jacobian(J, dR, self.from_z(z)[1])
        return np.column_stack([J, dR])

    def coefficients(self, z: FloatArray) -> ComplexArray:
        """Fourier coefficients of all DOFs (H+1, n_dof) at z."""
        x, lam = self.from_z(z)
        if isinstance(self.hb, CondensedHB):
            return self.hb.recover(x, lam)
        xr = x.reshape(2 * self.H + 1, self.problem.n_dof)
        X = np.empty((self.H + 1, self.problem.n_dof), dtype=complex)
        X[0] = xr[0]
        X[1:] = xr[1::2] + 1j * xr[2::2]
        return X

    def aliasing(self, z: FloatArray) -> float:
        """Relative change of the nonlinear-force coefficients if N doubled
        (:func:`~rotorsfd.harmonic.fourier.aliasing_error`; the ``"grow"`` rule)."""
        x, lam = self.from_z(z)
        xs = self.hb.nl_part(x)
        if isinstance(self.hb, CondensedHB):
            return self.hb.aliasing(xs, lam)
        return aliasing_error(self.problem.law(lam).force, xs, self.problem.frequency(lam),
                              self.N, self.hb.last_G(xs, lam))

    def nl_tangent(self, t: FloatArray) -> FloatArray:
        """The tangent's components on the nonlinear DOFs and lam (the condensed layout)."""
        if self.condensed:
            return t
        x = t[:-1].reshape(2 * self.H + 1, self.problem.n_dof)[:, self.problem.nl_dofs]
        return np.append(x.ravel(), t[-1])

    # sampling error in the units of the convergence test (the "adaptive" N_f rule) ----------
    def force_coefficients(self, z: FloatArray, N: int) -> FloatArray:
        """Nonlinear-force coefficients (2H+1, m) at z computed with N samples."""
        x, lam = self.from_z(z)
        xs = np.ascontiguousarray(self.hb.nl_part(x))
        if isinstance(self.hb, CondensedHB):
            return self.hb.force_coefficients(xs, lam, N)
        G = self.hb.last_G(xs, lam) if N == self.N else None
        if G is None:
            G = nonlinear_coefficients(self.problem, aft_matrices(self.H, N), xs,
                                       self.problem.frequency(lam), jac=False, lam=lam).G
        return G

    def residual_change(self, z: FloatArray, dG: FloatArray) -> float:
        """2-norm of the change of the scaled residual (the quantity the Newton test
        bounds by tol) caused by a change dG (2H+1, m) of the force coefficients:
        ``|Ht dG| / c`` condensed (a displacement over the length scale), ``|dG| / (c
        kappa)`` at nl_dofs in the full residual (a force over the force scale)."""
        if isinstance(self.hb, CondensedHB):
            return self.hb.residual_change(dG, self.from_z(z)[1])
        r = dG / self.cr.reshape(2 * self.H + 1, -1)[:, self.problem.nl_dofs]
        return float(np.linalg.norm(r))

    def sampling_error(self, z: FloatArray, N: int, G_hi: FloatArray | None = None
                       ) -> tuple[float, FloatArray]:
        """Error estimate of N samples at z: :meth:`residual_change` of ``G_2N - G_N``
        (``G_hi`` = G_2N if known); returns it and G_N."""
        if isinstance(self.hb, CondensedHB):   # the same criterion as the fold curve
            x, lam = self.from_z(z)
            return self.hb.sampling_error(np.ascontiguousarray(self.hb.nl_part(x)), lam, N,
                                          G_hi)
        G_lo = self.force_coefficients(z, N)
        if G_hi is None:
            G_hi = self.force_coefficients(z, 2 * N)
        return self.residual_change(z, G_hi - G_lo), G_lo

    def smallest_n_samples(self, z: FloatArray, n_min: int, n_max: int, target: float
                           ) -> int:
        """Smallest power of two N in [n_min, n_max] whose :meth:`sampling_error` at z is
        <= target (n_max if none)."""
        return smallest_n_samples(lambda N: self.sampling_error(z, N)[0], n_min, n_max,
                                  target)

    def coarser_n_samples(self, z: FloatArray, n_floor: int, target: float) -> int:
        """This N halved while the error of the halved count (against the current one)
        stays <= target and N/2 >= n_floor."""
        N = self.N
        G_hi = self.force_coefficients(z, N)
        while N // 2 >= n_floor:
            err, G_lo = self.sampling_error(z, N // 2, G_hi)
            if err > target:
                break
            N, G_hi = N // 2, G_lo
        return N


def initial_guess(problem: PeriodicProblem, H: int, lam: float,
                  X0: ComplexArray | None, condenser: CondensedHB | None = None
                  ) -> ComplexArray:
    """All-DOF start (H+1, n): X0, or the linear response with the nonlinearity replaced by
    its linearisation at rest (``u = Zt^-1 F``), shrunk until nl_limit < 1. ``condenser``
    (H harmonics): the one to condense with, with the lam-derivatives, so that a condensed
    solve at this lam can take it over (:meth:`CondensedHB.adopt_condensation`)."""
    if X0 is not None:
        X0 = np.asarray(X0, dtype=complex)
        if X0.shape == (H + 1, problem.n_dof):
            return X0
        X = np.zeros((H + 1, problem.n_dof), dtype=complex)
        h = min(H, X0.shape[0] - 1)
        if X0.shape[1] == problem.n_dof:
            X[: h + 1] = X0[: h + 1]
            return X
        raise ValueError(f"X0 must have shape (H+1, n_dof)=({H + 1}, {problem.n_dof}); "
                         f"got {X0.shape}")
    cond = condenser if condenser is not None else CondensedHB(problem, H, 4 * H + 4)
    cond.set_shift(np.zeros((2 * H + 1, problem.m)), lam)
    X = cond.condense(lam, deriv=condenser is not None).u.copy()
    if problem.nl_limit is not None:
        E = cond.aft.E
        for i in range(120):   # the harmonics first, then (an element carrying the static
            if problem.limit(E @ to_real(X[:, problem.nl_dofs])) < 0.9:   # load) all
                break
            X[1 if i < 60 else 0:] *= 0.5
    return X


def hb_system(problem: PeriodicProblem, H: int, lam: float, X0: ComplexArray | None,
              n_samples: int | None, condensed: bool, lam_scale: float, limit_max: float
              ) -> tuple[HBSystem, FloatArray]:
    """The extended HB system of ``problem`` at ``lam`` and its first unknowns ``z0``
    (from ``X0``, or the linearised response; N_f by the sampling rule if not given)."""
    # from the linear response: its condensation (shift of the linearisation at rest) is
    # the solver's first one; at fixed lam the Newton iterates of the receptance form do
    # not depend on the shift (condensation module), so the solve keeps it (one
    # condensation of H + 1 harmonics per point less; the solution the same to rounding)
    guess = CondensedHB(problem, H, 4 * H + 4) if X0 is None and condensed else None
    Xg = initial_guess(problem, H, lam, X0, guess)
    xg = to_real(Xg)
    N = n_samples or choose_n_samples(problem.law(lam).force, xg[:, problem.nl_dofs],
                                      problem.frequency(lam))
    system = HBSystem(problem, H, N, condensed, lam, lam_scale, limit_max)
    if isinstance(system.hb, CondensedHB):
        if guess is None or not system.hb.adopt_condensation(guess):
            system.hb.set_shift(xg[:, problem.nl_dofs], lam)
        z0 = system.to_z(xg[:, problem.nl_dofs], lam)
    else:
        z0 = system.to_z(xg, lam)
    return system, z0
