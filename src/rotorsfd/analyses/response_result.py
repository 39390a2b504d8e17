"""The result of a response branch: its table, files, plots and summary
(:class:`ResponseResult`; the columns are listed in :mod:`rotorsfd.analyses.response`)."""

from __future__ import annotations

import dataclasses
import re
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.response_words import (
    PARAMETER_UNITS,
    column_slug,
    failure_words,
    system_parameter,
)
from rotorsfd.continuation.branch import Branch, BranchPoint
from rotorsfd.harmonic.truncation import point_info_columns
from rotorsfd.model import dofs
from rotorsfd.model.node_names import (
    NodeNames,
    node_words,
    with_shaft_coords,
    write_node_table,
)
from rotorsfd.model.system import RotorSystem

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure


from rotorsfd.harmonic.synthesis import max_radius, orbit_samples
from rotorsfd.io import atomic
from rotorsfd.io.provenance import netcdf_attrs

FloatArray = NDArray[np.float64]



@dataclass(frozen=True)
class PointStability:
    """Stability of one converged point, as returned by a ``stability`` hook."""

    stable: bool
    max_multiplier: float
    multipliers: NDArray[np.complex128] | None = None
    stop: bool = False          # True stops the continuation after this point


StabilityHook = Callable[[BranchPoint], "PointStability | None"]


@dataclass
class ResponseResult:
    """A response branch with what is needed to report it (see the module docstring)."""

    branch: Branch
    system: RotorSystem
    reference_speed: float
    nodes: tuple[int, ...]
    directions: tuple[str, ...] = ("y", "z")
    parameter: str = "speed"                  # config path (or RotorSystem name)
    speed: float | None = None                # fixed speed when parameter != speed
    title: str = ""
    elapsed: float = 0.0
    stable: NDArray[np.bool_] | None = None
    max_multiplier: FloatArray | None = None
    multipliers: NDArray[np.complex128] | None = None
    bifurcations: list[dict[str, Any]] | None = None
    info: dict[str, Any] = field(default_factory=dict)
    #: The orbit's period in T = 2 pi / Omega: the branch's harmonic k is k Omega / period
    #: (``branch.frequency`` is Omega / period; 2 on a period-2 branch).
    period: int = 1

    FILES = ("branch.nc", "branch.csv")

    # ---- basic quantities -----------------------------------------------------------------
    @property
    def success(self) -> bool:
        return bool(self.branch.success)

    @property
    def ended(self) -> str:
        """How the branch ended: ``"range"`` (at the end of its range, or closed on
        itself), ``"limit"`` (an element reached its validity limit,
        ``analysis.response.max_eccentricity``: the branch is a result up to there),
        ``"stopped"`` (on request, e.g. Ctrl-C) or ``"failed"`` (a numerical failure: no
        converged point beyond the last even at the smallest step, ``max_points``)."""
        b = self.branch
        if str(b.message).startswith("stopped by the callback"):
            return "stopped"
        if b.success:
            return "range"
        return "limit" if self.limit_text() else "failed"

    @property
    def message(self) -> str:
        """The outcome in the user's terms: where the branch ended and why, with the
        solver's own text in brackets when it stopped early."""
        b = self.branch
        if not b.n_points:
            return str(b.message)
        last = (f"Omega~ = {b.frequency[-1] / self.reference_speed:.5g}" if self.is_speed
                else f"{self.parameter} = {b.lam[-1]:.6g} {self.parameter_units}")
        if self.ended == "stopped":
            return f"response branch stopped on request after {b.n_points} points at {last}"
        if b.success:     # the continuation's warnings (e.g. the truncation error) kept
            solver = str(b.message)
            at = solver.find("; warning")
            return (f"reached the end of the range at {last} ({b.n_points} points)"
                    + (self.in_user_terms(solver[at:]) if at >= 0 else ""))
        limit = self.limit_text()
        reason = limit or failure_words(str(b.message))
        head = (f"response branch {'ended' if limit else 'stopped'} after "
                f"{b.n_points} points at {last}")
        return f"{head}: {reason} [solver: {b.message}]" if reason else f"{head}: {b.message}"

    def in_user_terms(self, text: str) -> str:
        """The continuation's ``lam=<value> (H=<n>)`` written as the parameter (Omega~ and
        rad/s for the speed) and ``H = n``."""
        def value(m: re.Match) -> str:
            lam = float(m.group(1))
            if self.is_speed:
                return f"Omega~ = {lam / self.reference_speed:.5g} ({lam:.6g} rad/s)"
            return f"{self.parameter} = {lam:.6g} {self.parameter_units}"

        text = re.sub(r"lam=([-+0-9.eE]+)", value, text)
        return re.sub(r"\(H=(\d+)\)", r"(H = \1)", text)

    @property
    def is_speed(self) -> bool:
        return system_parameter(self.parameter) == "speed"

    @property
    def parameter_units(self) -> str:
        return PARAMETER_UNITS[system_parameter(self.parameter)]

    @property
    def parameter_column(self) -> str:
        """First CSV column: ``speed_rad_s``, or the parameter with its unit."""
        if self.is_speed:
            return "speed_rad_s"
        return f"{column_slug(self.parameter)}_{column_slug(self.parameter_units)}"

    @property
    def node_names(self) -> NodeNames | None:
        """Shaft-wise node names of a multi-shaft rotor (None: one shaft)."""
        return NodeNames.of(self.system.rotor)

    @property
    def clearance(self) -> float:
        """The elements' length scale C [m] (the smallest clearance; the scale of r~)."""
        return float(self.system.length_scale or 1.0)

    @property
    def speeds(self) -> FloatArray:
        """Rotor speed of every point [rad/s]: ``period`` x the branch's frequency."""
        return self.period * np.asarray(self.branch.frequency, dtype=float)

    def static(self, node: int, direction: str) -> FloatArray:
        """X_0 of (node, direction) along the branch [m]."""
        return self.branch.X[:, 0, dofs.dof_index(node, direction)].real.copy()

    def amplitude(self, node: int, direction: str, k: int = 1) -> FloatArray:
        """|X_k| of (node, direction) along the branch [m]."""
        return self.branch.amplitude(dofs.dof_index(node, direction), k)

    def deflection(self, node: int) -> FloatArray:
        """r~ = max_t sqrt(y^2 + z^2) / C at ``node`` along the branch."""
        X = self.branch.X
        Xy, Xz = X[:, :, dofs.dof_index(node, "y")], X[:, :, dofs.dof_index(node, "z")]
        return max_radius(Xy, Xz) / self.clearance

    def subharmonic(self, node: int) -> FloatArray:
        """``sqrt(sum_k |X_k,y|^2 + |X_k,z|^2) / C`` at ``node`` over the harmonics k that
        are not multiples of ``period`` (the part that is not T-periodic; 0 on period 1)."""
        X = self.branch.X
        k = np.arange(X.shape[1]) % self.period != 0
        Xy, Xz = X[:, k, dofs.dof_index(node, "y")], X[:, k, dofs.dof_index(node, "z")]
        return np.sqrt((np.abs(Xy) ** 2 + np.abs(Xz) ** 2).sum(axis=1)) / self.clearance

    def harmonic_name(self, k: int) -> str:
        """The column tag of the branch's harmonic k, of frequency k Omega / ``period``:
        ``h<k/period>`` for a harmonic of the speed, ``h<k>_<period>`` otherwise
        (``h1_2``: the Omega/2 subharmonic)."""
        p = self.period
        return f"h{k // p}" if k % p == 0 else f"h{k}_{p}"

    def table(self) -> dict[str, NDArray[Any]]:
        """The columns of ``branch.csv`` in order (module docstring)."""
        speeds = self.speeds
        cols: dict[str, NDArray[Any]] = {}
        if not self.is_speed:
            cols[self.parameter_column] = np.asarray(self.branch.lam, dtype=float)
        cols["speed_rad_s"] = speeds
        cols["speed_ratio"] = speeds / self.reference_speed
        for n in self.nodes:
            for d in self.directions:
                cols[f"static_{n}_{d}"] = self.static(n, d)
                for k in range(1, self.branch.H + 1):
                    cols[f"amp_{n}_{d}_{self.harmonic_name(k)}"] = self.amplitude(n, d, k)
        for n in self.nodes:
            cols[f"defl_{n}"] = self.deflection(n)
            if self.period > 1:
                cols[f"sub_{n}"] = self.subharmonic(n)
        cols.update(self.element_columns())
        cols.update(point_info_columns(self.branch))
        if self.stable is not None:
            cols["stable"] = np.asarray(self.stable, dtype=bool)
        if self.max_multiplier is not None:
            cols["max_multiplier"] = np.asarray(self.max_multiplier, dtype=float)
        cols.update(self.floquet_columns())
        return cols

    def element_columns(self) -> dict[str, FloatArray]:
        """Every element's orbit diagnostics along the branch, ``<key>_<element name>``
        (``eps_max_<name>`` of an SFD): the element's ``diagnostics`` of the orbit sampled
        at ``max(1024, 64 (H + 1))`` phases, ``v = w dq/dtheta``."""
        el = self.system.elements
        b = self.branch
        if not len(el) or not b.n_points:
            return {}
        q, v = orbit_samples(b.X[:, :, el.nl_dofs], b.frequency)   # (points, n, m)
        rows = [el.diagnostics(q[i], v[i]) for i in range(b.n_points)]
        return {key: np.array([r[key] for r in rows]) for key in rows[0]}

    def limit_text(self) -> str:
        """Which element reached its validity limit (``analysis.response.max_eccentricity``)
        at the last point, in the user's terms; "" if none is near it."""
        el = self.system.elements
        b = self.branch
        limit = self.info.get("limit_max")
        if not len(el) or not b.n_points or limit is None:
            return ""
        reached = el.at_limit(orbit_samples(b.X[-1][:, el.nl_dofs])[0], limit)
        if reached is None:
            return ""
        element, value = reached
        return (f"{element.describe()} reached {element.limit_label} = {value:.3f}, the limit "
                f"analysis.response.max_eccentricity = {limit:g} (raise it, up to 0.999, to "
                "follow the branch closer to the housing)")

    def floquet_columns(self) -> dict[str, NDArray[Any]]:
        """``floquet_intervals`` (the Newmark M of every point), ``multiplier_error``
        (the step control's estimate of the largest multipliers' error), ``floquet_modes``
        (the fixed-interface modes in the reduced basis ``max_multiplier`` covers; the
        interior DOFs for the full basis) and ``max_multiplier_outside`` (the modes above
        the basis' cut-off, :mod:`rotorsfd.stability.outside`), when known."""
        n = self.branch.n_points
        out: dict[str, NDArray[Any]] = {}
        for key, dtype in (("floquet_intervals", np.int64), ("multiplier_error", float),
                           ("floquet_modes", np.int64), ("max_multiplier_outside", float)):
            v = self.info.get(key)
            if v is not None and np.shape(v) == (n,) and np.all(np.isfinite(v)):
                out[key] = np.asarray(v, dtype=dtype)
        return out

    def with_stability(self, stable: Sequence[bool], max_multiplier: Sequence[float],
                       multipliers: Any = None,
                       bifurcations: Sequence[Mapping[str, Any]] | None = None
                       ) -> ResponseResult:
        """A copy carrying per-point stability (one entry per point) and, optionally, the
        bifurcation rows (keys of :data:`rotorsfd.io.branch_files.BIFURCATION_COLUMNS`)."""
        n = self.branch.n_points
        stable = np.asarray(stable, dtype=bool)
        mm = np.asarray(max_multiplier, dtype=float)
        if stable.shape != (n,) or mm.shape != (n,):
            raise ValueError(f"stability arrays need {n} entries, got {stable.shape}, "
                             f"{mm.shape}")
        mu = None if multipliers is None else np.asarray(multipliers, dtype=complex)
        if mu is not None and mu.shape[0] != n:
            raise ValueError(f"multipliers need {n} rows, got {mu.shape}")
        rows = None if bifurcations is None else [dict(b) for b in bifurcations]
        return dataclasses.replace(self, stable=stable, max_multiplier=mm, multipliers=mu,
                                   bifurcations=rows)

    # ---- files ----------------------------------------------------------------------------
    def to_dataset(self) -> xr.Dataset:
        """The branch as an xarray Dataset (layout: :mod:`rotorsfd.io.branch_files`)."""
        from rotorsfd.io.branch_files import branch_dataset

        attrs = {"run_title": self.title, "clearance_m": self.clearance,
                 "elements": "; ".join(e.describe() for e in self.system.elements),
                 "output_nodes":
                 np.asarray(self.nodes, dtype=np.int32), "output_directions":
                 " ".join(self.directions), **netcdf_attrs(),
                 "elapsed_s": float(self.elapsed), "ended": self.ended,
                 "outcome": self.message}
        if self.speed is not None:
            attrs["fixed_speed_rad_s"] = float(self.speed)
        ds = with_shaft_coords(branch_dataset(
            self.branch, parameter=self.parameter, parameter_units=self.parameter_units,
            speeds=self.speeds, reference_speed=self.reference_speed, stable=self.stable,
            max_multiplier=self.max_multiplier, multipliers=self.multipliers,
            bifurcations=self.bifurcations, attrs=attrs), self.node_names)
        long = {"floquet_intervals": "Newmark intervals per period of the monodromy",
                "multiplier_error": "estimated error of the largest Floquet multipliers' "
                                    "moduli (|mu(M) - mu(M/2)| / 3)",
                "floquet_modes": "fixed-interface modes in the reduced Floquet basis",
                "max_multiplier_outside": "largest |exp(lambda_j T)| of the structural "
                                          "modes above the Floquet basis' cut-off "
                                          "(averaged model)"}
        if "floquet_basis" in self.info:
            ds.attrs["floquet_basis"] = str(self.info["floquet_basis"])
        for key, values in self.floquet_columns().items():
            ds[key] = ("point", values, {"long_name": long[key], "units": "1"})
        for n in self.nodes:
            ds[f"defl_{n}"] = ("point", self.deflection(n), {
                "long_name": "largest radius over the period at "
                             f"{node_words(self.node_names, n)} / C (r~)",
                "units": "1"})
            if self.period > 1:
                ds[f"sub_{n}"] = ("point", self.subharmonic(n), {
                    "long_name": "harmonics that are not T-periodic at "
                                 f"{node_words(self.node_names, n)}, 2-norm / C",
                    "units": "1"})
        if "config_toml" in self.info:
            ds.attrs["config_toml"] = self.info["config_toml"]
        info = self.system.elements.diagnostic_info()
        for key, values in self.element_columns().items():
            text, unit = info.get(key, (key, ""))
            ds[key] = ("point", values, {"long_name": text, "units": unit})
        if "n_multipliers" in self.info and self.multipliers is not None:
            ds["multiplier_count"] = ("point", np.asarray(self.info["n_multipliers"],
                                                          np.int32),
                                      {"long_name": "multipliers in the row (rest is 0)",
                                       "units": "1"})
        return ds

    def write(self, directory: str | Path, plots: bool = True,
              multipliers_at: float | None = None) -> dict[str, Path]:
        """Write ``branch.nc``, ``branch.csv``, ``bifurcations.csv`` (when there is a
        bifurcation table) and the plots (``response_*.png``, and ``multipliers.png`` when
        the multipliers are known: at the point nearest ``multipliers_at``, a speed ratio
        for a speed branch, else the parameter in SI; default the point of largest
        ``|mu|max``) atomically."""
        # deferred: io.branch_files (loads xarray, pandas, multiprocessing)
        from rotorsfd.io.branch_files import bifurcation_columns, write_netcdf, write_table

        out = Path(directory)
        paths = {"branch.nc": write_netcdf(self.to_dataset(), out / "branch.nc"),
                 "branch.csv": write_table(out / "branch.csv", self.table()),
                 **write_node_table(out, self.node_names, self.nodes)}
        if self.bifurcations is not None:
            cols = {c: [row[c] for row in self.bifurcations]
                    for c in bifurcation_columns(self.bifurcations)}
            paths["bifurcations.csv"] = write_table(out / "bifurcations.csv", cols)
        if plots:
            paths.update(atomic.save_figures(self.plot(multipliers_at), out))
        return paths

    # ---- multipliers of one point ---------------------------------------------------------
    @property
    def multiplier_counts(self) -> NDArray[np.int64]:
        """Multipliers in each row of ``multipliers`` (the rest of a row is zero padding,
        see :class:`~rotorsfd.stability.branch_stability.BranchStability`); the full row
        width when no counts were recorded (stability hook, :meth:`with_stability`)."""
        if self.multipliers is None:
            raise ValueError("no multipliers: run the response with stability enabled")
        n, width = self.multipliers.shape[0], self.multipliers.shape[-1]
        counts = self.info.get("n_multipliers")
        if counts is not None and np.shape(counts) == (n,) and max(counts, default=0) <= width:
            return np.asarray(counts, dtype=np.int64)
        return np.full(n, width, dtype=np.int64)

    def point_multipliers(self, index: int) -> NDArray[np.complex128]:
        """The Floquet multipliers of point ``index`` (padding dropped)."""
        if self.multipliers is None:
            raise ValueError("no multipliers: run the response with stability enabled")
        i = range(self.branch.n_points)[index]
        row = np.asarray(self.multipliers[i], dtype=complex).ravel()
        return row[: int(self.multiplier_counts[i])].copy()

    def point_index(self, speed_ratio: float | None = None,
                    parameter: float | None = None) -> int:
        """Index of the point nearest ``speed_ratio`` (Omega / Omega_ref) or ``parameter``
        (the continuation parameter, SI); with neither, the point of largest ``|mu|max``.
        Where a fold puts several points near the same value, the first nearest wins."""
        if speed_ratio is not None and parameter is not None:
            raise ValueError("give speed_ratio or parameter, not both")
        if speed_ratio is not None:
            x, target = self.speeds / self.reference_speed, float(speed_ratio)
        elif parameter is not None:
            x, target = np.asarray(self.branch.lam, dtype=float), float(parameter)
        else:
            if self.max_multiplier is not None:
                return int(np.argmax(self.max_multiplier))
            if self.multipliers is None:
                raise ValueError("no multipliers: run the response with stability enabled")
            return int(np.argmax(np.abs(self.multipliers).max(axis=-1)))
        return int(np.argmin(np.abs(x - target)))

    def plot_multipliers(self, index: int | None = None, speed_ratio: float | None = None,
                         parameter: float | None = None) -> Figure:
        """The multipliers of one point against the unit circle
        (:func:`rotorsfd.plots.response.plot_multipliers`): point ``index``, or the one
        chosen by :meth:`point_index`."""
        # deferred: plots.response (loads matplotlib)
        from rotorsfd.plots.response import plot_multipliers

        if index is not None and (speed_ratio is not None or parameter is not None):
            raise ValueError("give index, speed_ratio or parameter, not several")
        i = (range(self.branch.n_points)[index] if index is not None
             else self.point_index(speed_ratio, parameter))
        mu = self.point_multipliers(i)
        ratio = self.speeds[i] / self.reference_speed
        where = (f"Omega~ = {ratio:.5g} (point {i})" if self.is_speed else
                 f"{self.parameter} = {self.branch.lam[i]:.5g} {self.parameter_units}, "
                 f"Omega~ = {ratio:.4g} (point {i})")
        mm = None if self.max_multiplier is None else float(self.max_multiplier[i])
        st = None if self.stable is None else bool(self.stable[i])
        return plot_multipliers(mu, where=where, max_multiplier=mm, stable=st,
                                title=self.title)

    # ---- plots and text -------------------------------------------------------------------
    def plot(self, multipliers_at: float | None = None) -> dict[str, Figure]:
        """Frequency-response figures by file name (:mod:`rotorsfd.plots.response`) and,
        when the multipliers are known, ``multipliers.png`` at the point nearest
        ``multipliers_at`` (see :meth:`write`)."""
        figures = self.response_figures()
        if self.multipliers is not None and self.branch.n_points:
            at = ({} if multipliers_at is None else {"speed_ratio": multipliers_at}
                  if self.is_speed else {"parameter": multipliers_at})
            figures["multipliers.png"] = self.plot_multipliers(**at)
        return figures

    def response_figures(self) -> dict[str, Figure]:
        """The frequency-response figures by file name (:mod:`rotorsfd.plots.response`)."""
        # deferred: plots.response (loads matplotlib)
        from rotorsfd.plots.response import response_figures

        x_name = "speed_ratio" if self.is_speed else self.parameter_column
        x_label = (r"$\tilde\Omega = \Omega / \Omega_{ref}$" if self.is_speed
                   else f"{self.parameter} [{self.parameter_units}]")
        return response_figures(self.table(), x_name=x_name, x_label=x_label,
                                nodes=self.nodes, directions=self.directions,
                                H=self.branch.H, clearance=self.clearance,
                                bifurcations=self.bifurcations, title=self.title,
                                node_labels={n: node_words(self.node_names, n)
                                             for n in self.nodes})

    def _bifurcation_line(self, row: Mapping[str, Any]) -> str:
        """One summary line: type, where, the critical multiplier at the located point and
        at the nearest computed point, and the check."""
        where = (f"Omega~ = {row['speed_ratio']:.6f}" if self.is_speed
                 else f"{self.parameter} = {row['parameter']:.6g}")
        text = f"{row['type']} at {where}"
        if "located_multiplier_re" in row:
            im = row["located_multiplier_im"]
            text += (f": critical multiplier {row['located_multiplier_re']:+.5f}"
                     + (f"{im:+.5f}i" if abs(im) > 0 else "") + " at the located point, "
                     f"|mu| = {row['nearest_multiplier_abs']:.5f} at the nearest point")
        else:
            text += f": |mu| = {row['max_multiplier']:.5f} at the nearest point"
        status = row.get("status")
        if status == "confirmed":
            text += (f"; confirmed at H = {row['check_harmonics']}, M = "
                     f"{row['check_intervals']} (moves {row['check_shift']:.1e})")
        elif status == "unconfirmed":
            moved = row.get("check_shift")
            text += (f"; UNCONFIRMED at H = {row['check_harmonics']}, M = "
                     f"{row['check_intervals']}: " + ("it vanishes (a truncation artefact)"
                                                      if moved == "" else
                                                      f"it moves {moved:.1e} (relative)"))
        return text

    def harmonics_text(self) -> str:
        """``"H=3"``, or ``"H=1..15 (auto)"``, with the largest truncation estimate."""
        b = self.branch
        Hs = b.info.get("harmonics")
        if Hs is None or not np.size(Hs):
            return f"H={b.H}"
        lo, hi = int(np.min(Hs)), int(np.max(Hs))
        text = f"H={lo}" if lo == hi else f"H={lo}..{hi}"
        if b.info.get("adaptive_harmonics"):
            text += " (auto)"
        te = np.asarray(b.info.get("truncation_error", []), dtype=float)
        if te.size and np.all(np.isfinite(te)):
            text += f", truncation error <= {te.max():.1e} C"
        return text

    def summary(self) -> str:
        """A few lines: the branch, the peak deflection per node, the outcome."""
        b = self.branch
        lo, hi = float(b.lam.min()), float(b.lam.max())
        unit = self.parameter_units
        lines = [f"{b.n_points} points, {self.parameter} from {lo:.6g} to {hi:.6g} {unit}, "
                 f"{self.harmonics_text()}, N_f={b.n_samples}, {len(b.folds())} folds, "
                 f"{self.elapsed:.2f} s"]
        x = self.speeds / self.reference_speed if self.is_speed else b.lam
        x_name = "Omega~" if self.is_speed else self.parameter
        names = self.node_names
        for n in self.nodes:
            r = self.deflection(n)
            i = int(np.argmax(r))
            lines.append(f"{node_words(names, n)}: max r~ = {r[i]:.4g} at {x_name} = {x[i]:.5g}")
        if "orbit_difference" in self.info:
            lines.append(f"from the orbit {self.info['from_orbit']} at Omega~ = "
                         f"{self.info['orbit_speed'] / self.reference_speed:.6g}: HB orbit "
                         f"within {self.info['orbit_difference']:.2g} C of it over the "
                         "period; " + ("the branch closes on itself (an isola)"
                                       if self.info["closed"] else "not a closed loop"))
        if self.stable is not None:
            lines.append(f"unstable points: {int(np.sum(~self.stable))} of {b.n_points}")
        for row in self.bifurcations or ():
            lines.append(self._bifurcation_line(row))
        ended = self.ended
        lines.append({"range": "ok: ", "limit": "ended at a validity limit: ",
                      "stopped": "stopped: "}.get(ended, "FAILED: ") + self.message)
        return "\n".join(lines)
