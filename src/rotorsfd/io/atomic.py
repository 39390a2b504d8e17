"""Atomic file writes: a reader never sees a half-written result file.

Each writer writes to a temporary file in the destination's folder, flushes it to disk
(fsync), then renames it over the destination (``os.replace``, atomic on POSIX and
Windows). If the writer fails, the temporary file is removed and any previous file at the
destination is left untouched.
"""

from __future__ import annotations

import contextlib
import csv
import io
import json
import math
import os
import tempfile
from collections.abc import Iterable, Iterator, Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np


def _umask() -> int:
    mask = os.umask(0)
    os.umask(mask)
    return mask


def _fsync_dir(folder: Path) -> None:
    if os.name != "posix":
        return
    fd = os.open(folder, os.O_RDONLY)
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


@contextlib.contextmanager
def atomic_path(path: str | Path) -> Iterator[Path]:
    """Yield a temporary path next to ``path`` (same suffix); on success move it onto
    ``path`` atomically, on error delete it. Creates missing parent folders."""
    final = Path(path)
    final.parent.mkdir(parents=True, exist_ok=True)
    fd, name = tempfile.mkstemp(prefix=f".{final.name}.", suffix=f".tmp{final.suffix}",
                                dir=final.parent)
    os.close(fd)
    tmp = Path(name)
    try:
        yield tmp
        with open(tmp, "rb+") as fh:
            fh.flush()
            os.fsync(fh.fileno())
        os.chmod(tmp, 0o666 & ~_umask())
        os.replace(tmp, final)
        _fsync_dir(final.parent)
    except BaseException:
        tmp.unlink(missing_ok=True)
        raise


def write_bytes(path: str | Path, data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically."""
    with atomic_path(path) as tmp:
        tmp.write_bytes(data)
    return Path(path)


def write_text(path: str | Path, text: str) -> Path:
    """Write UTF-8 ``text`` to ``path`` atomically."""
    return write_bytes(path, text.encode("utf-8"))


def json_safe(obj: Any) -> Any:
    """JSON-safe copy: numpy scalars and arrays to Python, NaN/inf to None (never NaN in a
    results file), tuples to lists, keys to strings, anything else to its text."""
    if isinstance(obj, dict):
        return {str(k): json_safe(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [json_safe(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return json_safe(obj.tolist())
    if isinstance(obj, np.bool_ | bool):
        return bool(obj)
    if isinstance(obj, np.integer | int):
        return int(obj)
    if isinstance(obj, np.floating | float):
        return float(obj) if math.isfinite(obj) else None
    return obj if obj is None or isinstance(obj, str) else str(obj)


def write_json(path: str | Path, obj: Any) -> Path:
    """Write ``obj`` as indented JSON atomically (through :func:`json_safe`)."""
    return write_text(path, json.dumps(json_safe(obj), indent=2, allow_nan=False) + "\n")


def write_csv(path: str | Path, header: Sequence[str], rows: Iterable[Sequence[Any]]) -> Path:
    """Write a CSV table (floats with full precision) atomically."""
    buf = io.StringIO()
    writer = csv.writer(buf, lineterminator="\n")
    writer.writerow(header)
    for row in rows:
        writer.writerow([repr(float(v)) if isinstance(v, float) else v for v in row])
    return write_text(path, buf.getvalue())


def save_figure(fig: Any, path: str | Path, **kwargs: Any) -> Path:
    """``fig.savefig`` atomically (format from the suffix of ``path``)."""
    fmt = kwargs.pop("format", Path(path).suffix.lstrip(".") or None)
    with atomic_path(path) as tmp:
        fig.savefig(tmp, format=fmt, **kwargs)
    return Path(path)


def save_figures(figures: Mapping[str, Any], directory: str | Path,
                 dpi: int = 120) -> dict[str, Path]:
    """Save named figures (``{"campbell.png": fig}``) in ``directory`` atomically;
    returns the paths by name."""
    out = Path(directory)
    paths = {}
    for name, fig in figures.items():
        paths[name] = save_figure(fig, out / name, dpi=dpi)
    return paths


def write_netcdf(dataset: Any, path: str | Path, **kwargs: Any) -> Path:
    """``xarray.Dataset.to_netcdf`` atomically."""
    with atomic_path(path) as tmp:
        dataset.to_netcdf(tmp, **kwargs)
    return Path(path)


def folder_problem(path: str | Path) -> str | None:
    """Why results cannot be written in the folder ``path`` (created if missing), or None.

    Checked before any work: ``path`` must be a folder or not exist yet, and its nearest
    existing ancestor must be a folder where a folder can be created (tried for real with
    a temporary folder, removed at once, so read-only folders and file systems, ``/proc``
    and permissions are all covered)."""
    folder = Path(path).absolute()
    if folder.exists() and not folder.is_dir():
        return "is a file, not a folder; give a folder (created if missing)"
    parent = folder
    while not parent.exists() and parent != parent.parent:
        parent = parent.parent
    if not parent.is_dir():
        return f"{parent} is a file, so no folder can be created in it"
    try:
        probe = tempfile.mkdtemp(prefix=".rotorsfd-write-check-", dir=parent)
    except OSError as exc:
        reason = exc.strerror or type(exc).__name__
        where = "in it" if parent == folder else f"in {parent}"
        return f"cannot write {where} ({reason}); give a folder you can write to"
    os.rmdir(probe)
    return None
