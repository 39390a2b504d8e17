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
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from rotorsfd.errors import ConfigError
from rotorsfd.model.lowrank import project
from rotorsfd.model.sparse import DENSE_MAX_DOF, lanczos_start


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
    given, the smaller set). At least one of them is required. M, D, K dense or
    scipy.sparse (then no dense n x n matrix is formed: :class:`FixedInterfaceBasis`).
    """
    if n_modes is None and omega_max is None:
        raise ConfigError("n_modes/omega_max", None, "give at least one of them")
    return FixedInterfaceBasis(M, K, boundary_dofs).reduce(D, n_modes, omega_max)


class FixedInterfaceBasis:
    """Craig-Bampton pieces of one (M, K): the constraint modes ``-K_ii^-1 K_ib`` and the
    fixed-interface modes (module docstring), reused for any D.

    Dense M, K (or at most ``rotorsfd.model.sparse.DENSE_MAX_DOF`` DOFs): every mode by
    ``scipy.linalg.eigh``. Sparse (scipy.sparse) M, K of a larger model: the constraint
    modes by one sparse LU of ``K_ii`` and only the modes asked for by shift-invert Lanczos
    (``eigsh``, sigma = 0) on the symmetric parts, their number doubled until the highest
    one found exceeds ``omega_max`` (or ``n_modes`` are found); the projections
    ``Psi^T X Psi`` as sparse-times-(n x r) products. ``matches(M, K)`` tells whether a
    basis is for these matrices (the same objects, or equal).
    """

    def __init__(self, M: ArrayLike, K: ArrayLike, boundary_dofs: ArrayLike) -> None:
        self.M, self.K = M, K
        n = M.shape[0]
        self.nl = np.asarray(boundary_dofs, dtype=np.intp).ravel()
        self.i = i = np.setdiff1d(np.arange(n), self.nl)
        self.sparse = sp.issparse(M) and sp.issparse(K) and n > DENSE_MAX_DOF
        if not self.sparse:
            Md = M.toarray() if sp.issparse(M) else np.asarray(M, float)
            Kd = K.toarray() if sp.issparse(K) else np.asarray(K, float)
            self.M, self.K = Md, Kd
            try:
                self.phi_c = -np.linalg.solve(Kd[np.ix_(i, i)], Kd[np.ix_(i, self.nl)])
            except np.linalg.LinAlgError as exc:
                raise _singular_interior() from exc
            Ks = 0.5 * (Kd[np.ix_(i, i)] + Kd[np.ix_(i, i)].T)
            Ms = 0.5 * (Md[np.ix_(i, i)] + Md[np.ix_(i, i)].T)
            w2, self.modes = sla.eigh(Ks, Ms)
            self.omegas = np.sqrt(np.clip(w2, 0.0, None))
        else:
            # deferred: scipy.sparse.linalg is heavy (loaded only when this runs)
            import scipy.sparse.linalg as spla

            self.M, self.K = sp.csr_matrix(M), sp.csr_matrix(K)
            Kii = self.K[i][:, i].tocsc()
            try:
                lu = spla.splu(Kii)
            except RuntimeError as exc:
                raise _singular_interior() from exc
            self.phi_c = -lu.solve(self.K[i][:, self.nl].toarray())
            Mii = self.M[i][:, i]
            self._Ks = (0.5 * (Kii + Kii.T)).tocsc()
            self._Ms = (0.5 * (Mii + Mii.T)).tocsc()
            self.modes = np.zeros((i.size, 0))
            self.omegas = np.zeros(0)
            self._complete = False
        self._models: dict[int, tuple[NDArray, NDArray, NDArray]] = {}

    def matches(self, M: ArrayLike, K: ArrayLike) -> bool:
        """Whether this basis is for (M, K): the same objects or equal entries."""
        def same(a, b) -> bool:
            if a is b:
                return True
            if sp.issparse(a) or sp.issparse(b):
                a = a if sp.issparse(a) else sp.csr_matrix(np.asarray(a, float))
                b = b if sp.issparse(b) else sp.csr_matrix(np.asarray(b, float))
                return a.shape == b.shape and (a != b).nnz == 0
            return np.array_equal(a, b)
        return same(M, self.M) and same(K, self.K)

    def _lowest(self, n_modes: int | None, omega_max: float | None) -> None:
        """Sparse: make sure the modes asked for are computed (module docstring; a fixed
        start vector, so the same modes bit for bit on every call)."""
        # deferred: scipy.sparse.linalg is heavy (loaded only when this runs)
        import scipy.sparse.linalg as spla

        ni = self.i.size
        while not self._complete:
            have = self.omegas.size
            if n_modes is not None and have >= n_modes:
                return
            if omega_max is not None and have and self.omegas[-1] > omega_max:
                return
            k = max(2 * have, 12, (n_modes or 0) + 2)
            if k >= ni - 1:   # (nearly) all: the dense problem is no larger
                w2, modes = sla.eigh(self._Ks.toarray(), self._Ms.toarray())
                self._complete = True
            else:
                w2, modes = spla.eigsh(self._Ks, k=k, M=self._Ms, sigma=0.0, which="LM",
                                       v0=lanczos_start(ni))
                order = np.argsort(w2)
                w2, modes = w2[order], modes[:, order]
            self.omegas = np.sqrt(np.clip(w2, 0.0, None))
            self.modes = modes

    def reduce(self, D: ArrayLike, n_modes: int | None, omega_max: float | None
               ) -> ReducedModel:
        """The reduced model with damping D (dense, sparse or
        :class:`~rotorsfd.model.lowrank.BandedLowRank`) and the modes kept by
        ``n_modes`` / ``omega_max`` (:func:`craig_bampton`)."""
        if self.sparse:
            self._lowest(n_modes, omega_max)
        keep = np.ones(self.omegas.size, bool)
        if omega_max is not None:
            keep &= self.omegas <= omega_max
        if n_modes is not None:
            keep &= np.arange(self.omegas.size) < n_modes
        k = int(keep.sum())  # modes are sorted: the kept set is the first k
        if k not in self._models:
            m, n = self.nl.size, self.M.shape[0]
            psi = np.zeros((n, m + k))
            psi[self.nl, :m] = np.eye(m)
            psi[np.ix_(self.i, np.arange(m))] = self.phi_c
            psi[np.ix_(self.i, np.arange(m, m + k))] = self.modes[:, :k]
            if self.sparse:
                self._models[k] = (psi, psi.T @ (self.M @ psi), psi.T @ (self.K @ psi))
            else:
                self._models[k] = (psi, psi.T @ self.M @ psi, psi.T @ self.K @ psi)
        psi, Mr, Kr = self._models[k]
        Dr = project(D, psi)      # dense, CSR or banded + low-rank (modal damping)
        return ReducedModel(np.asarray(Mr), np.asarray(Dr), np.asarray(Kr),
                            psi, np.arange(self.nl.size), self.omegas[:k])


def _singular_interior() -> ConfigError:
    return ConfigError("K", "singular interior stiffness",
                       "interior must be restrained once the boundary DOFs are fixed")
