"""The full-model HB residual (:class:`~rotorsfd.harmonic.residual.FullHB`) with a sparse
Jacobian, for the sparse LU of the Newton corrector (issue 17 item 2).

The same residual ``R_k = Z_k X_k - F_k - S^T G_k`` and exact derivatives as FullHB
(:mod:`rotorsfd.harmonic.residual`), with ``Z_k = K - (kw)^2 M + i kw D`` and ``dZ_k``
from the CSR matrices of the problem's banded linear part (``matrices.sparse(lam)``,
``matrices.dbanded(lam)``: no n x n array). In the real layout (harmonic-major, rows
``2k - 1, 2k`` = Re, Im of harmonic k) the Jacobian is the block matrix

    [[K]], and per k >= 1  [[Re Z_k, -Im Z_k], [Im Z_k, Re Z_k]],

plus the AFT block ``-dG/dx`` on the nonlinear DOFs: CSR with ``(2H+1)^2 m^2 +
(4H+1) nnz(K)`` entries instead of ``((2H+1) n)^2``. :func:`rotorsfd.continuation.newton`
solves the bordered system of a sparse Jacobian by SuperLU.
"""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from rotorsfd.harmonic.fourier import to_complex, to_real
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.residual import FullHB, nonlinear_coefficients

FloatArray = NDArray[np.float64]

#: Models above this many DOFs take the sparse full HB when the linear part is banded.
SPARSE_MIN_DOF = 400


def sparse_full_available(problem: PeriodicProblem) -> bool:
    """Whether the problem's linear part gives CSR matrices and band storage."""
    part = problem.matrices
    return hasattr(part, "sparse") and hasattr(part, "dbanded") and hasattr(part, "band")


def full_hb(problem: PeriodicProblem, H: int, N: int) -> FullHB:
    """The full-model HB residual: :class:`SparseFullHB` above SPARSE_MIN_DOF DOFs with a
    banded linear part, else the dense :class:`FullHB`."""
    if problem.n_dof > SPARSE_MIN_DOF and sparse_full_available(problem):
        return SparseFullHB(problem, H, N)
    return FullHB(problem, H, N)


class SparseFullHB(FullHB):
    """:class:`FullHB` with ``dR/dx`` as a CSR matrix (module docstring)."""

    def residual(self, x: FloatArray, lam: float, jac: bool = True
                 ) -> tuple[FloatArray, sp.csr_matrix | None, FloatArray | None]:
        """R (2H+1, n) and, if jac, dR/dx (nu, nu) CSR and dR/dlam (nu,)."""
        from rotorsfd.model.sparse import band_to_csr

        p, H, s = self.problem, self.H, self.problem.nl_dofs
        n = p.n_dof
        x = x.reshape(2 * H + 1, n)
        part = p.matrices
        M, D, K = part.sparse(lam)
        w = p.frequency(lam)
        X = to_complex(x)
        nl = nonlinear_coefficients(p, self.aft, x[:, s], w, jac, lam=lam)
        self._last = (lam, x[:, s].copy(), nl.G)
        Z = [(K - (k * w) ** 2 * M).tocsr() for k in range(H + 1)]   # real parts
        Rc = np.empty((H + 1, n), dtype=complex)
        for k in range(H + 1):
            Rc[k] = Z[k] @ X[k] + 1j * (k * w) * (D @ X[k])
        Rc -= p.forcing(lam, H)
        R = to_real(Rc)
        R[:, s] -= nl.G
        if not jac:
            return R, None, None
        nh = 2 * H + 1
        blocks: list[list] = [[None] * nh for _ in range(nh)]
        blocks[0][0] = Z[0]
        for k in range(1, H + 1):
            a, b = 2 * k - 1, 2 * k
            im = (k * w) * D
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
        kl, ku = part.band
        dM, dD, dK = (band_to_csr(a, kl, ku) for a in part.dbanded(lam))
        dw = p.dfrequency(lam)
        dZX = np.empty((H + 1, n), dtype=complex)
        for k in range(H + 1):
            kw = k * w
            dZX[k] = (dK @ X[k] - kw**2 * (dM @ X[k]) - 2 * k * kw * dw * (M @ X[k])
                      + 1j * k * (dw * (D @ X[k]) + w * (dD @ X[k])))
        dR = to_real(dZX - p.dforcing(lam, H))
        dR[:, s] -= dw * nl.dGdw
        law = p.law(lam)
        if law.dforce is not None:   # the force's own dependence on lam
            dR[:, s] -= self.aft.P @ law.dforce(nl.q, w * (self.aft.Ed @ x[:, s]))
        return R, J, dR.reshape(self.n_unknowns)
