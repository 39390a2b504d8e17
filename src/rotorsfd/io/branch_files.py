"""Branch of periodic solutions <-> files: an xarray Dataset (``branch.nc``) and a flat table
(``branch.csv``).

netCDF layout (complex numbers are not portable in netCDF, so real and imaginary parts are
separate variables)::

    dims     point, harmonic (0..H), dof (4 per node: y, z, ty, tz), unknown
    coords   point, harmonic, dof, node(dof), direction(dof), parameter(point),
             speed_rad_s(point), speed_ratio(point)
    vars     X_real, X_imag (point, harmonic, dof)   q(t) = Re sum_k X_k exp(i k w t)
             frequency_rad_s, iterations, ds, aliasing, n_samples (point), tangent
             (point, unknown); optional stability: stable (int8 0/1), max_multiplier
             (point), multiplier_real/imag (point, multiplier), and the bifurcation table
             bifurcation_* (bifurcation)
    attrs    H, parameter name/units, reference speed, clearance, success, message, ...

:func:`coefficients` turns a Dataset back into the complex (n_points, H+1, n_dof) array.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from rotorsfd.continuation.branch import Branch
from rotorsfd.harmonic.truncation import POINT_INFO_LONG_NAMES, point_info_columns
from rotorsfd.io import atomic
from rotorsfd.model.dofs import DIRECTIONS

FloatArray = NDArray[np.float64]

#: Columns of ``bifurcations.csv``
#: (:meth:`rotorsfd.stability.branch_stability.BranchStability.rows` says what each is).
BIFURCATION_COLUMNS: tuple[str, ...] = (
    "type", "speed_rad_s", "speed_ratio", "parameter", "located_multiplier_re",
    "located_multiplier_im", "located_multiplier_abs", "nearest_point",
    "nearest_multiplier_re", "nearest_multiplier_im", "nearest_multiplier_abs",
    "nearest_max_multiplier", "status", "check_parameter", "check_speed_ratio",
    "check_shift", "check_harmonics", "check_intervals")
#: The columns of rows made before the checks (a stability hook, ``with_stability``).
LEGACY_BIFURCATION_COLUMNS: tuple[str, ...] = ("type", "speed_rad_s", "speed_ratio",
                                               "parameter", "max_multiplier",
                                               "multiplier_re", "multiplier_im")


def bifurcation_columns(rows: Sequence[Mapping[str, Any]]) -> tuple[str, ...]:
    """The columns the bifurcation rows have: :data:`BIFURCATION_COLUMNS`, or the legacy
    ones for rows without the located multiplier."""
    if rows and all(all(c in r for c in BIFURCATION_COLUMNS) for r in rows):
        return BIFURCATION_COLUMNS
    return LEGACY_BIFURCATION_COLUMNS


def bifurcation_units(column: str, parameter_units: str) -> str:
    """The unit of a bifurcation table column (``bifurcation_<column>`` in branch.nc)."""
    if column == "speed_rad_s":
        return "rad/s"
    if column in ("parameter", "check_parameter"):
        return parameter_units
    return "1"


def dof_labels(n_dof: int) -> tuple[NDArray[np.int64], NDArray[np.str_]]:
    """(node, direction) of every global DOF (nodes from 1, directions y, z, ty, tz)."""
    idx = np.arange(n_dof)
    return idx // 4 + 1, np.array([DIRECTIONS[i % 4] for i in idx])


def branch_dataset(branch: Branch, *, parameter: str, parameter_units: str,
                   speeds: FloatArray, reference_speed: float,
                   stable: NDArray[np.bool_] | None = None,
                   max_multiplier: FloatArray | None = None,
                   multipliers: NDArray[np.complex128] | None = None,
                   bifurcations: Sequence[Mapping[str, Any]] | None = None,
                   attrs: Mapping[str, Any] | None = None) -> xr.Dataset:
    """The Dataset of ``branch`` (module docstring). ``speeds`` (n_points,) rotor speeds
    [rad/s]; the stability arrays, if given, have one entry (row) per point."""
    n, n_dof = branch.n_points, branch.X.shape[2]
    node, direction = dof_labels(n_dof)
    lam = np.asarray(branch.lam, dtype=float)
    speeds = np.broadcast_to(np.asarray(speeds, dtype=float), (n,))
    coords = {
        "point": ("point", np.arange(n), {"long_name": "continuation point, in branch "
                                                        "order", "units": "1"}),
        "harmonic": ("harmonic", np.arange(branch.H + 1),
                     {"long_name": "harmonic order k of the response frequency",
                      "units": "1"}),
        "dof": ("dof", np.arange(n_dof), {"long_name": "global DOF index 4 (node - 1) + "
                                                      "(y, z, ty, tz)", "units": "1"}),
        "node": ("dof", node, {"long_name": "rotor node of the DOF (from 1)", "units": "1"}),
        "direction": ("dof", direction.astype(str),
                      {"long_name": "direction of the DOF (y, z, ty, tz)", "units": ""}),
        "parameter": ("point", lam, {"long_name": parameter, "units": parameter_units}),
        "speed_rad_s": ("point", speeds.copy(), {"long_name": "rotor speed Omega",
                                                  "units": "rad/s"}),
        "speed_ratio": ("point", speeds / reference_speed,
                        {"long_name": "Omega / reference speed", "units": "1"}),
    }
    harm = ("point", "harmonic", "dof")
    unit = "m (y, z) or rad (ty, tz)"
    data: dict[str, Any] = {
        "X_real": (harm, branch.X.real.reshape(n, branch.H + 1, n_dof),
                   {"long_name": "real part of the Fourier coefficient X_k", "units": unit}),
        "X_imag": (harm, branch.X.imag.reshape(n, branch.H + 1, n_dof),
                   {"long_name": "imaginary part of the Fourier coefficient X_k",
                    "units": unit}),
        "frequency_rad_s": ("point", np.asarray(branch.frequency, float),
                            {"long_name": "response fundamental frequency w",
                             "units": "rad/s"}),
        "iterations": ("point", np.asarray(branch.iterations, np.int32),
                       {"long_name": "Newton corrector iterations", "units": "1"}),
        "ds": ("point", np.asarray(branch.ds, float),
               {"long_name": "arc-length step (scaled unknowns)", "units": "1"}),
        "aliasing": ("point", np.asarray(branch.aliasing, float),
                     {"long_name": "AFT aliasing indicator of the nonlinear force",
                      "units": "1"}),
    }
    if "n_samples" in branch.info:
        data["n_samples"] = ("point", np.asarray(branch.info["n_samples"], np.int32),
                             {"long_name": "AFT time samples N_f", "units": "1"})
    for name, values in point_info_columns(branch).items():
        data[name] = ("point", values, {"long_name": POINT_INFO_LONG_NAMES[name],
                                        "units": "1"})
    if branch.tangents.size:
        data["tangent"] = (("point", "unknown"), np.asarray(branch.tangents, float),
                           {"long_name": "unit tangent in scaled unknowns (last: parameter)",
                            "units": "1"})
    if stable is not None:
        data["stable"] = ("point", np.asarray(stable, dtype=bool).astype(np.int8),
                          {"long_name": "1 stable, 0 unstable", "units": "1"})
    if max_multiplier is not None:
        data["max_multiplier"] = ("point", np.asarray(max_multiplier, float),
                                  {"long_name": "largest Floquet multiplier modulus",
                                   "units": "1"})
    if multipliers is not None:
        mu = np.asarray(multipliers, dtype=complex).reshape(n, -1)
        data["multiplier_real"] = (("point", "multiplier"), mu.real,
                                   {"long_name": "real part of the Floquet multiplier",
                                    "units": "1"})
        data["multiplier_imag"] = (("point", "multiplier"), mu.imag,
                                   {"long_name": "imaginary part of the Floquet multiplier",
                                    "units": "1"})
    for name in bifurcation_columns(bifurcations or []):
        if bifurcations:
            values = [row[name] for row in bifurcations]
            text = any(isinstance(v, str) for v in values)
            data[f"bifurcation_{name}"] = ("bifurcation", np.asarray(
                [str(v) for v in values] if text else values, dtype=str if text else float),
                {"long_name": f"located bifurcation: {name.replace('_', ' ')}",
                 "units": bifurcation_units(name, parameter_units) if not text else ""})
    ds = xr.Dataset(data, coords=coords)
    for dim, text in (("unknown", "scaled HB unknown (real coefficients, then lam)"),
                      ("multiplier", "Floquet multiplier, largest modulus first"),
                      ("bifurcation", "located bifurcation, in branch order")):
        if dim in ds.dims:
            ds = ds.assign_coords({dim: (dim, np.arange(ds.sizes[dim]),
                                         {"long_name": text, "units": "1"})})
    ds.attrs.update({
        "title": "rotorsfd periodic response branch",
        "convention": "q(t) = Re(sum_k (X_real + i X_imag)_k exp(i k w t)), w = "
                      "frequency_rad_s; |X_k| is the half peak-to-peak amplitude",
        "H": int(branch.H), "n_samples": int(branch.n_samples),
        "condensed": int(branch.condensed), "success": int(branch.success),
        "message": str(branch.message), "continuation_parameter": parameter,
        "parameter_units": parameter_units, "reference_speed_rad_s": float(reference_speed),
        "nl_dofs": np.asarray(branch.nl_dofs, dtype=np.int32),
    })
    for key, value in (attrs or {}).items():
        ds.attrs[key] = int(value) if isinstance(value, bool) else value
    return ds


def coefficients(ds: xr.Dataset) -> NDArray[np.complex128]:
    """Complex Fourier coefficients (n_points, H+1, n_dof) of a branch Dataset."""
    return ds["X_real"].values + 1j * ds["X_imag"].values


def check_finite(ds: xr.Dataset) -> None:
    """ValueError naming the variable if any numeric variable holds NaN or inf."""
    for name, var in {**ds.data_vars, **ds.coords}.items():
        if np.issubdtype(var.dtype, np.number) and not np.all(np.isfinite(var.values)):
            raise ValueError(f"non-finite values in {name!r}: refusing to write NaN/inf")


def write_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` atomically (netCDF4 format, compressed coefficient arrays)."""
    check_finite(ds)
    enc = {v: {"zlib": True, "complevel": 4} for v in ("X_real", "X_imag") if v in ds}
    return atomic.write_netcdf(ds, path, encoding=enc)


def read_branch(path: str | Path) -> xr.Dataset:
    """Load a ``branch.nc`` into memory (file closed on return)."""
    with xr.open_dataset(path) as ds:
        return ds.load()


def write_table(path: str | Path, columns: Mapping[str, Any]) -> Path:
    """Write equal-length columns as a CSV table atomically (floats at full precision,
    booleans as 0/1); ValueError on NaN/inf."""
    names = list(columns)
    cols = [np.asarray(columns[k]) for k in names]
    lengths = {c.shape[0] for c in cols}
    if len(lengths) > 1:
        raise ValueError(f"columns of unequal lengths {sorted(lengths)}")
    out = []
    for name, col in zip(names, cols, strict=True):
        if col.dtype == bool:
            col = col.astype(int)
        if np.issubdtype(col.dtype, np.number) and not np.all(np.isfinite(col)):
            raise ValueError(f"non-finite values in column {name!r}: refusing to write NaN/inf")
        out.append([v.item() if isinstance(v, np.generic) else v for v in col])
    return atomic.write_csv(path, names, zip(*out, strict=True) if out else [])
