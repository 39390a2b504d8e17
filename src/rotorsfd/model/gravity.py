"""Gravity as a base acceleration, and its direction in a rotating base frame.

A body in a uniform gravity field g is equivalent to a base accelerating with -g, so the
rotor sees the effective base acceleration ``a_eff = a0 - g`` and the load
``F = -m a_eff`` on every mass (see :mod:`rotorsfd.model.base_terms`).

Gravity is fixed in inertial space; the base rotates with angular velocity w (base
components), so in the base frame the gravity vector obeys the Poisson equation

    dg/dt = -w x g,     g(0) = g0                                       (1)

(base and inertial axes coincide at t = 0). ``frame="inertial"`` (default) integrates (1)
exactly: closed form for constant w (rotation of g0 by the angle -|w| t about w, Rodrigues),
otherwise an adaptive DOP853 integration (rtol 1e-11) with dense output, cached.
``frame="base"`` keeps g fixed in the base frame: the approximation for small attitude
excursions (e.g. harmonic pitching of small angle amplitude A0) or for a gravity direction
defined relative to the vehicle.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from rotorsfd.errors import ConfigError

STANDARD_GRAVITY = 9.80665


@dataclass(frozen=True)
class Gravity:
    """Uniform gravity of ``magnitude`` [m/s^2] along ``direction`` (base frame at t = 0).

    Default: 9.80665 m/s^2 along -z (z is vertical). ``enabled=False`` switches it off.
    """

    magnitude: float = STANDARD_GRAVITY
    direction: tuple[float, float, float] = (0.0, 0.0, -1.0)
    frame: str = "inertial"
    enabled: bool = True
    _cache: dict = field(default_factory=dict, init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        if not np.isfinite(self.magnitude) or self.magnitude < 0.0:
            raise ConfigError("gravity.magnitude", self.magnitude, "must be finite and >= 0")
        d = np.asarray(self.direction, dtype=float)
        if d.shape != (3,) or not np.all(np.isfinite(d)) or np.linalg.norm(d) == 0.0:
            raise ConfigError("gravity.direction", self.direction, "a nonzero 3-vector")
        if self.frame not in ("inertial", "base"):
            raise ConfigError("gravity.frame", self.frame, "'inertial' or 'base'")

    @property
    def vector(self) -> np.ndarray:
        """g0 = magnitude * direction / |direction| (base frame at t = 0) [m/s^2]."""
        d = np.asarray(self.direction, dtype=float)
        return self.magnitude * d / np.linalg.norm(d)


def rotate_constant_rate(g0: np.ndarray, w: np.ndarray, t: np.ndarray) -> np.ndarray:
    """Solution of (1) for constant w: g(t) = R(-|w| t, w/|w|) g0 (Rodrigues), shape (3,)+t."""
    t = np.asarray(t, dtype=float)
    wn = float(np.linalg.norm(w))
    if wn == 0.0:
        return np.multiply.outer(g0, np.ones_like(t))
    k = np.asarray(w, float) / wn
    ang = -wn * t
    c, s = np.cos(ang), np.sin(ang)
    kxg = np.cross(k, g0)
    kdg = float(k @ g0)
    return (np.multiply.outer(g0, c) + np.multiply.outer(kxg, s)
            + np.multiply.outer(k * kdg, 1.0 - c))


def _integrate(g0: np.ndarray, rates: Callable[[np.ndarray], np.ndarray], t_end: float):
    from scipy.integrate import solve_ivp  # deferred: scipy.integrate (0.7 s to import)

    def rhs(t: float, g: np.ndarray) -> np.ndarray:
        return -np.cross(rates(np.asarray(t)), g)

    sol = solve_ivp(rhs, (0.0, t_end), g0, method="DOP853", rtol=1e-11,
                    atol=1e-13 * max(1.0, float(np.linalg.norm(g0))), dense_output=True)
    if not sol.success:  # pragma: no cover - smooth rates always integrate
        raise RuntimeError(f"gravity attitude integration failed: {sol.message}")
    return sol.sol


def gravity_in_base(gravity: Gravity, rates: Callable[[np.ndarray], np.ndarray],
                    t: np.ndarray | float, constant_rates: bool = False,
                    cache_key: object = None) -> np.ndarray:
    """Gravity vector in the base frame at time(s) t, shape (3,) or (3, nt); eq. (1).

    ``rates(t) -> w (3,)`` is the base angular velocity. The dense integral of (1) is cached
    on the Gravity object under ``cache_key`` (a hashable description of the rate laws; no
    caching if None) and extended when t leaves its range.
    """
    t = np.asarray(t, dtype=float)
    g0 = gravity.vector
    if not gravity.enabled:
        return np.zeros((3, *t.shape))
    if gravity.frame == "base":
        return np.multiply.outer(g0, np.ones_like(t))
    if constant_rates:
        return rotate_constant_rate(g0, np.asarray(rates(np.asarray(0.0)), float), t)
    t1 = np.atleast_1d(t).ravel()
    out = np.empty((3, t1.size))
    for sign in (1.0, -1.0):
        mask = (t1 >= 0.0) if sign > 0 else (t1 < 0.0)
        if not np.any(mask):
            continue
        t_far = float(np.max(np.abs(t1[mask])))
        entry = None if cache_key is None else gravity._cache.get((cache_key, sign))
        if entry is None or entry[0] < t_far:
            t_end = max(t_far, 1e-12) * 1.25
            entry = (t_end, _integrate(g0, rates, sign * t_end))
            if cache_key is not None:
                gravity._cache[(cache_key, sign)] = entry
        out[:, mask] = entry[1](t1[mask])
    return out.reshape((3, *t.shape))
