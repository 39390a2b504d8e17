"""Fit support stiffnesses so that the rotor's critical speeds match target values.

Unknowns ``k_j`` are searched as ``log10 k_j`` (positive, scale-free); the residuals are
the relative errors ``r_i = Omega_i(k) / Omega_i^target - 1`` of the lowest critical
speeds (root-found, :func:`rotorsfd.linear.critical.critical_speeds`), minimised with
``scipy.optimize.least_squares`` (trust-region reflective within ``bounds``). With as many
unknowns as targets the minimum is 0 if the targets are reachable; otherwise the result
is the least-squares compromise and ``exact`` is False.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass

import numpy as np
from scipy.optimize import least_squares

from rotorsfd.linear.critical import critical_speeds
from rotorsfd.linear.modal import LinearDynamics


@dataclass(frozen=True)
class SupportFit:
    """Result of :func:`fit_support_stiffness`."""

    stiffnesses: tuple[float, ...]       # fitted k_j [N/m], in the order of x0
    critical_speeds: tuple[float, ...]   # resulting critical speeds [rad/s]
    targets: tuple[float, ...]
    relative_errors: tuple[float, ...]   # Omega_i / target_i - 1
    exact: bool                          # all |relative error| <= tol
    message: str


def fit_support_stiffness(
    build: Callable[..., LinearDynamics],
    targets: Sequence[float] = (811.3, 2784.6),
    x0: Sequence[float] = (1e7, 1e7),
    whirl: str = "forward",
    bounds: tuple[float, float] = (1e5, 1e11),
    tol: float = 1e-6,
    speed_range: tuple[float, float] | None = None,
) -> SupportFit:
    """Find stiffnesses ``k`` with ``build(*k)`` having critical speeds ``targets``.

    ``build(k_1, ..., k_m)`` returns a LinearDynamics system (e.g. a Rotor);
    ``targets`` are the lowest ``whirl`` critical speeds in increasing order [rad/s].
    """
    targets_arr = np.asarray(targets, dtype=float)
    n_t = targets_arr.size
    rng = speed_range if speed_range is not None else (0.0, 2.5 * float(targets_arr.max()))

    def speeds_of(logk: np.ndarray) -> np.ndarray:
        system = build(*(10.0 ** logk))
        crit = critical_speeds(system, n=n_t, whirl=whirl, speed_range=rng, n_grid=41)
        out = np.full(n_t, rng[1])            # missing critical speed: beyond the range
        out[: len(crit)] = [c.speed_rad_s for c in crit]
        return out

    def residual(logk: np.ndarray) -> np.ndarray:
        return speeds_of(logk) / targets_arr - 1.0

    lb, ub = np.log10(bounds[0]), np.log10(bounds[1])
    start = np.clip(np.log10(np.asarray(x0, dtype=float)), lb + 1e-6, ub - 1e-6)
    sol = least_squares(residual, start, bounds=(lb, ub), x_scale=1.0, diff_step=1e-6,
                        xtol=1e-14, ftol=1e-14, gtol=1e-14, max_nfev=200)
    crit = speeds_of(sol.x)
    rel = crit / targets_arr - 1.0
    exact = bool(np.all(np.abs(rel) <= tol))
    msg = ("targets met" if exact else
           f"targets not both met: least-squares relative errors {rel.tolist()}") + \
          f" ({sol.nfev} evaluations; {sol.message})"
    return SupportFit(tuple(float(k) for k in 10.0 ** sol.x), tuple(float(c) for c in crit),
                      tuple(float(t) for t in targets_arr), tuple(float(r) for r in rel),
                      exact, msg)
