"""Multipliers of the structural modes above the Craig-Bampton cut-off (issue 22 item 4).

The branch's multipliers are those of the reduced model: the nonlinear DOFs ``q_b`` plus
the fixed-interface modes with ``omega <= omega_max``. The structural modes of the whole
model above the cut-off are not in it. The perturbation equation of the orbit is

    M y'' + (D - P Jv(t) P^T) y' + (K - P Jq(t) P^T) y = 0,

``Jq, Jv`` the element Jacobians ``dF/dq, dF/dv`` along the orbit (period T), ``P`` the
nonlinear DOFs. Split ``J(t) = J_bar + J~(t)`` (mean and periodic part). The mean gives
the time-invariant (averaged) model

    (lambda^2 M + lambda (D - P Jv_bar P^T) + K - P Jq_bar P^T) phi = 0,

whose multipliers are exactly ``mu_j = exp(lambda_j T)``. For a mode far above the orbit's
frequencies (``omega_j > omega_max = M / (4 T)``, at least ``M / (8 pi)`` = 16 times the
speed at M = 400) the periodic part ``J~`` acts on it only through its harmonics near
``2 omega_j`` (parametric) or through the orbit's motion, whose coefficients are small:
first-order averaging removes ``J~`` and the exponent is ``lambda_j + O(|J~|^2)``. So the
averaged model's modes with ``|Im lambda_j| > omega_max`` are what the full model has
outside the basis; ``max_multiplier_outside`` is their largest ``|exp(lambda_j T)|``
(exact for the averaged model, to second order in the periodic part for the full one;
checked against the full-model monodromy at M = 6400 in tests/stability/test_outside.py).

The full-model Newmark monodromy (average acceleration = trapezoidal rule on the
first-order form) maps a mode onto ``r(lambda h)^N``, ``r(z) = (1 + z/2) / (1 - z/2)``,
``h = T / N`` (:func:`newmark_multipliers`); for ``|lambda| h >> 1`` ``|r| -> 1``
whatever the damping: the unresolved modes of a full-model Newmark monodromy sit near the
unit circle although their exact multipliers are small (why the reduction exists). The
reported value is the exact one.

Dense models (at most ``DENSE_MAX_DOF``): every mode of the companion form. Larger (sparse)
ones (:meth:`FloquetEvaluator.outside`): the Ritz values of the averaged model on the
Craig-Bampton basis extended to twice the cut-off, the modes just above the cut-off (the
least damped ones for damping that grows with the frequency, Rayleigh or modal); a
lightly damped mode far above the cut-off (one with a node at every damper) is then
missed: the dense path, or ``basis = "full"``, sees it. (:func:`averaged_eigenvalues` also
takes sparse matrices: shift-invert Arnoldi nearest ``i omega_max``, 0.4 s per point at
5124 DOF, too slow per branch point.)
"""

from __future__ import annotations

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray


def mode_eigenvalues(M: ArrayLike, D: ArrayLike, K: ArrayLike) -> NDArray[np.complex128]:
    """Eigenvalues of ``lambda^2 M + lambda D + K`` (k x k, dense) by the companion
    linearisation ``[[0, I], [-M^-1 K, -M^-1 D]]``."""
    M, D, K = (np.asarray(a, float) for a in (M, D, K))
    k = M.shape[0]
    if k == 0:
        return np.zeros(0, complex)
    A = np.block([[np.zeros((k, k)), np.eye(k)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    return sla.eigvals(A)


#: Sparse models: the eigenvalues computed nearest ``i omega_max``.
N_SPARSE = 12


def averaged_eigenvalues(M: ArrayLike, D: ArrayLike, K: ArrayLike, nl: NDArray,
                         Jq_bar: NDArray, Jv_bar: NDArray, *, omega_max: float
                         ) -> NDArray[np.complex128]:
    """Eigenvalues with ``|Im lambda| > omega_max`` of the averaged model (module
    docstring), ``Jq_bar, Jv_bar`` the (m, m) mean Jacobians of the nonlinear DOFs ``nl``;
    M, D, K dense or (large) scipy.sparse."""
    nl = np.asarray(nl, dtype=np.intp)
    if not sp.issparse(M):
        Kb, Db = np.array(K, float), np.array(D, float)
        Kb[np.ix_(nl, nl)] -= Jq_bar
        Db[np.ix_(nl, nl)] -= Jv_bar
        lam = mode_eigenvalues(M, Db, Kb)
    else:
        # deferred: scipy.sparse.linalg is heavy (loaded only when this runs)
        import scipy.sparse.linalg as spla

        n = M.shape[0]
        rows, cols = np.repeat(nl, nl.size), np.tile(nl, nl.size)
        Kb = sp.csr_matrix(K) - sp.csr_matrix((np.ravel(Jq_bar), (rows, cols)), (n, n))
        Db = sp.csr_matrix(D) - sp.csr_matrix((np.ravel(Jv_bar), (rows, cols)), (n, n))
        eye = sp.identity(n, format="csr")
        A = sp.bmat([[None, eye], [-Kb, -Db]], format="csc").astype(complex)
        B = sp.block_diag([eye, sp.csr_matrix(M)], format="csc").astype(complex)
        lam = spla.eigs(A, k=N_SPARSE, M=B, sigma=1j * omega_max, which="LM",
                        return_eigenvectors=False)
    return lam[np.abs(lam.imag) > omega_max]


def exact_multipliers(lam: ArrayLike, period: float) -> NDArray[np.complex128]:
    """``exp(lambda T)``: the multipliers of the time-invariant modes."""
    return np.exp(np.asarray(lam, complex) * period)


def newmark_multipliers(lam: ArrayLike, period: float, n_intervals: int
                        ) -> NDArray[np.complex128]:
    """``r(lambda h)^N``, ``r(z) = (1 + z/2) / (1 - z/2)``: what N average-acceleration
    Newmark steps make of the modes (module docstring)."""
    z = np.asarray(lam, complex) * (period / n_intervals)
    return ((1 + z / 2) / (1 - z / 2)) ** n_intervals


def largest_modulus(mu: ArrayLike) -> float:
    """``max |mu|`` (0 for none: nothing is outside the basis)."""
    mu = np.asarray(mu, complex)
    return float(np.max(np.abs(mu))) if mu.size else 0.0
