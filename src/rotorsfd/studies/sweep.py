"""Parameter sweeps: a grid over config fields, one task per grid point, run on an executor,
stored point by point, combined into ``sweep.nc`` and ``summary.csv``.

``run_sweep(config, axes, task, directory=DIR)`` writes into DIR::

    points/<id>.json   one record per finished point (:mod:`rotorsfd.studies.store`)
    sweep.nc           xarray/netCDF over the grid axes (layout: :func:`sweep_dataset`)
    summary.csv        one row per grid point: grid values, point_id, status, message,
                       the task's summary columns (empty cell = missing)
    sweep.json         the manifest: task, axes, counts, ``complete`` (false: partial)

Output files depend only on the finished records, sorted by point id (no timestamps, fixed
netCDF encoding), so 1 worker, N workers and a Dask cluster give identical files, and so
does a killed-and-resumed sweep. A task exception marks its point ``failed`` (with the
reason) and the sweep goes on. Ctrl-C stops the workers, writes the files for what
finished (``complete`` = 0) and re-raises; ``resume=True`` then recomputes only the
points without a valid record. Records are matched by key (base config + task + point
values): a record whose config or task changed is stale; an extended grid reuses the
records of the values it already had.
"""

from __future__ import annotations

import contextlib
import json
import sys
import time
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError, RotorsfdError
from rotorsfd.io import atomic
from rotorsfd.io.config import dump_config, with_values
from rotorsfd.io.provenance import netcdf_attrs
from rotorsfd.io.schema import Config
from rotorsfd.studies.executors import Executor, make_executor
from rotorsfd.studies.grid import (
    Grid,
    GridPoint,
    config_digest,
    grid_from_axes,
    grid_from_config,
    point_key,
    slug,
)
from rotorsfd.studies.store import FORMAT, PointStore, check_scalar, decode_array, encode_array
from rotorsfd.studies.tasks import Task, make_task

STATUS_CODES = {"ok": 0, "incomplete": 1, "failed": 2, "pending": 3}
FILES = ("sweep.nc", "summary.csv", "sweep.json")
INT_FILL = -2147483647          # netCDF default fill of int
BYTE_FILL = -127                # netCDF default fill of byte


def _one_line(text: str) -> str:
    return " ".join(str(text).split())


def failure_text(exc: BaseException) -> str:
    """A failed point's message: a rotorsfd error's own text (in the user's terms, the
    solver's account in brackets), any other exception as an internal error with its
    type."""
    if isinstance(exc, RotorsfdError):
        return _one_line(exc)
    return _one_line(f"internal error ({type(exc).__name__}): {exc}")


# ---- one grid point (runs on a worker) -----------------------------------------------------


def execute_point(task: Task, config: Config, point: GridPoint, key: str) -> dict[str, Any]:
    """Set the point's values, run the task, return the store record (never raises for
    an error of the task or of the point's config: the record is then ``failed``)."""
    t0 = time.perf_counter()
    values = point.as_dict()
    record: dict[str, Any] = {
        "format": FORMAT, "point_id": point.point_id, "index": list(point.indices),
        "values": values, "key": key, "task": task.spec}
    try:
        out = task(with_values(config, values), values)
        if out.status not in ("ok", "incomplete"):
            raise ValueError(f"task returned status {out.status!r}")
        record.update(status=out.status, message=_one_line(out.message),
                      scalars={k: check_scalar(k, v) for k, v in out.scalars.items()},
                      arrays={k: encode_array(a.dims, a.data) for k, a in out.arrays.items()})
    except Exception as exc:
        record.update(status="failed", message=failure_text(exc), scalars={}, arrays={})
    record["elapsed_s"] = time.perf_counter() - t0
    return record


# ---- the result ------------------------------------------------------------------------------


@dataclass
class SweepResult:
    """Finished records of a sweep over ``grid`` (by point id) and how the run went."""

    grid: Grid
    task: str
    records: dict[str, dict[str, Any]]
    config: dict[str, Any]
    computed: int = 0              # points run in this call
    interrupted: bool = False
    lost: int = 0                  # points whose worker failed (not recorded: pending)
    lost_message: str = ""

    @property
    def complete(self) -> bool:
        return len(self.records) == len(self.grid)

    def status(self, point_id: str) -> str:
        rec = self.records.get(point_id)
        return "pending" if rec is None else rec["status"]

    def counts(self) -> dict[str, int]:
        out = dict.fromkeys(STATUS_CODES, 0)
        for p in self.grid.points():
            out[self.status(p.point_id)] += 1
        return out

    def _sorted(self) -> list[dict[str, Any]]:
        return [self.records[k] for k in sorted(self.records)]

    def scalar_names(self) -> list[str]:
        """Summary columns of the task, in order of first appearance by point id."""
        names: dict[str, None] = {}
        for rec in self._sorted():
            names.update(dict.fromkeys(rec["scalars"]))
        return list(names)

    # ---- files ---------------------------------------------------------------------------
    def table(self) -> tuple[list[str], list[list[Any]]]:
        """Header and rows of ``summary.csv`` (module docstring)."""
        axes = self.grid.axes
        cols = [a.name if a.units == "1" else f"{a.name}_{slug(a.units)}" for a in axes]
        names = self.scalar_names()
        header = [*cols, "point_id", "status", "message", *names]
        rows = []
        for p in self.grid.points():
            rec = self.records.get(p.point_id)
            row: list[Any] = [v for _, v in p.values]
            row += [p.point_id, self.status(p.point_id), "" if rec is None else rec["message"]]
            for n in names:
                v = None if rec is None else rec["scalars"].get(n)
                row.append("" if v is None else (int(v) if isinstance(v, bool) else v))
            rows.append(row)
        return header, rows

    def to_dataset(self) -> Any:
        """The sweep as an xarray Dataset (see :func:`sweep_dataset`)."""
        return sweep_dataset(self)

    def manifest(self) -> dict[str, Any]:
        """Contents of ``sweep.json``."""
        return {"format": "rotorsfd-sweep/1", "task": self.task, "axes": self.grid.describe(),
                "shape": list(self.grid.shape), "n_points": len(self.grid),
                "counts": self.counts(), "complete": self.complete, "files": list(FILES)}

    def plot(self) -> dict[str, Any]:
        """No figures: a sweep records scalars per point (summary.csv, sweep.nc)."""
        return {}

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """Write ``sweep.nc``, ``summary.csv`` and ``sweep.json`` atomically (``plots``:
        the protocol's flag; a sweep draws nothing itself)."""
        out = Path(directory)
        ds = self.to_dataset()
        ds.attrs.update(netcdf_attrs())   # version, git revision, command line
        header, rows = self.table()
        return {"sweep.nc": atomic.write_netcdf(ds, out / "sweep.nc",
                                                encoding=netcdf_encoding(ds)),
                "summary.csv": atomic.write_csv(out / "summary.csv", header, rows),
                "sweep.json": atomic.write_json(out / "sweep.json", self.manifest())}

    def summary(self) -> str:
        """One line: points by status, completeness."""
        c = self.counts()
        text = (f"{len(self.grid)} points ({' x '.join(map(str, self.grid.shape))}): "
                f"{c['ok']} ok, {c['incomplete']} incomplete, {c['failed']} failed, "
                f"{c['pending']} pending; {self.computed} computed in this run")
        if self.lost:
            text += f"; {self.lost} lost to worker failures ({self.lost_message})"
        if not self.complete:
            text += "; PARTIAL (continue with --resume)"
        return text


# ---- combining -------------------------------------------------------------------------------


def _scalar_kind(values: Sequence[Any]) -> str:
    present = [v for v in values if v is not None]
    if not present:
        return "float"       # all missing: NaN-filled floats
    if present and all(isinstance(v, bool) for v in present):
        return "bool"
    if present and all(isinstance(v, int) and not isinstance(v, bool) for v in present):
        return "int"
    if present and all(isinstance(v, int | float) and not isinstance(v, bool)
                       for v in present):
        return "float"
    return "str"


def _fill(kind: str) -> Any:
    return {"bool": BYTE_FILL, "int": INT_FILL, "float": np.nan, "str": ""}[kind]


def _dtype(kind: str) -> Any:
    return {"bool": np.int8, "int": np.int32, "float": np.float64, "str": object}[kind]


def sweep_dataset(result: SweepResult) -> Any:
    """The Dataset of a sweep::

        dims     one per axis (slug of its path, e.g. base_pitching_value), plus the
                 task's array dims (e.g. branch_point, interval, bifurcation)
        coords   the axis values (SI; attrs long_name = dotted path, units)
        vars     point_id (int), status (int8: 0 ok, 1 incomplete, 2 failed, 3 pending;
                 CF flag_values/flag_meanings), message (str); each task scalar over the
                 axes (bool -> int8 0/1, int -> int32, float, str); each task array over
                 (axes..., its dims), padded, with n_<dim> its length per point
        missing  _FillValue (float NaN, int -2147483647, int8 -127 (set only when a
                 value is missing), str ""); the status variable says why a point has no
                 data; a column missing everywhere is float
        attrs    task, axes, complete (0/1), counts, config (JSON of the base config)
    """
    # deferred: xarray is heavy (loaded only when this runs)
    import xarray as xr

    grid = result.grid
    dims = tuple(a.name for a in grid.axes)
    shape = grid.shape
    points = list(grid.points())
    recs = [result.records.get(p.point_id) for p in points]
    coords = {a.name: (a.name, np.asarray(a.values, dtype=float),
                       {"long_name": a.path, "units": a.units}) for a in grid.axes}
    status = np.array([STATUS_CODES[result.status(p.point_id)] for p in points], np.int8)
    data: dict[str, Any] = {
        "point_id": (dims, np.arange(len(points), dtype=np.int32).reshape(shape),
                     {"long_name": "grid point id (flat C-order index)"}),
        "status": (dims, status.reshape(shape), {
            "flag_values": np.array(list(STATUS_CODES.values()), np.int8),
            "flag_meanings": " ".join(STATUS_CODES)}),
        "message": (dims, np.array([("" if r is None else r["message"]) for r in recs],
                                   dtype=object).reshape(shape)),
    }
    for name in result.scalar_names():
        vals = [None if r is None else r["scalars"].get(name) for r in recs]
        kind = _scalar_kind(vals)
        fill = _fill(kind)
        arr = np.array([fill if v is None else (str(v) if kind == "str" else v)
                        for v in vals], dtype=_dtype(kind)).reshape(shape)
        attrs = {"ancillary_variables": "status"}
        if kind == "bool":
            attrs["flag_values"], attrs["flag_meanings"] = np.array([0, 1], np.int8), \
                "false true"
        data[name] = (dims, arr, attrs)
    data.update(_arrays(recs, dims, shape))
    ds = xr.Dataset(data, coords=coords)
    c = result.counts()
    ds.attrs.update({
        "title": "rotorsfd parameter sweep", "task": result.task,
        "axes": " ".join(a.path for a in grid.axes), "complete": int(result.complete),
        **{f"n_{k}": int(v) for k, v in c.items()},
        "config": json.dumps(result.config, sort_keys=True)})
    return ds


def _arrays(recs: list[dict[str, Any] | None], dims: tuple[str, ...],
            shape: tuple[int, ...]) -> dict[str, Any]:
    """Task arrays padded to common lengths, and the n_<dim> length variables."""
    decoded: dict[str, list[tuple[tuple[str, ...], np.ndarray] | None]] = {}
    for i, r in enumerate(recs):
        for name, obj in ({} if r is None else r["arrays"]).items():
            decoded.setdefault(name, [None] * len(recs))[i] = decode_array(obj)
    sizes: dict[str, int] = {}
    lengths: dict[str, np.ndarray] = {}
    for name, items in decoded.items():
        for i, item in enumerate(items):
            if item is None:
                continue
            for d, n in zip(item[0], item[1].shape, strict=True):
                if d in dims:
                    raise ValueError(f"task array {name!r} uses the grid dim {d!r}")
                sizes[d] = max(sizes.get(d, 0), n)
                lengths.setdefault(d, np.zeros(len(recs), np.int32))
                lengths[d][i] = max(lengths[d][i], n)
    out: dict[str, Any] = {}
    for d, n in lengths.items():
        out[f"n_{d}"] = (dims, n.reshape(shape), {"long_name": f"length of {d} per point"})
    for name, items in decoded.items():
        first = next(it for it in items if it is not None)
        adims = first[0]
        kind = ("str" if first[1].dtype.kind in "US" else
                "bool" if first[1].dtype.kind == "b" else
                "int" if first[1].dtype.kind in "iu" and all(
                    it is None or it[1].dtype.kind in "iu" for it in items) else
                "float" if first[1].dtype.kind in "iuf" else "str")
        if kind == "int" and first[1].dtype == np.int8:
            kind = "bool"  # small flags (e.g. stable 0/1) keep int8
        arr = np.full((len(items), *[sizes[d] for d in adims]), _fill(kind),
                      dtype=_dtype(kind))
        for i, it in enumerate(items):
            if it is None:
                continue
            if it[0] != adims:
                raise ValueError(f"task array {name!r} has dims {it[0]} and {adims}")
            arr[(i, *[slice(0, n) for n in it[1].shape])] = it[1]
        out[name] = ((*dims, *adims), arr.reshape(*shape, *arr.shape[1:]),
                     {"ancillary_variables": "status " + " ".join(f"n_{d}" for d in adims)})
    return out


def netcdf_encoding(ds: Any) -> dict[str, dict[str, Any]]:
    """Fixed encoding of every variable (fill values and dtypes), a function of the data
    only, so that the same data always give the same bytes. Integer variables get a
    _FillValue only when they have a missing value (so complete ones load as integers)."""
    enc: dict[str, dict[str, Any]] = {}
    for name, var in ds.variables.items():
        fixed = name in ds.dims or name == "point_id" or name.startswith("n_") \
            or name == "status"
        if var.dtype == object:
            enc[name] = {"dtype": str, "_FillValue": None}
        elif var.dtype == np.float64:
            enc[name] = {"_FillValue": None if fixed else np.nan, "dtype": "float64"}
        elif var.dtype in (np.int8, np.int32):
            fill = var.dtype.type(BYTE_FILL if var.dtype == np.int8 else INT_FILL)
            missing = not fixed and bool(np.any(var.values == fill))
            enc[name] = {"_FillValue": fill if missing else None, "dtype": var.dtype.name}
    return enc


# ---- running -------------------------------------------------------------------------------


def resolve_grid(config: Config, axes: Grid | Mapping[str, Sequence[Any]] | None) -> Grid:
    """A Grid from a Grid, ``{path: values}`` or (None) ``[analysis.sweep]``."""
    if axes is None:
        return grid_from_config(config)
    if isinstance(axes, Grid):
        return axes
    return grid_from_axes(config, axes)


def run_sweep(config: Config, axes: Grid | Mapping[str, Sequence[Any]] | None = None,
              task: Task | str | None = None, *, directory: str | Path,
              executor: Executor | None = None, workers: int | None = None,
              scheduler: str | None = None, progress: bool = True, resume: bool = False,
              retry_failed: bool = False, search_path: str | Path | None = None
              ) -> SweepResult:
    """Run ``task`` at every point of the grid and write the results into ``directory``.

    ``axes``: a Grid, ``{dotted path: values}`` (SI or unit strings) or None (from
    ``[analysis.sweep]``); ``task``: a Task, a spec ``"name:key=value"`` or None
    (``analysis.sweep.task``). Without ``executor`` one is made from ``workers`` /
    ``scheduler`` (:func:`~rotorsfd.studies.executors.make_executor`). ``resume`` keeps
    the valid records in ``directory`` (failed points too, unless ``retry_failed``);
    without it, a folder that already holds records is an error. A progress bar (tqdm,
    stderr) unless ``progress`` is False. Ctrl-C writes the partial files, then re-raises.
    """
    grid = resolve_grid(config, axes)
    if task is None or isinstance(task, str):
        task = make_task(task or config.analysis.sweep.task, search_path=search_path)
    _check_some_point_valid(config, list(grid.points()))  # before the folder is made
    store = PointStore(directory)
    with store.lock():
        return _run(config, grid, task, store, Path(directory), executor, workers,
                    scheduler, progress, resume, retry_failed)


def _run(config: Config, grid: Grid, task: Task, store: PointStore, out: Path,
         executor: Executor | None, workers: int | None, scheduler: str | None,
         progress: bool, resume: bool, retry_failed: bool) -> SweepResult:
    """run_sweep with the folder locked."""
    digest = config_digest(config, task.spec)
    points = list(grid.points())
    keys = {p.point_id: point_key(digest, p) for p in points}
    if store.ids() and not resume:
        raise ConfigError("-o", str(out), "already holds a sweep (points/): use --resume "
                          "to continue it, or choose an empty folder")
    records = store.finished(keys, {p.point_id: p.indices for p in points}) if resume \
        else {}
    if retry_failed:
        records = {k: r for k, r in records.items() if r["status"] != "failed"}
    result = SweepResult(grid, task.spec, records, dump_config(config))
    todo = [p for p in points if p.point_id not in records]
    _check_some_point_valid(config, todo)
    own = executor is None
    if own and todo:
        executor = make_executor(workers, scheduler)
    atomic.write_json(out / "sweep.json", result.manifest())
    bar = _bar(len(points), len(records), progress)
    futures: dict[Any, GridPoint] = {}
    try:
        if todo:
            share = getattr(executor, "share", lambda obj: obj)
            shared = share(config)
            futures = {executor.submit(execute_point, task, shared, p, keys[p.point_id]): p
                       for p in todo}
            for fut in executor.as_completed(list(futures)):
                try:
                    rec = fut.result()
                except Exception as exc:  # the worker died, not the task
                    result.lost += 1
                    result.lost_message = _one_line(f"{type(exc).__name__}: {exc}")
                    continue
                store.save(rec)
                result.records[rec["point_id"]] = rec
                result.computed += 1
                bar.update(1)
                if rec["status"] == "failed":
                    bar.set_postfix_str(f"{_n_failed(result)} failed", refresh=False)
    except BaseException as exc:  # Ctrl-C, or an error of the sweep itself
        result.interrupted = isinstance(exc, KeyboardInterrupt)
        for fut in futures:
            cancel = getattr(fut, "cancel", None)
            if cancel is not None:
                cancel()
        if own and executor is not None:
            executor.shutdown(interrupted=True)   # running points are abandoned
        bar.close()
        with contextlib.suppress(Exception):      # the partial files, if they can be
            # what the store holds (a record saved just before the interrupt included)
            result.records.update(store.finished(keys))
            result.write(out)
        raise
    bar.close()
    if own and executor is not None:
        executor.shutdown()
    result.write(out)
    return result


def _check_some_point_valid(config: Config, points: Sequence[GridPoint]) -> None:
    """Raise the first point's ConfigError if no point gives a valid config (the grid
    itself is wrong, e.g. a base rate whose law is 'off'); single invalid points are
    recorded as failed when they run."""
    first: ConfigError | None = None
    for p in points:
        try:
            with_values(config, p.as_dict())
            return
        except ConfigError as exc:
            first = first or exc
    if first is not None:
        raise ConfigError(first.field, first.value, first.allowed + " (at every grid "
                          "point)")


def _n_failed(result: SweepResult) -> int:
    return sum(r["status"] == "failed" for r in result.records.values())


def _bar(total: int, done: int, enabled: bool) -> Any:
    # deferred: tqdm is heavy (loaded only when this runs)
    from tqdm import tqdm

    return tqdm(total=total, initial=done, desc="sweep", unit="pt", disable=not enabled,
                file=sys.stderr, dynamic_ncols=True, smoothing=0.1)


def load_sweep(directory: str | Path) -> Any:
    """``sweep.nc`` of ``directory`` loaded into memory (file closed)."""
    # deferred: xarray is heavy (loaded only when this runs)
    import xarray as xr

    with xr.open_dataset(Path(directory) / "sweep.nc") as ds:
        return ds.load()
