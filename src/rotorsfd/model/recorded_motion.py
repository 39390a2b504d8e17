"""Base-motion laws for manoeuvres and shocks: a recorded history and a shock pulse.

Both are :class:`~rotorsfd.model.base_motion.TimeLaw` s, so a base component (a rotation
rate w_b(t) or an origin displacement x0(t)) may be either; the base terms need the law
``f`` with ``f'`` (rates: w'; translations: the velocity v0) and ``f''`` (translations:
the acceleration), which must be one function and its exact derivatives, or the rotor
sees a base that does not move as recorded.

**Recorded** (:class:`RecordedLaw`): samples ``(t_i, y_i)`` of the law's ``order``-th
derivative ``y = f^(order)``: for a rotation rate ``order`` is 0 (rates recorded, as a
gyroscope gives them) or -1 (angles recorded: ``f = y'``); for a translation 0
(displacements), 1 (velocities) or 2 (accelerations, as an accelerometer gives them).
The samples are interpolated by one C2 cubic spline ``S`` (scipy's
``make_interp_spline``, not-a-knot), and

    f = D^(-order) S,   f' = D^(1-order) S,   f'' = D^(2-order) S

with ``D^-1`` the antiderivative from ``t_0`` (zero there: the velocity and displacement
of an integrated acceleration record start at rest, at the origin). An optional
``filter`` (cut-off frequency [rad/s]) low-passes the record first: resampled uniformly at
the smallest sample interval, filtered forward and backward by a 4th-order Butterworth
(``scipy.signal.sosfiltfilt``: zero phase, so no delay), then splined. Differentiating a
noisy displacement record twice amplifies its noise by (w dt)^-2: filter it. Outside
``[t_0, t_n]`` the law holds its end values with zero derivatives (a record starting from
rest and ending at rest is continuous there).

**Pulse** (:class:`PulseLaw`): a shock of amplitude ``A``, duration ``T`` from ``t_s``,
with ``s = t - t_s`` on ``[0, T]`` and the shape applied to the ``order``-th derivative
(0: a rate pulse; 2: an acceleration pulse of a translation, the landing / shock case):

    half-sine:  p(s) = A sin(pi s / T)
    versine:    p(s) = (A / 2) (1 - cos(2 pi s / T))      (= A sin^2(pi s / T))

and zero outside. The lower derivatives are its integrals in closed form (below, ``Pk``
the k-th antiderivative from s = 0): half-sine ``P1 = A T/pi (1 - cos(pi s/T))``,
``P2 = A T/pi (s - T/pi sin(pi s/T))``; versine ``P1 = A/2 (s - T/(2 pi) sin(2 pi s/T))``,
``P2 = A/2 (s^2/2 + (T/(2 pi))^2 (cos(2 pi s/T) - 1))``; after the pulse ``P1`` keeps its
final value (the velocity change ``2 A T/pi``, resp. ``A T/2``) and ``P2`` grows linearly
with it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from pathlib import Path
from typing import Literal

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model.base_motion import ArrayLike, TimeLaw

PulseShape = Literal["half_sine", "versine"]


def read_record(path: Path, field_name: str) -> tuple[np.ndarray, np.ndarray]:
    """(times [s], values [SI]) of a two-column CSV (one header line allowed) or of a
    netCDF file with one data variable over a ``time`` coordinate."""
    if not path.is_file():
        raise ConfigError(field_name, str(path), "an existing CSV or netCDF file")
    if path.suffix.lower() in (".nc", ".nc4", ".netcdf"):
        # deferred: xarray is heavy (loaded only when this runs)
        import xarray as xr

        with xr.open_dataset(path) as ds:
            names = [n for n, v in ds.data_vars.items() if v.dims == ("time",)]
            if len(names) != 1 or "time" not in ds.coords:
                raise ConfigError(field_name, str(path), "a netCDF file with one data "
                                  "variable over a 'time' coordinate [s]")
            t = np.asarray(ds["time"].values, dtype=float)
            y = np.asarray(ds[names[0]].values, dtype=float)
    else:
        try:
            data = np.genfromtxt(path, delimiter=",", comments="#", skip_header=0)
        except ValueError as exc:
            raise ConfigError(field_name, str(path), f"two numeric columns: {exc}") from None
        data = np.atleast_2d(data)
        data = data[~np.all(np.isnan(data), axis=1)] if data.size else data
        if data.ndim != 2 or data.shape[1] != 2:
            raise ConfigError(field_name, str(path), "two numeric columns: time [s], value "
                              "[SI], comma separated (one header line allowed)")
        t, y = data[:, 0], data[:, 1]
    return t, y


def _checked(times: np.ndarray, values: np.ndarray, field_name: str) -> tuple[np.ndarray, ...]:
    t = np.asarray(times, dtype=float).reshape(-1)
    y = np.asarray(values, dtype=float).reshape(-1)
    if t.size < 4 or t.size != y.size:
        raise ConfigError(field_name, t.size, "at least 4 samples, as many times as values")
    if not (np.all(np.isfinite(t)) and np.all(np.diff(t) > 0.0)):
        raise ConfigError(field_name, t.tolist()[:4], "times finite and increasing")
    if not np.all(np.isfinite(y)):
        raise ConfigError(field_name, "a value", "every value finite")
    return t, y


def lowpass(t: np.ndarray, y: np.ndarray, cutoff: float,
            field_name: str = "filter") -> tuple[np.ndarray, np.ndarray]:
    """The record resampled uniformly at its smallest interval and filtered by a zero-phase
    4th-order Butterworth low-pass of cut-off ``cutoff`` [rad/s] (module docstring)."""
    # deferred: scipy.signal is heavy (loaded only when this runs)
    from scipy.signal import butter, sosfiltfilt

    dt = float(np.min(np.diff(t)))
    n = math.floor((t[-1] - t[0]) / dt + 1e-9) + 1
    tu = t[0] + dt * np.arange(n)
    yu = np.interp(tu, t, y)
    nyquist = math.pi / dt
    if not 0.0 < cutoff < nyquist:
        raise ConfigError(field_name, cutoff, f"a cut-off below the record's Nyquist "
                          f"frequency {nyquist:.6g} rad/s")
    sos = butter(4, cutoff / nyquist, output="sos")
    pad = min(3 * 9, n - 1)
    return tu, sosfiltfilt(sos, yu, padlen=pad)


@dataclass(frozen=True)
class RecordedLaw(TimeLaw):
    """A law through recorded samples of its ``order``-th derivative (module docstring)."""

    times: np.ndarray
    values: np.ndarray
    order: int = 0
    cutoff: float | None = None
    where: str = "base"
    kind: str = field(default="recorded", init=False)
    _splines: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        # deferred: scipy.interpolate is heavy (loaded only when this runs)
        from scipy.interpolate import make_interp_spline

        if self.order not in (-1, 0, 1, 2):
            raise ConfigError(f"{self.where}.quantity", self.order, "order -1, 0, 1 or 2")
        t, y = _checked(self.times, self.values, f"{self.where}.file")
        if self.cutoff is not None:
            t, y = lowpass(t, y, float(self.cutoff), f"{self.where}.filter")
        s = make_interp_spline(t, y, k=3)
        # D^(k - order) S for k = 0, 1, 2 (the law, f', f'')
        splines = []
        for k in range(3):
            m = k - self.order
            splines.append(s.derivative(m) if m > 0 else s.antiderivative(-m) if m < 0 else s)
        object.__setattr__(self, "times", t)
        object.__setattr__(self, "values", y)
        object.__setattr__(self, "_splines", tuple(splines))

    def _eval(self, k: int, t: ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        t0, t1 = self.times[0], self.times[-1]
        tc = np.clip(t, t0, t1)
        out = np.asarray(self._splines[k](tc), dtype=float)
        if k > 0:
            out = np.where((t >= t0) & (t <= t1), out, 0.0)
        return out

    def value(self, t: ArrayLike) -> np.ndarray:
        return self._eval(0, t)

    def d1(self, t: ArrayLike) -> np.ndarray:
        return self._eval(1, t)

    def d2(self, t: ArrayLike) -> np.ndarray:
        return self._eval(2, t)

    def support_times(self) -> np.ndarray:
        return self.times[:: max(1, self.times.size // 64)]

    @property
    def span(self) -> tuple[float, float]:
        """(first, last) recorded time [s]."""
        return float(self.times[0]), float(self.times[-1])


@dataclass(frozen=True)
class PulseLaw(TimeLaw):
    """A half-sine or versine shock on the ``order``-th derivative (module docstring)."""

    shape: PulseShape
    amplitude: float
    duration: float
    start: float = 0.0
    order: int = 0
    kind: str = field(default="pulse", init=False)

    def __post_init__(self) -> None:
        if self.shape not in ("half_sine", "versine"):
            raise ConfigError("shape", self.shape, "'half_sine' or 'versine'")
        if not (math.isfinite(self.duration) and self.duration > 0.0):
            raise ConfigError("duration", self.duration, "must be finite and > 0 s")
        if not (math.isfinite(self.start) and self.start >= 0.0):
            raise ConfigError("start", self.start, "must be finite and >= 0 s")
        if self.order not in (0, 1, 2):
            raise ConfigError("order", self.order, "0, 1 or 2")

    def support_times(self) -> np.ndarray:
        return self.start + self.duration * np.array([0.25, 0.5, 0.75, 2.0])

    def _integral(self, k: int, t: ArrayLike) -> np.ndarray:
        """P_k(s): the k-th antiderivative of the pulse from its start (k = 0: the pulse)."""
        A, T = float(self.amplitude), float(self.duration)
        s = np.asarray(t, dtype=float) - self.start
        sc = np.clip(s, 0.0, T)
        after = np.maximum(s - T, 0.0)
        if self.shape == "half_sine":
            a = math.pi / T
            p = [A * np.sin(a * sc), A / a * (1.0 - np.cos(a * sc)),
                 A / a * (sc - np.sin(a * sc) / a)]
            end1 = 2.0 * A / a
        else:
            b = 2.0 * math.pi / T
            p = [0.5 * A * (1.0 - np.cos(b * sc)), 0.5 * A * (sc - np.sin(b * sc) / b),
                 0.5 * A * (0.5 * sc**2 + (np.cos(b * sc) - 1.0) / b**2)]
            end1 = 0.5 * A * T
        if k == 0:
            return np.where((s >= 0.0) & (s <= T), p[0], 0.0)
        if k == 1:
            return p[1]
        return p[2] + end1 * after

    def _level(self, k: int, t: ArrayLike) -> np.ndarray:
        """f^(k) = P_(order - k) (a derivative of the pulse beyond it is not needed)."""
        m = self.order - k
        if m < 0:
            raise ValueError("derivative of the pulse beyond its own order")
        return self._integral(m, t)

    def value(self, t: ArrayLike) -> np.ndarray:
        return self._level(0, t)

    def d1(self, t: ArrayLike) -> np.ndarray:
        if self.order == 0:
            return self._pulse_derivative(t)
        return self._level(1, t)

    def d2(self, t: ArrayLike) -> np.ndarray:
        if self.order == 2:
            return self._level(2, t)
        if self.order == 1:
            return self._pulse_derivative(t)
        raise ValueError("the second derivative of a rate pulse is not used")

    def _pulse_derivative(self, t: ArrayLike) -> np.ndarray:
        """dp/ds on the pulse (the rate pulse's w')."""
        A, T = float(self.amplitude), float(self.duration)
        s = np.asarray(t, dtype=float) - self.start
        on = (s >= 0.0) & (s <= T)
        if self.shape == "half_sine":
            a = math.pi / T
            d = A * a * np.cos(a * s)
        else:
            b = 2.0 * math.pi / T
            d = 0.5 * A * b * np.sin(b * s)
        return np.where(on, d, 0.0)
