"""Structural (non-rotating) damping models of the rotor.

Both act on the assembled, supported, non-rotating rotor (M, K including the support
stiffness, dense or scipy.sparse) and return a symmetric damping matrix added to C:
Rayleigh damping keeps the band (sparse in, sparse out); modal damping is a full matrix
(dense).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.sparse as sp

from rotorsfd.errors import ConfigError


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
    """Equal modal damping ratio zeta on every undamped non-rotating mode.

    With the mass-normalised modes ``Phi`` (``Phi^T M Phi = I``, ``Phi^T K Phi = diag w^2``
    of the symmetric part of K): ``C_s = M Phi diag(2 zeta w_r) Phi^T M``, so that
    ``Phi^T C_s Phi = diag(2 zeta w_r)``. Rigid-body modes (w = 0) get no damping.
    """

    ratio: float

    def __post_init__(self) -> None:
        if not 0.0 <= self.ratio:
            raise ConfigError("damping.ratio", self.ratio, "must be >= 0")

    def matrix(self, mass: np.ndarray, stiffness: np.ndarray) -> np.ndarray:
        """C_s = M Phi diag(2 zeta w_r) Phi^T M (dense)."""
        mass, stiffness = (a.toarray() if sp.issparse(a) else np.asarray(a, dtype=float)
                           for a in (mass, stiffness))
        k_sym = 0.5 * (stiffness + stiffness.T)
        w2, phi = scipy.linalg.eigh(k_sym, mass)
        w = np.sqrt(np.clip(w2, 0.0, None))
        mp = mass @ phi
        c = (mp * (2.0 * self.ratio * w)) @ mp.T
        return 0.5 * (c + c.T)
