"""Fold (saddle-node) curves of HB solutions in two parameters: the condensed HB-AFT
residual as a two-parameter system, and the fold curves traced from the turning points of
a one-parameter branch.

:class:`TwoParameterHB` writes the condensed residual
(:class:`~rotorsfd.harmonic.condensation.CondensedHB`, receptance form, fixed shift) of a
:class:`TwoParameterProblem` as ``R(x, lam1, lam2)`` in scaled unknowns with the exact
``[R_x, R_lam1, R_lam2]``: the :class:`~rotorsfd.continuation.folds.TwoParameterSystem`
that the generic fold-curve driver (:func:`rotorsfd.continuation.folds.continue_folds`)
continues, and that the period-doubling (:mod:`rotorsfd.harmonic.pd_curve`) and
Neimark-Sacker (:mod:`rotorsfd.harmonic.ns_curve`) augmented systems are built on.
:func:`trace_fold_curves` starts one fold curve at every located turning point not reached
by an earlier curve; :func:`needed_n_samples` is the AFT sampling rule along the curves.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.branch import BranchPoint
from rotorsfd.continuation.folds import FoldBranch, FoldOptions, continue_folds
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import smallest_n_samples, to_real
from rotorsfd.harmonic.problem import PeriodicProblem

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass
class TwoParameterProblem:
    """A periodic problem in two parameters, as its two one-parameter views:
    ``first(lam2)`` the :class:`PeriodicProblem` in lam1 at fixed lam2 and
    ``second(lam1)`` the one in lam2 at fixed lam1 (the same system at (lam1, lam2), each
    with exact derivatives in its own parameter). ``names`` label the parameters."""

    first: Callable[[float], PeriodicProblem]
    second: Callable[[float], PeriodicProblem]
    names: tuple[str, str] = ("lam1", "lam2")


class TwoParameterHB:
    """Condensed HB-AFT residual ``R(xs, lam1, lam2)`` (receptance form, fixed shift
    Delta) in scaled unknowns ``z = (xs / c, lam1 / scale1, lam2 / scale2)``, with the
    exact ``[R_x, R_lam1, R_lam2]``: R, R_x, R_lam1 from the condensation of
    ``first(lam2)`` at lam1, R_lam2 from that of ``second(lam1)`` at lam2 (one complex LU
    per harmonic each). The shift is set once, at ``(xs0, lam1_0, lam2_0)``.
    """

    def __init__(self, problem: TwoParameterProblem, H: int, N: int,
                 scales: tuple[float, float], xs0: FloatArray, lam0: tuple[float, float],
                 limit_max: float = 1.0) -> None:
        self.problem, self.H, self.N = problem, H, N
        self.scales = (float(scales[0]), float(scales[1]))
        self.limit_max = limit_max
        p1 = problem.first(lam0[1])
        self.template = p1
        self.n = (2 * H + 1) * p1.m
        self.cx = np.tile(p1.dof_scale[p1.nl_dofs], 2 * H + 1)
        hb = CondensedHB(p1, H, N)
        hb.set_shift(np.reshape(xs0, (2 * H + 1, p1.m)), lam0[0])
        self._shifted = hb   # holds the fixed shift, passed on by CondensedHB.with_problem
        self.aft = hb.aft
        self._key: tuple[float, float] | None = None
        self._hb: tuple[CondensedHB, CondensedHB] | None = None

    def to_z(self, xs: FloatArray, lam1: float, lam2: float) -> FloatArray:
        return np.concatenate([np.ravel(xs) / self.cx,
                               [lam1 / self.scales[0], lam2 / self.scales[1]]])

    def from_z(self, z: FloatArray) -> tuple[FloatArray, float, float]:
        return (z[: self.n] * self.cx, float(z[-2]) * self.scales[0],
                float(z[-1]) * self.scales[1])

    def _condensers(self, lam1: float, lam2: float) -> tuple[CondensedHB, CondensedHB]:
        if self._key != (lam1, lam2) or self._hb is None:
            self._key = (lam1, lam2)
            self._hb = (self._shifted.with_problem(self.problem.first(lam2)),
                        self._shifted.with_problem(self.problem.second(lam1)))
        return self._hb

    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        xs, l1, l2 = self.from_z(z)
        hb1, hb2 = self._condensers(l1, l2)
        R, Rx, R1 = hb1.residual(xs, l1, jac=True)
        R2 = hb2.residual(xs, l2, jac=True)[2]
        cx, n = self.cx, self.n
        J = np.empty((n, n + 2))
        J[:, :n] = Rx * (cx[None, :] / cx[:, None])
        J[:, n] = R1 * (self.scales[0] / cx)
        J[:, n + 1] = R2 * (self.scales[1] / cx)
        return R.ravel() / cx, J

    def admissible(self, z: FloatArray) -> bool:
        if self.template.nl_limit is None:
            return True
        xs = z[: self.n] * self.cx
        val = self.template.limit(self.aft.E @ xs.reshape(2 * self.H + 1, self.template.m))
        return bool(np.isfinite(val) and val < self.limit_max)

    def coefficients(self, z: FloatArray) -> ComplexArray:
        """Fourier coefficients of all DOFs (H+1, n_dof) at z."""
        xs, l1, l2 = self.from_z(z)
        return self._condensers(l1, l2)[0].recover(xs, l1)

    def sampling_error(self, z: FloatArray, N: int) -> float:
        """Error of N AFT samples at z in the units of the Newton test of R (scaled by
        c): :meth:`CondensedHB.sampling_error
        <rotorsfd.harmonic.condensation.CondensedHB.sampling_error>`, the criterion of
        ``continue_periodic``'s adaptive N_f rule."""
        xs, l1, l2 = self.from_z(z)
        xs = np.ascontiguousarray(xs.reshape(2 * self.H + 1, self.template.m))
        return self._condensers(l1, l2)[0].sampling_error(xs, l1, N)[0]

    def z_from_point(self, X: ComplexArray, lam1: float, lam2: float) -> FloatArray:
        """Scaled z of all-DOF coefficients X (H+1, n_dof) at (lam1, lam2)."""
        return self.to_z(to_real(np.asarray(X))[:, self.template.nl_dofs], lam1, lam2)


def trace_fold_curves(family: TwoParameterProblem, H: int, N: int,
                      scales: tuple[float, float], folds: Sequence[BranchPoint],
                      range2: tuple[float, float], options: FoldOptions | None = None,
                      ) -> tuple[TwoParameterHB, list[FoldBranch], list[str]]:
    """Fold curves from every located turning point ``folds`` (of the branch in lam1 at
    ``lam2 = range2[0]``) not reached by an earlier curve, continued towards
    ``range2[1]`` (physical units; scaled by ``scales``). A curve that turns (a cusp) and
    comes back to ``range2[0]`` at another start fold covers it. Returns the residual,
    the curves and their messages."""
    hb = TwoParameterHB(family, H, N, scales, folds[0].xs, (folds[0].lam, range2[0]))
    lam_range = (range2[0] / scales[1], range2[1] / scales[1])
    curves: list[FoldBranch] = []
    covered = [False] * len(folds)
    messages = []
    for i, p in enumerate(folds):
        if covered[i]:
            continue
        covered[i] = True
        curve = continue_folds(hb, hb.to_z(p.xs, p.lam, range2[0]), lam_range, options,
                               lam_physical=lambda lam: lam * scales[1])
        curves.append(curve)
        messages.append(curve.message)
        end_speed, end_value = hb.from_z(curve.z[-1])[1:]
        if curve.cusps and np.isclose(end_value, range2[0], rtol=0, atol=1e-9 * scales[1]):
            for j, q in enumerate(folds):
                if not covered[j] and abs(q.lam - end_speed) <= 1e-6 * q.lam:
                    covered[j] = True
    return hb, curves, messages


def needed_n_samples(hb: TwoParameterHB, curves: Sequence[FoldBranch], target: float,
                     n_max: int) -> int:
    """The smallest power of two N >= hb.N whose sampling error
    (:meth:`TwoParameterHB.sampling_error`, the criterion of ``continue_periodic``'s
    adaptive rule) is <= target at every point of the curves (n_max if none)."""
    N = hb.N
    for c in curves:
        for z in c.z:
            if N < n_max and hb.sampling_error(z, N) > target:
                N = smallest_n_samples(lambda n, z=z: hb.sampling_error(z, n), 2 * N, n_max,
                                       target)
    return N
