"""Structural (non-rotating) damping models of the rotor.

Both act on the assembled, supported, non-rotating rotor (M, K including the support
stiffness, dense or scipy.sparse) and return a symmetric damping matrix added to C:
Rayleigh damping keeps the band (sparse in, sparse out); modal damping is a full matrix
(dense). Modal damping of the lowest ``modes`` modes only is also available as its factors
``C_s = U diag(c) U^T`` (``U = M Phi`` n x r): a low-rank term that the harmonic-balance
solvers apply beside the banded rest (Woodbury), without forming the dense matrix.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from rotorsfd.errors import ConfigError
from rotorsfd.model.sparse import lanczos_start

#: Up to this many DOFs the modes of :class:`ModalDamping` come from a dense ``eigh``
#: (every mode); above, with ``modes`` given, from shift-invert Lanczos (those modes only).
DENSE_EIGH_MAX_DOF = 400


@dataclass(frozen=True)
class RayleighDamping:
    """Proportional damping ``C_s = alpha M + beta K``."""

    alpha: float
    beta: float

    def matrix(self, mass, stiffness):
        """C_s = alpha M + beta K (sparse for sparse M, K)."""
        return self.alpha * mass + self.beta * stiffness


@dataclass(frozen=True)
class ModalDamping:
    """Equal modal damping ratio zeta on the undamped non-rotating modes (all of them, or
    the lowest ``modes``).

    With the mass-normalised modes ``Phi`` (``Phi^T M Phi = I``, ``Phi^T K Phi = diag w^2``
    of the symmetric part of K): ``C_s = M Phi diag(2 zeta w_r) Phi^T M``, so that
    ``Phi^T C_s Phi = diag(2 zeta w_r)`` (0 beyond the lowest ``modes`` when given).
    Rigid-body modes (w = 0) get no damping.
    """

    ratio: float
    modes: int | None = None

    def __post_init__(self) -> None:
        if not 0.0 <= self.ratio:
            raise ConfigError("damping.ratio", self.ratio, "must be >= 0")
        if self.modes is not None and self.modes < 1:
            raise ConfigError("damping.modes", self.modes, "must be an integer >= 1")

    def factors(self, mass, stiffness) -> tuple[np.ndarray, np.ndarray]:
        """(U (n, r), c (r,)) with ``C_s = U diag(c) U^T``, ``U = M Phi``,
        ``c = 2 zeta w`` (the modes with w > 0 only). Dense eigh of every mode when
        ``modes`` is None or n <= DENSE_EIGH_MAX_DOF (the lowest ``modes`` kept), else
        shift-invert Lanczos for the lowest ``modes`` of the sparse pencil."""
        n = mass.shape[0]
        if self.modes is None or n <= DENSE_EIGH_MAX_DOF or not (
                sp.issparse(mass) and sp.issparse(stiffness)):
            m, k = (a.toarray() if sp.issparse(a) else np.asarray(a, dtype=float)
                    for a in (mass, stiffness))
            w2, phi = scipy.linalg.eigh(0.5 * (k + k.T), m)
            if self.modes is not None:
                w2, phi = w2[: self.modes], phi[:, : self.modes]
            u = m @ phi
        else:
            # deferred: scipy.sparse.linalg is heavy (loaded only when this runs)
            import scipy.sparse.linalg as spla

            m = sp.csc_matrix(mass, dtype=float)
            k = sp.csc_matrix(0.5 * (stiffness + stiffness.T), dtype=float)
            # shift below zero: a free rotor's rigid-body modes keep K singular
            scale = float(abs(k.diagonal()).max() / max(abs(m.diagonal()).max(), 1e-300))
            r = min(self.modes, n - 2)
            w2, phi = spla.eigsh(k, k=r, M=m, sigma=-1e-9 * scale, which="LM",
                                 v0=lanczos_start(n))     # the same factors every call
            order = np.argsort(w2)
            w2, phi = w2[order], phi[:, order]
            u = m @ phi
        w = np.sqrt(np.clip(w2, 0.0, None))
        keep = w > 0.0
        return np.ascontiguousarray(u[:, keep]), 2.0 * self.ratio * w[keep]

    def matrix(self, mass: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
        """C_s = M Phi diag(2 zeta w_r) Phi^T M (dense)."""
        u, c = self.factors(mass, stiffness)
        out = (u * c) @ u.T
        return 0.5 * (out + out.T)
