"""Hill's method: Floquet exponents from the truncated Fourier (Hill) matrix.

First-order form ``y' = A(t) y``, ``y = (q, q')``, with two-sided Fourier coefficients
``A(t) = sum_k A_k exp(i k w t)``. Floquet form ``y = exp(lambda t) sum_l c_l exp(i l w t)``
gives the Hill eigenproblem (``l, j = -H..H``)::

    sum_j (A_{l-j} - i l w delta_lj) c_j = lambda c_l        (size 2n(2H+1))

Each physical exponent appears 2H+1 times (shifted by ``i k w``); two selections:

* ``'symmetric'``: keep the 2n eigenvalues whose eigenvectors are most centred on the
  zeroth harmonic, i.e. smallest ``|sum_l l |c_l|^2 / sum_l |c_l|^2|`` (symmetric-weight
  criterion, Lazarus & Thomas 2010); multipliers ``exp(lambda T)``. Only eigenvalues that
  belong to a ladder are eligible first: a physical exponent reappears shifted by
  ``+-i w`` (its ``ladder defect``, the distance in units of w to the nearest eigenvalue
  at ``lambda +- i w``, is the truncation error); an eigenvalue of the truncated matrix
  that is not (defect ~ 1) is spurious. For a real ``A(t)`` a *real* eigenvalue has a
  conjugate-symmetric eigenvector, so its centroid is exactly 0 whether it is physical
  or not: without the ladder test, spurious real eigenvalues (stiff, strongly
  time-varying film coefficients near journal contact) outrank the true exponents with
  ``Im = w/2`` (centroid 1/2, multiplier -1) and turn a period doubling into a
  'saddle-node' or hide it. ``info``: ``n_spurious`` (selected exponents without a
  ladder), ``critical_defect`` (ladder defect of the exponent of largest multiplier:
  above ``LADDER_TOL`` the truncation H is too small for it, raise H).
* ``'koopman'``: sorting-free Koopman-Hill projection (Bayer & Leine 2023)::

      Phi(T) = C expm(H_hill T) W,  C = [I I ... I],  W = e_0 (x) I

  (exact for H -> infinity since ``H_hill P = P R`` for the Floquet factor ``P(t)``).

Project Fourier convention (one-sided): ``K_nl(t) = Re sum_{k=0}^{L} K_k exp(i k w t)``.
"""

from __future__ import annotations

from typing import Literal

import numpy as np
import scipy.linalg as sla
from numpy.typing import ArrayLike, NDArray

from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.stability.floquet import STABILITY_TOL, FloquetResult, sort_multipliers


def fourier_coefficients(samples: ArrayLike, n_harmonics: int) -> NDArray[np.complex128]:
    """One-sided coefficients ``X_k`` (k = 0..L) of samples ``x(t_j)``, ``t_j = j T/N``,
    ``j = 0..N-1`` (axis 0), so that ``x(t) = Re sum_k X_k exp(i k w t)``. Needs N > 2L."""
    x = np.asarray(samples)
    N = x.shape[0]
    if N <= 2 * n_harmonics:
        raise ConfigError("samples", N, f"more than 2L = {2 * n_harmonics} samples")
    c = np.fft.fft(x, axis=0) / N
    X = 2.0 * c[: n_harmonics + 1]
    X[0] = c[0]
    return X


def two_sided(X: ArrayLike) -> NDArray[np.complex128]:
    """Two-sided coefficients ``c_k`` (index ``k + L``, k = -L..L) from one-sided ``X_k``:
    ``c_0 = X_0``, ``c_k = X_k / 2``, ``c_-k = conj(X_k) / 2``."""
    X = np.asarray(X, dtype=complex)
    half = 0.5 * X[1:]
    return np.concatenate([np.conj(half[::-1]), X[:1], half], axis=0)


def hill_matrix(A_hat: ArrayLike, omega: float, n_harmonics: int) -> NDArray[np.complex128]:
    """Hill matrix, blocks ``(l, j)``: ``A_{l-j} - i l w delta_lj``, ``l, j = -H..H``.

    ``A_hat``: two-sided coefficients (2L+1, N, N), index ``k + L``; terms |k| > L are 0.
    """
    A_hat = np.asarray(A_hat, dtype=complex)
    L = (A_hat.shape[0] - 1) // 2
    Ns = A_hat.shape[1]
    H = n_harmonics
    Hm = np.zeros(((2 * H + 1) * Ns, (2 * H + 1) * Ns), dtype=complex)
    for li, l in enumerate(range(-H, H + 1)):
        for ji, j in enumerate(range(-H, H + 1)):
            k = l - j
            if abs(k) <= L:
                Hm[li * Ns:(li + 1) * Ns, ji * Ns:(ji + 1) * Ns] = A_hat[k + L]
        Hm[li * Ns:(li + 1) * Ns, li * Ns:(li + 1) * Ns] -= 1j * l * omega * np.eye(Ns)
    return Hm


def first_order_coefficients(M: ArrayLike, D: ArrayLike, K: ArrayLike,
                             nl_dofs: ArrayLike = (), dFdq_hat: ArrayLike | None = None,
                             dFdv_hat: ArrayLike | None = None) -> NDArray[np.complex128]:
    """Two-sided coefficients of ``A(t) = [[0, I], [-M^-1 K(t), -M^-1 D(t)]]`` for
    ``K(t) = K - P K_nl(t) P^T``, ``D(t) = D - P C_nl(t) P^T`` (one-sided ``*_hat``)."""
    M, D, K = (np.atleast_2d(np.asarray(x, float)) for x in (M, D, K))
    n = M.shape[0]
    nl = np.asarray(nl_dofs, dtype=np.intp).ravel()
    m = nl.size
    hats = [np.zeros((1, m, m)) if h is None else np.asarray(h, complex).reshape(-1, m, m)
            for h in (dFdq_hat, dFdv_hat)]
    L = max(h.shape[0] for h in hats) - 1
    kq, kv = (two_sided(np.concatenate([h, np.zeros((L + 1 - h.shape[0], m, m))]))
              for h in hats)
    Minv = np.linalg.inv(M)
    A = np.zeros((2 * L + 1, 2 * n, 2 * n), dtype=complex)
    A[L, :n, n:] = np.eye(n)
    A[L, n:, :n] = -Minv @ K
    A[L, n:, n:] = -Minv @ D
    if m:
        MinvP = Minv[:, nl]
        A[:, n:, nl] += np.einsum("im,kmj->kij", MinvP, kq)
        A[:, n:, n + nl] += np.einsum("im,kmj->kij", MinvP, kv)
    return A


def sampled_first_order_coefficients(M: ArrayLike, D: ArrayLike, K: ArrayLike,
                                     nl_dofs: ArrayLike, dFdq: ArrayLike, dFdv: ArrayLike,
                                     dFda: ArrayLike, n_harmonics: int
                                     ) -> NDArray[np.complex128]:
    """Two-sided coefficients (k = -L..L) of ``A(t)`` with a time-varying mass
    ``M(t) = M - P dFda(t) P^T`` (a force of the acceleration, fluid inertia):
    ``A = [[0, I], [-M(t)^-1 K(t), -M(t)^-1 D(t)]]`` formed at the samples of one period
    (``t_j = j T / N``, N > 2L, axis 0 of the Jacobian samples) and transformed (the
    inverse mass makes A's series infinite: the samples' aliasing is its truncation)."""
    M, D, K = (np.atleast_2d(np.asarray(x, float)) for x in (M, D, K))
    n = M.shape[0]
    nl = np.asarray(nl_dofs, dtype=np.intp).ravel()
    Jq, Jv, Ja = (np.asarray(x, float) for x in (dFdq, dFdv, dFda))
    N = Jq.shape[0]
    if N <= 2 * n_harmonics:
        raise ConfigError("samples", N, f"more than 2L = {2 * n_harmonics} samples")
    A = np.zeros((N, 2 * n, 2 * n))
    A[:, :n, n:] = np.eye(n)
    block = np.ix_(nl, nl)
    for j in range(N):
        Mj, Dj, Kj = M.copy(), D.copy(), K.copy()
        Mj[block] -= Ja[j]
        Dj[block] -= Jv[j]
        Kj[block] -= Jq[j]
        A[j, n:, :] = -np.linalg.solve(Mj, np.hstack([Kj, Dj]))
    return two_sided(fourier_coefficients(A, n_harmonics))


LADDER_TOL = 1e-2
"""An exponent is resolved by the Hill truncation when its ladder defect (module
docstring, units of w) is at most this; it is spurious above ``SPURIOUS_DEFECT``."""
SPURIOUS_DEFECT = 0.1


def ladder_defect(lam: NDArray, omega: float) -> NDArray[np.float64]:
    """For each Hill eigenvalue, ``max_{k=+-1} min_j |lam_j - lam - i k w| / w``: about 0
    (the truncation error) for the central members of the ladder of a physical exponent,
    about 1 for a spurious eigenvalue of the truncated matrix."""
    # deferred: scipy.spatial is heavy (loaded only when this runs)
    from scipy.spatial import cKDTree

    pts = np.column_stack([lam.real, lam.imag]) / omega
    tree = cKDTree(pts)
    shift = np.array([0.0, 1.0])
    up, _ = tree.query(pts + shift)
    down, _ = tree.query(pts - shift)
    return np.maximum(up, down)


def _select_centred(lam: NDArray, centroid: NDArray, omega: float, count: int,
                    rel_tol: float = 1e-6, defect: NDArray | None = None
                    ) -> NDArray[np.intp]:
    """Indices of ``count`` exponents by increasing ``|centroid|``, those with a ladder
    (``defect <= SPURIOUS_DEFECT``, if given) first, skipping shifted copies
    ``lam' = lam + i k omega`` (k != 0) of exponents already taken: exact ones (they tie
    at ``|centroid| = 1/2`` when ``Im lam = omega/2``) and, with ``defect``, truncated
    ones (``|lam' - lam - i k omega| <= |k| (defect + defect')``, defects up to
    ``LADDER_TOL``), which would otherwise fill the count twice with one multiplier."""
    if defect is None:
        spurious, slack = np.zeros(lam.size, bool), np.zeros(lam.size)
    else:
        spurious = ~(defect <= SPURIOUS_DEFECT)
        slack = np.where(defect <= LADDER_TOL, defect, 0.0)
    taken: list[int] = []
    for i in np.lexsort((np.abs(centroid), spurious)):
        d = lam[i] - lam[taken] if taken else np.empty(0)
        k = np.rint(d.imag / omega)
        tol = rel_tol + np.abs(k) * (slack[i] + slack[taken])
        copy = (k != 0) & (np.abs(d - 1j * k * omega) <= tol * omega)
        if not copy.any():
            taken.append(int(i))
            if len(taken) == count:
                break
    return np.asarray(taken, dtype=np.intp)


def _multipliers(lam: NDArray, defect: NDArray, omega: float, T: float,
                 rel_tol: float = 1e-9) -> NDArray[np.complex128]:
    """``exp(lam T)``, real when ``Im lam`` is a multiple of ``omega/2`` to within the
    exponent's truncation error (its ladder defect, at most ``LADDER_TOL``): for a real
    system the exact Hill spectrum is conjugate-symmetric and a multiplier -1 (+1) has
    ``Im lam = (k + 1/2) omega`` (``k omega``) exactly; truncation shifts it by about the
    defect, which would make a period-doubling multiplier complex (a 'secondary-hopf')."""
    mu = np.exp(lam * T)
    half = lam.imag / (0.5 * omega)
    k = np.rint(half)
    tol = np.maximum(rel_tol, np.where(defect <= LADDER_TOL, defect, 0.0))
    real = np.abs(half - k) * 0.5 <= tol
    mu[real] = np.exp(lam.real[real] * T) * np.where(k[real] % 2 == 0, 1.0, -1.0)
    return mu


def hill_floquet(M: ArrayLike, D: ArrayLike, K: ArrayLike, omega: float, *,
                 nl_dofs: ArrayLike = (), dFdq_hat: ArrayLike | None = None,
                 dFdv_hat: ArrayLike | None = None, n_harmonics: int = 10,
                 method: Literal["symmetric", "koopman"] = "symmetric",
                 tol: float = STABILITY_TOL, A_hat: ArrayLike | None = None
                 ) -> FloquetResult:
    """Floquet multipliers of ``M q'' + (D - P C_nl P^T) q' + (K - P K_nl P^T) q = 0``.

    ``dFdq_hat``, ``dFdv_hat``: one-sided Fourier coefficients (L+1, m, m) of the
    nonlinear Jacobians on the orbit (``fourier_coefficients`` of samples), fundamental
    frequency ``omega`` (period ``T = 2 pi / omega``). ``n_harmonics``: Hill truncation H
    (coefficients up to ``2H`` are used when given). ``A_hat``: the first-order system's
    two-sided coefficients instead (``sampled_first_order_coefficients``: a time-varying
    added mass).
    """
    if A_hat is None:
        A_hat = first_order_coefficients(M, D, K, nl_dofs, dFdq_hat, dFdv_hat)
    A_hat = np.asarray(A_hat, dtype=complex)
    if not np.all(np.isfinite(A_hat)):
        raise ConvergenceError("Hill matrix not finite: check the Jacobian coefficients")
    Ns = A_hat.shape[1]
    H = int(n_harmonics)
    T = 2.0 * np.pi / omega
    Hm = hill_matrix(A_hat, omega, H)
    L = (A_hat.shape[0] - 1) // 2
    log_det = float(np.trace(A_hat[L]).real) * T
    info = {"n_harmonics": H, "size": Hm.shape[0]}
    if method == "symmetric":
        lam, vec = np.linalg.eig(Hm)
        w = np.abs(vec.reshape(2 * H + 1, Ns, -1)) ** 2
        w = w.sum(axis=1)
        centroid = np.arange(-H, H + 1) @ w / w.sum(axis=0)
        defect = ladder_defect(lam, omega)
        sel = _select_centred(lam, centroid, omega, Ns, defect=defect)
        mu = _multipliers(lam[sel], defect[sel], omega, T)
        info["max_centroid"] = float(np.abs(centroid[sel]).max())
        info["n_spurious"] = int(np.sum(~(defect[sel] <= SPURIOUS_DEFECT)))
        info["critical_defect"] = float(defect[sel][np.argmax(np.abs(mu))])
        return FloquetResult(sort_multipliers(mu), T, "hill-symmetric", log_det, None, tol,
                             info)
    if method == "koopman":
        W = np.zeros((Hm.shape[0], Ns))
        W[H * Ns:(H + 1) * Ns] = np.eye(Ns)
        EW = sla.expm(Hm * T) @ W
        Phi = EW.reshape(2 * H + 1, Ns, Ns).sum(axis=0).real
        return FloquetResult(sort_multipliers(np.linalg.eigvals(Phi)), T, "hill-koopman",
                             log_det, Phi, tol, info)
    raise ConfigError("method", method, "'symmetric' or 'koopman'")
