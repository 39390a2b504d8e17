"""Tabulated surrogate of the finite film over the eccentricity ratio.

For these films the force is linear in the velocity, ``G = M(eps) w`` in the frame of the
line of centres (:mod:`rotorsfd.model.film_finite`), so the discrete film at any state is
the 2 x 2 matrix ``M`` and its derivative ``dM/deps`` at one ``eps``. They are tabulated
at ``N`` nodes clustered towards the contact limit::

    eps_k = eps_max (1 - (1 - t_k)^2),   t_k = k / (N - 1)

as ``Y = (1 - eps^2)^(5/2) M`` (bounded up to contact: the film grows like
``(1 - eps^2)^(-5/2)``) with ``dY/dt``, and interpolated by cubic Hermite polynomials in
``t``. The surrogate's Jacobian is the exact derivative of the interpolant
(``dM/deps = (dY/dt / (deps/dt) + 5 eps M (1 - eps^2)^(3/2)) / (1 - eps^2)^(5/2)``), so
HB, Floquet and time stepping see a consistent force and Jacobian. Its error against the
solver is measured when the table is built (at every interval's midpoint:
:attr:`rotorsfd.model.film_finite.FiniteSFD.table_error`). Per node 8 numbers:
``Y`` (m00, m01, m10, m11) then ``dY/dt``.

The Guembel film's clamp depends on the direction of ``w``, so its table holds the two
basis fields themselves (``Y = (1 - eps^2)^3 Pi`` on the grid, then ``dY/dt``; the clamp
and its sums are then applied to the interpolated fields, exactly as to solved ones).
"""

from __future__ import annotations

import math

import numpy as np
from numba import njit

__all__ = ["TABLE_NODES", "hermite_fields", "hermite_matrices", "table_eps"]

#: Default number of table nodes (measured midpoint error ~4e-6 in M, 2e-5 in dM/deps).
TABLE_NODES = 256


def table_eps(n: int, eps_max: float) -> tuple[np.ndarray, np.ndarray]:
    """Nodes ``eps_k`` and ``deps/dt`` there."""
    t = np.linspace(0.0, 1.0, n)
    return eps_max * (1.0 - (1.0 - t) ** 2), 2.0 * eps_max * (1.0 - t)


@njit(cache=True)
def hermite_matrices(eps: float, eps_max: float, table: np.ndarray, start: int, n: int
                     ) -> tuple[float, float, float, float, float, float, float, float]:
    """``(M, dM/deps)`` (row-major 2 x 2 each) of the table ``table[start:start + 8 n]``
    at ``0 <= eps < eps_max``."""
    t = 1.0 - math.sqrt(max(1.0 - eps / eps_max, 0.0))
    h = 1.0 / (n - 1)
    k = min(int(t / h), n - 2)
    s = (t - k * h) / h
    s2 = s * s
    s3 = s2 * s
    h00, h10, h01, h11 = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, -2 * s3 + 3 * s2, s3 - s2
    g00, g10 = (6 * s2 - 6 * s) / h, 3 * s2 - 4 * s + 1
    g01, g11 = (-6 * s2 + 6 * s) / h, 3 * s2 - 2 * s
    deps_dt = 2.0 * eps_max * (1.0 - t)
    c = (1.0 - eps) * (1.0 + eps)
    scale = c * c * math.sqrt(c)  # (1 - eps^2)^(5/2)
    dlog = -5.0 * eps / c  # d ln(scale) / deps
    a = start + 8 * k
    b = a + 8
    out = np.empty(8)
    for r in range(4):
        y = h00 * table[a + r] + h10 * h * table[a + 4 + r] + h01 * table[b + r] \
            + h11 * h * table[b + 4 + r]
        dy = (g00 * table[a + r] + g10 * table[a + 4 + r] + g01 * table[b + r]
              + g11 * table[b + 4 + r]) / deps_dt
        mval = y / scale
        out[r] = mval
        out[4 + r] = (dy - dlog * y) / scale
    return out[0], out[1], out[2], out[3], out[4], out[5], out[6], out[7]


@njit(cache=True)
def hermite_fields(eps: float, eps_max: float, table: np.ndarray, start: int, n: int,
                   pi_: np.ndarray, dpi: np.ndarray) -> None:
    """The basis fields ``Pi`` and ``dPi/deps`` (each ``(n_theta, nb, 2)``, written into
    ``pi_, dpi``) from a field table: per node ``Y = (1 - eps^2)^3 Pi`` then ``dY/dt``
    (the Guembel film, whose clamp needs the fields, not only ``M``)."""
    size = pi_.size
    t = 1.0 - math.sqrt(max(1.0 - eps / eps_max, 0.0))
    h = 1.0 / (n - 1)
    k = min(int(t / h), n - 2)
    s = (t - k * h) / h
    s2 = s * s
    s3 = s2 * s
    h00, h10, h01, h11 = 2 * s3 - 3 * s2 + 1, s3 - 2 * s2 + s, -2 * s3 + 3 * s2, s3 - s2
    g00, g10 = (6 * s2 - 6 * s) / h, 3 * s2 - 4 * s + 1
    g01, g11 = (-6 * s2 + 6 * s) / h, 3 * s2 - 2 * s
    deps_dt = 2.0 * eps_max * (1.0 - t)
    c = (1.0 - eps) * (1.0 + eps)
    scale = c * c * c
    dlog = -6.0 * eps / c
    a = start + 2 * size * k
    b = a + 2 * size
    flat = pi_.reshape(size)
    dflat = dpi.reshape(size)
    for r in range(size):
        y = h00 * table[a + r] + h10 * h * table[a + size + r] + h01 * table[b + r] \
            + h11 * h * table[b + size + r]
        dy = (g00 * table[a + r] + g10 * table[a + size + r] + g01 * table[b + r]
              + g11 * table[b + size + r]) / deps_dt
        flat[r] = y / scale
        dflat[r] = (dy - dlog * y) / scale
