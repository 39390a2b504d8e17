"""Two-parameter continuation of Neimark-Sacker (secondary Hopf) points of a forced response.

A perturbation ``dq = exp(i sigma t) p(t)`` of a T-periodic orbit (``p`` T-periodic,
``p = sum_k p_k exp(i k w t)``) has the Floquet multiplier ``exp(i sigma T)``. Linearising
``M q'' + D q' + K q = f + g(q, q')`` (``g`` on the nonlinear DOFs, the linear DOFs
eliminated exactly) gives the shifted Hill operator on the nonlinear DOFs

    A(sigma)_kj = Zs(k w + sigma) delta_kj - Jq_{k-j} - i (j w + sigma) Jv_{k-j},
    Zs(W) = (S Z(W)^{-1} S^T)^{-1},   Z(W) = K - W^2 M + i W D,

with ``Jq_l, Jv_l`` the two-sided Fourier coefficients of ``dg/dq, dg/dv`` along the
orbit (AFT). A multiplier on the unit circle at ``exp(i sigma T)``, ``0 < sigma < w/2``,
is where ``A(sigma)`` is singular. Harmonics ``k = -K .. K-1`` (2K blocks, symmetric
about ``-sigma/w`` at ``sigma = w/2``: there A is the odd-harmonic block of
:mod:`rotorsfd.harmonic.pd_curve` with H2 = 2K, a check). The complex bordered test
function

    [A(sigma) b] [v]   [0]
    [c^T      0] [g] = [1],        Re g = Im g = 0,

with ``theta = sigma / w`` an extra unknown, added to the period-1 HB equations
``R(x, lam1, lam2) = 0``, gives ``n + 2`` equations in ``(x, lam1, theta, lam2)``: a
curve, continued in lam2 by the fold curve's driver
(:func:`rotorsfd.continuation.folds.continue_folds`, another ``augmented`` system).
``dg/d(x, lam1, theta, lam2)`` by central differences of g at fixed borders; R exact.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.folds import (
    FoldBranch,
    FoldOptions,
    bordered,
    bordered_null_vectors,
    continue_folds,
    unit_borders,
)
from rotorsfd.continuation.newton import newton_extended
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.banded_receptance import banded_receptances
from rotorsfd.harmonic.condensation import banded_band
from rotorsfd.harmonic.fold_curve import TwoParameterHB, TwoParameterProblem
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.harmonic.synthesis import orbit_samples
from rotorsfd.model.sparse import DENSE_MAX_DOF

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

NS_FD_STEP = 1e-6
"""Central-difference step of g in the scaled unknowns."""

THETA_MARGIN = 0.05
"""theta is admitted in (-THETA_MARGIN, 1/2 + THETA_MARGIN) (a step may pass theta = 0 or
1/2 before the end event stops the curve)."""

THETA_FIT = 0.005
"""The 1:1 / 1:2 end (theta = t, 0 or 1/2) is extrapolated from the curve's points at
theta = t +- j h, j = 1, 2, 3, h = min(THETA_FIT, |theta_start - t| / 4) (a curve that
starts close to t spans only that range of theta); the curve stops (an event, located)
where theta comes within h / 2 of t."""


def receptance_blocks(problem, lam: float, theta: float, K: int) -> ComplexArray:
    """The diagonal blocks ``Zs(k w + sigma)`` of ``A(sigma)``, ``k = -K .. K-1``, at
    ``lam`` (``sigma = theta * w``): (2K, m, m). A banded linear part above
    ``DENSE_MAX_DOF`` DOFs: one banded LU of ``Z(W)`` per frequency and the nonlinear
    DOFs' columns only (:mod:`rotorsfd.harmonic.banded_receptance`, no n x n array);
    otherwise one batched dense solve. Then one batched m x m inverse."""
    w = float(problem.frequency(lam))
    nl = np.asarray(problem.nl_dofs)
    W = (np.arange(-K, K) + theta) * w
    part = problem.matrices
    if banded_band(part) is not None and problem.n_dof > DENSE_MAX_DOF:
        return np.linalg.inv(banded_receptances(part, lam, nl, W))
    M, D, Kmat = (np.asarray(a) for a in part(lam))
    Z = (Kmat[None] - W[:, None, None] ** 2 * M[None] + 1j * W[:, None, None] * D[None])
    E = np.broadcast_to(np.eye(Kmat.shape[0])[:, nl], (W.size, Kmat.shape[0], nl.size))
    return np.linalg.inv(np.linalg.solve(Z, E)[:, nl, :])


def shifted_hill(problem, X: ComplexArray, lam: float, theta: float, K: int,
                 n_samples: int = 64, blocks: ComplexArray | None = None) -> ComplexArray:
    """``A(sigma)`` (module docstring) of ``problem`` at ``lam`` on the orbit ``X``
    (H+1, n_dof), ``sigma = theta * w``, harmonics ``k = -K .. K-1``: (2K m, 2K m).
    ``blocks``: :func:`receptance_blocks` at (lam, theta), if already computed."""
    w = float(problem.frequency(lam))
    sigma = theta * w
    nl = np.asarray(problem.nl_dofs)
    m = nl.size
    ks = np.arange(-K, K)
    if blocks is None:
        blocks = receptance_blocks(problem, lam, theta, K)
    A = np.zeros((2 * K, m, 2 * K, m), dtype=complex)
    A[np.arange(2 * K), :, np.arange(2 * K), :] = blocks
    A = A.reshape(2 * K * m, 2 * K * m)
    N = max(n_samples, 4 * K + 2 * X.shape[0])
    q, v = orbit_samples(np.asarray(X)[:, nl], w, N)
    Jq, Jv = problem.law(lam).jacobian(q, v)    # the law at lam (speed-dependent films)
    Jq_hat = np.fft.fft(np.asarray(Jq), axis=0) / N      # Jq_hat[l] ~ exp(+i l w t)
    Jv_hat = np.fft.fft(np.asarray(Jv), axis=0) / N
    lag = (ks[:, None] - ks[None, :]) % N                  # (2K, 2K)
    conv = Jq_hat[lag] + 1j * (ks * w + sigma)[None, :, None, None] * Jv_hat[lag]
    A -= conv.transpose(0, 2, 1, 3).reshape(2 * K * m, 2 * K * m)
    return A


class NeimarkSackerSystem:
    """``F = [R; Re g; Im g]`` in ``z = (x, lam1, theta, lam2)`` over a
    :class:`~rotorsfd.harmonic.fold_curve.TwoParameterHB`; the interface of
    :class:`~rotorsfd.continuation.folds.FoldSystem` (module docstring)."""

    def __init__(self, base: TwoParameterHB, z0: FloatArray, K: int,
                 fd_step: float = NS_FD_STEP) -> None:
        self.base, self.K, self.fd_step = base, K, fd_step
        self.n = base.n + 2
        self.weights = None
        self._problems: dict[float, object] = {}
        self._blocks: dict[tuple[float, float, float], ComplexArray] = {}
        self.unit = 1.0
        A = self.hill(z0)
        U, sv, Vh = np.linalg.svd(A)
        self.unit = 1.0 / sv[0]   # A scaled to unit norm at the start: g ~ 1 / cond
        self.c, self.b = Vh[-1].copy(), U[:, -1].copy()

    def embed(self, z: FloatArray) -> FloatArray:
        """The base z ``(x, lam1, lam2)`` (theta dropped)."""
        return np.delete(np.asarray(z, dtype=float), -2)

    def theta(self, z: FloatArray) -> float:
        return float(z[-2])

    def hill(self, z: FloatArray) -> ComplexArray:
        zb = self.embed(z)
        _, lam1, lam2 = self.base.from_z(zb)
        X = self.base.coefficients(zb)
        if lam2 not in self._problems:
            if len(self._problems) > 4:
                self._problems.clear()
            self._problems[lam2] = self.base.problem.first(lam2)
        key = (lam1, self.theta(z), lam2)
        if key not in self._blocks:   # the linear part: only the orbit changes with x
            if len(self._blocks) > 8:
                self._blocks.clear()
            self._blocks[key] = receptance_blocks(self._problems[lam2], lam1,
                                                  self.theta(z), self.K)
        return self.unit * shifted_hill(self._problems[lam2], X, lam1, self.theta(z),
                                        self.K, self.base.N, blocks=self._blocks[key])

    def admissible(self, z: FloatArray) -> bool:
        return (self.base.admissible(self.embed(z))
                and -THETA_MARGIN < self.theta(z) < 0.5 + THETA_MARGIN)

    def g(self, z: FloatArray) -> complex:
        return bordered(self.hill(z), self.b, self.c)[1]

    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        z = np.asarray(z, dtype=float)
        R, J = self.base.evaluate(self.embed(z))
        g0 = self.g(z)
        dg = np.empty(z.size, dtype=complex)
        for i in range(z.size):
            dz = np.zeros_like(z)
            dz[i] = self.fd_step
            dg[i] = (self.g(z + dz) - self.g(z - dz)) / (2 * self.fd_step)
        Jn = np.zeros((self.n, z.size))
        Jn[: self.base.n, : self.base.n + 1] = J[:, : self.base.n + 1]
        Jn[: self.base.n, -1] = J[:, -1]
        Jn[-2], Jn[-1] = dg.real, dg.imag
        return np.concatenate([R, [g0.real, g0.imag]]), Jn

    def update_border(self, z: FloatArray) -> None:
        """b, c <- the unit left and right null vectors of A at z (bordered solves,
        conjugated: :func:`~rotorsfd.continuation.folds.unit_borders`)."""
        borders = unit_borders(*bordered_null_vectors(self.hill(z), self.b, self.c)[:2])
        if borders is not None:
            self.c, self.b = borders


#: Largest relative move of lam1 from the given secondary Hopf to the curve's first point
#: (a located Hopf is within the locating tolerance, ~1e-6; more is another solution).
START_RTOL = 1e-3


def continue_neimark_sacker(problem: TwoParameterProblem, X: ComplexArray, lam1: float,
                            lam2: float, theta: float, lam2_range: tuple[float, float], *,
                            H: int, N: int, K: int, scales: tuple[float, float],
                            options: FoldOptions | None = None, limit_max: float = 1.0,
                            on_point: Callable[[FloatArray, int], None] | None = None,
                            event_xtol: float = 1e-10,
                            ) -> tuple[TwoParameterHB, FoldBranch]:
    """The Neimark-Sacker curve through the secondary Hopf near ``(X, lam1, theta)`` at
    ``lam2`` (X the period-1 coefficients (H+1, n_dof), theta = arg(mu) / 2 pi of the
    critical multiplier, in (0, 1/2)), continued from lam2 towards ``lam2_range[1]``
    (physical units, scaled by ``scales``) with K shifted harmonic pairs. Points
    ``z = (x, lam1, theta, lam2)`` scaled; ``leg.system.embed(z)`` gives the base z.
    The curve ends where theta reaches 0 or 1/2 (a 1:1 or 1:2 resonance: the pair meets
    at +1 or -1): :func:`resonance_end`, the last point, and ``leg.ended_at`` is 0
    (theta = 0) or 1 (theta = 1/2)."""
    template = problem.first(lam2)
    xs0 = to_real(np.asarray(X))[:, template.nl_dofs]
    hb = TwoParameterHB(problem, H, N, scales, xs0, (lam1, lam2), limit_max=limit_max)
    zb = hb.to_z(xs0, lam1, lam2)
    z0 = np.concatenate([zb[:-1], [theta], zb[-1:]])
    ns = NeimarkSackerSystem(hb, z0, K)
    lo, hi = lam2_range[0] / scales[1], lam2_range[1] / scales[1]
    h = (min(THETA_FIT, abs(theta) / 4), min(THETA_FIT, abs(0.5 - theta) / 4))
    leg = continue_folds(hb, z0, (lo, hi), options, on_point=on_point,
                         lam_physical=lambda s: s * scales[1],
                         augmented=lambda base, z: ns,
                         events=(lambda z: float(z[-2]) - 0.5 * h[0],
                                 lambda z: 0.5 - 0.5 * h[1] - float(z[-2])),
                         event_xtol=event_xtol)
    if leg.z.shape[0]:
        start = hb.from_z(ns.embed(leg.z[0]))[1]
        if abs(start - lam1) > START_RTOL * abs(lam1):
            raise ConvergenceError(
                f"the Neimark-Sacker equations from the secondary Hopf at {lam1:.6g} "
                f"converged at {start:.6g} (theta {float(leg.z[0][-2]):.4g}): another "
                "solution, not that point; no curve from it")
    if leg.ended_at is not None:
        leg = resonance_end(leg, options.tol if options else 1e-8, h[leg.ended_at])
    return hb, leg


def resonance_end(leg: FoldBranch, tol: float = 1e-8, step: float = THETA_FIT
                  ) -> FoldBranch:
    """The 1:1 (``leg.ended_at`` 0) or 1:2 (1) resonance at the end of a Neimark-Sacker
    leg, extrapolated to theta = t (0 or 1/2) and stored as its last point.

    At t the curve meets a second solution set of the same equations (at theta = 0 the
    shifted Hill operator is real-equivalent, so Im g = 0 there identically, and every
    point where it is singular, a +1 curve, solves them; at 1/2 the period-doubling
    curve): a branch point, where the continuation may slide onto the other set rather
    than pass. So the end is not located on theta itself: the curve is mirror-symmetric
    about t (theta -> -theta, or 1 - theta: the same multiplier pair), its unknowns even
    functions of (theta - t), and the points solved at fixed theta = t +- j * step
    (j = 1, 2, 3; Newton on the NS equations from the nearest curve point) are fitted by
    ``c0 + c1 u + c2 u^2``, ``u = (theta - t)^2``: c0, error O(step^6), is the end.
    Points of the leg closer to t than ``step`` are dropped (they may lie on the other set).
    """
    t = 0.0 if leg.ended_at == 0 else 0.5
    side = 1.0 if leg.ended_at == 0 else -1.0
    system = leg.system
    e = np.zeros(system.n + 1)
    e[-2] = 1.0
    keep = np.flatnonzero(side * (leg.z[:, -2] - t) >= step)
    if keep.size == 0:
        return leg
    last = int(keep[-1])
    thetas, zs = [], []
    for j in (1, 2, 3):
        th = t + side * j * step
        z0 = leg.z[int(np.argmin(np.abs(leg.z[: last + 1, -2] - th)))]
        res = newton_extended(system, z0, e, th, tol, 30)
        if not res.converged:
            return leg
        thetas.append(th)
        zs.append(res.z)
    u = (np.asarray(thetas) - t) ** 2
    V = np.vander(u, 3, increasing=True)
    z_end = np.linalg.solve(V, np.asarray(zs))[0]
    z_end[-2] = t
    d = float(np.linalg.norm(z_end - leg.z[last]))
    return dataclasses.replace(
        leg, z=np.vstack([leg.z[: last + 1], z_end]),
        tangents=np.vstack([leg.tangents[: last + 1], leg.tangents[last]]),
        s=np.append(leg.s[: last + 1], leg.s[last] + d),
        segment=np.append(leg.segment[: last + 1], leg.segment[last]),
        cusps=[c for c in leg.cusps if c.index <= last])

