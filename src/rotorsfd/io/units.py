"""Physical quantities in configuration files: a number in SI, or a string with units.

``to_si("0.127 mm", "length") == 1.27e-4``. Strings are parsed with pint, with two
conventions of rotordynamics that pint does not share:

- ``mil`` is the thousandth of an inch (0.0254 mm), not pint's angular mil;
- for angular rates, ``Hz`` means revolutions per second (``1 Hz = 2*pi rad/s``), as
  ``rpm`` does, instead of pint's ``1 Hz = 1 rad/s``.

A string without units (``"1e7"``) is taken as SI, like a bare number.
"""

from __future__ import annotations

import math
import pickle
import re
from dataclasses import dataclass
from functools import cache
from typing import TYPE_CHECKING

if TYPE_CHECKING:
    import pint


@dataclass(frozen=True)
class Kind:
    """A physical kind of quantity: its SI unit (as printed) and pint dimensionality."""

    name: str
    unit: str
    example: str

    @property
    def dimensionality(self) -> pint.util.UnitsContainer:
        return _registry().Quantity(1.0, self.unit).dimensionality


KINDS: dict[str, Kind] = {
    k.name: k
    for k in (
        Kind("length", "m", "0.127 mm"),
        Kind("mass", "kg", "12 kg"),
        Kind("density", "kg/m^3", "7810 kg/m^3"),
        Kind("modulus", "Pa", "211 GPa"),
        Kind("inertia", "kg*m^2", "0.1 kg*m^2"),
        Kind("unbalance", "kg*m", "360.04 g*mm"),
        Kind("stiffness", "N/m", "1e7 N/m"),
        Kind("damping", "N*s/m", "100 N*s/m"),
        Kind("viscosity", "Pa*s", "0.0051 Pa*s"),
        Kind("angular_velocity", "rad/s", "3000 rpm"),
        Kind("angle", "rad", "90 deg"),
        Kind("velocity", "m/s", "0.1 m/s"),
        Kind("acceleration", "m/s^2", "9.81 m/s^2"),
        Kind("time", "s", "0.1 s"),
        Kind("ratio", "1", "0.485 %"),
        Kind("rayleigh_beta", "s", "1e-5 s"),
        Kind("rayleigh_alpha", "1/s", "0.5 1/s"),
    )
}

_MIL = re.compile(r"(?<![A-Za-z_])mils?\b")
_HERTZ = re.compile(r"hertz$")


@cache
def _registry() -> pint.UnitRegistry:
    """The unit registry, built once on first use from pint's on-disk cache of its parsed
    definitions (``~/.cache/pint``: 0.05 s instead of 0.45 s to parse them), or without
    it where that folder cannot be written."""
    import pint  # deferred: pint (and dask, which pint imports when installed)

    try:
        return pint.UnitRegistry(cache_folder=":auto:")
    except (OSError, EOFError, pickle.UnpicklingError):  # unwritable or damaged cache
        return pint.UnitRegistry()


class UnitError(ValueError):
    """A value that is not a quantity of the expected kind; the message says what is allowed."""


def parse_quantity(text: str) -> pint.Quantity:
    """Parse ``text`` (e.g. ``"5 mil"``) into a pint quantity; raise UnitError if unreadable."""
    cleaned = _MIL.sub("thou", text.strip().replace("µ", "u"))
    try:
        q = _registry().Quantity(cleaned)
    except Exception as exc:  # pint raises many error types for bad strings
        raise UnitError(f"cannot read {text!r} as a number with units ({exc})") from None
    import pint  # deferred: pint (loaded by _registry already)

    if not isinstance(q, pint.Quantity):  # a bare number string like "3"
        q = _registry().Quantity(float(q))
    return q


def to_si(value: object, kind: str) -> float:
    """Convert ``value`` (an SI number or a string with units) to a float in SI units of
    ``kind`` (a key of KINDS). Raise UnitError on a wrong dimension or an unreadable value.
    """
    k = KINDS[kind]
    if isinstance(value, bool):
        raise UnitError(f"expected {describe(kind)}, not a boolean")
    if isinstance(value, int | float):
        out = float(value)
    elif isinstance(value, str):
        q = parse_quantity(value)
        if not q.unit_items():  # no units written: SI
            out = float(q.magnitude)
        elif q.dimensionality != k.dimensionality:
            hint = ""
            if kind == "acceleration" and [n for n, _ in q.unit_items()] == ["gram"]:
                hint = " (standard gravity is 'g0', e.g. '20 g0')"
            raise UnitError(f"expected {describe(kind)}; {value!r} is {_dim_name(q)}{hint}")
        else:
            # 15 significant digits: drop the last-bit noise of the unit conversion
            out = float(f"{float(q.to(k.unit).magnitude):.15g}")
            if kind == "angular_velocity":
                # pint takes 1 Hz = 1 rad/s; a rotor engineer means one revolution per second
                power = sum(p for name, p in q.unit_items() if _HERTZ.search(name))
                out *= (2.0 * math.pi) ** power
    else:
        raise UnitError(f"expected {describe(kind)}, got a {type(value).__name__}")
    if not math.isfinite(out):
        raise UnitError(f"expected a finite value: {describe(kind)}")
    return out


def describe(kind: str) -> str:
    """``"a length in m (a number in m, or a string with units like '0.127 mm')"``."""
    k = KINDS[kind]
    if k.unit == "1":
        return f"a dimensionless {k.name} (a number, or a string like {k.example!r})"
    name = k.name.replace("_", " ")
    article = "an" if name[0] in "aeiou" else "a"
    return (f"{article} {name} in {k.unit} (a number in {k.unit}, or a string with units "
            f"like {k.example!r})")


def _dim_name(q: pint.Quantity) -> str:
    """``"a mass"``, ``"an angular velocity"``, or the dimension."""
    for k in KINDS.values():
        if k.unit != "1" and q.dimensionality == k.dimensionality:
            name = k.name.replace("_", " ")
            return f"{'an' if name[0] in 'aeiou' else 'a'} {name}"
    return f"a quantity of dimension {q.dimensionality}"
