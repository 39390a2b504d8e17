"""Branch of tori -> ``torus.nc`` (an xarray Dataset; the table ``torus.csv`` is written by
:func:`rotorsfd.io.branch_files.write_table`).

netCDF layout (real and imaginary parts separate, as in ``branch.nc``)::

    dims     point, harmonic (the half lattice), dof (4 per node: y, z, ty, tz), lyapunov
    coords   point, harmonic, k1(harmonic), k2(harmonic), dof, node(dof), direction(dof),
             speed_rad_s(point), speed_ratio(point), base_frequency_rad_s(point),
             parameter(point) (a branch in another parameter than the speed)
    vars     X_real, X_imag (point, harmonic, dof)
                 q(t) = Re sum_k X_k exp(i (k1 Omega + k2 w_b) t)
             iterations, aliasing, validity_measure, arc_length, defl_<n> (point);
             with stability: lyapunov_point, lyapunov_per_period, lyapunov_uncertainty,
             stable (lyapunov)
    attrs    H1, H2, lattice shape, grid, success, message, reference speed, clearance,
             config_toml, rotorsfd_version, ...

:func:`torus_coefficients` turns a Dataset back into the complex (n_points, nk, n_dof)
array.
"""

from __future__ import annotations

from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import xarray as xr
from numpy.typing import NDArray

from rotorsfd.io import atomic
from rotorsfd.io.branch_files import check_finite, dof_labels

#: long names of the index-like variables (the others carry their own)
FALLBACK_NAMES = {"point": "continuation point", "dof": "global degree of freedom",
                  "node": "node (from 1)", "direction": "DOF direction (y, z, ty, tz)",
                  "lyapunov": "point with a Lyapunov exponent"}


def torus_dataset(branch: Any, *, reference_speed: float,
                  deflection: Mapping[int, NDArray[np.float64]],
                  lyapunov: Mapping[int, Any] | None = None,
                  attrs: Mapping[str, Any] | None = None,
                  parameter: tuple[str, str] | None = None,
                  node_labels: Mapping[int, str] | None = None) -> xr.Dataset:
    """The Dataset of a :class:`~rotorsfd.quasiperiodic.TorusBranch` (module docstring);
    ``deflection`` node -> r~ per point, ``lyapunov`` point index ->
    :class:`~rotorsfd.quasiperiodic.torus_stability.TorusLyapunov`; ``parameter``
    (config path, SI unit) of a branch in another parameter than the speed (None: the
    speed), whose values ``branch.lam`` become the coordinate ``parameter(point)``;
    ``node_labels`` the nodes' names in the long names (default ``node <n>``)."""
    lat = branch.lattice
    n, nk, n_dof = branch.X.shape
    node, direction = dof_labels(n_dof)
    omega = np.asarray(branch.omega, dtype=float)
    coords = {
        "point": np.arange(n),
        "harmonic": ("harmonic", np.arange(nk), {"long_name": "harmonic (k1, k2) of the "
                                                 "half lattice"}),
        "k1": ("harmonic", lat.k[:, 0].astype(np.int32),
               {"long_name": "multiple of the rotor speed Omega", "units": "1"}),
        "k2": ("harmonic", lat.k[:, 1].astype(np.int32),
               {"long_name": "multiple of the base frequency w_b", "units": "1"}),
        "dof": np.arange(n_dof), "node": ("dof", node),
        "direction": ("dof", direction.astype(str)),
        "speed_rad_s": ("point", omega, {"long_name": "rotor speed Omega",
                                         "units": "rad/s"}),
        "speed_ratio": ("point", omega / reference_speed,
                        {"long_name": "Omega / reference speed", "units": "1"}),
        "base_frequency_rad_s": ("point", np.asarray(branch.wb, dtype=float),
                                 {"long_name": "base frequency w_b", "units": "rad/s"}),
    }
    if parameter is not None:
        coords["parameter"] = ("point", np.asarray(branch.lam, dtype=float),
                               {"long_name": parameter[0], "units": parameter[1]})
    harm = ("point", "harmonic", "dof")
    unit = {"units": "m (y, z) or rad (ty, tz)"}
    data: dict[str, Any] = {
        "X_real": (harm, branch.X.real, {**unit, "long_name": "Re X_(k1,k2)"}),
        "X_imag": (harm, branch.X.imag, {**unit, "long_name": "Im X_(k1,k2)"}),
        "iterations": ("point", np.asarray(branch.iterations, np.int32),
                       {"long_name": "Newton iterations"}),
        "aliasing": ("point", np.asarray(branch.aliasing, float),
                     {"long_name": "sampling error of the torus grid (scaled residual "
                                   "change when N1 or N2 doubles)", "units": "1"}),
        "validity_measure": ("point", np.asarray(branch.limit, float),
                             {"long_name": "largest element validity measure over the "
                                           "torus (an SFD's eccentricity ratio)",
                              "units": "1"}),
        "arc_length": ("point", np.asarray(branch.s, float),
                       {"long_name": "arc length (scaled unknowns)", "units": "1"}),
    }
    for nd, values in deflection.items():
        data[f"defl_{nd}"] = ("point", np.asarray(values, float), {
            "long_name": "largest radius over the torus at "
                         f"{(node_labels or {}).get(nd, f'node {nd}')} / C (r~)",
            "units": "1"})
    if lyapunov:
        idx = sorted(lyapunov)
        data["lyapunov_point"] = ("lyapunov", np.asarray(idx, np.int32),
                                  {"long_name": "point index of the exponent"})
        data["lyapunov_per_period"] = ("lyapunov", np.array(
            [lyapunov[i].per_period for i in idx]), {
            "long_name": "largest Lyapunov exponent times the rotor period 2 pi / Omega",
            "units": "1"})
        data["lyapunov_uncertainty"] = ("lyapunov", np.array(
            [lyapunov[i].uncertainty for i in idx]), {
            "long_name": "uncertainty of lyapunov_per_period", "units": "1"})
        data["stable"] = ("lyapunov", np.array([int(lyapunov[i].stable) for i in idx],
                                               np.int8),
                          {"long_name": "1 stable (exponent + uncertainty < 0), 0 unstable"})
    ds = xr.Dataset(data, coords=coords)
    for name, text in FALLBACK_NAMES.items():     # units and long_name on every variable
        if name in ds.variables:
            ds[name].attrs.setdefault("long_name", text)
    for name in ds.variables:
        ds[name].attrs.setdefault("units", "1")
    ds.attrs.update({
        "title": "rotorsfd quasi-periodic response branch (torus)",
        "convention": "q(t) = Re(sum_k (X_real + i X_imag)_k exp(i (k1 Omega + k2 w_b) t)) "
                      "over the half lattice (k1 = 0: k2 >= 0; k1 >= 1: all k2); |X_k| is "
                      "the half peak-to-peak amplitude of the line at k1 Omega + k2 w_b",
        "H1": int(lat.H1), "H2": int(lat.H2), "lattice": str(lat.shape),
        "grid": np.asarray(branch.grid, dtype=np.int32), "success": int(branch.success),
        "message": str(branch.message),
        "continuation_parameter": "speed" if parameter is None else parameter[0],
        "parameter_units": "rad/s" if parameter is None else parameter[1],
        "reference_speed_rad_s": float(reference_speed),
    })
    for key, value in (attrs or {}).items():
        ds.attrs[key] = int(value) if isinstance(value, bool) else value
    return ds


def torus_coefficients(ds: xr.Dataset) -> NDArray[np.complex128]:
    """Complex coefficients (n_points, nk, n_dof) of a torus Dataset."""
    return ds["X_real"].values + 1j * ds["X_imag"].values


def write_torus_netcdf(ds: xr.Dataset, path: str | Path) -> Path:
    """Write ``ds`` atomically (netCDF4, compressed coefficients); ValueError on NaN."""
    check_finite(ds)
    enc = {v: {"zlib": True, "complevel": 4} for v in ("X_real", "X_imag")}
    return atomic.write_netcdf(ds, path, encoding=enc)
