"""Shaft-wise names of the global nodes of a multi-shaft rotor (issue 20 item 1).

Nodes are numbered globally in the order of the shafts (shaft 1: 1..n_1, shaft 2:
n_1 + 1..n_1 + n_2, ...). Global node ``n`` of shaft ``s`` (first global node ``f_s``) is
that shaft's node ``n - f_s + 1`` (from 1). The results files keep the global numbers
(``node``, ``defl_<n>``, ``amp_<n>_...``: every reader stays valid) and, for a rotor with
several shafts, add the coordinates ``shaft`` (the shaft's name) and ``shaft_node`` (its
local node) along ``node`` or ``dof``, and a companion table ``nodes.csv`` (``node, shaft,
shaft_node, label``) next to the CSV tables; texts and legends say ``hp node 3``. A
single-shaft rotor has no :class:`NodeNames` (``None``): its files and texts are unchanged.
"""

from __future__ import annotations

from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.io import atomic

#: long names of the added coordinates
SHAFT_LONG_NAME = "shaft of the node ([[rotor.shafts]] name)"
SHAFT_NODE_LONG_NAME = "node number within its shaft (from 1)"


@dataclass(frozen=True)
class NodeNames:
    """The shafts' names and node counts, in the order of the global numbering."""

    names: tuple[str, ...]
    counts: tuple[int, ...]

    @classmethod
    def of(cls, rotor: Any) -> NodeNames | None:
        """From a model rotor with ``shafts`` (each ``name``, ``n_nodes``) or a
        :class:`~rotorsfd.io.schema.RotorConfig`; None for a single shaft."""
        shafts = getattr(rotor, "shafts", None)
        if not shafts or len(shafts) < 2:
            return None
        return cls(tuple(str(s.name) for s in shafts), tuple(int(s.n_nodes) for s in shafts))

    @property
    def first(self) -> tuple[int, ...]:
        """First global node of every shaft."""
        return tuple(int(v) for v in 1 + np.cumsum([0, *self.counts[:-1]]))

    def locate(self, node: int) -> tuple[str, int]:
        """(shaft name, local node from 1) of global ``node``; ValueError outside."""
        for name, f, c in zip(self.names, self.first, self.counts, strict=True):
            if f <= node < f + c:
                return name, int(node) - f + 1
        raise ValueError(f"node {node} is not a node of the rotor, 1..{sum(self.counts)}")

    def label(self, node: int) -> str:
        """``hp:3`` (shaft, local node)."""
        name, local = self.locate(node)
        return f"{name}:{local}"

    def words(self, node: int) -> str:
        """``hp node 3``."""
        name, local = self.locate(node)
        return f"{name} node {local}"

    def global_node(self, shaft: str, local: int) -> int:
        """Global node of ``shaft``'s node ``local`` (from 1); ValueError if none."""
        if shaft not in self.names:
            raise ValueError(f"no shaft {shaft!r} (shafts: {', '.join(self.names)})")
        k = self.names.index(shaft)
        if not 1 <= local <= self.counts[k]:
            raise ValueError(f"shaft {shaft!r} has nodes 1..{self.counts[k]}, not {local}")
        return self.first[k] + int(local) - 1

    def arrays(self, nodes: Any) -> tuple[NDArray[np.str_], NDArray[np.int32]]:
        """(shaft names, local nodes) of the global ``nodes``."""
        pairs = [self.locate(int(n)) for n in np.asarray(nodes).ravel()]
        return (np.array([p[0] for p in pairs], dtype=str),
                np.array([p[1] for p in pairs], dtype=np.int32))


def node_words(names: NodeNames | None, node: int) -> str:
    """``node 12`` (a single shaft) or ``hp node 3``."""
    return f"node {node}" if names is None else names.words(node)


def with_shaft_coords(ds: Any, names: NodeNames | None) -> Any:
    """``ds`` with ``shaft`` and ``shaft_node`` along its ``node`` dimension (a time
    series; its ``dof`` dimension then gets ``dof_shaft``, ``dof_shaft_node``) or along
    ``dof`` (a branch: from the ``node`` coordinate of each DOF, else 4 DOFs a node);
    unchanged for None."""
    if names is None:
        return ds
    dims = [d for d in ("node", "dof") if d in ds.dims]
    for dim in dims:
        if dim == "node":
            nodes = ds["node"].values
        elif "node" in ds.coords and ds["node"].dims == ("dof",):
            nodes = ds["node"].values
        else:
            nodes = ds["dof"].values // 4 + 1
        shaft, local = names.arrays(nodes)
        prefix = "dof_" if dim == "dof" and "node" in dims else ""
        ds = ds.assign_coords({
            f"{prefix}shaft": (dim, shaft, {"long_name": SHAFT_LONG_NAME, "units": ""}),
            f"{prefix}shaft_node": (dim, local, {"long_name": SHAFT_NODE_LONG_NAME,
                                                 "units": "1"})})
    return ds


def node_table(names: NodeNames, nodes: Any) -> dict[str, Any]:
    """Columns of ``nodes.csv``: ``node, shaft, shaft_node, label`` of the global
    ``nodes``."""
    nodes = np.asarray(nodes, dtype=np.int64).ravel()
    shaft, local = names.arrays(nodes)
    return {"node": nodes, "shaft": shaft, "shaft_node": local,
            "label": np.array([names.label(int(n)) for n in nodes], dtype=str)}


def write_node_table(directory: str | Path, names: NodeNames | None,
                     nodes: Any) -> dict[str, Path]:
    """``nodes.csv`` in ``directory`` for a multi-shaft rotor (``{}`` for None)."""
    if names is None:
        return {}
    cols = node_table(names, nodes)
    rows = zip(*([v.item() for v in c] for c in cols.values()), strict=True)
    return {"nodes.csv": atomic.write_csv(Path(directory) / "nodes.csv", list(cols), rows)}


#: the analysis sections whose ``nodes`` may name a shaft's node (``"hp:3"``)
NODE_SECTIONS = ("response", "simulate")


class BadNodeName(ValueError):
    """A ``"<shaft>:<node>"`` that names no node: ``path``, ``value``, ``allowed``."""

    def __init__(self, path: tuple[str | int, ...], value: Any, allowed: str) -> None:
        super().__init__(f"{'.'.join(map(str, path))}: got {value!r}; {allowed}")
        self.path, self.value, self.allowed = path, value, allowed


def resolve_shaft_nodes(data: Any) -> Any:
    """A raw config (dict) with every ``"<shaft>:<local node>"`` of
    ``analysis.<section>.nodes`` (:data:`NODE_SECTIONS`) replaced by its global node
    (shafts counted from the raw ``[[rotor.shafts]]``: each ``sum(n_elements) + 1`` nodes);
    :class:`BadNodeName` for an unknown shaft or node, or a shaft name without shafts."""
    if not isinstance(data, dict):
        return data
    analysis = data.get("analysis")
    if not isinstance(analysis, dict):
        return data
    names: NodeNames | None = None
    shafts = (data.get("rotor") or {}).get("shafts") if isinstance(data.get("rotor"),
                                                                     dict) else None
    for section in NODE_SECTIONS:
        table = analysis.get(section)
        given = table.get("nodes") if isinstance(table, dict) else None
        if not isinstance(given, list) or not any(isinstance(v, str) for v in given):
            continue
        if names is None:
            names = _raw_names(shafts)
        out = []
        for i, value in enumerate(given):
            path = ("analysis", section, "nodes", i)
            if not isinstance(value, str):
                out.append(value)
                continue
            shaft, sep, local = value.partition(":")
            if names is None or not sep or not local.strip().isdigit():
                allowed = ("a node number" if names is None else
                           "a node number or <shaft>:<node of that shaft> (shafts: "
                           + ", ".join(names.names) + ")")
                raise BadNodeName(path, value, allowed)
            try:
                out.append(names.global_node(shaft.strip(), int(local)))
            except ValueError as exc:
                raise BadNodeName(path, value, str(exc)) from None
        data = {**data, "analysis": {**analysis, section: {**table, "nodes": out}}}
        analysis = data["analysis"]
    return data


def _raw_names(shafts: Any) -> NodeNames | None:
    """NodeNames of the raw ``[[rotor.shafts]]`` tables (None if they are not usable)."""
    try:
        return NodeNames(tuple(str(s["name"]) for s in shafts),
                         tuple(sum(int(t["n_elements"]) for t in s["sections"]) + 1
                               for s in shafts))
    except (TypeError, KeyError, ValueError):
        return None
