"""argparse types of the command-line options: each checks a value before any work and
says in one line what is allowed (argparse prefixes the option's name); and
:func:`check_exists` for input paths, called by a handler before its work."""

from __future__ import annotations

import argparse
import math
from collections.abc import Callable
from pathlib import Path

from rotorsfd.errors import ConfigError


def speed(text: str) -> float:
    """An angular velocity in rad/s: a number (rad/s) or a string with units."""
    # deferred: io.units (keeps `import rotorsfd.api` and --help fast)
    from rotorsfd.io.units import UnitError, to_si

    try:
        return to_si(text, "angular_velocity")
    except UnitError as exc:
        raise argparse.ArgumentTypeError(str(exc)) from None


def ratio(text: str) -> float:
    """A finite number."""
    try:
        value = float(text)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected a number, got {text!r}") from None
    if not math.isfinite(value):
        raise argparse.ArgumentTypeError(f"expected a finite number, got {text!r}")
    return value


def integer(low: int) -> Callable[[str], int]:
    """An argparse type: an integer >= ``low``."""
    def parse(text: str) -> int:
        try:
            value = int(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected an integer, got {text!r}") from None
        if value < low:
            raise argparse.ArgumentTypeError(f"must be >= {low}, got {text!r}")
        return value

    parse.__name__ = f"integer >= {low}"
    return parse


def check_exists(option: str, path: Path | None) -> None:
    """ConfigError naming ``option`` if ``path`` (a simulate output folder or its
    timeseries.nc) is given and does not exist; called by a command before its work (not
    an argparse type: a command line that only parses needs no files)."""
    if path is not None and not path.exists():
        raise ConfigError(option, str(path), "no such file or folder (give a simulate "
                          "output folder or its timeseries.nc)")


def positive_ratio(text: str) -> float:
    """A speed ratio > 0."""
    value = ratio(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0 (the rotor speed over the "
                                         f"[reference] speed), got {text!r}")
    return value


def positive_speed(text: str) -> float:
    """An angular velocity > 0 rad/s."""
    value = speed(text)
    if not value > 0:
        raise argparse.ArgumentTypeError(f"must be > 0 rad/s, got {text!r}")
    return value
