"""The mode record, the ``LinearDynamics`` protocol and the rule that picks the modes from
the roots of ``det(lambda^2 M + lambda D + K) = 0``, shared by the dense and the sparse
eigensolvers (:mod:`rotorsfd.linear.modal`, :mod:`rotorsfd.linear.sparse_modes`); the
definitions (damping ratio, log decrement, whirl direction) are in the former's docstring.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol, runtime_checkable

import numpy as np
import scipy.linalg

from rotorsfd.errors import ConvergenceError

RIGID_BODY_TOL = 1e-7


class EigenvalueMeasures:
    """What the eigenvalues ``lambda = -zeta w_n + i w_d`` of a result (its
    ``eigenvalues`` attribute, any shape) say, for the modal and the Campbell results."""

    eigenvalues: np.ndarray

    @property
    def frequencies(self) -> np.ndarray:
        """Damped natural frequencies Im(lambda) [rad/s]."""
        return self.eigenvalues.imag

    @property
    def damping_ratios(self) -> np.ndarray:
        """zeta = -Re(lambda) / |lambda|."""
        return -self.eigenvalues.real / np.abs(self.eigenvalues)

    @property
    def log_decrements(self) -> np.ndarray:
        """delta = -2 pi Re(lambda) / Im(lambda)."""
        return -2.0 * np.pi * self.eigenvalues.real / self.eigenvalues.imag


@runtime_checkable
class LinearDynamics(Protocol):
    """Any object with ``n_dof`` and ``matrices(speed) -> (M, D, K)``, D containing speed*G."""

    n_dof: int

    def matrices(self, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]: ...


@dataclass(frozen=True)
class ModalResult(EigenvalueMeasures):
    """Modes at one speed, sorted by damped frequency (``n_modes`` of them)."""

    speed: float
    eigenvalues: np.ndarray      # (n_modes,) complex, Im > 0
    mode_shapes: np.ndarray      # (n_dof, n_modes) complex, largest translation = 1
    whirl: np.ndarray            # (n_modes,) "forward" | "backward"

    @property
    def natural_frequencies(self) -> np.ndarray:
        """Undamped-equivalent |lambda| [rad/s]."""
        return np.abs(self.eigenvalues)


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


def normalise_shapes(shapes: np.ndarray) -> np.ndarray:
    """Scale each column so that its largest translational entry is 1 (real): all columns
    at once (one pass over the n x m shapes instead of m; the same divisions)."""
    if shapes.shape[1] == 0:
        return shapes.copy()
    trans = np.zeros(shapes.shape[0], dtype=bool)
    trans[0::4] = trans[1::4] = True
    mag = np.abs(shapes)
    sub = np.where(trans[:, None], mag, 0.0)
    tilt = sub.max(axis=0) < 1e-12 * mag.max(axis=0)      # no translation: all entries
    k = np.where(tilt, np.argmax(mag, axis=0), np.argmax(sub, axis=0))
    return shapes / shapes[k, np.arange(shapes.shape[1])]


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
    vecs = normalise_shapes(_split_degenerate(lam, vecs))
    whirl = np.array([whirl_direction(vecs[:, j]) for j in range(vecs.shape[1])], dtype="<U8")
    return ModalResult(float(speed), lam, vecs, whirl)
