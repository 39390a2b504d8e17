"""Real DFT matrices of the alternating frequency/time (AFT) scheme and the sample-count rule.

Convention (docs/INTERFACES.md): ``q(t) = Re(sum_{k=0}^{H} X_k exp(i k w t))`` with
``X_k = a_k - i b_k``. The real unknowns of one DOF are stored in the *real layout*
``x = [Re X_0, Re X_1, Im X_1, ..., Re X_H, Im X_H]`` (length 2H+1), i.e.
``x = [a_0, a_1, -b_1, ..., a_H, -b_H]``. Arrays of several DOFs have shape (2H+1, n).

With ``tau_n = 2 pi n / N`` (n = 0..N-1):

- ``q(tau_n) = E @ x``           E[n, 2k-1] = cos(k tau_n), E[n, 2k] = -sin(k tau_n)
- ``dq/dtau(tau_n) = Ed @ x``    (so ``q' = w Ed @ x``)
- ``x_F = P @ f(tau_n)``         the Fourier coefficients of samples f in the same layout:
  F_0 = mean(f), F_k = (2/N) sum_n f_n exp(-i k tau_n).

``P @ E = I`` exactly when N > 2H.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass(frozen=True)
class AFTMatrices:
    """Sampling (E), derivative sampling (Ed) and projection (P) matrices for H, N."""

    H: int
    N: int
    E: FloatArray   # (N, 2H+1)
    Ed: FloatArray  # (N, 2H+1)
    P: FloatArray   # (2H+1, N)


@lru_cache(maxsize=64)
def aft_matrices(H: int, N: int) -> AFTMatrices:
    """Build the real DFT matrices (module docstring) for H harmonics and N > 2H samples."""
    if H < 0 or N <= 2 * H:
        raise ValueError(f"need H >= 0 and N > 2H, got H={H}, N={N}")
    tau = 2.0 * np.pi * np.arange(N) / N
    k = np.arange(1, H + 1)
    c = np.cos(np.outer(tau, k))
    s = np.sin(np.outer(tau, k))
    E = np.zeros((N, 2 * H + 1))
    Ed = np.zeros((N, 2 * H + 1))
    E[:, 0] = 1.0
    E[:, 1::2] = c
    E[:, 2::2] = -s
    Ed[:, 1::2] = -k * s
    Ed[:, 2::2] = -k * c
    P = np.zeros((2 * H + 1, N))
    P[0] = 1.0 / N
    P[1::2] = 2.0 / N * c.T
    P[2::2] = -2.0 / N * s.T
    return AFTMatrices(H, N, E, Ed, P)


def to_real(X: ComplexArray) -> FloatArray:
    """Complex coefficients (H+1, n) -> real layout (2H+1, n)."""
    X = np.asarray(X)
    H = X.shape[0] - 1
    x = np.empty((2 * H + 1, *X.shape[1:]))
    x[0] = X[0].real
    x[1::2] = X[1:].real
    x[2::2] = X[1:].imag
    return x


def to_complex(x: FloatArray) -> ComplexArray:
    """Real layout (2H+1, n) -> complex coefficients (H+1, n)."""
    x = np.asarray(x, dtype=float)
    H = (x.shape[0] - 1) // 2
    X = np.empty((H + 1, *x.shape[1:]), dtype=complex)
    X[0] = x[0]
    X[1:] = x[1::2] + 1j * x[2::2]
    return X


def default_min_samples(H: int) -> int:
    """Smallest power of two >= 8(H+1): 32 for H = 3, 128 for H = 8.

    A polynomial of degree p is alias-free on the retained harmonics when N > (p+1)H, so
    this floor is exact up to degree 7; rational forces (the SFD) are checked by doubling.
    """
    return int(2 ** np.ceil(np.log2(8 * (H + 1))))


def aliasing_error(force: Callable[[FloatArray, FloatArray], FloatArray],
                   xs: FloatArray, w: float, N: int, G_N: FloatArray | None = None) -> float:
    """Relative change of the retained nonlinear-force coefficients when N doubles.

    ``|P_2N f(E_2N x) - P_N f(E_N x)| / max(|P_2N f(E_2N x)|, tiny)`` (max norms), for the
    nonlinear DOF coefficients ``xs`` (2H+1, m) at frequency w; ``G_N`` the coefficients
    with N samples if already known.
    """
    H = (xs.shape[0] - 1) // 2
    out = []
    for n in (N, 2 * N):
        if n == N and G_N is not None:
            out.append(G_N)
            continue
        A = aft_matrices(H, n)
        out.append(A.P @ force(A.E @ xs, w * (A.Ed @ xs)))
    scale = max(float(np.max(np.abs(out[1]))), np.finfo(float).tiny)
    return float(np.max(np.abs(out[1] - out[0]))) / scale


def smallest_n_samples(error: Callable[[int], float], n_min: int, n_max: int,
                       target: float) -> int:
    """Smallest power of two N in [n_min, n_max] (n_min a power of two) with
    ``error(N) <= target``, doubling from n_min; n_max if none."""
    N = n_min
    while N < n_max and error(N) > target:
        N *= 2
    return min(N, n_max)


def choose_n_samples(force: Callable[[FloatArray, FloatArray], FloatArray],
                     xs: FloatArray, w: float, tol: float = 1e-8,
                     n_min: int | None = None, n_max: int = 4096) -> int:
    """Sample-count rule: the smallest power of two N >= ``default_min_samples(H)`` (or
    ``n_min``) such that doubling N changes the nonlinear-force coefficients of the
    retained harmonics by less than ``tol`` (relative, :func:`aliasing_error`) at ``xs``.

    Returns ``n_max`` if the rule is not met below it.
    """
    H = (xs.shape[0] - 1) // 2
    N = n_min if n_min is not None else default_min_samples(H)
    N = max(int(2 ** np.ceil(np.log2(max(N, 2 * H + 1)))), 2)
    # "less than tol": an error above the largest float below tol fails
    return smallest_n_samples(lambda n: aliasing_error(force, xs, w, n), N, n_max,
                              float(np.nextafter(tol, -np.inf)))
