"""A damping matrix kept as a sparse (banded) part plus a low-rank modal term.

Modal damping of the lowest r modes (:class:`rotorsfd.model.damping.ModalDamping` with
``modes``) is ``C_s = U diag(c) U^T`` with ``U = M Phi`` (n x r): full as a matrix, rank r
as factors. :class:`BandedLowRank` holds ``D = B + U diag(c) U^T`` (B a CSR matrix: the
supports' damping, ``Omega G``, the base terms) and applies it without forming it::

    D x = B x + U (c * (U^T x))                   O(nnz(B) + 2 n r) per column
    Psi^T D Psi = Psi^T (B Psi) + (U^T Psi)^T diag(c) (U^T Psi)   (a Galerkin projection)

so the linear analyses, the Craig-Bampton projections of the Floquet basis and of the
time step and the sparse eigensolvers keep the band. ``toarray()`` forms the dense matrix
(small models and the reference tests only).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import scipy.sparse as sp


class BandedLowRank:
    """``D = B + U diag(c) U^T`` (module docstring): ``band`` CSR (n, n), ``U`` (n, r),
    ``c`` (r,). Supports ``D @ x`` (x of shape (n,) or (n, k)), ``shape``, ``toarray()``,
    ``T`` (itself transposed: ``B^T`` plus the same symmetric term) and ``+`` / ``*`` with
    a scalar or a sparse matrix (the sparse part changes, the low-rank term stays)."""

    __array_priority__ = 100.0      # ndarray @ D defers to __rmatmul__

    def __init__(self, band: Any, U: np.ndarray, c: np.ndarray) -> None:
        self.band = sp.csr_matrix(band, dtype=float)
        self.U = np.ascontiguousarray(U, dtype=float)
        self.c = np.asarray(c, dtype=float).reshape(-1)
        if self.U.shape != (self.band.shape[0], self.c.size):
            raise ValueError(f"U {self.U.shape} and c {self.c.shape} do not match the "
                             f"band {self.band.shape}")

    @property
    def shape(self) -> tuple[int, int]:
        return self.band.shape

    @property
    def ndim(self) -> int:
        return 2

    @property
    def lowrank(self) -> tuple[np.ndarray, np.ndarray]:
        """(U, c) of the low-rank term."""
        return self.U, self.c

    @property
    def T(self) -> BandedLowRank:
        return BandedLowRank(self.band.T.tocsr(), self.U, self.c)

    def lowrank_times(self, x: np.ndarray) -> np.ndarray:
        """``U diag(c) U^T x``."""
        x = np.asarray(x)
        p = self.U.T @ x
        return self.U @ (self.c[:, None] * p if p.ndim == 2 else self.c * p)

    def __matmul__(self, x: Any) -> np.ndarray:
        if sp.issparse(x):
            x = x.toarray()
        x = np.asarray(x)
        return self.band @ x + self.lowrank_times(x)

    def __rmatmul__(self, x: Any) -> np.ndarray:     # x D = (D^T x^T)^T, D^T = B^T + term
        x = np.asarray(x)
        return np.asarray(x @ self.band) + self.lowrank_times(x.T).T

    def dot(self, x: Any) -> np.ndarray:
        return self @ x

    def __add__(self, other: Any) -> BandedLowRank:
        if isinstance(other, BandedLowRank):
            raise ValueError("one low-rank damping term only")
        if np.isscalar(other) and other == 0:
            return self
        if not sp.issparse(other):
            raise TypeError("BandedLowRank + a sparse matrix (dense: use toarray())")
        return BandedLowRank(self.band + other, self.U, self.c)

    __radd__ = __add__

    def __mul__(self, s: float) -> BandedLowRank:
        return BandedLowRank(float(s) * self.band, self.U, float(s) * self.c)

    __rmul__ = __mul__

    def toarray(self) -> np.ndarray:
        """The dense matrix (symmetrised low-rank term, as the dense damping is formed)."""
        full = (self.U * self.c) @ self.U.T
        return self.band.toarray() + 0.5 * (full + full.T)

    def copy(self) -> BandedLowRank:
        return BandedLowRank(self.band.copy(), self.U.copy(), self.c.copy())

    def diagonal(self) -> np.ndarray:
        return self.band.diagonal() + np.einsum("ij,j,ij->i", self.U, self.c, self.U)


def with_lowrank(band: Any, lowrank: tuple[np.ndarray, np.ndarray] | None) -> Any:
    """``band`` itself without a low-rank term, else :class:`BandedLowRank`."""
    return band if lowrank is None else BandedLowRank(band, *lowrank)


def project(D: Any, psi: np.ndarray) -> np.ndarray:
    """Galerkin projection ``Psi^T D Psi`` of D (dense, sparse or :class:`BandedLowRank`:
    ``Psi^T (B Psi) + W^T diag(c) W``, ``W = U^T Psi``)."""
    if isinstance(D, BandedLowRank):
        W = D.U.T @ psi
        return np.asarray(psi.T @ (D.band @ psi)) + W.T @ (D.c[:, None] * W)
    if sp.issparse(D):
        return np.asarray(psi.T @ (D @ psi))
    return psi.T @ np.asarray(D, dtype=float) @ psi


def dense(a: Any) -> np.ndarray:
    """``a`` (dense, sparse or :class:`BandedLowRank`) as a dense float array."""
    if isinstance(a, BandedLowRank) or sp.issparse(a):
        return a.toarray()
    return np.asarray(a, dtype=float)


__all__ = ["BandedLowRank", "dense", "project", "with_lowrank"]
