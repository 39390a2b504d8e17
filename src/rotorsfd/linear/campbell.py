"""Campbell diagram: modes over a list of spin speeds, tracked from speed to speed.

Tracking: the modes at speed k+1 are assigned to the branches of speed k by the
Hungarian algorithm (``scipy.optimize.linear_sum_assignment``) on the cost
``(1 - MAC) + |w_new - w_old| / max(w_old, w_new)``, so a branch follows its mode shape
(MAC) and its eigenvalue continuity through crossings of branches of other shapes.
Branch numbers are the order at the first speed (1-based). Whirl is per point.

With the sparse eigensolver (``method`` "sparse", or "auto" on a large model) the modes at
every speed come from a reduced model on exact modes at a few speeds
(:mod:`rotorsfd.linear.reduced`), refined until its measured relative eigenvalue error is
below ``tol``; that error is ``CampbellResult.info["reduced_error"]``.
"""

from __future__ import annotations

import csv
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np
from scipy.optimize import linear_sum_assignment

from rotorsfd.linear.modal import LinearDynamics, ModalResult, eigen, mac, use_sparse
from rotorsfd.linear.modes import EigenvalueMeasures


@dataclass(frozen=True)
class CampbellResult(EigenvalueMeasures):
    """Tracked modes: arrays of shape (n_speeds, n_modes), branch j in column j."""

    speeds: np.ndarray          # (n_speeds,) [rad/s]
    eigenvalues: np.ndarray     # complex
    whirl: np.ndarray           # "forward" | "backward"
    info: dict[str, Any] = field(default_factory=dict)   # how the modes were computed

    def to_csv(self, path: str | Path) -> Path:
        """Write one row per (speed, mode): speed_rad_s, mode (1-based branch), whirl,
        frequency_rad_s, damping_ratio, log_decrement."""
        path = Path(path)
        freq, zeta, dec = self.frequencies, self.damping_ratios, self.log_decrements
        with path.open("w", newline="") as fh:
            w = csv.writer(fh)
            w.writerow(["speed_rad_s", "mode", "whirl", "frequency_rad_s",
                        "damping_ratio", "log_decrement"])
            for i, s in enumerate(self.speeds):
                for j in range(freq.shape[1]):
                    w.writerow([repr(float(s)), j + 1, self.whirl[i, j], repr(float(freq[i, j])),
                                repr(float(zeta[i, j])), repr(float(dec[i, j]))])
        return path

    def to_dataset(self) -> Any:
        """xarray Dataset over ``(speed, mode)``: eigenvalue real and imaginary parts,
        damped natural frequency, damping ratio, log decrement, whirl."""
        import xarray as xr  # deferred: xarray

        dims = ("speed", "mode")
        return xr.Dataset(
            {"eigenvalue_re": (dims, self.eigenvalues.real, {"units": "1/s"}),
             "eigenvalue_im": (dims, self.eigenvalues.imag, {"units": "rad/s"}),
             "frequency": (dims, self.frequencies,
                           {"units": "rad/s", "long_name": "damped natural frequency"}),
             "damping_ratio": (dims, self.damping_ratios, {"units": "1"}),
             "log_decrement": (dims, self.log_decrements, {"units": "1"}),
             "whirl": (dims, self.whirl.astype(str))},
            coords={"speed": ("speed", self.speeds, {"units": "rad/s",
                                                     "long_name": "spin speed"}),
                    "mode": ("mode", np.arange(1, self.eigenvalues.shape[1] + 1),
                             {"long_name": "tracked branch (1-based)"})},
            attrs={"method": str(self.info.get("method", ""))})


def _track(prev: ModalResult, cur: ModalResult, n_modes: int) -> np.ndarray:
    """Column of ``cur`` assigned to each of the ``n_modes`` branches of ``prev``."""
    m = mac(prev.mode_shapes[:, :n_modes], cur.mode_shapes)
    wp, wc = prev.frequencies[:n_modes, None], cur.frequencies[None, :]
    cost = (1.0 - m) + np.abs(wc - wp) / np.maximum(wp, wc)
    rows, cols = linear_sum_assignment(cost)
    out = np.empty(n_modes, dtype=int)
    out[rows] = cols
    return out


def campbell(system: LinearDynamics, speeds: Sequence[float], n_modes: int = 8,
             spare_modes: int = 4, method: str = "auto", tol: float = 1e-9
             ) -> CampbellResult:
    """Modes at each speed, tracked (see module docstring). ``spare_modes`` extra modes are
    computed at each speed so a branch can be followed when others cross into the window.
    ``method``: the eigensolver ("auto", "dense", "sparse"; see :func:`eigen`); ``tol``:
    relative eigenvalue error of the reduced model of the sparse path."""
    speeds = np.asarray(speeds, dtype=float)
    n_speeds = speeds.size
    sparse = use_sparse(system, method)
    info: dict[str, Any] = {"method": "sparse" if sparse else "dense"}

    def solve(s: float, m: int) -> ModalResult:
        return eigen(system, s, m, "sparse" if sparse else "dense")

    if sparse and n_speeds > 6 and speeds.max() > speeds.min():
        # deferred: linear.sparse_modes loads scipy.sparse.linalg (only above 200 DOF)
        from rotorsfd.linear.sparse_modes import pencil_of

        if pencil_of(system).terms is not None:   # affine in the speed: a reduced model
            from rotorsfd.linear.reduced import reduced_modes

            model = reduced_modes(system, float(speeds.min()), float(speeds.max()),
                                  n_modes + spare_modes, tol)
            info = {"method": "reduced", "reduced_error": model.error,
                    "snapshots_rad_s": list(model.snapshots), "basis_size": model.basis.shape[1]}
            if model.error <= tol:
                solve = model.eigen  # type: ignore[assignment]
            else:                    # not met with max_snapshots: exact at every speed
                info["method"] = "sparse"
    lam = np.empty((n_speeds, n_modes), dtype=complex)
    whirl = np.empty((n_speeds, n_modes), dtype="<U8")
    prev: ModalResult | None = None
    for i, s in enumerate(speeds):
        res = solve(float(s), n_modes + spare_modes)
        if prev is None:
            idx = np.arange(n_modes)
        else:
            idx = _track(prev, res, n_modes)
        lam[i] = res.eigenvalues[idx]
        whirl[i] = res.whirl[idx]
        prev = ModalResult(res.speed, res.eigenvalues[idx], res.mode_shapes[:, idx],
                           res.whirl[idx])
    return CampbellResult(speeds, lam, whirl, info)
