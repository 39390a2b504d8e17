"""Modes over a speed range from a reduced model built on exact modes at a few speeds.

The displacement parts of the exact lowest modes (sparse shift-invert,
:func:`rotorsfd.linear.sparse_modes.sparse_eigen`) at snapshot speeds, real and imaginary
parts, span the basis V (orthonormal, from an SVD that drops directions below
``SVD_RTOL`` = 1e-8 of the largest singular value). The Galerkin projection of the
affine pencil,

    (lambda^2 V^T M V + lambda V^T (D0 + Omega D1) V + V^T K V) y = 0,   q = V y,

(a low-rank modal damping ``U diag(c) U^T`` beside D0 projected as ``W^T diag(c) W``,
``W = U^T V``),

is solved densely at every speed. Its error is measured, not assumed: at the midpoint of
every two neighbouring snapshots the exact modes are computed and compared (largest
|lambda_r - lambda| / |lambda| over the modes asked for); where it exceeds ``tol`` the
midpoint becomes a snapshot, until every check passes or ``max_snapshots`` is reached.
The last measured error is kept (``ReducedModes.error``).
"""

from __future__ import annotations

from dataclasses import dataclass
from itertools import pairwise

import numpy as np
import scipy.linalg

from rotorsfd.errors import ConvergenceError
from rotorsfd.linear.modal import LinearDynamics, ModalResult, kept_roots, select_modes
from rotorsfd.linear.sparse_modes import pencil_of, sparse_eigen

GUARD_MODES = 2          # exact modes kept in the snapshots beyond the ones asked for
SVD_RTOL = 1e-8


def _relative_error(a: ModalResult, b: ModalResult, n_modes: int) -> float:
    """Largest |a_i - b_i| / |b_i| over the first ``n_modes`` (inf if a count differs)."""
    m = min(n_modes, b.eigenvalues.size)
    if a.eigenvalues.size < m:
        return float("inf")
    return float(np.max(np.abs(a.eigenvalues[:m] - b.eigenvalues[:m])
                        / np.abs(b.eigenvalues[:m]), initial=0.0))


@dataclass
class ReducedModes:
    """The projected pencil of ``system`` on the basis of exact modes at ``snapshots``."""

    basis: np.ndarray                 # (n_dof, r) orthonormal
    mass: np.ndarray                  # (r, r) V^T M V
    damping: tuple[np.ndarray, np.ndarray]   # V^T D0 V, V^T D1 V
    stiffness: tuple[np.ndarray, np.ndarray]
    snapshots: list[float]
    checks: list[float]
    error: float                      # largest relative eigenvalue error at ``checks``
    scale: float                      # lower bound of the full model's max|lambda|
    _inverse_mass: tuple[np.ndarray, ...] | None = None   # Mr^-1 K0, K1, D0, D1

    @classmethod
    def build(cls, system: LinearDynamics, exact: dict[float, ModalResult]) -> ReducedModes:
        """Basis and projected matrices from the exact modes at the speeds of ``exact``."""
        pencil = pencil_of(system)
        if pencil.terms is None:
            raise ConvergenceError("the reduced model needs matrices affine in the speed")
        shapes = np.hstack([r.mode_shapes for r in exact.values()])
        u, sv, _ = np.linalg.svd(np.hstack([shapes.real, shapes.imag]), full_matrices=False)
        v = u[:, sv > SVD_RTOL * sv[0]]
        (m0, _), (d0, d1), (k0, k1) = pencil.terms

        def project(a) -> np.ndarray:
            return v.T @ (a @ v)

        d0r = project(d0)
        if pencil.lowrank is not None:        # + W^T diag(c) W, W = U^T V (modal damping)
            U, c = pencil.lowrank
            W = U.T @ v
            d0r = d0r + W.T @ (c[:, None] * W)
        return cls(v, project(m0), (d0r, project(d1)), (project(k0), project(k1)),
                   sorted(exact), [], float("nan"), pencil.scale)

    def eigen(self, speed: float, n_modes: int) -> ModalResult:
        """The ``n_modes`` lowest modes of the reduced model at ``speed``."""
        r = self.basis.shape[1]
        if self._inverse_mass is None:
            try:
                factor = scipy.linalg.cho_factor(self.mass)
            except np.linalg.LinAlgError as exc:
                raise ConvergenceError(f"reduced mass matrix not positive definite: {exc}"
                                       ) from None
            self._inverse_mass = tuple(scipy.linalg.cho_solve(factor, x)
                                       for x in (*self.stiffness, *self.damping))
        k0, k1, d0, d1 = self._inverse_mass
        a = np.zeros((2 * r, 2 * r))
        a[:r, r:] = np.eye(r)
        a[r:, :r] = -(k0 + speed * k1)
        a[r:, r:] = -(d0 + speed * d1)
        lam, y = scipy.linalg.eig(a, overwrite_a=True, check_finite=False)
        scale = max(float(np.abs(lam).max()) if lam.size else 1.0, self.scale)
        # lift only the roots select_modes keeps (the same rule), the lowest n_modes
        keep = np.flatnonzero(kept_roots(lam, scale))
        keep = keep[np.argsort(lam.imag[keep], kind="stable")][:n_modes]
        yc = y[:r, keep]
        shapes = self.basis @ yc.real + 1j * (self.basis @ yc.imag)
        return select_modes(lam[keep], shapes, speed, n_modes, scale)


def reduced_modes(system: LinearDynamics, lo: float, hi: float, n_modes: int,
                  tol: float = 1e-9, max_snapshots: int = 17) -> ReducedModes:
    """Reduced model of ``system`` for the ``n_modes`` lowest modes over [lo, hi] rad/s,
    refined until its measured relative eigenvalue error is below ``tol`` (see module)."""
    n_snap = n_modes + GUARD_MODES
    exact = {float(s): sparse_eigen(system, float(s), n_snap) for s in (lo, 0.5 * (lo + hi), hi)}
    while True:
        model = ReducedModes.build(system, exact)
        speeds = model.snapshots
        mids = [0.5 * (a + b) for a, b in pairwise(speeds)]
        errors = {}
        for s in mids:
            ref = sparse_eigen(system, s, n_snap)
            errors[s] = (_relative_error(model.eigen(s, n_modes), ref, n_modes), ref)
        model.checks = mids
        model.error = max((e for e, _ in errors.values()), default=0.0)
        bad = [s for s, (e, _) in errors.items() if e > tol]
        if not bad or len(exact) >= max_snapshots:
            return model
        for s in bad[:max_snapshots - len(exact)]:
            exact[s] = errors[s][1]
