"""External forcing and time-varying matrices of the integrated system.

The integrated system is ``M q'' + D(t) q' + K(t) q = f(t) + F_nl(q[nl], q'[nl])`` with::

    f(t) = f0 + sum_h [ fc_h cos(k_h w t) + fs_h sin(k_h w t) ] + sum_j c_j(t) f_j
    D(t) = D0 + sum_i d_i(t) D_i,    K(t) = K0 + sum_i k_i(t) K_i

``w`` is the base (forcing) frequency, ``k_h`` real multiples of it (not necessarily
integers). A coefficient ``c_j``, ``d_i``, ``k_i`` is either a callable ``c(t) -> array``
(vectorised over a time array) or an array of its values on the time grid
``t_k = t0 + k dt``, ``k = 0 .. n_steps``.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field

import numpy as np

Coefficient = Callable[[np.ndarray], np.ndarray] | np.ndarray


@dataclass(frozen=True)
class HarmonicLoad:
    """``fc cos(multiple w t) + fs sin(multiple w t)``; ``fs`` defaults to zero."""

    multiple: float
    cos: np.ndarray
    sin: np.ndarray | None = None


@dataclass(frozen=True)
class Forcing:
    """``f(t) = constant + sum harmonics + sum_j c_j(t) f_j`` (module docstring).

    ``omega`` [rad/s] is the base frequency; it defines the forcing period
    ``2 pi / omega`` used for steps per period and Poincare sampling.
    ``series`` is a sequence of ``(coefficient, vector)`` pairs.
    """

    omega: float = 0.0
    constant: np.ndarray | None = None
    harmonics: Sequence[HarmonicLoad] = ()
    series: Sequence[tuple[Coefficient, np.ndarray]] = ()

    @property
    def period(self) -> float:
        """Forcing period ``2 pi / omega``."""
        if not self.omega > 0.0:
            raise ValueError("forcing.omega must be > 0 to define a forcing period")
        return 2.0 * np.pi / self.omega

    def at(self, t: float | np.ndarray, n_dof: int) -> np.ndarray:
        """``f(t)`` for callables only (array coefficients need a grid index); ``(.., n)``."""
        t = np.asarray(t, dtype=float)
        f = np.zeros((*t.shape, n_dof))
        if self.constant is not None:
            f += np.asarray(self.constant, dtype=float)
        for h in self.harmonics:
            ph = h.multiple * self.omega * t[..., None]
            f += np.cos(ph) * np.asarray(h.cos, dtype=float)
            if h.sin is not None:
                f += np.sin(ph) * np.asarray(h.sin, dtype=float)
        for c, vec in self.series:
            if not callable(c):
                raise TypeError("Forcing.at needs callable series coefficients")
            f += np.asarray(c(t), dtype=float)[..., None] * np.asarray(vec, dtype=float)
        return f


@dataclass(frozen=True)
class TimeVaryingMatrices:
    """``D(t) = D0 + sum d_i(t) D_i``, ``K(t) = K0 + sum k_i(t) K_i``: sequences of
    ``(coefficient, matrix)`` pairs added to the constant ``D0``, ``K0``."""

    damping: Sequence[tuple[Coefficient, np.ndarray]] = field(default_factory=tuple)
    stiffness: Sequence[tuple[Coefficient, np.ndarray]] = field(default_factory=tuple)

    @property
    def n_terms(self) -> int:
        """Number of time-varying matrices."""
        return len(self.damping) + len(self.stiffness)


def sample_coefficient(c: Coefficient, t0: float, dt: float, n_steps: int,
                       name: str = "coefficient") -> np.ndarray:
    """Values of ``c`` on the grid ``t_k = t0 + k dt``, ``k = 0..n_steps``."""
    if callable(c):
        t = t0 + dt * np.arange(n_steps + 1)
        values = np.asarray(c(t), dtype=float)
        if values.ndim == 0:
            values = np.full(n_steps + 1, float(values))
    else:
        values = np.asarray(c, dtype=float)
    if values.shape != (n_steps + 1,):
        raise ValueError(f"{name}: expected {n_steps + 1} samples, got shape {values.shape}")
    if not np.all(np.isfinite(values)):
        raise ValueError(f"{name}: non-finite values")
    return values
