"""The grid of a parameter study: a Cartesian product of axes over scalar config fields.

An axis is a dotted config path (``base.pitching.value``, ``unbalance[0].magnitude``,
``elements.sfd.clearance_ratio``) with its values in SI (strings with units are converted with the
field's kind). Point ``i`` is the C-order (last axis fastest) flat index of the product;
its id is ``f"{i:06d}"``, so ids sort like the grid and are the same in every run of the
same sweep. ``grid.config_at(config, point)`` sets the point's values with
:func:`rotorsfd.io.config.with_values`.
"""

from __future__ import annotations

import hashlib
import itertools
import json
import math
import re
from collections.abc import Iterator, Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import dump_config, parse_override, with_values
from rotorsfd.io.schema import Config, ParameterAxis, axis_values, parameter_values, resolve_kind
from rotorsfd.io.units import KINDS

ID_WIDTH = 6


def slug(text: str) -> str:
    """``"unbalance[0].magnitude"`` -> ``"unbalance_0_magnitude"`` (netCDF/CSV names)."""
    return re.sub(r"_+", "_", re.sub(r"[^A-Za-z0-9]", "_", text)).strip("_")


@dataclass(frozen=True)
class Axis:
    """One grid axis: a dotted config path and its values (SI)."""

    path: str
    values: tuple[float, ...]
    units: str = "1"

    @property
    def name(self) -> str:
        """Dimension / column name: the slug of the path."""
        return slug(self.path)


@dataclass(frozen=True)
class GridPoint:
    """A point of the grid: flat index, id, index along each axis, values by path (SI)."""

    index: int
    indices: tuple[int, ...]
    values: tuple[tuple[str, float], ...]

    @property
    def point_id(self) -> str:
        return f"{self.index:0{ID_WIDTH}d}"

    def as_dict(self) -> dict[str, float]:
        return dict(self.values)


@dataclass(frozen=True)
class Grid:
    """Cartesian product of :class:`Axis` objects (C order)."""

    axes: tuple[Axis, ...]

    def __post_init__(self) -> None:
        names = [a.name for a in self.axes]
        if len(set(names)) != len(names):
            raise ConfigError("analysis.sweep.axes", [a.path for a in self.axes],
                              "each config field may appear on one axis only")
        for a in self.axes:
            if not a.values:
                raise ConfigError("analysis.sweep.axes", a.path, "needs at least one value")
            if not all(math.isfinite(v) for v in a.values):
                raise ConfigError("analysis.sweep.axes", a.path, "values must be finite")

    @property
    def shape(self) -> tuple[int, ...]:
        return tuple(len(a.values) for a in self.axes)

    def __len__(self) -> int:
        return math.prod(self.shape)

    def points(self) -> Iterator[GridPoint]:
        """Every point in id order."""
        ranges = [range(n) for n in self.shape]
        for i, idx in enumerate(itertools.product(*ranges)):
            yield GridPoint(i, tuple(idx), tuple((a.path, a.values[j])
                                                 for a, j in zip(self.axes, idx, strict=True)))

    def config_at(self, config: Config, point: GridPoint) -> Config:
        """``config`` with the point's values set (validated; ConfigError if out of range)."""
        return with_values(config, point.as_dict())

    def describe(self) -> list[dict[str, Any]]:
        """JSON-able description (paths, units, values)."""
        return [{"path": a.path, "name": a.name, "units": a.units, "values": list(a.values)}
                for a in self.axes]


def _kind(config: Config, path: str, where: str) -> str:
    if path.strip() == "speed":
        raise ConfigError(where, path, "a sweep axis must be a config field (the rotor "
                          "speed is swept by the task itself: analysis.response.speed_range, "
                          "or analysis.simulate.speed)")
    try:
        return resolve_kind(config, path)
    except KeyError as exc:
        raise ConfigError(where, path, exc.args[0]) from None


def make_axis(config: Config, path: str, values: Sequence[Any], where: str = "axis") -> Axis:
    """An axis over the field at ``path`` with ``values`` (SI numbers or unit strings)."""
    kind = _kind(config, path, where)
    try:
        si = parameter_values(config, path, list(values))
    except Exception as exc:  # UnitError and friends: one line naming the field
        raise ConfigError(where, list(values), str(exc)) from None
    return Axis(path.strip(), tuple(float(v) for v in si), KINDS[kind].unit)


def grid_from_axes(config: Config, axes: Mapping[str, Sequence[Any]]) -> Grid:
    """A grid from ``{dotted path: values}`` (in axis order)."""
    return Grid(tuple(make_axis(config, p, v, f"axis {p}") for p, v in axes.items()))


def grid_from_config(config: Config) -> Grid:
    """The grid of ``[analysis.sweep]`` axes (``values`` or ``start``/``stop``/``n``)."""
    axes = config.analysis.sweep.axes
    if not axes:
        raise ConfigError("analysis.sweep.axes", [], "give at least one axis, e.g. "
                          "[[analysis.sweep.axes]] parameter = 'elements.sfd.clearance_ratio'")
    out = []
    for i, ax in enumerate(axes):
        where = f"analysis.sweep.axes[{i}].parameter"
        kind = _kind(config, ax.parameter, where)
        out.append(Axis(ax.parameter.strip(), tuple(axis_values(config, ax)),
                        KINDS[kind].unit))
    return Grid(tuple(out))


def parameter_axis(path: str, values: Sequence[Any]) -> ParameterAxis:
    """A schema :class:`ParameterAxis` with explicit values (for building configs)."""
    return ParameterAxis(parameter=path, values=list(values))


def config_digest(config: Config, task_spec: str) -> str:
    """Hash of the base config (its sweep table excluded) and the task."""
    data = dump_config(config)
    data.get("analysis", {}).pop("sweep", None)
    text = json.dumps({"config": data, "task": task_spec}, sort_keys=True,
                      separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()


def point_key(digest: str, point: GridPoint) -> str:
    """What determines a point's result: :func:`config_digest` and the point's values.
    A stored point with another key is recomputed on resume."""
    text = json.dumps({"digest": digest, "values": point.values}, separators=(",", ":"))
    return hashlib.sha256(text.encode()).hexdigest()[:32]


def parse_axis(text: str) -> tuple[str, list[Any]]:
    """``"elements.sfd.clearance_ratio=0.4 %,0.5 %"`` -> ``("elements.sfd.clearance_ratio",
    ["0.4 %", "0.5 %"])`` (each value a TOML number or a string with units)."""
    path, _, rest = text.partition("=")
    items = [s.strip() for s in rest.split(",")]
    if not path.strip() or not all(items):
        raise ConfigError("--axis", text, "expected PATH=V1,V2,..., e.g. "
                          "elements.sfd.clearance_ratio='0.4 %,0.5 %'")
    return path.strip(), [parse_override(f"v={s}")[1] for s in items]
