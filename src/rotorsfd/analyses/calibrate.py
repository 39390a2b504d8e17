"""Calibration: config fields fitted to quantities the tool computes (``rotorsfd calibrate``).

Unknowns ``p_j`` are config fields at dotted paths (any scalar physical quantity, e.g.
``elements.sfd.centring_stiffness``, ``rotor.supports[0].stiffness``,
``rotor.damping.ratio``), each within bounds ``[lo_j, hi_j]`` (default ``[p0/100,
100 p0]`` for a positive start value ``p0``). Targets ``t_i`` with scales ``s_i`` (the
tolerance given, else ``|t_i|``) give the weighted residuals::

    r_i(p) = (f_i(p) - t_i) / s_i,      min_p  sum_i r_i^2      (lo <= p <= hi)

solved by ``scipy.optimize.least_squares`` (trust-region reflective, ``x_scale`` = the
start values). ``f_i``: ``critical_speed[k]`` (k-th lowest critical speed of
``analysis.modal.whirl``; exact derivative from the eigenproblem), ``fold_speed[k|lower|
upper]`` (located saddle-nodes of the ``[analysis.response]`` branch, ascending),
``bifurcation_speed[k|TYPE]`` and ``peak_amplitude[NODE]`` (central finite differences on
rebuilt configs; a fold speed's derivative in a registered continuation parameter --
unbalance, base rates, film fields -- exact, from the fold-augmented system); see
:mod:`rotorsfd.analyses.calibrate_targets` and :mod:`~rotorsfd.analyses.calibrate_model`.

Uncertainty: with ``J = dr/dp`` at the optimum, ``cov = (J^T J)^-1 sigma^2`` where
``sigma^2 = 1`` when every target has a tolerance (the tolerances taken as one standard
deviation), else ``sum r^2 / (m - n)`` (m targets, n fields; not estimated when m = n).
More fields than targets: the problem is underdetermined and refused (ConfigError, one
line) -- no regularisation is applied.

Entry path: a calibration is of a configuration (its unknowns are config fields), so
``run_calibration(config, ...)`` is its only one; every evaluation builds the system of
the config at ``p`` with the one builder (``linear_system(config_at(p))``, the modal
view) and runs the response targets on ``run_response(config_at(p))``, the same code as
``rotorsfd modal`` and ``rotorsfd response``.
"""

from __future__ import annotations

import datetime
import re
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.io import atomic
from rotorsfd.io.units import UnitError, to_si

__all__ = ["CalibrationResult", "FitField", "Target", "parse_fit", "parse_target",
           "run_calibration"]

TARGET_KINDS = {"critical_speed": "angular_velocity", "fold_speed": "angular_velocity",
                "bifurcation_speed": "angular_velocity", "peak_amplitude": "length"}


@dataclass(frozen=True)
class FitField:
    """A config field to fit: dotted ``path``, its ``kind``, start value and bounds (SI)."""

    path: str
    kind: str
    start: float
    lower: float
    upper: float


@dataclass(frozen=True)
class Target:
    """A target quantity ``kind[selector] = value`` (SI) with an optional tolerance."""

    kind: str
    selector: str
    value: float
    tolerance: float | None = None

    @property
    def name(self) -> str:
        return f"{self.kind}[{self.selector}]"

    @property
    def scale(self) -> float:
        return self.tolerance if self.tolerance is not None else abs(self.value) or 1.0


def parse_fit(config: Any, text: str) -> FitField:
    """``PATH`` or ``PATH=LO:HI`` (values with units allowed) -> FitField."""
    # deferred: io.config, io.schema (loads scipy, pydantic)
    from rotorsfd.io.config import get_path, with_values
    from rotorsfd.io.schema import resolve_kind

    path, sep, rng = text.partition("=")
    path = path.strip()
    try:
        kind = resolve_kind(config, path)
    except KeyError as exc:
        raise ConfigError("--fit", text, exc.args[0]) from None
    start = get_path(config, path)
    start = float(start) if isinstance(start, int | float) else 0.0
    if sep:
        lo_text, colon, hi_text = rng.partition(":")
        if not colon:
            raise ConfigError("--fit", text, "expected PATH=LO:HI, e.g. "
                              "rotor.supports[0].stiffness=1e6:1e8")
        try:
            lower, upper = to_si(lo_text.strip(), kind), to_si(hi_text.strip(), kind)
        except UnitError as exc:
            raise ConfigError("--fit", text, str(exc)) from None
    elif start > 0.0:
        lower, upper = start / 100.0, start * 100.0
    else:
        raise ConfigError("--fit", text, f"{path} starts at {start:g}: give bounds, "
                          "PATH=LO:HI")
    if not lower < upper:
        raise ConfigError("--fit", text, "the lower bound must be below the upper")
    if not lower <= start <= upper:
        start = lower + 0.5 * (upper - lower) if start == 0.0 or lower <= 0.0 else \
            float(np.sqrt(lower * upper))
    try:    # the config must accept a value there (e.g. a damping ratio needs kind "modal")
        with_values(config, {path: start})
    except ConfigError as exc:
        raise ConfigError("--fit", text, f"the config does not accept a value there: "
                          f"{exc}") from None
    return FitField(path, kind, start, lower, upper)


TARGET_RE = re.compile(r"^\s*([a-z_]+)\[([^\]]+)\]\s*=\s*(.+?)\s*$")


def parse_target(text: str) -> Target:
    """``KIND[SEL]=VALUE`` or ``KIND[SEL]=VALUE+-TOL`` (units allowed) -> Target."""
    m = TARGET_RE.match(text)
    if m is None:
        raise ConfigError("--target", text, "expected KIND[SELECTOR]=VALUE[+-TOL], e.g. "
                          "critical_speed[1]=811.3 or fold_speed[upper]='1040 rad/s'")
    kind, sel, rest = m.groups()
    if kind not in TARGET_KINDS:
        raise ConfigError("--target", text, "kind must be one of " + ", ".join(TARGET_KINDS))
    sel = sel.strip()
    if kind in ("critical_speed", "peak_amplitude") and not sel.isdigit():
        raise ConfigError("--target", text, f"{kind}[N] needs a positive integer N")
    if kind == "critical_speed" and int(sel) < 1:
        raise ConfigError("--target", text, "critical speeds are numbered from 1")
    if kind == "fold_speed" and not (sel.isdigit() or sel in ("lower", "upper")):
        raise ConfigError("--target", text, "fold_speed[N], fold_speed[lower] or "
                          "fold_speed[upper]")
    value_text, pm, tol_text = rest.replace("±", "+-").partition("+-")
    try:
        value = to_si(value_text.strip().strip("'\""), TARGET_KINDS[kind])
        tol = to_si(tol_text.strip().strip("'\""), TARGET_KINDS[kind]) if pm else None
    except UnitError as exc:
        raise ConfigError("--target", text, str(exc)) from None
    if tol is not None and not tol > 0.0:
        raise ConfigError("--target", text, "the tolerance must be positive")
    return Target(kind, sel, value, tol)


def check_problem(fields: Sequence[FitField], targets: Sequence[Target]) -> None:
    """ConfigError unless there are targets, distinct fields and no more fields than
    targets (an underdetermined fit is refused, not regularised)."""
    if not fields or not targets:
        raise ConfigError("--fit/--target", f"{len(fields)} fields, {len(targets)} targets",
                          "give at least one --fit and one --target")
    if len(fields) > len(targets):
        raise ConfigError("--fit", f"{len(fields)} fields",
                          f"more fields than targets ({len(targets)}): the fit is "
                          "underdetermined; fit at most as many fields as targets")
    paths = [f.path for f in fields]
    if len(set(paths)) != len(paths):
        raise ConfigError("--fit", ", ".join(paths), "each field at most once")


@dataclass
class CalibrationResult:
    """The fitted fields, the targets' residuals, the Jacobian and the covariance."""

    fields: list[FitField]
    targets: list[Target]
    values: np.ndarray            # fitted p [SI]
    computed: np.ndarray          # f_i(p)
    jacobian: np.ndarray          # df_i / dp_j (unweighted)
    derivative_kinds: list[str]   # per target: EXACT or FINITE
    covariance: np.ndarray | None
    covariance_basis: str
    config: Any                   # the fitted Config
    message: str
    n_evaluations: int
    success: bool = True
    created: str = field(default_factory=lambda: datetime.datetime.now(
        datetime.UTC).strftime("%Y-%m-%d %H:%M:%S UTC"))

    @property
    def residuals(self) -> np.ndarray:
        return self.computed - np.array([t.value for t in self.targets])

    @property
    def standard_errors(self) -> np.ndarray | None:
        if self.covariance is None:
            return None
        return np.sqrt(np.clip(np.diag(self.covariance), 0.0, None))

    def header(self) -> str:
        """The comment lines at the top of the fitted config."""
        lines = [f"# rotorsfd calibrate, {self.created}: fitted "
                 + ", ".join(f.path for f in self.fields) + " to "
                 + ", ".join(f"{t.name} = {t.value:.8g}" for t in self.targets) + " (SI)"]
        for f, v in zip(self.fields, self.values, strict=True):
            lines.append(f"#   {f.path} = {v:.10g} (start {f.start:.6g}, bounds "
                         f"[{f.lower:.6g}, {f.upper:.6g}])")
        for t, c in zip(self.targets, self.computed, strict=True):
            lines.append(f"#   {t.name}: {c:.10g} (target {t.value:.10g}, residual "
                         f"{c - t.value:+.3e})")
        lines.append(f"#   {self.message}")
        return "\n".join(lines)

    def to_dict(self) -> dict[str, Any]:
        """The contents of ``calibration.json`` (no NaN: missing estimates are null)."""
        se = self.standard_errors
        cov = self.covariance
        return {
            "created": self.created, "message": self.message, "success": self.success,
            "n_evaluations": self.n_evaluations,
            "fields": [{"path": f.path, "kind": f.kind, "start": f.start, "lower": f.lower,
                        "upper": f.upper, "value": float(v),
                        "standard_error": None if se is None else float(se[j])}
                       for j, (f, v) in enumerate(zip(self.fields, self.values,
                                                      strict=True))],
            "targets": [{"name": t.name, "target": t.value, "tolerance": t.tolerance,
                         "computed": float(c), "residual": float(c - t.value),
                         "relative_residual": float((c - t.value) / t.value)
                         if t.value else None,
                         "derivative": d, "sensitivities": [float(x) for x in row]}
                        for t, c, d, row in zip(self.targets, self.computed,
                                                self.derivative_kinds, self.jacobian,
                                                strict=True)],
            "jacobian": [[float(x) for x in row] for row in self.jacobian],
            "covariance": None if cov is None else [[float(x) for x in r] for r in cov],
            "covariance_basis": self.covariance_basis}

    def summary(self) -> str:
        """The printed table (:meth:`table`)."""
        return self.table()

    def table(self) -> str:
        """The printed table: targets (computed, residual, derivative) and fields (value,
        standard error, sensitivities)."""
        lines = [f"{'target':24s} {'computed':>14s} {'target':>14s} {'residual':>11s}  "
                 "derivative"]
        for t, c, d in zip(self.targets, self.computed, self.derivative_kinds, strict=True):
            lines.append(f"{t.name:24s} {c:14.8g} {t.value:14.8g} {c - t.value:+11.3e}  {d}")
        se = self.standard_errors
        lines.append(f"{'field':36s} {'value':>14s} {'std error':>11s}  d target / d field")
        for j, (f, v) in enumerate(zip(self.fields, self.values, strict=True)):
            err = "-" if se is None else f"{se[j]:.3e}"
            sens = ", ".join(f"{x:.4e}" for x in self.jacobian[:, j])
            lines.append(f"{f.path:36s} {v:14.8g} {err:>11s}  [{sens}]")
        lines.append(f"uncertainty: {self.covariance_basis}")
        lines.append(self.message)
        return "\n".join(lines)

    def to_dataset(self) -> Any:
        """The fit as a Dataset: fitted ``value`` and ``standard_error`` over ``field``,
        ``computed``, ``target`` and ``residual`` over ``target``, the ``jacobian``
        (target, field) and the ``covariance`` (field, field; NaN where not estimated,
        the files write null)."""
        import xarray as xr  # deferred: xarray

        nf = len(self.fields)
        se = self.standard_errors
        cov = self.covariance if self.covariance is not None else np.full((nf, nf), np.nan)
        return xr.Dataset(
            {"value": ("field", self.values), "start": ("field", [f.start for f in self.fields]),
             "standard_error": ("field", np.full(nf, np.nan) if se is None else se),
             "computed": ("target", self.computed),
             "target_value": ("target", [t.value for t in self.targets]),
             "residual": ("target", self.residuals),
             "derivative": ("target", list(self.derivative_kinds)),
             "jacobian": (("target", "field"), self.jacobian),
             "covariance": (("field", "field_2"), cov)},
            coords={"field": [f.path for f in self.fields],
                    "field_2": [f.path for f in self.fields],
                    "target": [t.name for t in self.targets]},
            attrs={"message": self.message, "success": int(self.success),
                   "covariance_basis": self.covariance_basis, "created": self.created})

    def plot(self) -> dict[str, Any]:
        """No figures: the fit is a table (:meth:`summary`, ``calibration.json``)."""
        return {}

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """``calibration.json`` and ``calibrated.toml`` (the fitted config, resolved, SI,
        with :meth:`header`), atomically (``plots``: the protocol's flag; the fit draws
        nothing)."""
        # deferred: io.config (loads scipy, pydantic)
        from rotorsfd.io.config import dump_config, to_toml

        out = Path(directory)
        paths = {"calibration.json": out / "calibration.json",
                 "calibrated.toml": out / "calibrated.toml"}
        atomic.write_json(paths["calibration.json"], self.to_dict())
        atomic.write_text(paths["calibrated.toml"],
                          self.header() + "\n" + to_toml(dump_config(self.config)))
        return paths


def covariance(jac_w: np.ndarray, r_w: np.ndarray, targets: Sequence[Target]
               ) -> tuple[np.ndarray | None, str]:
    """(J^T J)^-1 sigma^2 of the weighted Jacobian (module docstring) and how it was
    scaled; None where it cannot be estimated."""
    m, n = jac_w.shape
    if all(t.tolerance is not None for t in targets):
        sigma2, basis = 1.0, "(J^T J)^-1 with the target tolerances as standard deviations"
    elif m > n:
        sigma2 = float(r_w @ r_w) / (m - n)
        basis = (f"(J^T J)^-1 scaled by the residual variance {sigma2:.3e} "
                 f"({m - n} degrees of freedom)")
    else:
        return None, ("not estimated: as many targets as fields and no tolerances (give "
                      "VALUE+-TOL to every target)")
    jtj = jac_w.T @ jac_w
    if np.linalg.cond(jtj) > 1e14:
        return None, "not estimated: J^T J is singular (a field the targets do not see)"
    return np.linalg.inv(jtj) * sigma2 * 1.0, basis


def run_calibration(config: Any, fields: Sequence[FitField], targets: Sequence[Target],
                    search_path: Path | None = None, max_nfev: int = 100
                    ) -> CalibrationResult:
    """Fit ``fields`` of ``config`` to ``targets`` (module docstring)."""
    # deferred: scipy.optimize, analyses.calibrate_model (loads numba, scipy, pydantic)
    from scipy.optimize import least_squares

    from rotorsfd.analyses.calibrate_model import TargetModel

    check_problem(fields, targets)
    model = TargetModel(config, fields, targets, search_path)
    scale = np.array([t.scale for t in targets])
    goal = np.array([t.value for t in targets])
    start = np.array([f.start for f in fields])
    lower = np.array([f.lower for f in fields])
    upper = np.array([f.upper for f in fields])
    x_scale = np.where(start != 0.0, np.abs(start), upper - lower)

    def residual(p: np.ndarray) -> np.ndarray:
        return (model.values(p) - goal) / scale

    def jac(p: np.ndarray) -> np.ndarray:
        return model.jacobian(p) / scale[:, None]

    sol = least_squares(residual, start, jac=jac, bounds=(lower, upper), x_scale=x_scale,
                        method="trf", xtol=1e-13, ftol=1e-13, gtol=1e-13,
                        max_nfev=max_nfev)
    p = sol.x
    computed = model.values(p)
    jac_full = model.jacobian(p)
    r_w = (computed - goal) / scale
    cov_w, basis = covariance(jac_full / scale[:, None], r_w, targets)
    return CalibrationResult(list(fields), list(targets), p, computed, jac_full,
                             model.derivative_kinds(), cov_w, basis,
                             model.config_at(p),
                             f"{sol.message} ({sol.nfev} residual and {sol.njev} Jacobian "
                             "evaluations)", int(sol.nfev), bool(sol.status > 0))
