"""Initial states of a time-domain run: every node displaced, on the HB periodic orbit
(at any phase of it), or the final state of a previous run (``timeseries.nc``).

The HB orbit ``q(t) = Re sum_k X_k exp(i k Omega t)`` gives ``q(0) = Re sum X_k``,
``v(0) = Re sum i k Omega X_k``; a phase ``p`` of the period is ``X_k exp(i k 2 pi p)``.
A saved state continues exactly at the same speed (t0 = the saved time); at another speed
the run starts where the new rotor phase equals the saved one.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path

import numpy as np

from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.model.system import RotorSystem

__all__ = ["SavedState", "displaced_state", "hb_start", "hb_state", "load_state",
           "shift_phase", "timeseries_path"]


def displaced_state(n_dof: int, displacement: float) -> np.ndarray:
    """``q0`` with every node's y and z displaced by ``displacement`` (rotations zero)."""
    q0 = np.zeros(n_dof)
    q0[0::4] = q0[1::4] = displacement
    return q0


def hb_state(X: np.ndarray, speed: float) -> tuple[np.ndarray, np.ndarray]:
    """``(q(0), v(0))`` of ``q(t) = Re sum_k X_k exp(i k Omega t)``, X (H+1, n_dof)."""
    k = np.arange(X.shape[0])[:, None]
    return X.sum(axis=0).real.copy(), (1j * k * speed * X).sum(axis=0).real.copy()


def shift_phase(X: np.ndarray, phase: float) -> np.ndarray:
    """Coefficients of ``q(t + phase T)``: ``X_k exp(i k 2 pi phase)``, X (H+1, ...)."""
    k = np.arange(X.shape[0]).reshape((-1,) + (1,) * (X.ndim - 1))
    return X * np.exp(2j * math.pi * k * float(phase))


def hb_start(system: RotorSystem, speed: float, harmonics: int = 3,
             n_samples: int | None = None, phase: float = 0.0
             ) -> tuple[np.ndarray, np.ndarray]:
    """Initial state on the HB periodic solution at ``speed`` (constant base only), taken
    a fraction ``phase`` of the period later (:func:`shift_phase`).

    Newton from the linearised response; if that fails (strongly nonlinear points), the
    branch is continued from ``speed / 2`` and its first arrival at ``speed`` taken.
    """
    problem = system.periodic_problem()
    try:
        sol = solve_periodic(problem, speed, harmonics, n_samples=n_samples)
        return hb_state(shift_phase(sol.X, phase), speed)
    except ConvergenceError as first:
        branch = continue_periodic(problem, 0.5 * speed, speed, harmonics,
                                   n_samples=n_samples, limit_max=0.999)
        if not (branch.n_points and abs(branch.lam[-1] - speed) <= 1e-9 * speed):
            raise ConvergenceError(
                f"HB start at {speed:.6g} rad/s: {' '.join(str(first).split())}; "
                f"continuation from {0.5 * speed:.6g} rad/s: {branch.message}") from None
        return hb_state(shift_phase(branch.X[-1], phase), speed)


@dataclass(frozen=True)
class SavedState:
    """The final state of a run (``timeseries.nc``): every DOF's displacement ``q`` [m]
    and velocity ``v`` [m/s] at time ``t`` [s], rotor speed ``speed`` [rad/s]."""

    q: np.ndarray
    v: np.ndarray
    t: float
    speed: float
    source: str = ""

    @property
    def phase(self) -> float:
        """Rotor phase ``Omega t mod 2 pi`` at the saved time [rad]."""
        return float(math.fmod(self.speed * self.t, 2.0 * math.pi))

    def start_time(self, speed: float) -> float:
        """Start time of a run at ``speed`` from this state: the saved time at the same
        speed (exact continuation), else the time where ``speed * t`` is the saved phase."""
        if abs(speed - self.speed) <= 1e-12 * self.speed:
            return self.t
        return self.phase / speed


def timeseries_path(path: str | Path) -> Path:
    """``path`` itself, or ``path/timeseries.nc`` for a directory."""
    p = Path(path)
    return p / "timeseries.nc" if p.is_dir() else p


def load_state(path: str | Path) -> SavedState:
    """The final state stored in a ``timeseries.nc`` (or a directory holding one)."""
    # deferred: xarray is heavy (loaded only when this runs)
    import xarray as xr

    p = timeseries_path(path)
    if not p.is_file():
        raise ConfigError("initial_state", str(path), "no such file (give a simulate "
                          "output directory or its timeseries.nc)")
    with xr.open_dataset(p) as ds:
        if "final_displacement" not in ds or "t_final_s" not in ds.attrs:
            raise ConfigError("initial_state", str(path), "this timeseries.nc has no final "
                              "state (written by an older rotorsfd): run it again")
        return SavedState(np.asarray(ds["final_displacement"].values, float),
                          np.asarray(ds["final_velocity"].values, float),
                          float(ds.attrs["t_final_s"]), float(ds.attrs["speed_rad_s"]),
                          str(p))
