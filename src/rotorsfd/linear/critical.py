"""Critical speeds: spin speeds where a whirl branch meets the harmonic line.

Branch ``i`` of a whirl kind is the i-th lowest damped frequency among the modes of that
whirl at a given speed, ``w_i(Omega)``; sorted frequencies are continuous in Omega. A
critical speed is a root of ``g_i(Omega) = w_i(Omega) - h Omega`` (h = ``harmonic``):
sign changes of ``g_i`` are bracketed on a grid over ``speed_range`` and each root is
located by ``scipy.optimize.brentq`` (not read off the grid).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from rotorsfd.errors import ConfigError
from rotorsfd.linear.modal import LinearDynamics, eigen


@dataclass(frozen=True)
class CriticalSpeed:
    """Critical speed of branch ``mode`` (1-based within its whirl kind)."""

    mode: int
    whirl: str
    speed_rad_s: float


def branch_frequency(system: LinearDynamics, speed: float, mode: int, whirl: str = "forward",
                     n_modes: int = 16) -> float:
    """w_mode(speed): the ``mode``-th (1-based) lowest damped frequency of the given whirl
    ("forward", "backward" or "any"); NaN when fewer such modes are among ``n_modes``."""
    res = eigen(system, speed, n_modes)
    freq = res.frequencies if whirl == "any" else res.frequencies[res.whirl == whirl]
    return float(freq[mode - 1]) if freq.size >= mode else float("nan")


def critical_speeds(system: LinearDynamics, n: int = 2, whirl: str = "forward",
                    harmonic: float = 1.0, speed_range: tuple[float, float] = (0.0, 2e4),
                    n_grid: int = 81, n_modes: int | None = None,
                    xtol: float = 1e-9) -> list[CriticalSpeed]:
    """The ``n`` lowest critical speeds [rad/s] in ``speed_range`` (fewer if not found)."""
    if whirl not in ("forward", "backward", "any"):
        raise ConfigError("whirl", whirl, "one of 'forward', 'backward', 'any'")
    if not harmonic > 0.0:
        raise ConfigError("harmonic", harmonic, "must be positive")
    n_modes = n_modes if n_modes is not None else 4 * n + 8
    n_branch = n + 2
    lo, hi = speed_range
    grid = np.linspace(lo, hi, n_grid)

    def g(speed: float, mode: int) -> float:
        return branch_frequency(system, speed, mode, whirl, n_modes) - harmonic * speed

    table = np.full((n_grid, n_branch), np.nan)
    for k, s in enumerate(grid):
        res = eigen(system, s, n_modes)
        freq = res.frequencies if whirl == "any" else res.frequencies[res.whirl == whirl]
        m = min(freq.size, n_branch)
        table[k, :m] = freq[:m] - harmonic * s
    found: list[CriticalSpeed] = []
    for b in range(n_branch):
        col = table[:, b]
        for k in range(n_grid - 1):
            a, c = col[k], col[k + 1]
            if not (np.isfinite(a) and np.isfinite(c)) or a * c > 0.0 or a == c == 0.0:
                continue
            if a == 0.0:
                root = grid[k]
            else:
                root = brentq(g, grid[k], grid[k + 1], args=(b + 1,), xtol=xtol,
                              rtol=4 * np.finfo(float).eps)
            found.append(CriticalSpeed(b + 1, whirl, float(root)))
    found.sort(key=lambda c: c.speed_rad_s)
    return found[:n]
