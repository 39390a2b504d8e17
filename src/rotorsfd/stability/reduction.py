"""Craig-Bampton reduction of the constant linear part, keeping the nonlinear DOFs physical.

``q = Psi p``, ``p = [q_b, eta]``, with ``q_b`` the boundary (nonlinear) DOFs and::

    Psi = [[ I            , 0     ],      (rows: boundary DOFs b)
           [ -K_ii^-1 K_ib, Phi_f ]]      (rows: interior DOFs i)

``Phi_f``: fixed-interface modes ``K_ii^s phi = omega^2 M_ii^s phi`` (symmetric parts, used
as a Ritz basis only). Reduced matrices by Galerkin projection ``Psi^T X Psi`` of the full
(possibly non-symmetric, gyroscopic) M, D, K. Because the boundary coordinates stay
physical, the nonlinear Jacobians act on ``p[:m]`` unchanged.

Why: with ``h = T/N`` the average-acceleration scheme cannot resolve modes with
``omega h >~ 1`` and maps lightly damped ones onto ``|mu| ~ 1`` (false bifurcations).
Dropping interior modes above ``omega_max`` keeps their quasi-static effect (constraint
modes) and removes the unresolved dynamics.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg as sla
from numpy.typing import ArrayLike, NDArray

from rotorsfd.errors import ConfigError


@dataclass(frozen=True)
class ReducedModel:
    """Reduced second-order model ``M_r p'' + D_r p' + K_r p = P_r^T F_nl``.

    ``basis`` maps reduced to physical coordinates (``q = basis @ p``); the nonlinear DOFs
    are the reduced coordinates ``nl_dofs = 0..m-1``; ``omegas`` are the kept
    fixed-interface natural frequencies [rad/s].
    """

    M: NDArray[np.float64]
    D: NDArray[np.float64]
    K: NDArray[np.float64]
    basis: NDArray[np.float64]
    nl_dofs: NDArray[np.intp]
    omegas: NDArray[np.float64]

    @property
    def n_dof(self) -> int:
        return self.M.shape[0]


def craig_bampton(M: ArrayLike, D: ArrayLike, K: ArrayLike, boundary_dofs: ArrayLike, *,
                  n_modes: int | None = None,
                  omega_max: float | None = None) -> ReducedModel:
    """Craig-Bampton model keeping ``boundary_dofs`` and fixed-interface modes.

    Modes kept: the ``n_modes`` lowest, or all with ``omega <= omega_max`` (if both are
    given, the smaller set). At least one of them is required.
    """
    M = np.asarray(M, float)
    D = np.asarray(D, float)
    K = np.asarray(K, float)
    n = M.shape[0]
    b = np.asarray(boundary_dofs, dtype=np.intp).ravel()
    if n_modes is None and omega_max is None:
        raise ConfigError("n_modes/omega_max", None, "give at least one of them")
    i = np.setdiff1d(np.arange(n), b)
    Kii, Kib = K[np.ix_(i, i)], K[np.ix_(i, b)]
    try:
        phi_c = -np.linalg.solve(Kii, Kib)
    except np.linalg.LinAlgError as exc:
        raise ConfigError("K", "singular interior stiffness",
                          "interior must be restrained once the boundary DOFs are fixed"
                          ) from exc
    Ks = 0.5 * (Kii + Kii.T)
    Ms = 0.5 * (M[np.ix_(i, i)] + M[np.ix_(i, i)].T)
    w2, modes = sla.eigh(Ks, Ms)
    omegas = np.sqrt(np.clip(w2, 0.0, None))
    keep = np.ones(omegas.size, bool)
    if omega_max is not None:
        keep &= omegas <= omega_max
    if n_modes is not None:
        keep &= np.arange(omegas.size) < n_modes
    modes, omegas = modes[:, keep], omegas[keep]
    m, k = b.size, modes.shape[1]
    psi = np.zeros((n, m + k))
    psi[b, :m] = np.eye(m)
    psi[np.ix_(i, np.arange(m))] = phi_c
    psi[np.ix_(i, np.arange(m, m + k))] = modes
    return ReducedModel(psi.T @ M @ psi, psi.T @ D @ psi, psi.T @ K @ psi, psi,
                        np.arange(m), omegas)
