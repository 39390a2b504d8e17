"""Synthesis of periodic orbits from their Fourier coefficients: samples of the orbit and
its velocity, and the exact largest radius of a (y, z) orbit over the period."""

from __future__ import annotations

from typing import Any

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]


def orbit_samples(X: NDArray[np.complex128], frequency: Any = 0.0, n: int | None = None
                  ) -> tuple[FloatArray, FloatArray]:
    """``(q, v)``, each ``(..., n, m)``: ``q(theta) = Re sum_k X_k exp(i k theta)`` of the
    coefficients ``X (..., H+1, m)`` (leading axes: several orbits, e.g. a branch's points)
    at ``n`` phases (default ``max(1024, 64 (H+1))``) and ``v = w dq/dtheta`` at the
    frequency ``w`` [rad/s] (a scalar or one per orbit)."""
    X = np.asarray(X, dtype=complex)
    k = np.arange(X.shape[-2])
    n = n or max(1024, 64 * X.shape[-2])
    E = np.exp(1j * np.outer(k, 2 * np.pi * np.arange(n) / n))       # (H+1, n)
    q = np.einsum("...km,kn->...nm", X, E).real
    w = np.asarray(frequency, dtype=float)[..., None, None]
    v = w * np.einsum("...km,kn->...nm", 1j * k[:, None] * X, E).real
    return q, v


def max_radius(Xy: NDArray[np.complex128], Xz: NDArray[np.complex128],
               n_grid: int | None = None) -> FloatArray:
    """max over one period of sqrt(y^2 + z^2), y(theta) = Re sum_k Xy_k exp(i k theta).

    ``Xy, Xz`` (..., H+1). Grid of ``n_grid`` phases (default max(256, 64 (H+1))), then
    Newton steps on d(r^2)/dtheta = 0 from the best grid phase (r^2 is a trigonometric
    polynomial, so the refined maximum is exact to rounding); never below the grid value.
    """
    Xy, Xz = np.asarray(Xy, complex), np.asarray(Xz, complex)
    H = Xy.shape[-1] - 1
    k = np.arange(H + 1)
    n = n_grid or max(256, 64 * (H + 1))
    theta = 2 * np.pi * np.arange(n) / n
    E = np.exp(1j * np.outer(k, theta))                       # (H+1, n)
    r2 = (Xy @ E).real ** 2 + (Xz @ E).real ** 2               # (..., n)
    best = r2.max(axis=-1)
    th = theta[r2.argmax(axis=-1)]
    step_max = 2 * np.pi / n
    for _ in range(8):
        e = np.exp(1j * k * th[..., None])                     # (..., H+1)
        y, z = [(X * e).sum(-1) for X in (Xy, Xz)]
        y1, z1 = [(1j * k * X * e).sum(-1) for X in (Xy, Xz)]
        y2, z2 = [(-(k**2) * X * e).sum(-1) for X in (Xy, Xz)]
        d1 = 2 * (y.real * y1.real + z.real * z1.real)
        d2 = 2 * (y1.real**2 + y.real * y2.real + z1.real**2 + z.real * z2.real)
        ok = d2 < 0
        th = th - np.where(ok, np.clip(d1 / np.where(ok, d2, -1.0), -step_max, step_max), 0)
    e = np.exp(1j * k * th[..., None])
    r2_ref = (Xy * e).sum(-1).real ** 2 + (Xz * e).sum(-1).real ** 2
    return np.sqrt(np.maximum(best, r2_ref))


# ---- the result ----------------------------------------------------------------------------
