"""The base rotation rates of a stability chart as functions of the chart parameters.

Each rotation rate is off, constant or harmonic::

    w(t) = value + a sin(w_b t + phase),   a = amplitude, or A0 w_b (angle amplitude A0)

(the paper's ``w_by = A0 w_b sin(w_b t)``), all with the same ``w_b``, so that the system
is periodic with ``T = 2 pi / w_b`` (no harmonic rate: ``T = 2 pi / Omega``). A chart
axis is a "coefficient" parameter when it is ``speed`` or
``base.{rolling,pitching,yawing}.{value, amplitude, angle_amplitude, frequency, phase}``
(:func:`coefficient_target`): :class:`ChartParams` maps a grid row's values of the two
parameters to the speed and the three rate laws, and gives the scalar coefficients
``c_i(t), k_i(t)`` of the 12 base matrices (:func:`rotorsfd.model.base_terms.base_coefficients`),
linear in Omega: ``k(Omega) = k(0) + Omega (k(1) - k(0))``.
"""

from __future__ import annotations

import threading
from collections.abc import Callable
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import split_path
from rotorsfd.model.base_motion import BaseMotion, BaseState, Harmonic
from rotorsfd.model.base_terms import base_coefficients

if TYPE_CHECKING:
    from rotorsfd.io.schema import Config

__all__ = ["RATE_FIELDS", "RATE_KINDS", "RATE_UNITS", "ROTATIONS", "ChartParams",
           "CoefficientCache", "RateSpec", "coefficient_target", "rate_specs_from_config",
           "rate_specs_from_motion"]

ROTATIONS: tuple[str, ...] = ("rolling", "pitching", "yawing")
RATE_FIELDS: tuple[str, ...] = ("value", "amplitude", "angle_amplitude", "frequency", "phase")
#: SI unit of each rate field
RATE_UNITS = {"value": "rad/s", "amplitude": "rad/s", "angle_amplitude": "rad",
              "frequency": "rad/s", "phase": "rad"}
#: the physical kind (``rotorsfd.io.units.KINDS``) of each rate field
RATE_KINDS = {"value": "angular_velocity", "amplitude": "angular_velocity",
              "angle_amplitude": "angle", "frequency": "angular_velocity", "phase": "angle"}


@dataclass(frozen=True)
class RateSpec:
    """One base rotation rate: ``law`` off / constant / harmonic and its fields (SI).

    ``amplitude`` is the rate amplitude; if None (or if an axis sets the angle
    amplitude), ``angle_amplitude * frequency``.
    """

    law: str = "off"
    value: float = 0.0
    amplitude: float | None = None
    angle_amplitude: float | None = None
    frequency: float = 0.0
    phase: float = 0.0

    def law_at(self, values: dict[str, Any]) -> Harmonic:
        """The rate as a :class:`Harmonic` law whose fields may be arrays (``values``:
        field -> value overriding this spec)."""
        get = {f: values.get(f, getattr(self, f)) for f in RATE_FIELDS}
        if self.law == "off":
            return Harmonic(0.0, 0.0)
        if self.law == "constant":
            return Harmonic(0.0, 0.0, 0.0, get["value"])
        freq = get["frequency"]
        if "angle_amplitude" not in values and (self.amplitude is not None
                                                or "amplitude" in values):
            amp = get["amplitude"]
        else:
            a0 = get["angle_amplitude"]
            amp = (0.0 if a0 is None else a0) * freq
        return Harmonic(amp, freq, _or0(get["phase"]), _or0(get["value"]))


def _or0(v: Any) -> Any:
    return 0.0 if v is None else v


def rate_specs_from_config(config: Config) -> tuple[RateSpec, RateSpec, RateSpec]:
    """The three rotation rates of ``[base]``; ConfigError for a callable law."""
    out = []
    for name in ROTATIONS:
        c = getattr(config.base, name)
        if c.law == "callable":
            raise ConfigError(f"base.{name}.law", c.law, "a stability chart needs 'off', "
                              "'constant' or 'harmonic' base rates (a known period)")
        out.append(RateSpec(c.law, c.value or 0.0, c.amplitude, c.angle_amplitude,
                            c.frequency or 0.0, c.phase or 0.0))
    return tuple(out)  # type: ignore[return-value]


def rate_specs_from_motion(motion: BaseMotion | None) -> tuple[RateSpec, RateSpec, RateSpec]:
    """The three rotation rates of a :class:`BaseMotion` (harmonic laws keep their rate
    amplitude); ValueError for other laws."""
    if motion is None:
        return RateSpec(), RateSpec(), RateSpec()
    out = []
    for name, law in zip(ROTATIONS, motion.rotation, strict=True):
        if law.kind == "off":
            out.append(RateSpec())
        elif law.kind == "constant":
            out.append(RateSpec("constant", float(law.c)))
        elif law.kind == "harmonic":
            out.append(RateSpec("harmonic", law.mean, law.amplitude, None, law.frequency,
                                law.phase))
        else:
            raise ValueError(f"base {name} law {law.kind!r}: a stability chart needs off, "
                             "constant or harmonic rates")
    return tuple(out)  # type: ignore[return-value]


def coefficient_target(path: str) -> tuple[int, str] | None:
    """``(-1, 'speed')`` for ``speed``, ``(component, field)`` for a base-rate field,
    None for any other (structural) path."""
    path = path.strip()
    if path == "speed":
        return -1, "speed"
    try:
        parts = split_path(path)
    except ValueError:
        return None
    if len(parts) == 3 and parts[0] == "base" and parts[1] in ROTATIONS \
            and parts[2] in RATE_FIELDS:
        return ROTATIONS.index(str(parts[1])), str(parts[2])
    return None


@dataclass(frozen=True)
class ChartParams:
    """Maps the chart parameters (p1, p2) to the speed and the three rate laws."""

    specs: tuple[RateSpec, ...]
    speed: float | None
    p1: tuple[int, str] | None = None   # what p1 is (None: unused)
    p2: tuple[int, str] | None = None

    def resolve(self, p1: Any, p2: Any) -> tuple[Any, list[Harmonic]]:
        over: list[dict[str, Any]] = [{}, {}, {}]
        speed = self.speed
        for target, value in ((self.p1, p1), (self.p2, p2)):
            if target is None:
                continue
            comp, name = target
            if comp < 0:
                speed = value
            else:
                over[comp][name] = value
        return speed, [s.law_at(o) for s, o in zip(self.specs, over, strict=True)]

    def period(self, p1: Any, p2: Any) -> NDArray:
        """``2 pi / w_b`` (``2 pi / Omega`` without a harmonic rate), broadcast."""
        speed, laws = self.resolve(p1, p2)
        freqs = [np.asarray(law.frequency, float) for law, s in zip(laws, self.specs,
                                                                      strict=True)
                 if s.law == "harmonic"]
        shape = np.broadcast_shapes(np.shape(p1), np.shape(p2))
        w = np.broadcast_to(freqs[0] if freqs else np.asarray(speed, float), shape)
        return 2.0 * np.pi / w

    def coefficients(self, t: NDArray, p1: Any, p2: Any) -> tuple[NDArray, NDArray]:
        """``(c_C, c_K)`` (12, *t.shape) of the base matrices at times t."""
        speed, laws = self.resolve(p1, p2)
        shape = np.broadcast_shapes(np.shape(t), np.shape(p1), np.shape(p2))
        w = np.array([np.broadcast_to(law.value(t), shape) for law in laws])
        dw = np.array([np.broadcast_to(law.d1(t), shape) for law in laws])
        state = BaseState(w=w, dw=dw, a0=np.zeros_like(w))
        c0 = base_coefficients(state, 0.0)
        c1 = base_coefficients(state, 1.0)
        om = np.asarray(speed, float)
        return c0.c_C + om * (c1.c_C - c0.c_C), c0.c_K + om * (c1.c_K - c0.c_K)


class CoefficientCache:
    """Per-thread cache of the last ``ChartParams.coefficients`` call (every term of a grid
    row asks for the same arrays)."""

    def __init__(self, params: ChartParams) -> None:
        self.params = params
        self.local = threading.local()

    def get(self, t: NDArray, p1: Any, p2: Any) -> tuple[NDArray, NDArray]:
        key = (t.shape, t.tobytes(), np.asarray(p1).tobytes(), np.asarray(p2).tobytes())
        if getattr(self.local, "key", None) != key:
            self.local.value = self.params.coefficients(t, p1, p2)
            self.local.key = key
        return self.local.value

    def term(self, which: int, i: int) -> Callable[[NDArray, Any, Any], NDArray]:
        return lambda t, p1, p2: self.get(np.asarray(t, float), p1, p2)[which][i]
