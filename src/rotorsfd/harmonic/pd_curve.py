"""Two-parameter continuation of period-doubling (flip) points of a forced response.

In harmonics of ``w/2`` (:func:`~rotorsfd.harmonic.branch_switching.period_doubled`, H2
harmonics) a T-periodic solution has only even harmonics, and the HB Jacobian there does
not couple even and odd harmonics: with the unknowns split as ``x = (x_e, x_o)``,

    R_x = [[A_ee, 0], [0, A_oo]]    at x_o = 0,

``R_e(x_e, lam1, lam2) = 0`` are the period-1 HB equations (H2 / 2 harmonics of w) and
the odd block ``A_oo`` is singular exactly where a Floquet multiplier is -1 (a
perturbation with ``dq(t + T) = -dq(t)``). A period-doubling curve is therefore

    F(x_e, lam1, lam2) = [R_e; g] = 0,     [A_oo b] [v]   [0]
                                           [c^T  0] [g] = [1]

(the bordered test function of :mod:`rotorsfd.continuation.folds` on the odd block
instead of the whole Jacobian, Govaerts 2000), continued in lam2 by the fold curve's
pseudo arc-length driver, turns in lam2 located the same way (where the two flips of a
pair meet: the lowest forcing, base rate, ... at which the period doubling exists).
``dg/dy = -w^T (dA_oo/dy) v`` for y in (x_e, lam1, lam2) is the odd rows of the
directional derivative of the full Jacobian along (0, v) (mixed partials commute), by a
central difference as for folds; R_e and g are exact. The flip located here is that of
the HB equations with H2 harmonics; it converges to the monodromy's as H2 grows.
"""

from __future__ import annotations

from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.folds import (
    FD_STEP,
    FoldBranch,
    FoldOptions,
    bordered_null_vectors,
    continue_folds,
    null_vectors,
    unit_borders,
)
from rotorsfd.harmonic.branch_switching import doubled_coefficients, period_doubled
from rotorsfd.harmonic.fold_curve import TwoParameterHB, TwoParameterProblem
from rotorsfd.harmonic.fourier import to_real

FloatArray = NDArray[np.float64]


def odd_rows(H2: int) -> NDArray[np.int64]:
    """Rows of the real layout (2 H2 + 1) that hold odd harmonics of w/2."""
    k = np.arange(1, H2 + 1)
    odd = k[k % 2 == 1]
    return np.sort(np.concatenate([2 * odd - 1, 2 * odd]))


class PeriodDoublingSystem:
    """``F = [R_e; g]`` in ``z_e = (x_e, lam1, lam2)`` over a period-2
    :class:`~rotorsfd.harmonic.fold_curve.TwoParameterHB` (module docstring); the interface
    of :class:`~rotorsfd.continuation.folds.FoldSystem` (a continuation system in lam2)."""

    def __init__(self, base: TwoParameterHB, z0: FloatArray, fd_step: float = FD_STEP
                 ) -> None:
        self.base, self.fd_step = base, fd_step
        m, H2 = base.template.m, base.H
        rows = odd_rows(H2)
        odd = (rows[:, None] * m + np.arange(m)[None, :]).ravel()
        mask = np.zeros(base.n, dtype=bool)
        mask[odd] = True
        self.crit = np.flatnonzero(mask)
        self.keep = np.flatnonzero(~mask)
        self.cols = np.concatenate([self.keep, [base.n, base.n + 1]])
        self.n = self.keep.size + 1
        self.weights = None
        z = np.asarray(z0, dtype=float)
        if z.size == base.n + 2:          # a full period-2 z: keep its even part
            z = z[self.cols]
        _, J = base.evaluate(self.embed(z))
        self.c, self.b = null_vectors(J[np.ix_(self.crit, self.crit)])

    def embed(self, ze: FloatArray) -> FloatArray:
        """The full period-2 z with zero odd harmonics."""
        z = np.zeros(self.base.n + 2)
        z[self.cols] = ze
        return z

    def admissible(self, z: FloatArray) -> bool:
        return self.base.admissible(self.embed(z))

    def null_vectors(self, A: FloatArray) -> tuple[FloatArray, FloatArray, float]:
        return bordered_null_vectors(A, self.b, self.c)

    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        full = self.embed(z)
        R, J = self.base.evaluate(full)
        v, w, g = self.null_vectors(J[np.ix_(self.crit, self.crit)])
        h = self.fd_step / max(float(np.linalg.norm(v)), 1e-300)
        dz = np.zeros_like(full)
        dz[self.crit] = h * v
        Jp = self.base.evaluate(full + dz)[1]
        Jm = self.base.evaluate(full - dz)[1]
        dg = -(w @ (Jp - Jm)[np.ix_(self.crit, self.cols)]) / (2.0 * h)
        return (np.append(R[self.keep], g),
                np.vstack([J[np.ix_(self.keep, self.cols)], dg]))

    def update_border(self, z: FloatArray) -> None:
        """b, c <- the unit left and right null vectors of the odd block at z."""
        _, J = self.base.evaluate(self.embed(z))
        borders = unit_borders(*self.null_vectors(J[np.ix_(self.crit, self.crit)])[:2])
        if borders is not None:
            self.c, self.b = borders


def period_doubling_problem(problem: TwoParameterProblem) -> TwoParameterProblem:
    """Both one-parameter views of ``problem`` written in harmonics of w/2."""
    return TwoParameterProblem(first=lambda lam2: period_doubled(problem.first(lam2)),
                               second=lambda lam1: period_doubled(problem.second(lam1)),
                               names=problem.names)


def continue_period_doublings(problem: TwoParameterProblem, X: NDArray[np.complex128],
                              lam1: float, lam2: float, lam2_range: tuple[float, float],
                              *, H2: int, N: int, scales: tuple[float, float],
                              options: FoldOptions | None = None, limit_max: float = 1.0,
                              on_point: Callable[[FloatArray, int], None] | None = None,
                              both_ways: bool = True,
                              ) -> tuple[TwoParameterHB, list[FoldBranch]]:
    """The period-doubling curve through the flip near ``(X, lam1)`` at ``lam2``
    (``X`` the period-1 coefficients (H+1, n_dof) there, e.g. of a located flip of a
    speed branch), continued in lam2 both ways over ``lam2_range`` (physical units;
    scaled by ``scales``) with H2 harmonics of w/2 and N AFT samples per period 2T.
    Returns the period-2 residual and the two legs (towards ``lam2_range[0]``, then
    towards ``lam2_range[1]``; each turns where the flips of a pair meet and goes on),
    whose points ``z`` are in the even unknowns: ``leg.system.embed(z)`` gives the full
    period-2 z (its last two entries the scaled lam1, lam2). ``both_ways=False``: only
    the leg towards ``lam2_range[1]`` (a start at ``lam2 = lam2_range[0]``)."""
    p2 = period_doubling_problem(problem)
    X2 = doubled_coefficients(np.asarray(X), H2)
    template = p2.first(lam2)
    xs0 = to_real(X2)[:, template.nl_dofs]
    hb = TwoParameterHB(p2, H2, N, scales, xs0, (lam1, lam2), limit_max=limit_max)
    z0 = hb.to_z(xs0, lam1, lam2)
    lo, hi = lam2_range[0] / scales[1], lam2_range[1] / scales[1]
    legs = []
    for target in ((hi, lo), (lo, hi)) if both_ways else ((lo, hi),):
        pd = PeriodDoublingSystem(hb, z0)
        legs.append(continue_folds(hb, z0[pd.cols], target, options, on_point=on_point,
                                   lam_physical=lambda s: s * scales[1],
                                   augmented=lambda base, z, pd=pd: pd))
    return hb, legs
