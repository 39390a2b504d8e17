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


class SparseLowRank:
    """A (p, q) matrix ``A = S + L R^T``: ``S`` CSR, ``L`` (p, r), ``R`` (q, r) dense, r
    small. The Jacobian of the full-model HB residual with a low-rank damping term
    (:class:`rotorsfd.harmonic.full_sparse.SparseFullHB`): S keeps the band, the modal term
    stays in the factors. The bordered Newton system ``[A; a^T] x = b`` is solved by
    Woodbury from one sparse LU of ``A_b = [S; a^T]``::

        Y = A_b^-1 [L; 0],  y = A_b^-1 b,  x = y - Y (I + R^T Y)^-1 (R^T y)
    """

    def __init__(self, S: Any, L: np.ndarray, R: np.ndarray) -> None:
        self.S = sp.csr_matrix(S, dtype=float)
        self.L = np.asarray(L, dtype=float)
        self.R = np.asarray(R, dtype=float)
        p, q = self.S.shape
        if self.L.shape[0] != p or self.R.shape[0] != q or self.L.shape[1] != self.R.shape[1]:
            raise ValueError(f"L {self.L.shape} and R {self.R.shape} do not match S "
                             f"{self.S.shape}")

    @property
    def shape(self) -> tuple[int, int]:
        return self.S.shape

    @property
    def ndim(self) -> int:
        return 2

    def is_finite(self) -> bool:
        """Whether every stored entry is finite."""
        return bool(np.all(np.isfinite(self.S.data)) and np.all(np.isfinite(self.L))
                    and np.all(np.isfinite(self.R)))

    def __matmul__(self, x: Any) -> np.ndarray:
        x = np.asarray(x)
        return self.S @ x + self.L @ (self.R.T @ x)

    def toarray(self) -> np.ndarray:
        """The dense matrix (small problems and the tests only)."""
        return self.S.toarray() + self.L @ self.R.T

    def __array__(self, dtype: Any = None, copy: Any = None) -> np.ndarray:
        out = self.toarray()
        return out if dtype is None else out.astype(dtype)

    def scaled(self, rows: np.ndarray, cols: np.ndarray) -> SparseLowRank:
        """``diag(rows) A diag(cols)``."""
        rows, cols = np.asarray(rows, float), np.asarray(cols, float)
        return SparseLowRank(sp.diags(rows) @ self.S @ sp.diags(cols),
                             rows[:, None] * self.L, cols[:, None] * self.R)

    def with_column(self, col: np.ndarray) -> SparseLowRank:
        """``[A, col]`` (p, q + 1): the column beside S, a zero row under R."""
        col = np.asarray(col, dtype=float).reshape(-1, 1)
        return SparseLowRank(sp.hstack([self.S, sp.csr_matrix(col)], format="csr"), self.L,
                             np.vstack([self.R, np.zeros((1, self.R.shape[1]))]))

    def without_last_column(self) -> tuple[SparseLowRank, np.ndarray]:
        """(A[:, :-1], A[:, -1] dense)."""
        last = self.S[:, -1].toarray().ravel() + self.L @ self.R[-1]
        return SparseLowRank(self.S[:, :-1], self.L, self.R[:-1]), last

    def bordered_solve(self, a: np.ndarray, rhs: np.ndarray) -> np.ndarray:
        """``x`` of ``[A; a^T] x = rhs`` (A square plus one column; class docstring);
        LinAlgError if the sparse part's bordered matrix is exactly singular."""
        # deferred: scipy.sparse.linalg is heavy (loaded only when this runs)
        import scipy.sparse.linalg as spla

        Ab = sp.vstack([self.S, sp.csr_matrix(np.asarray(a, dtype=float)[None, :])],
                       format="csc")
        try:
            lu = spla.splu(Ab)
        except RuntimeError as err:          # SuperLU: "Factor is exactly singular"
            raise np.linalg.LinAlgError(str(err)) from err
        rhs = np.asarray(rhs, dtype=float)
        r = self.L.shape[1]
        Lp = np.vstack([self.L, np.zeros((1, r))])
        sol = lu.solve(np.column_stack([Lp, rhs.reshape(rhs.shape[0], -1)]))
        Y, y = sol[:, :r], sol[:, r:]
        cap = np.eye(r) + self.R.T @ Y
        x = y - Y @ np.linalg.solve(cap, self.R.T @ y)
        return x.reshape(rhs.shape)


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
    """``a`` (dense, sparse, :class:`BandedLowRank` or :class:`SparseLowRank`) as a dense
    float array."""
    if isinstance(a, BandedLowRank | SparseLowRank) or sp.issparse(a):
        return a.toarray()
    return np.asarray(a, dtype=float)


__all__ = ["BandedLowRank", "SparseLowRank", "dense", "project", "with_lowrank"]
