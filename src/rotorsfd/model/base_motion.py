"""Time laws of the base motion and the base state seen by the rotor.

The base is a rigid body carrying the rotor's bearings; the equations of motion are
written in the base frame ``Oxyz`` (x along the shaft axis, y horizontal, z vertical).
Six scalar laws describe its motion (paper section 2.1):

* translations ``x0(t), y0(t), z0(t)`` [m]: their time derivatives are the base-frame
  components of the velocity of the origin O, ``v0 = (x0', y0', z0')`` (the convention of
  the paper and its reference [20]); the absolute acceleration of O in base components is

      a0 = v0' + w x v0                                              (1)

  (exactly ``(x0'', y0'', z0'')`` when the base does not rotate);
* angular velocity of the base ``w = (w_bx, w_by, w_bz)`` [rad/s] in base components
  (rolling about x, pitching about y, yawing about z) and its derivative ``w'``.

Each law is :class:`Off`, :class:`Constant`, :class:`UniformAcceleration` (quadratic in
t), :class:`Harmonic` or :class:`CallableLaw`. ``BaseMotion(...).state(t)`` evaluates all
of them (vectorised over arrays of t) into a :class:`BaseState`, which the base terms
(:mod:`rotorsfd.model.base_terms`) and the unbalance force consume.

Gravity (:mod:`rotorsfd.model.gravity`) enters the state as the base-frame vector ``g``;
the rotor sees the effective acceleration ``a_eff = a0 - g`` (a body in gravity g is
equivalent to a base accelerating with -g).
"""

from __future__ import annotations

import math
import warnings
from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model.gravity import Gravity, gravity_in_base

ArrayLike = float | np.ndarray
_EPS = np.finfo(float).eps


# ---------------------------------------------------------------------------------------
# scalar time laws f(t) with f', f''
# ---------------------------------------------------------------------------------------
class TimeLaw:
    """A scalar function of time with its first and second derivatives."""

    kind: str = "law"

    def value(self, t: ArrayLike) -> np.ndarray:
        raise NotImplementedError

    def d1(self, t: ArrayLike) -> np.ndarray:
        raise NotImplementedError

    def d2(self, t: ArrayLike) -> np.ndarray:
        raise NotImplementedError

    @property
    def is_constant(self) -> bool:
        """True if f is constant in time (f' = f'' = 0)."""
        return False

    @property
    def is_zero(self) -> bool:
        """True if f, f', f'' vanish identically."""
        return False

    def support_times(self) -> np.ndarray:
        """Times inside the interval where a law that acts only for a while (a pulse, a
        record) is nonzero (empty: the law is not local)."""
        return np.zeros(0)


@dataclass(frozen=True)
class Off(TimeLaw):
    """f(t) = 0."""

    kind: str = field(default="off", init=False)

    def value(self, t: ArrayLike) -> np.ndarray:
        return np.zeros_like(np.asarray(t, dtype=float))

    d1 = value
    d2 = value

    @property
    def is_constant(self) -> bool:
        return True

    @property
    def is_zero(self) -> bool:
        return True


@dataclass(frozen=True)
class Constant(TimeLaw):
    """f(t) = c (a constant rate; for a translation, a constant offset without effect)."""

    c: float
    kind: str = field(default="constant", init=False)

    def value(self, t: ArrayLike) -> np.ndarray:
        return np.full_like(np.asarray(t, dtype=float), float(self.c))

    def d1(self, t: ArrayLike) -> np.ndarray:
        return np.zeros_like(np.asarray(t, dtype=float))

    d2 = d1

    @property
    def is_constant(self) -> bool:
        return True

    @property
    def is_zero(self) -> bool:
        return self.c == 0.0


@dataclass(frozen=True)
class UniformAcceleration(TimeLaw):
    """f(t) = f0 + v t + a t^2 / 2 (for translations: constant base acceleration a)."""

    acceleration: float
    velocity: float = 0.0
    offset: float = 0.0
    kind: str = field(default="uniform_acceleration", init=False)

    def value(self, t: ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.offset + self.velocity * t + 0.5 * self.acceleration * t**2

    def d1(self, t: ArrayLike) -> np.ndarray:
        return self.velocity + self.acceleration * np.asarray(t, dtype=float)

    def d2(self, t: ArrayLike) -> np.ndarray:
        return np.full_like(np.asarray(t, dtype=float), float(self.acceleration))

    @property
    def is_constant(self) -> bool:
        return self.acceleration == 0.0 and self.velocity == 0.0

    @property
    def is_zero(self) -> bool:
        return self.acceleration == 0.0 and self.velocity == 0.0 and self.offset == 0.0


@dataclass(frozen=True)
class Harmonic(TimeLaw):
    """f(t) = A sin(w t + phi) + c  (amplitude A, angular frequency w [rad/s], phase phi).

    The paper's harmonic pitching ``w_by = A0 w_b sin(w_b t)`` is
    ``Harmonic(amplitude=A0 * w_b, frequency=w_b)``.
    """

    amplitude: float
    frequency: float
    phase: float = 0.0
    mean: float = 0.0
    kind: str = field(default="harmonic", init=False)

    def value(self, t: ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.mean + self.amplitude * np.sin(self.frequency * t + self.phase)

    def d1(self, t: ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return self.amplitude * self.frequency * np.cos(self.frequency * t + self.phase)

    def d2(self, t: ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        return -self.amplitude * self.frequency**2 * np.sin(self.frequency * t + self.phase)

    @property
    def is_constant(self) -> bool:
        return self.amplitude == 0.0 or self.frequency == 0.0

    @property
    def is_zero(self) -> bool:
        return self.is_constant and float(self.value(0.0)) == 0.0


def _call(f: Callable, t: np.ndarray) -> np.ndarray:
    """f(t) for an array t, falling back to a loop if f is not vectorised."""
    out = np.asarray(f(t))
    if out.shape != t.shape:
        out = np.array([f(ti) for ti in t.ravel()]).reshape(t.shape)
    return out


def numerical_derivative(f: Callable, t: ArrayLike) -> np.ndarray:
    """f'(t) by the complex step ``Im f(t + i h) / h``, h = 1e-20 (exact to rounding).

    Used when f accepts complex input and returns a complex value (numpy ufuncs do);
    otherwise the central difference ``(f(t+h) - f(t-h)) / (2 h)`` with
    ``h = eps^(1/3) max(1, |t|)`` (error O(h^2), about 1e-10 relative for smooth f).
    """
    t = np.asarray(t, dtype=float)
    h = 1e-20
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("error", np.exceptions.ComplexWarning)
            fc = np.asarray(f(t + 1j * h))
        if np.iscomplexobj(fc) and fc.shape == t.shape and np.any(fc.imag != 0.0):
            return fc.imag / h
    except (TypeError, ValueError, np.exceptions.ComplexWarning):
        pass
    hc = _EPS ** (1.0 / 3.0) * np.maximum(1.0, np.abs(t))
    return (_call(f, t + hc) - _call(f, t - hc)) / (2.0 * hc)


def _central(f: Callable, t: np.ndarray) -> np.ndarray:
    hc = _EPS ** (1.0 / 3.0) * np.maximum(1.0, np.abs(t))
    return (f(t + hc) - f(t - hc)) / (2.0 * hc)


@dataclass(frozen=True)
class CallableLaw(TimeLaw):
    """User law f(t) with optional analytic derivatives df(t), ddf(t).

    Missing derivatives: f' by :func:`numerical_derivative` (complex step, else central
    difference); f'' as the central difference of f' (h = eps^(1/3) max(1, |t|)).
    ``constant=True`` declares f constant in time (used by ``BaseMotion.is_constant``).
    """

    f: Callable[[np.ndarray], np.ndarray]
    df: Callable[[np.ndarray], np.ndarray] | None = None
    ddf: Callable[[np.ndarray], np.ndarray] | None = None
    constant: bool = False
    kind: str = field(default="callable", init=False)

    def value(self, t: ArrayLike) -> np.ndarray:
        return _call(self.f, np.asarray(t, dtype=float)).astype(float)

    def d1(self, t: ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if self.df is not None:
            return _call(self.df, t).astype(float)
        return numerical_derivative(self.f, t)

    def d2(self, t: ArrayLike) -> np.ndarray:
        t = np.asarray(t, dtype=float)
        if self.ddf is not None:
            return _call(self.ddf, t).astype(float)
        return _central(self.d1, t)

    @property
    def is_constant(self) -> bool:
        return self.constant


def as_law(value: TimeLaw | float | Callable | None, name: str) -> TimeLaw:
    """Coerce None -> Off, a number -> Constant, a callable -> CallableLaw."""
    if value is None:
        return Off()
    if isinstance(value, TimeLaw):
        return value
    if isinstance(value, int | float) and not isinstance(value, bool):
        if not math.isfinite(value):
            raise ConfigError(f"base_motion.{name}", value, "must be finite")
        return Off() if value == 0.0 else Constant(float(value))
    if callable(value):
        return CallableLaw(value)
    raise ConfigError(f"base_motion.{name}", value,
                      "expected None, a number, a callable or a TimeLaw")


# ---------------------------------------------------------------------------------------
# base state
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class BaseState:
    """Base motion at time t, base-frame components; arrays (3,) or (3, nt).

    w: angular velocity (w_bx, w_by, w_bz) [rad/s]; dw: its derivative [rad/s^2];
    v0: velocity of the origin [m/s]; a0: absolute acceleration of the origin, eq. (1)
    [m/s^2]; g: gravity vector in the base frame [m/s^2] (zero if off).
    """

    w: np.ndarray
    dw: np.ndarray
    a0: np.ndarray
    v0: np.ndarray | None = None
    g: np.ndarray | None = None
    t: ArrayLike | None = None

    @property
    def a_eff(self) -> np.ndarray:
        """Effective base acceleration a0 - g (gravity as an upward base acceleration)."""
        a0 = np.asarray(self.a0, dtype=float)
        return a0 if self.g is None else a0 - np.asarray(self.g, dtype=float)

    def acceleration_slope(self, axis: int) -> np.ndarray:
        """d a0 / d w[axis] = e_axis x v0 (eq. 1, the origin velocity v0 held; zero
        without v0): how the origin acceleration follows a base rate."""
        if self.v0 is None:
            return np.zeros(3)
        return np.cross(np.eye(3)[axis], np.asarray(self.v0, dtype=float), axis=0)

    def with_rate(self, axis: int, value: float) -> BaseState:
        """This (constant) state with the base rate ``w[axis]`` set to ``value`` and the
        rest of the base motion held: v0, v0' and g; the origin acceleration
        a0 = v0' + w x v0 (eq. 1) follows the rate, affine in it,
        ``a0 + (value - w[axis]) e_axis x v0``. (Gravity stays constant in the base frame
        only if it is fixed to the base or along the axis: the caller checks that.)"""
        w = np.array(self.w, dtype=float)
        step = float(value) - w[axis]
        w[axis] = value
        slope = self.acceleration_slope(axis)
        a0 = self.a0
        if np.any(slope != 0.0):     # without translation: a0 itself (the same bits)
            a0 = np.asarray(a0, dtype=float) + step * slope
        return BaseState(w, np.asarray(self.dw, dtype=float), a0, self.v0, self.g)

    @classmethod
    def fixed(cls) -> BaseState:
        """A base at rest, no gravity."""
        return cls(np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3))

    @classmethod
    def constant(cls, w: ArrayLike = (0.0, 0.0, 0.0), a0: ArrayLike = (0.0, 0.0, 0.0),
                 g: ArrayLike = (0.0, 0.0, 0.0)) -> BaseState:
        """Constant rates w (w' = 0), origin acceleration a0 and gravity g (a_eff = a0 - g)."""
        return cls(np.asarray(w, float), np.zeros(3), np.asarray(a0, float), None,
                   np.asarray(g, float))


# ---------------------------------------------------------------------------------------
# base motion
# ---------------------------------------------------------------------------------------
class BaseMotion:
    """The six laws of the base motion plus optional gravity.

    ``BaseMotion(x0=..., y0=..., z0=..., wx=..., wy=..., wz=..., gravity=None)``; each law is a
    :class:`TimeLaw`, a number (constant), a callable (:class:`CallableLaw`) or None (off).
    Gravity is off by default.
    """

    def __init__(self, x0: TimeLaw | float | Callable | None = None,
                 y0: TimeLaw | float | Callable | None = None,
                 z0: TimeLaw | float | Callable | None = None,
                 wx: TimeLaw | float | Callable | None = None,
                 wy: TimeLaw | float | Callable | None = None,
                 wz: TimeLaw | float | Callable | None = None,
                 gravity: Gravity | None = None) -> None:
        self.translation: tuple[TimeLaw, TimeLaw, TimeLaw] = (
            as_law(x0, "x0"), as_law(y0, "y0"), as_law(z0, "z0"))
        self.rotation: tuple[TimeLaw, TimeLaw, TimeLaw] = (
            as_law(wx, "wx"), as_law(wy, "wy"), as_law(wz, "wz"))
        self.gravity = gravity

    # ---- rates -------------------------------------------------------------------------
    def rates(self, t: ArrayLike) -> np.ndarray:
        """w(t), shape (3,) or (3, nt)."""
        return np.array([law.value(t) for law in self.rotation])

    def rate_derivatives(self, t: ArrayLike) -> np.ndarray:
        """w'(t), shape (3,) or (3, nt)."""
        return np.array([law.d1(t) for law in self.rotation])

    @property
    def rates_constant(self) -> bool:
        """True if every rotation law is constant in time."""
        return all(law.is_constant for law in self.rotation)

    @property
    def is_fixed(self) -> bool:
        """True if the base does not move and gravity is off (all base terms vanish)."""
        return (all(law.is_zero for law in self.rotation)
                and all(law.is_zero or law.kind == "constant" for law in self.translation)
                and (self.gravity is None or not self.gravity.enabled))

    @property
    def is_constant(self) -> bool:
        """True if w, w' and a0 - g are constant in time (harmonic balance needs this).

        Rates constant; the origin's acceleration a0 = v0' + w x v0 constant (translation
        laws with constant v0, or w = 0 and uniform accelerations); gravity constant in
        the base frame (off, fixed to the base, or w parallel to g).
        """
        if not self.rates_constant:
            return False
        w = self.rates(0.0)
        rotating = bool(np.any(w != 0.0))
        for law in self.translation:
            if law.kind in ("off", "constant"):
                continue
            if law.kind == "uniform_acceleration" and (not rotating or law.acceleration == 0.0):
                continue
            if law.is_constant:
                continue
            return False
        g = self.gravity
        if g is not None and g.enabled and g.frame == "inertial" and rotating:
            return bool(np.linalg.norm(np.cross(w, g.vector)) == 0.0)
        return True

    def support_times(self) -> np.ndarray:
        """The laws' :meth:`TimeLaw.support_times` together (probes of the base terms)."""
        return np.concatenate([law.support_times()
                               for law in (*self.translation, *self.rotation)])

    # ---- state -------------------------------------------------------------------------
    def state(self, t: ArrayLike) -> BaseState:
        """Base state at time(s) t: w, w', v0, a0 = v0' + w x v0 (eq. 1), gravity g."""
        t_arr = np.asarray(t, dtype=float)
        w = self.rates(t_arr)
        dw = self.rate_derivatives(t_arr)
        v0 = np.array([law.d1(t_arr) for law in self.translation])
        dv0 = np.array([law.d2(t_arr) for law in self.translation])
        a0 = dv0 + np.cross(w, v0, axis=0)
        if self.gravity is None or not self.gravity.enabled:
            g = np.zeros_like(a0)
        else:
            g = gravity_in_base(self.gravity, self.rates, t_arr,
                                constant_rates=self.rates_constant, cache_key=self.rotation)
        return BaseState(w=w, dw=dw, a0=a0, v0=v0, g=g, t=t)

    def __repr__(self) -> str:
        names = ("x0", "y0", "z0", "wx", "wy", "wz")
        laws = self.translation + self.rotation
        parts = [f"{n}={law!r}" for n, law in zip(names, laws, strict=True) if not law.is_zero]
        if self.gravity is not None and self.gravity.enabled:
            parts.append(f"gravity={self.gravity!r}")
        return f"BaseMotion({', '.join(parts)})"
