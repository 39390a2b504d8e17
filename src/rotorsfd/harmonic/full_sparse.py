"""The full-model HB residual (:class:`~rotorsfd.harmonic.residual.FullHB`) with a sparse
Jacobian, for the sparse LU of the Newton corrector (issue 17 item 2).

The same residual ``R_k = Z_k X_k - F_k - S^T G_k`` and exact derivatives as FullHB
(:mod:`rotorsfd.harmonic.residual`), with ``Z_k = K - (kw)^2 M + i kw D`` and ``dZ_k``
from the CSR matrices of the problem's banded linear part (``matrices.split(lam)``,
``matrices.dsplit(lam)``, once per lam: no n x n array). In the real layout
(harmonic-major, rows ``2k - 1, 2k`` = Re, Im of harmonic k) the Jacobian is the block
matrix

    [[K]], and per k >= 1  [[Re Z_k, -Im Z_k], [Im Z_k, Re Z_k]],

plus the AFT block ``-dG/dx`` on the nonlinear DOFs: CSR with ``(2H+1)^2 m^2 +
(4H+1) nnz(K)`` entries instead of ``((2H+1) n)^2``. A modal damping of r modes
``D = D_b + U diag(c) U^T`` stays split: ``D x = D_b x + U (c * U^T x)`` in the residual,
and the Jacobian is ``J_b + L R^T`` (:class:`~rotorsfd.model.lowrank.SparseLowRank`, rank
2 H r: the blocks ``-+ kw U diag(c) U^T``). :func:`rotorsfd.continuation.newton` solves the
bordered system of a CSR Jacobian by SuperLU, of a SparseLowRank one by Woodbury from
the SuperLU of its sparse part.
"""

from __future__ import annotations

from typing import Any, NamedTuple

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from rotorsfd.harmonic.fourier import to_complex, to_real
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.residual import FullHB, nonlinear_coefficients
from rotorsfd.model.lowrank import BandedLowRank, SparseLowRank

FloatArray = NDArray[np.float64]

#: Models above this many DOFs take the sparse full HB when the linear part is banded.
SPARSE_MIN_DOF = 400


def sparse_full_available(problem: PeriodicProblem) -> bool:
    """Whether the problem's linear part gives CSR matrices and band storage."""
    part = problem.matrices
    return hasattr(part, "split") and hasattr(part, "dsplit") and hasattr(part, "band")


def full_hb(problem: PeriodicProblem, H: int, N: int) -> FullHB:
    """The full-model HB residual: :class:`SparseFullHB` above SPARSE_MIN_DOF DOFs with a
    banded linear part, else the dense :class:`FullHB`."""
    if problem.n_dof > SPARSE_MIN_DOF and sparse_full_available(problem):
        return SparseFullHB(problem, H, N)
    return FullHB(problem, H, N)


class FullHBLinear(NamedTuple):
    """The linear part of the full HB at one lam: CSR M, K, the lam-derivatives dM, dD,
    dK (CSR) and D as CSR or :class:`~rotorsfd.model.lowrank.BandedLowRank` (band +
    ``U diag(c) U^T``)."""

    lam: float
    M: sp.csr_matrix
    D: Any
    K: sp.csr_matrix
    dM: sp.csr_matrix
    dD: sp.csr_matrix
    dK: sp.csr_matrix


class SparseFullHB(FullHB):
    """:class:`FullHB` with ``dR/dx`` as a CSR matrix (module docstring); with a low-rank
    damping term a :class:`~rotorsfd.model.lowrank.SparseLowRank` (the CSR of the band
    plus the term's factors). The linear part is split once per lam
    (:meth:`linear_terms`) and reused by the residual and Jacobian calls at that lam."""

    def __init__(self, problem: PeriodicProblem, H: int, N: int) -> None:
        super().__init__(problem, H, N)
        self._linear: FullHBLinear | None = None

    def linear_terms(self, lam: float) -> FullHBLinear:
        """(M, D, K, dM, dD, dK) at lam from the banded linear part, cached on lam."""
        c = self._linear
        if c is not None and c.lam == lam:
            return c
        part = self.problem.matrices
        M, D, K = part.split(lam)
        dM, dD, dK = part.dsplit(lam)
        self._linear = FullHBLinear(lam, M, D, K, dM, dD, dK)
        return self._linear

    def lowrank_factors(self, w: float, D: BandedLowRank) -> tuple[FloatArray, FloatArray]:
        """(L, R) of the Jacobian's low-rank part ``L R^T``: per harmonic k the blocks
        ``-kw T`` at (Re k, Im k) and ``+kw T`` at (Im k, Re k), ``T = U diag(c) U^T``."""
        H, n = self.H, self.problem.n_dof
        U, cw = D.U, D.U * D.c
        r = U.shape[1]
        L = np.zeros((2 * H + 1, n, 2 * H, r))
        R = np.zeros((2 * H + 1, n, 2 * H, r))
        for k in range(1, H + 1):
            a, b = 2 * k - 1, 2 * k
            kw = k * w
            R[b, :, a - 1] = U                 # column group of the Im block ...
            L[a, :, a - 1] = -kw * cw          # ... into the Re rows
            R[a, :, b - 1] = U
            L[b, :, b - 1] = kw * cw
        nu = (2 * H + 1) * n
        return L.reshape(nu, 2 * H * r), R.reshape(nu, 2 * H * r)

    def residual(self, x: FloatArray, lam: float, jac: bool = True
                 ) -> tuple[FloatArray, Any, FloatArray | None]:
        """R (2H+1, n) and, if jac, dR/dx (nu, nu) CSR or SparseLowRank and dR/dlam
        (nu,)."""
        p, H, s = self.problem, self.H, self.problem.nl_dofs
        n = p.n_dof
        x = x.reshape(2 * H + 1, n)
        lin = self.linear_terms(lam)
        M, D, K = lin.M, lin.D, lin.K
        lowrank = isinstance(D, BandedLowRank)
        Db = D.band if lowrank else D
        w = p.frequency(lam)
        X = to_complex(x)
        nl = nonlinear_coefficients(p, self.aft, x[:, s], w, jac, lam=lam)
        self._last = (lam, x[:, s].copy(), nl.G)
        DX = np.asarray(D @ X.T).T                                     # (H+1, n)
        MX = np.asarray(M @ X.T).T
        Rc = np.asarray(K @ X.T).T - (np.arange(H + 1) * w)[:, None] ** 2 * MX \
            + 1j * (np.arange(H + 1) * w)[:, None] * DX
        Rc -= p.forcing(lam, H)
        R = to_real(Rc)
        R[:, s] -= nl.G
        if not jac:
            return R, None, None
        nh = 2 * H + 1
        Z = [(K - (k * w) ** 2 * M).tocsr() for k in range(H + 1)]   # real parts
        blocks: list[list] = [[None] * nh for _ in range(nh)]
        blocks[0][0] = Z[0]
        for k in range(1, H + 1):
            a, b = 2 * k - 1, 2 * k
            im = (k * w) * Db
            blocks[a][a] = blocks[b][b] = Z[k]
            blocks[a][b] = -im
            blocks[b][a] = im
        J = sp.bmat(blocks, format="csr")
        m = p.m
        rows = (np.arange(nh)[:, None] * n + s[None, :]).ravel()       # (nh m,)
        dG = nl.dG.reshape(nh * m, nh * m)
        J = (J - sp.csr_matrix((dG.ravel(), (np.repeat(rows, nh * m),
                                             np.tile(rows, nh * m))),
                               shape=J.shape)).tocsr()
        if lowrank:
            J = SparseLowRank(J, *self.lowrank_factors(w, D))
        dM, dD, dK = lin.dM, lin.dD, lin.dK
        dw = p.dfrequency(lam)
        kk = np.arange(H + 1)[:, None]
        kw = kk * w
        dZX = (np.asarray(dK @ X.T).T - kw**2 * np.asarray(dM @ X.T).T
               - 2 * kk * kw * dw * MX
               + 1j * kk * (dw * DX + w * np.asarray(dD @ X.T).T))
        dR = to_real(dZX - p.dforcing(lam, H))
        dR[:, s] -= dw * nl.dGdw
        law = p.law(lam)
        if law.dforce is not None:   # the force's own dependence on lam
            dR[:, s] -= self.aft.P @ law.dforce(nl.q, w * (self.aft.Ed @ x[:, s]))
        return R, J, dR.reshape(self.n_unknowns)
