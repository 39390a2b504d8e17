"""Dense LAPACK path of the condensation (:mod:`rotorsfd.harmonic.condensation`), for
linear parts too wide for the compiled band kernel: per harmonic the complex LU of

    Zt_k = K - (kw)^2 M + i kw D + S^T Delta_k S,

``sol_k = Zt_k^-1 [S^T, F_k]`` and, with the lam-derivatives, ``dsol_k = S Zt_k^-1 (dF_k e -
dZ_k sol_k)``, ``dZ_k = dK - (kw)^2 dM - 2 k^2 w w' M + i k (w' D + w dD)``.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import lapack

from rotorsfd.harmonic.problem import PeriodicProblem

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: Entries of the dense Zt_k formed at once by the dense path (a chunk of harmonics, at
#: least one; 128 kB of complex: small models form all harmonics in a few numpy calls).
DENSE_CHUNK = 1 << 13


def dense_solves(problem: PeriodicProblem, H: int, delta: ComplexArray, M: FloatArray,
                 D: FloatArray, K: FloatArray, dM: FloatArray, dD: FloatArray,
                 dK: FloatArray, w: float, dw: float, F: ComplexArray, dF: ComplexArray,
                 deriv: bool, sol: ComplexArray, dsol: ComplexArray, k_first: int = 0
                 ) -> None:
    """Dense complex LU (LAPACK) of Zt_k per harmonic; the same outputs as
    :func:`rotorsfd.harmonic.banded.condense_banded`. ``k_first``: harmonics below it are
    already in sol and dsol (copied from a condensation of the same problem with the same
    shift at fewer harmonics) and are left alone: only ``k >= k_first`` are factorised.

    The Zt_k are formed a chunk of harmonics at a time (:data:`DENSE_CHUNK` entries:
    all of them for a small model, where the per-harmonic numpy calls cost more than
    the LU). With deriv, the LU of Zt_k^T also gives the rows ``S Zt_k^-1`` (Zt_k^T
    y = S^T), so ``dsol_k = S Zt_k^-1 (dF_k e - dZ_k sol_k)`` after the loop, with the
    products ``dZ_k sol_k`` for all k at once (no dZ_k formed)."""
    s, m, n = problem.nl_dofs, problem.m, problem.n_dof
    getrf, getrs = lapack.zgetrf, lapack.zgetrs
    rhs = np.zeros((m + 1, n), dtype=complex)   # rhs.T: [S^T, F_k], Fortran (n, m+1)
    rhs[np.arange(m), s] = 1.0
    unit = np.asfortranarray(rhs[:m].T)        # S^T
    rows = np.empty((H + 1, n, m), dtype=complex) if deriv else None
    block = (slice(None), s[:, None], s[None, :])
    step = max(1, min(H + 1, DENSE_CHUNK // (n * n)))
    Zbuf = np.empty((step, n, n), dtype=complex)
    for k0 in range(k_first, H + 1, step):
        ks = np.arange(k0, min(H + 1, k0 + step))
        kw = (ks * w)[:, None, None]
        # C-ordered Z[i], so Z[i].T is Fortran-contiguous: LAPACK factors Z_k^T in place
        Z = Zbuf[: ks.size]
        Z.real = K - kw**2 * M
        Z.imag = kw * D
        Z[block] += delta[ks]
        for i, k in enumerate(ks):
            lu, piv, info = getrf(Z[i].T, overwrite_a=True)
            if info != 0:
                raise FloatingPointError(f"singular dynamic stiffness Z_{k} "
                                         f"(w={w:.6g})")
            rhs[m] = F[k]
            sol[k] = getrs(lu, piv, rhs.T, trans=1)[0]          # Z_k x = rhs
            if deriv:
                rows[k] = getrs(lu, piv, unit, trans=0)[0]      # Z_k^T y = S^T
    if deriv and k_first <= H:
        # dZ_k = dK - (k w)^2 dM - 2 k^2 w w' M + i k (w' D + w dD), applied to sol_k
        k = np.arange(k_first, H + 1)[:, None, None]
        kw = k * w
        x = sol[k_first:]
        r2 = (kw**2 * (dM @ x) + (2 * dw) * (k * kw) * (M @ x) - dK @ x
              - 1j * k * ((dw * D + w * dD) @ x))
        r2[:, :, m] += dF[k_first:]
        np.matmul(rows[k_first:].transpose(0, 2, 1), r2, out=dsol[k_first:])
