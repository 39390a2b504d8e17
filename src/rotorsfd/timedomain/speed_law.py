"""Rotor speed laws Omega(t) for the time domain: constant, linear ramp, table, callable.

A law gives the spin speed relative to the base ``Omega(t)`` [rad/s], its derivative
``dOmega/dt`` [rad/s^2] and the rotor angle ``theta(t) = int_0^t Omega(s) ds`` [rad]
(the unbalance's angle is ``theta(t) + eta``), vectorised over a time array. The three
must agree (``theta' = Omega``, ``Omega' = dOmega/dt``): the ramp in closed form, the
table by one shape-preserving cubic (scipy's PchipInterpolator, C1) with its exact
derivative and antiderivative, the callable by a derivative and an angle given with it
or computed (central difference, adaptive quadrature).

Terms of a varying speed (fixed base; the base terms in ``analyses/runup.py``). A mass
m_u at eccentricity e at rho = e (cos phi, sin phi) in (y, z), phi = theta + eta, has
rho'' = e Omega' (-sin phi, cos phi) - e Omega^2 (cos phi, sin phi); the force on the
rotor is minus m_u times it:

    F_y = m_u e [Omega^2 cos(phi) + Omega' sin(phi)]
    F_z = m_u e [Omega^2 sin(phi) - Omega' cos(phi)]

(the tangential term opposes the acceleration: the rotor drives the mass). It is
``model/unbalance.py`` with ``Omega t -> theta(t)`` and ``wx' -> wx' + Omega'`` (both
are the axial angular acceleration of the spinning disk). The disk's axial angular
velocity in the tilted frame is ``Omega - tz' sin(ty)`` (derivations/base_motion.py),
so ``1/2 Ip (Omega - tz' ty)^2`` gives the gyroscopic ``Omega(t) G`` and, from
``d/dt(-Ip Omega ty)`` in the tz equation, a stiffness ``-Ip Omega' `` at (tz, ty): the
pattern ``-(Omega'/2)(PS + PJ)`` of ``model/base_terms.py``, whose ``wx'`` enters the
polar-inertia patterns the same way.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Protocol

import numpy as np
from scipy.integrate import quad
from scipy.interpolate import PchipInterpolator

from rotorsfd.errors import ConfigError

FIELD = "analysis.simulate.speed_law"


class SpeedLaw(Protocol):
    """Omega(t), dOmega/dt and theta(t) = int_0^t Omega (vectorised)."""

    def omega(self, t: np.ndarray) -> np.ndarray: ...
    def domega(self, t: np.ndarray) -> np.ndarray: ...
    def angle(self, t: np.ndarray) -> np.ndarray: ...


@dataclass(frozen=True)
class ConstantSpeed:
    """Omega(t) = speed."""

    speed: float

    def __post_init__(self) -> None:
        if not (np.isfinite(self.speed) and self.speed > 0.0):
            raise ConfigError(f"{FIELD}.speed", self.speed, "must be finite and > 0 rad/s")

    def omega(self, t):
        return np.full(np.shape(t), float(self.speed))

    def domega(self, t):
        return np.zeros(np.shape(t))

    def angle(self, t):
        return float(self.speed) * np.asarray(t, dtype=float)

    def describe(self) -> str:
        return f"constant {self.speed:g} rad/s"


@dataclass(frozen=True)
class RampSpeed:
    """Omega = start until ``t_start``, then linear to ``stop`` over ``duration``, then
    ``stop``: ``theta`` is the area under that polygon (exact)."""

    start: float
    stop: float
    duration: float
    t_start: float = 0.0

    def __post_init__(self) -> None:
        for name in ("start", "stop"):
            v = getattr(self, name)
            if not (np.isfinite(v) and v > 0.0):
                raise ConfigError(f"{FIELD}.{name}", v, "must be finite and > 0 rad/s")
        if not (np.isfinite(self.duration) and self.duration > 0.0):
            raise ConfigError(f"{FIELD}.duration", self.duration, "must be finite and > 0 s")
        if not (np.isfinite(self.t_start) and self.t_start >= 0.0):
            raise ConfigError(f"{FIELD}.t_start", self.t_start, "must be finite and >= 0 s")

    @property
    def rate(self) -> float:
        """dOmega/dt on the ramp [rad/s^2]."""
        return (self.stop - self.start) / self.duration

    def _tau(self, t):
        return np.clip(np.asarray(t, dtype=float) - self.t_start, 0.0, self.duration)

    def omega(self, t):
        return self.start + self.rate * self._tau(t)

    def domega(self, t):
        s = np.asarray(t, dtype=float) - self.t_start
        on = (s >= 0.0) & (s < self.duration)
        return np.where(on, self.rate, 0.0)

    def angle(self, t):
        t = np.asarray(t, dtype=float)
        tau = self._tau(t)
        before = self.start * np.minimum(t, self.t_start)
        ramp = self.start * tau + 0.5 * self.rate * tau**2
        after = self.stop * np.maximum(t - self.t_start - self.duration, 0.0)
        return before + ramp + after

    def describe(self) -> str:
        return (f"ramp {self.start:g} -> {self.stop:g} rad/s over {self.duration:g} s "
                f"from t = {self.t_start:g} s")


@dataclass(frozen=True)
class TableSpeed:
    """Omega through the points ``(times, speeds)`` by PchipInterpolator (monotone between
    points, C1); held at the end values outside the table."""

    times: np.ndarray
    speeds: np.ndarray
    _spline: object = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        t = np.asarray(self.times, dtype=float).reshape(-1)
        w = np.asarray(self.speeds, dtype=float).reshape(-1)
        if t.size < 2 or t.size != w.size:
            raise ConfigError(f"{FIELD}.times", t.size, "at least 2 times, as many as speeds")
        if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0.0)):
            raise ConfigError(f"{FIELD}.times", t.tolist()[:4], "finite and increasing")
        if not (np.all(np.isfinite(w)) and np.all(w > 0.0)):
            raise ConfigError(f"{FIELD}.speeds", w.tolist()[:4], "finite and > 0 rad/s")
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "speeds", w)
        object.__setattr__(self, "_spline", PchipInterpolator(t, w, extrapolate=False))

    def omega(self, t):
        t = np.asarray(t, dtype=float)
        tc = np.clip(t, self.times[0], self.times[-1])
        return np.asarray(self._spline(tc), dtype=float)

    def domega(self, t):
        t = np.asarray(t, dtype=float)
        inside = (t >= self.times[0]) & (t <= self.times[-1])
        tc = np.clip(t, self.times[0], self.times[-1])
        return np.where(inside, self._spline.derivative()(tc), 0.0)

    def angle(self, t):
        t = np.asarray(t, dtype=float)
        t0, t1 = self.times[0], self.times[-1]
        tc = np.clip(t, t0, t1)
        before = self.speeds[0] * (np.minimum(t, t0))
        inside = np.asarray(self._spline.antiderivative()(tc), dtype=float)
        after = self.speeds[-1] * np.maximum(t - t1, 0.0)
        return before + inside + after

    def describe(self) -> str:
        return (f"table of {self.times.size} points, {self.speeds[0]:g} -> "
                f"{self.speeds[-1]:g} rad/s over [{self.times[0]:g}, {self.times[-1]:g}] s")


@dataclass(frozen=True)
class CallableSpeed:
    """Omega = ``function(t)`` (vectorised); ``derivative`` and ``angle`` if known, else a
    central difference (step ``h``) and adaptive quadrature from 0."""

    function: Callable[[np.ndarray], np.ndarray]
    derivative: Callable[[np.ndarray], np.ndarray] | None = None
    integral: Callable[[np.ndarray], np.ndarray] | None = None
    h: float = 1e-6

    def omega(self, t):
        t = np.asarray(t, dtype=float)
        return np.broadcast_to(np.asarray(self.function(t), dtype=float), t.shape).copy()

    def domega(self, t):
        t = np.asarray(t, dtype=float)
        if self.derivative is not None:
            return np.broadcast_to(np.asarray(self.derivative(t), float), t.shape).copy()
        return (self.omega(t + self.h) - self.omega(t - self.h)) / (2.0 * self.h)

    def angle(self, t):
        t = np.asarray(t, dtype=float)
        if self.integral is not None:
            return np.broadcast_to(np.asarray(self.integral(t), float), t.shape).copy()
        flat = t.reshape(-1)
        order = np.argsort(flat)
        out = np.empty(flat.size)
        acc, last = 0.0, 0.0
        for i in order:                       # cumulative over the sorted times
            acc += quad(lambda s: float(self.function(np.asarray(s))), last, flat[i],
                        epsabs=0.0, epsrel=1e-12, limit=200)[0]
            last = flat[i]
            out[i] = acc
        return out.reshape(t.shape)

    def describe(self) -> str:
        return f"callable {getattr(self.function, '__name__', 'function')}"


def speed_range(law: SpeedLaw, t_end: float, samples: int = 2001) -> tuple[float, float]:
    """(min, max) of Omega on [0, t_end] (sampled; exact at a ramp's or table's points)."""
    t = np.linspace(0.0, t_end, samples)
    extra = [np.asarray(getattr(law, "times", []), float)]
    if isinstance(law, RampSpeed):
        extra.append(np.array([law.t_start, law.t_start + law.duration]))
    t = np.concatenate([t, *(e[(e >= 0.0) & (e <= t_end)] for e in extra)])
    w = law.omega(t)
    if not np.all(np.isfinite(w)) or np.any(w <= 0.0):
        raise ConfigError(FIELD, "Omega(t)", "must be finite and > 0 rad/s on the run")
    return float(w.min()), float(w.max())
