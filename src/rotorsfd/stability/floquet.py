"""Floquet multipliers: result object, stability decision, crossing type, Liouville check.

For ``M x'' + D(t) x' + K(t) x = 0`` with period T, the monodromy matrix ``Phi`` maps the
state ``(x, x')`` over one period; its eigenvalues are the Floquet multipliers ``mu``.
The periodic solution is asymptotically stable if ``max |mu| < 1`` (paper eq. 38).

Numerically, ``max |mu| = 1`` cannot be decided; we call a solution *unstable* when
``max |mu| > 1 + tol`` with the default ``STABILITY_TOL = 1e-5``: it sits above the
discretisation and round-off noise of neutral multipliers in our tests (about 1e-9 with
Hill/Magnus, 1e-7 with Newmark on a reduced model) and two orders below the smallest
margin reported in the paper (1.0014 - 1). Results carry the Liouville check so that
an unreliable monodromy (unresolved high modes) is visible.

Liouville (Abel-Jacobi) identity for the first-order form ``y' = A(t) y``::

    det Phi = exp( integral_0^T trace A dt ) = exp( -integral_0^T trace(M^-1 D(t)) dt )
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Literal

import numpy as np
from numpy.typing import NDArray

STABILITY_TOL: float = 1e-5
"""Unstable if ``max |mu| > 1 + STABILITY_TOL``."""

CrossingType = Literal["saddle-node", "period-doubling", "secondary-hopf"]


def sort_multipliers(mu: NDArray) -> NDArray[np.complex128]:
    """Multipliers sorted by decreasing modulus (ties: by angle), as complex."""
    mu = np.asarray(mu, dtype=complex).ravel()
    order = np.lexsort((np.angle(mu), -np.abs(mu)))
    return mu[order]


def multiplier_type(mu: complex, imag_tol: float = 1e-6) -> CrossingType:
    """Crossing type of a critical multiplier: real > 0 -> 'saddle-node' (through +1),
    real < 0 -> 'period-doubling' (through -1), complex -> 'secondary-hopf'.

    ``mu`` is taken as real when ``|Im mu| <= imag_tol * max(1, |mu|)``.
    """
    if abs(mu.imag) <= imag_tol * max(1.0, abs(mu)):
        return "saddle-node" if mu.real > 0 else "period-doubling"
    return "secondary-hopf"


def liouville_log_det(trace_minv_d: NDArray, period: float) -> float:
    """Exact ``log det Phi = -int_0^T trace(M^-1 D(t)) dt`` from samples of the trace at
    ``t_j = j T / N``, ``j = 0..N`` (trapezoidal quadrature, exact for constant D)."""
    tr = np.asarray(trace_minv_d, dtype=float)
    h = period / (tr.size - 1)
    return float(-h * (tr.sum() - 0.5 * (tr[0] + tr[-1])))


@dataclass
class FloquetResult:
    """Floquet multipliers of one periodic solution (or one linear periodic system).

    Attributes
    ----------
    multipliers : complex array, sorted by decreasing ``|mu|``.
    period : T.
    method : e.g. ``'newmark'``, ``'newmark-cb'`` (Craig-Bampton reduced), ``'magnus4'``,
        ``'hill-symmetric'``, ``'hill-koopman'``.
    log_det_exact : Liouville value ``-int tr(M^-1 D) dt`` (None if not available).
    monodromy : the monodromy matrix (None for Hill with eigenvalue sorting).
    tol : stability tolerance.
    info : method details (intervals, sizes, kept modes, ...).
    """

    multipliers: NDArray[np.complex128]
    period: float
    method: str
    log_det_exact: float | None = None
    monodromy: NDArray | None = None
    tol: float = STABILITY_TOL
    info: dict = field(default_factory=dict)

    @property
    def max_abs(self) -> float:
        """``max |mu|``."""
        return float(np.max(np.abs(self.multipliers)))

    @property
    def critical(self) -> complex:
        """The multiplier of largest modulus."""
        return complex(self.multipliers[0])

    @property
    def stable(self) -> bool:
        """``max |mu| <= 1 + tol``."""
        return self.max_abs <= 1.0 + self.tol

    @property
    def crossing_type(self) -> CrossingType | None:
        """Type of the critical multiplier if unstable, else None."""
        return None if self.stable else multiplier_type(self.critical)

    @property
    def exponents(self) -> NDArray[np.complex128]:
        """Floquet exponents ``log(mu) / T`` (imaginary part modulo 2 pi / T)."""
        with np.errstate(divide="ignore"):
            return np.log(self.multipliers.astype(complex)) / self.period

    @property
    def liouville_error(self) -> float | None:
        """``|sum log|mu| - log_det_exact|``: relative error of ``det Phi``.

        Large values flag an inaccurate monodromy (e.g. unresolved stiff modes). Infinite
        if a multiplier is exactly zero.
        """
        if self.log_det_exact is None:
            return None
        with np.errstate(divide="ignore"):
            s = float(np.sum(np.log(np.abs(self.multipliers))))
        return abs(s - self.log_det_exact)

    def summary(self) -> str:
        """One line: method, max |mu|, critical multiplier, stability, Liouville error."""
        c = self.critical
        le = self.liouville_error
        les = "n/a" if le is None else f"{le:.2e}"
        state = "stable" if self.stable else f"unstable ({self.crossing_type})"
        return (f"{self.method}: |mu|max={self.max_abs:.8f} mu=({c.real:.6f}"
                f"{c.imag:+.6f}j) {state}; Liouville err={les}")
