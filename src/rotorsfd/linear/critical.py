"""Critical speeds: spin speeds where a whirl branch meets the harmonic line.

Branch ``i`` of a whirl kind is the i-th lowest damped frequency among the modes of that
whirl at a given speed, ``w_i(Omega)``; sorted frequencies are continuous in Omega. A
critical speed is a root of ``g_i(Omega) = w_i(Omega) - h Omega`` (h = ``harmonic``):
sign changes of ``g_i`` are bracketed on a grid over ``speed_range`` and each root is
located by ``scipy.optimize.brentq`` (not read off the grid). The grid is scanned upwards
and stops once ``n`` sign changes are bracketed: every later root lies above them
(``full_grid=True`` scans it all, as before). With the sparse eigensolver each evaluation
computes only the lowest modes up to the branch asked for.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy.optimize import brentq

from rotorsfd.errors import ConfigError
from rotorsfd.linear.modal import LinearDynamics, ModalResult, dense_eigen, use_sparse
from rotorsfd.linear.sparse_modes import sparse_eigen


@dataclass(frozen=True)
class CriticalSpeed:
    """Critical speed of branch ``mode`` (1-based within its whirl kind)."""

    mode: int
    whirl: str
    speed_rad_s: float


def _modes(system: LinearDynamics, speed: float, n_modes: int, whirl: str, count: int,
           method: str) -> ModalResult:
    """The lowest modes at ``speed``: all ``n_modes`` (dense), or up to the ``count``-th of
    ``whirl`` among them (sparse: the same first modes, fewer computed)."""
    if use_sparse(system, method):
        return sparse_eigen(system, speed, n_modes, whirl=whirl, count=count)
    return dense_eigen(system, speed, n_modes)


def branch_frequency(system: LinearDynamics, speed: float, mode: int, whirl: str = "forward",
                     n_modes: int = 16, method: str = "auto") -> float:
    """w_mode(speed): the ``mode``-th (1-based) lowest damped frequency of the given whirl
    ("forward", "backward" or "any"); NaN when fewer such modes are among ``n_modes``."""
    res = _modes(system, speed, n_modes, whirl, mode, method)
    freq = res.frequencies if whirl == "any" else res.frequencies[res.whirl == whirl]
    return float(freq[mode - 1]) if freq.size >= mode else float("nan")


def critical_speeds(system: LinearDynamics, n: int = 2, whirl: str = "forward",
                    harmonic: float = 1.0, speed_range: tuple[float, float] = (0.0, 2e4),
                    n_grid: int = 81, n_modes: int | None = None,
                    xtol: float = 1e-9, method: str = "auto",
                    full_grid: bool = False) -> list[CriticalSpeed]:
    """The ``n`` lowest critical speeds [rad/s] in ``speed_range`` (fewer if not found).
    ``method``: the eigensolver ("auto", "dense", "sparse"; see :func:`eigen`)."""
    if whirl not in ("forward", "backward", "any"):
        raise ConfigError("whirl", whirl, "one of 'forward', 'backward', 'any'")
    if not harmonic > 0.0:
        raise ConfigError("harmonic", harmonic, "must be positive")
    use_sparse(system, method)  # validates method
    n_modes = n_modes if n_modes is not None else 4 * n + 8
    n_branch = n + 2
    lo, hi = speed_range
    grid = np.linspace(lo, hi, n_grid)

    def g(speed: float, mode: int) -> float:
        return branch_frequency(system, speed, mode, whirl, n_modes, method) - harmonic * speed

    table = np.full((n_grid, n_branch), np.nan)
    for k, s in enumerate(grid):
        res = _modes(system, s, n_modes, whirl, n_branch, method)
        freq = res.frequencies if whirl == "any" else res.frequencies[res.whirl == whirl]
        m = min(freq.size, n_branch)
        table[k, :m] = freq[:m] - harmonic * s
        if not full_grid and k > 0 and len(_brackets(table[:k + 1])) >= n:
            table = table[:k + 1]
            break
    found: list[CriticalSpeed] = []
    for b, k in _brackets(table):
        a = table[k, b]
        if a == 0.0:
            root = grid[k]
        else:
            root = brentq(g, grid[k], grid[k + 1], args=(b + 1,), xtol=xtol,
                          rtol=4 * np.finfo(float).eps)
        found.append(CriticalSpeed(b + 1, whirl, float(root)))
    found.sort(key=lambda c: c.speed_rad_s)
    return found[:n]


def _brackets(table: np.ndarray) -> list[tuple[int, int]]:
    """(branch, grid cell) of every sign change of g in ``table`` (n_speeds, n_branch)."""
    out = []
    for b in range(table.shape[1]):
        col = table[:, b]
        for k in range(table.shape[0] - 1):
            a, c = col[k], col[k + 1]
            if not (np.isfinite(a) and np.isfinite(c)) or a * c > 0.0 or a == c == 0.0:
                continue
            out.append((b, k))
    return out


def line_critical_speeds(system: LinearDynamics, lines: dict[str, float], n: int = 2,
                         **options) -> list[tuple[str, CriticalSpeed]]:
    """The ``n`` lowest critical speeds on each excitation line ``w = h Omega`` of
    ``lines`` (name -> slope h; a dual-spool rotor: each shaft's unbalance line against one
    spool's speed, :class:`~rotorsfd.model.multishaft.SpoolSpeed`), as ``(name, critical)``
    sorted by speed; ``options`` as for :func:`critical_speeds`."""
    out = [(name, c) for name, h in lines.items()
           for c in critical_speeds(system, n=n, harmonic=h, **options)]
    return sorted(out, key=lambda item: item[1].speed_rad_s)
