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

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import scipy.linalg

from rotorsfd.errors import ConfigError, ConvergenceError

RIGID_BODY_TOL = 1e-7


@runtime_checkable
class LinearDynamics(Protocol):
    """Any object with ``n_dof`` and ``matrices(speed) -> (M, D, K)``, D containing speed*G."""

    n_dof: int

    def matrices(self, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...


@dataclass(frozen=True)
class ModalResult:
    """Modes at one speed, sorted by damped frequency (``n_modes`` of them)."""

    speed: float
    eigenvalues: np.ndarray      # (n_modes,) complex, Im > 0
    mode_shapes: np.ndarray      # (n_dof, n_modes) complex, largest translation = 1
    whirl: np.ndarray            # (n_modes,) "forward" | "backward"

    @property
    def frequencies(self) -> np.ndarray:
        """Damped natural frequencies Im(lambda) [rad/s]."""
        return self.eigenvalues.imag

    @property
    def natural_frequencies(self) -> np.ndarray:
        """Undamped-equivalent |lambda| [rad/s]."""
        return np.abs(self.eigenvalues)

    @property
    def damping_ratios(self) -> np.ndarray:
        """zeta = -Re(lambda) / |lambda|."""
        return -self.eigenvalues.real / np.abs(self.eigenvalues)

    @property
    def log_decrements(self) -> np.ndarray:
        """delta = -2 pi Re(lambda) / Im(lambda)."""
        return -2.0 * np.pi * self.eigenvalues.real / self.eigenvalues.imag


def state_matrix(mass: np.ndarray, damping: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
    """A = [[0, I], [-M^-1 K, -M^-1 D]] (M must be positive definite)."""
    n = mass.shape[0]
    try:
        factor = scipy.linalg.cho_factor(mass)
    except np.linalg.LinAlgError as exc:
        raise ConvergenceError(f"mass matrix is not positive definite: {exc}") from None
    a = np.zeros((2 * n, 2 * n))
    a[:n, n:] = np.eye(n)
    a[n:, :n] = -scipy.linalg.cho_solve(factor, stiffness)
    a[n:, n:] = -scipy.linalg.cho_solve(factor, damping)
    return a


def _forward_backward(shapes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Forward and backward circular components phi_y + i phi_z, phi_y - i phi_z per node."""
    y, z = shapes[0::4], shapes[1::4]
    return y + 1j * z, y - 1j * z


def whirl_direction(shape: np.ndarray) -> str:
    """"forward" if |phi_y + i phi_z| >= |phi_y - i phi_z| at the node of largest
    translational amplitude |phi_y|^2 + |phi_z|^2, else "backward"."""
    y, z = shape[0::4], shape[1::4]
    amp = np.abs(y) ** 2 + np.abs(z) ** 2
    if amp.max() <= 1e-12 * max(np.abs(shape).max(), 1e-300):  # pure tilt: use slopes
        y, z = shape[3::4], -shape[2::4]                        # (tz, -ty) ~ (y', z')
        amp = np.abs(y) ** 2 + np.abs(z) ** 2
    k = int(np.argmax(amp))
    return "forward" if abs(y[k] + 1j * z[k]) >= abs(y[k] - 1j * z[k]) else "backward"


def _split_degenerate(lam: np.ndarray, vecs: np.ndarray, rtol: float = 1e-7) -> np.ndarray:
    """Within pairs of (numerically) equal eigenvalues, rotate the eigenvectors to the
    combinations extremising ||f||^2 - ||b||^2 (forward minus backward circular content)."""
    vecs = vecs.copy()
    i = 0
    scale = max(np.abs(lam).max(), 1e-300) if lam.size else 1.0
    while i < lam.size - 1:
        if abs(lam[i + 1] - lam[i]) <= rtol * max(abs(lam[i]), 1e-12 * scale):
            v = vecs[:, i:i + 2]
            f, b = _forward_backward(v)
            h = f.conj().T @ f - b.conj().T @ b
            g = v.conj().T @ v
            try:
                _, c = scipy.linalg.eigh(h, g)   # ascending: backward-most first
                vecs[:, i:i + 2] = v @ c
            except np.linalg.LinAlgError:
                pass
            i += 2
        else:
            i += 1
    return vecs


def _normalise(shapes: np.ndarray) -> np.ndarray:
    """Scale each column so that its largest translational entry is 1 (real)."""
    out = shapes.copy()
    trans = np.zeros(shapes.shape[0], dtype=bool)
    trans[0::4] = trans[1::4] = True
    for j in range(shapes.shape[1]):
        col = shapes[:, j]
        sub = np.where(trans, col, 0.0)
        if np.abs(sub).max() < 1e-12 * np.abs(col).max():
            sub = col
        k = int(np.argmax(np.abs(sub)))
        out[:, j] = col / col[k]
    return out


DENSE_MAX_DOF = 200   # method "auto": dense eig up to this many DOF, sparse above


def kept_roots(lam: np.ndarray, scale: float) -> np.ndarray:
    """Mask of the roots that are modes: Im > 1e-9 scale (not overdamped, one of each
    conjugate pair) and |lambda| > RIGID_BODY_TOL * scale (not rigid-body)."""
    # rigid-body roots (lambda = 0, defective) come out as noise ~ 1e-8 max|lambda|
    return (lam.imag > max(1e-9 * scale, 1e-12)) & (np.abs(lam) > RIGID_BODY_TOL * scale)


def select_modes(lam: np.ndarray, vecs: np.ndarray, speed: float, n_modes: int,
                 scale: float) -> ModalResult:
    """The ``n_modes`` lowest modes in damped frequency from roots ``lam`` and their
    displacement parts ``vecs`` (n_dof, n_roots): overdamped (real) and rigid-body roots
    (|lambda| < RIGID_BODY_TOL * scale, scale ~ max|lambda|) dropped, degenerate pairs
    split into forward/backward, shapes normalised, whirl classified."""
    keep = kept_roots(lam, scale)
    lam, vecs = lam[keep], vecs[:, keep]
    order = np.argsort(lam.imag, kind="stable")
    lam, vecs = lam[order][:n_modes], vecs[:, order][:, :n_modes]
    vecs = _normalise(_split_degenerate(lam, vecs))
    whirl = np.array([whirl_direction(vecs[:, j]) for j in range(vecs.shape[1])], dtype="<U8")
    return ModalResult(float(speed), lam, vecs, whirl)


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
        from rotorsfd.linear.sparse_modes import sparse_eigen

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
