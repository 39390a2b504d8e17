"""Complex modes of a linear rotor at one spin speed.

For ``M q'' + D q' + K q = 0`` (``D = C + Omega G``, any ``LinearDynamics`` system) the
state ``x = [q, q']`` obeys ``x' = A x`` with ``A = [[0, I], [-M^-1 K, -M^-1 D]]``; a mode
``q = phi exp(lambda t)``, ``lambda = -zeta w_n + i w_d``. Reported per mode (one of each
conjugate pair, ``Im lambda > 0``, sorted by ``w_d``):

    frequency      w_d = Im(lambda)                 [rad/s] (damped natural frequency)
    damping ratio  zeta = -Re(lambda) / |lambda|
    log decrement  delta = 2 pi zeta / sqrt(1 - zeta^2) = -2 pi Re(lambda) / Im(lambda)

Whirl direction: at the node of largest translational amplitude the orbit is
``y + i z = A_f exp(i w t) + A_b exp(-i w t)`` with ``A_f = (phi_y + i phi_z) / 2``,
``A_b = conj(phi_y - i phi_z) / 2``; the mode whirls "forward" (with the spin, from +y to
+z about +x) when ``|A_f| >= |A_b|``, else "backward". Repeated eigenvalues (an isotropic
rotor at rest) are split into their forward and backward circular combinations first.
"""

from __future__ import annotations

import numpy as np
import scipy.linalg

from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.linear.modes import (
    DENSE_MAX_DOF,
    RIGID_BODY_TOL,
    LinearDynamics,
    ModalResult,
    kept_roots,
    select_modes,
    state_matrix,
    whirl_direction,
)
from rotorsfd.linear.sparse_modes import sparse_eigen

__all__ = ["DENSE_MAX_DOF", "RIGID_BODY_TOL", "LinearDynamics", "ModalResult", "dense_eigen",
           "eigen", "kept_roots", "log_decrement", "mac", "mode_shapes", "select_modes",
           "state_matrix", "use_sparse", "whirl_direction"]


def dense_eigen(system: LinearDynamics, speed: float, n_modes: int = 8) -> ModalResult:
    """:func:`eigen` by ``scipy.linalg.eig`` of the whole 2n state matrix (the reference)."""
    mass, damping, stiffness = (np.asarray(m, dtype=float) for m in system.matrices(speed))
    n = mass.shape[0]
    lam, vecs = scipy.linalg.eig(state_matrix(mass, damping, stiffness))
    if not np.all(np.isfinite(lam)):
        raise ConvergenceError(f"non-finite eigenvalues at speed {speed} rad/s")
    scale = np.abs(lam).max() if lam.size else 1.0
    return select_modes(lam, vecs[:n], speed, n_modes, scale)


def eigen(system: LinearDynamics, speed: float, n_modes: int = 8,
          method: str = "auto") -> ModalResult:
    """Complex modes of ``system`` at spin ``speed`` [rad/s], the ``n_modes`` lowest in
    damped frequency. Overdamped (real) roots and rigid-body roots are dropped; a root is
    taken as rigid-body when |lambda| < RIGID_BODY_TOL * max|lambda|. ``method``: "dense"
    (every root of the state matrix), "sparse" (shift-invert Arnoldi for the few lowest,
    :mod:`rotorsfd.linear.sparse_modes`) or "auto" (dense up to DENSE_MAX_DOF DOF)."""
    if use_sparse(system, method):
        return sparse_eigen(system, speed, n_modes)
    return dense_eigen(system, speed, n_modes)


def use_sparse(system: LinearDynamics, method: str) -> bool:
    """True for method "sparse", or "auto" above DENSE_MAX_DOF; ConfigError otherwise."""
    if method not in ("auto", "dense", "sparse"):
        raise ConfigError("method", method, "one of 'auto', 'dense', 'sparse'")
    return method == "sparse" or (method == "auto" and system.n_dof > DENSE_MAX_DOF)


def mode_shapes(system: LinearDynamics, speed: float, n_modes: int = 8) -> np.ndarray:
    """(n_dof, n_modes) complex mode shapes at ``speed`` (see :func:`eigen`)."""
    return eigen(system, speed, n_modes).mode_shapes


def log_decrement(system: LinearDynamics, speed: float, n_modes: int = 8) -> np.ndarray:
    """Logarithmic decrements of the ``n_modes`` lowest modes at ``speed``."""
    return eigen(system, speed, n_modes).log_decrements


def mac(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """Modal assurance criterion |a_i^H b_j|^2 / (|a_i|^2 |b_j|^2) between columns."""
    num = np.abs(a.conj().T @ b) ** 2
    den = np.outer(np.sum(np.abs(a) ** 2, axis=0), np.sum(np.abs(b) ** 2, axis=0))
    return num / den
