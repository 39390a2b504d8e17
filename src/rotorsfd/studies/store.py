"""Per-point results of a sweep on disk: ``DIR/points/<point_id>.json``, one file per
finished grid point, written atomically, so that a killed sweep resumes where it stopped;
``DIR/.sweep.lock`` keeps a second sweep out of a folder in use.

A record (JSON object)::

    format    "rotorsfd-sweep-point/1"
    point_id  "000012"; index [i, j, ...] along the axes; values {path: SI value}
    key       hash of base config + task + values (a record with another key is stale)
    task      the task spec
    status    "ok" | "incomplete" (valid partial data) | "failed" (no data)
    message   why (failed: the error's text), "" when ok
    scalars   {name: number | string | bool | null}      (null: missing)
    arrays    {name: {"dims": [...], "dtype": "float64" | "int8" | ... | "str",
                      "data": nested lists}}
    elapsed_s wall time of the task (diagnostics only; not copied to sweep.nc)

Floats are written with ``repr`` precision (JSON round-trips them exactly); NaN and inf
are refused (a task returns None for missing values).
"""

from __future__ import annotations

import contextlib
import json
import math
from collections.abc import Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.io import atomic

FORMAT = "rotorsfd-sweep-point/1"
STATUSES = ("ok", "incomplete", "failed")


def encode_array(dims: tuple[str, ...], data: np.ndarray) -> dict[str, Any]:
    """JSON form of a named-dims array (numbers, bools or strings)."""
    a = np.asarray(data)
    if a.ndim != len(dims):
        raise ValueError(f"array with dims {dims} has {a.ndim} dimensions")
    if a.dtype.kind in "US":
        return {"dims": list(dims), "dtype": "str", "data": a.astype(str).tolist()}
    if a.dtype.kind == "f" and not np.all(np.isfinite(a)):
        raise ValueError("non-finite values in a task array: use a status or a shorter "
                         "array instead of NaN/inf")
    if a.dtype.kind not in "biuf":
        raise ValueError(f"unsupported array dtype {a.dtype}")
    return {"dims": list(dims), "dtype": a.dtype.name, "data": a.tolist()}


def decode_array(obj: Mapping[str, Any]) -> tuple[tuple[str, ...], np.ndarray]:
    """(dims, array) from :func:`encode_array` output."""
    dims = tuple(obj["dims"])
    dtype = str if obj["dtype"] == "str" else np.dtype(obj["dtype"])
    data = np.array(obj["data"], dtype=dtype)
    if data.ndim != len(dims):  # empty arrays lose their shape in lists
        data = data.reshape((0,) * len(dims))
    return dims, data


def check_scalar(name: str, value: Any) -> Any:
    """A JSON-able scalar (numpy scalars unwrapped); ValueError on NaN/inf."""
    if isinstance(value, np.generic):
        value = value.item()
    if value is None or isinstance(value, bool | int | str):
        return value
    if isinstance(value, float):
        if not math.isfinite(value):
            raise ValueError(f"non-finite value of {name!r}: return None for missing")
        return value
    raise ValueError(f"scalar {name!r} has unsupported type {type(value).__name__}")


class PointStore:
    """The folder of per-point records of one sweep."""

    def __init__(self, directory: str | Path) -> None:
        self.directory = Path(directory) / "points"

    @contextlib.contextmanager
    def lock(self) -> Iterator[None]:
        """Hold ``DIR/.sweep.lock`` (flock, released by the kernel even on SIGKILL) so that
        two sweeps never write into the same folder; ConfigError if it is held."""
        self.directory.parent.mkdir(parents=True, exist_ok=True)
        with open(self.directory.parent / ".sweep.lock", "a") as fh:
            try:
                # optional dependency: fcntl may be missing
                import fcntl
            except ImportError:  # pragma: no cover (not POSIX)
                yield
                return
            try:
                fcntl.flock(fh, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                raise ConfigError("-o", str(self.directory.parent), "another sweep is "
                                  "running in this folder") from None
            yield

    def path(self, point_id: str) -> Path:
        return self.directory / f"{point_id}.json"

    def save(self, record: Mapping[str, Any]) -> Path:
        """Write one record atomically (a reader sees the old file or the new one)."""
        text = json.dumps(record, indent=1, allow_nan=False, sort_keys=False) + "\n"
        return atomic.write_text(self.path(record["point_id"]), text)

    def load(self, point_id: str) -> dict[str, Any] | None:
        """The record of ``point_id``, or None if absent or unreadable."""
        try:
            record = json.loads(self.path(point_id).read_text())
        except (OSError, ValueError):
            return None
        if not isinstance(record, dict) or record.get("format") != FORMAT \
                or record.get("status") not in STATUSES:
            return None
        return record

    def ids(self) -> list[str]:
        """Ids of the records present (sorted)."""
        if not self.directory.is_dir():
            return []
        return sorted(p.stem for p in self.directory.glob("*.json")
                      if not p.name.startswith("."))

    def finished(self, keys: Mapping[str, str],
                 indices: Mapping[str, Sequence[int]] | None = None
                 ) -> dict[str, dict[str, Any]]:
        """Records of the points ``keys`` ({point_id: key}), matched by key: a record stored
        under another id (the grid was extended or reordered) is relabelled and saved under
        its new id; stale and foreign records are skipped."""
        by_key: dict[str, dict[str, Any]] = {}
        for pid in self.ids():
            rec = self.load(pid)
            if rec is not None and rec.get("point_id") == pid:
                by_key.setdefault(rec.get("key", ""), rec)
        out = {}
        for pid, key in keys.items():
            rec = by_key.get(key)
            if rec is not None:
                out[pid] = rec if rec["point_id"] == pid else {
                    **rec, "point_id": pid,
                    "index": list((indices or {}).get(pid, rec.get("index", [])))}
        for pid, rec in out.items():
            if rec is not by_key[keys[pid]]:
                self.save(rec)
        return out
