"""A speed law from its configuration (``[analysis.simulate] speed_law``) or the CLI text.

    { law = "constant", speed = "800 rad/s" }
    { law = "ramp", start = "500 rad/s", stop = "1200 rad/s", duration = "2 s" }
        (or rate = "350 rad/s^2" instead of duration; t_start = "0.1 s" holds start first)
    { law = "table", file = "speeds.csv" }     two columns: time [s], speed [rad/s]
    { law = "table", times = ["0 s", ...], speeds = ["500 rad/s", ...] }

On the command line: ``ramp,start=500 rad/s,stop=1200 rad/s,duration=2 s`` (the same keys)
or the path of a table file. Bad input: :class:`~rotorsfd.errors.ConfigError` naming the
field, the value and what is allowed.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.io.units import UnitError, parse_quantity, to_si
from rotorsfd.timedomain.speed_law import (
    FIELD,
    ConstantSpeed,
    RampSpeed,
    SpeedLaw,
    TableSpeed,
)

KEYS = {
    "constant": {"law", "speed"},
    "ramp": {"law", "start", "stop", "duration", "rate", "t_start"},
    "table": {"law", "file", "times", "speeds"},
}


def _si(spec: Mapping[str, Any], key: str, kind: str) -> float:
    try:
        return to_si(spec[key], kind)
    except UnitError as exc:
        raise ConfigError(f"{FIELD}.{key}", spec[key], str(exc)) from None


def _rate(value: Any) -> float:
    if isinstance(value, int | float) and not isinstance(value, bool):
        return float(value)
    try:
        q = parse_quantity(str(value))
        out = float(q.magnitude) if not q.unit_items() else float(q.to("rad/s^2").magnitude)
    except (UnitError, Exception):  # pint's DimensionalityError and parse errors
        raise ConfigError(f"{FIELD}.rate", value, "an angular acceleration, e.g. "
                          "'350 rad/s^2' or '1000 rpm/s'") from None
    return out


def read_table(path: Path) -> tuple[np.ndarray, np.ndarray]:
    """(times [s], speeds [rad/s]) from a two-column CSV (a header line is skipped)."""
    if not path.is_file():
        raise ConfigError(f"{FIELD}.file", str(path), "an existing CSV file (time, speed)")
    try:
        data = np.genfromtxt(path, delimiter=",", comments="#")
    except ValueError as exc:
        raise ConfigError(f"{FIELD}.file", str(path), f"two numeric columns: {exc}") from None
    data = np.atleast_2d(data)
    data = data[~np.all(np.isnan(data), axis=1)] if data.size else data
    if data.ndim != 2 or data.shape[1] != 2 or not np.all(np.isfinite(data)):
        raise ConfigError(f"{FIELD}.file", str(path), "two numeric columns: time [s], "
                          "speed [rad/s], comma separated (one header line allowed)")
    return data[:, 0], data[:, 1]


def speed_law_from_config(spec: Mapping[str, Any],
                          search_path: Path | None = None) -> SpeedLaw:
    """The law of ``spec`` (module docstring); a relative ``file`` is read from
    ``search_path`` (the configuration's folder)."""
    if not isinstance(spec, Mapping):
        raise ConfigError(FIELD, spec, 'a table such as { law = "ramp", start = ..., '
                          'stop = ..., duration = ... }')
    law = spec.get("law")
    if law not in KEYS:
        raise ConfigError(f"{FIELD}.law", law, '"constant", "ramp" or "table"')
    extra = sorted(set(spec) - KEYS[law])
    if extra:
        raise ConfigError(f"{FIELD}.{extra[0]}", spec[extra[0]],
                          f"{law} takes {', '.join(sorted(KEYS[law] - {'law'}))}")
    if law == "constant":
        if "speed" not in spec:
            raise ConfigError(f"{FIELD}.speed", None, "give the speed")
        return ConstantSpeed(_si(spec, "speed", "angular_velocity"))
    if law == "ramp":
        for key in ("start", "stop"):
            if key not in spec:
                raise ConfigError(f"{FIELD}.{key}", None, "give the ramp's start and stop")
        start = _si(spec, "start", "angular_velocity")
        stop = _si(spec, "stop", "angular_velocity")
        if ("duration" in spec) == ("rate" in spec):
            raise ConfigError(f"{FIELD}.duration", spec.get("duration"),
                              "give duration or rate (not both)")
        if "duration" in spec:
            duration = _si(spec, "duration", "time")
        else:
            rate = _rate(spec["rate"])
            if rate == 0.0 or (stop - start) / rate <= 0.0:
                raise ConfigError(f"{FIELD}.rate", spec["rate"], "non-zero, with the sign "
                                  "of stop - start")
            duration = (stop - start) / rate
        t0 = _si(spec, "t_start", "time") if "t_start" in spec else 0.0
        return RampSpeed(start, stop, duration, t0)
    if "file" in spec:
        if "times" in spec or "speeds" in spec:
            raise ConfigError(f"{FIELD}.file", spec["file"], "give file or times/speeds")
        path = Path(str(spec["file"]))
        if not path.is_absolute() and search_path is not None:
            path = search_path / path
        times, speeds = read_table(path)
        return TableSpeed(times, speeds)
    for key in ("times", "speeds"):
        if not isinstance(spec.get(key), list | tuple):
            raise ConfigError(f"{FIELD}.{key}", spec.get(key), "a list (or give file)")
    kinds = {"times": "time", "speeds": "angular_velocity"}
    values = {k: np.array([_si({k: v}, k, kinds[k]) for v in spec[k]]) for k in kinds}
    return TableSpeed(values["times"], values["speeds"])


def parse_speed_law_text(text: str) -> dict[str, Any]:
    """``law,key=value,...`` (or the path of a table CSV) as a config table."""
    text = text.strip()
    if "," not in text and "=" not in text and text not in KEYS:
        return {"law": "table", "file": text}
    head, *rest = (p.strip() for p in text.split(","))
    spec: dict[str, Any] = {"law": head}
    for part in rest:
        key, sep, value = part.partition("=")
        if not sep or not key.strip():
            raise ConfigError("--speed-law", text, "law,key=value,... e.g. 'ramp,start=500 "
                              "rad/s,stop=1200 rad/s,duration=2 s', or a table CSV")
        spec[key.strip()] = value.strip()
    return spec
