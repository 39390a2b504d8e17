"""The attractors of a census (:mod:`~rotorsfd.analyses.attractors`): grouping of the
starts, the HB correction of each periodic attractor, the table and its files.

Grouping. Two period-n outcomes are one attractor when their point sets match whatever
the phase: every Poincare point of one lies within ``cluster_tol`` (inf-norm, in length
scales) of a point of the other and back. Quasi-periodic and chaotic outcomes are one
attractor when their point clouds are within ``CLOUD_FACTOR * cluster_tol`` of each
other in the same (symmetric Hausdorff) sense; contact and failed starts form one group
each. The basin fraction of an attractor is ``p = k / N`` of the N starts with its
binomial standard error ``sqrt(p (1 - p) / N)``.

HB correction (period-n orbits). The last n recorded periods of the representative start
are fitted in harmonics of ``Omega / n`` (``n H`` of them, ``2 n H`` if Newton fails there,
:func:`~rotorsfd.analyses.orbit_branch.fit_samples`) and Newton solves the HB equations
of the same system written with that fundamental
(:func:`~rotorsfd.harmonic.branch_switching.period_n`: forcing
harmonic k moved to k n) from there; reported: the scaled residual norm, the largest
difference over the orbit between the HB and the time-domain orbit (length scales) and
the Floquet multiplier of largest modulus over ``n T``
(:class:`~rotorsfd.stability.floquet_evaluator.FloquetEvaluator`).
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import asdict, dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConvergenceError, ElementDomainError
from rotorsfd.io.atomic import save_figures, write_csv, write_json

CLOUD_FACTOR = 5.0


def set_distance(A: np.ndarray, B: np.ndarray) -> float:
    """Symmetric Hausdorff distance (inf-norm) of two point sets ``(n, d)``."""
    if A.size == 0 or B.size == 0:
        return float("inf")
    D = np.max(np.abs(A[:, None, :] - B[None, :, :]), axis=2)
    return float(max(D.min(axis=1).max(), D.min(axis=0).max()))


@dataclass
class Attractor:
    """One attractor: its class, period, the starts that reached it, a representative
    (the first of them), its Poincare points (length scales), the largest validity
    measure per element over the starts, and the HB correction (periodic ones)."""

    motion: str
    period: int | None
    members: list[int]
    points: np.ndarray
    eccentricity: dict[str, float] = field(default_factory=dict)
    hb: dict[str, Any] = field(default_factory=dict)

    @property
    def representative(self) -> int:
        return self.members[0]


def _same(a: Attractor, motion: str, period: int | None, P: np.ndarray, tol: float
          ) -> bool:
    if a.motion != motion or a.period != period:
        return False
    if motion in ("contact", "failed"):
        return True
    limit = tol if period is not None else CLOUD_FACTOR * tol
    return set_distance(a.points, P) <= limit


def hb_correction(model: Any, outcome: Any, harmonics: int) -> dict[str, Any]:
    """HB solution through a settled period-n outcome (module docstring): residual,
    orbit difference, largest multiplier and stability; ``{"hb_note": why}`` if none."""
    # deferred: these (loads numba, scipy, pydantic)
    from rotorsfd.analyses.orbit_branch import fit_samples
    from rotorsfd.harmonic.branch_switching import period_n  # deferred: as these
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.stability.floquet_evaluator import FloquetEvaluator

    n = outcome.period
    if model.problem is None or n is None or outcome.t.size == 0:
        return {"hb_note": "no HB problem or no recorded period"}
    problem = period_n(model.problem, n)
    nl = model.nl_dofs
    samples = {int(d): outcome.q[:, j] for j, d in enumerate(nl)}
    note = ""
    for Hn in (harmonics * n, 2 * harmonics * n):        # H, then 2H if Newton fails
        try:
            fit = fit_samples(outcome.t, samples, model.speed / n, Hn, problem.n_dof,
                              float(model.scale[0]), "census")
            X0 = np.zeros((Hn + 1, problem.n_dof), dtype=complex)
            X0[:, nl] = fit.X[:, nl]
            sol = solve_periodic(problem, model.speed, Hn, X0, condensed=True)
            fl = FloquetEvaluator(problem)(model.speed, sol.X)
            break
        except (ConvergenceError, ElementDomainError, np.linalg.LinAlgError) as exc:
            note = f"H={Hn}: " + " ".join(str(exc).split())[:200]
    else:
        return {"hb_note": note}
    return {"hb_residual": float(sol.residual_norm),
            "hb_orbit_difference": fit.difference(sol.X),
            "hb_max_multiplier": fl.max_abs, "hb_stable": bool(fl.stable),
            "hb_harmonics": Hn, "hb_X": sol.X}


def group(model: Any, outcomes: list[Any], coords: np.ndarray, options: Any
          ) -> list[Attractor]:
    """Attractors of the outcomes (module docstring), largest basin first, each periodic
    one HB-corrected."""
    found: list[Attractor] = []
    for r in outcomes:
        for a in found:
            if _same(a, r.motion, r.period, r.points, options.cluster_tol):
                a.members.append(r.index)
                for k, e in r.eccentricity.items():
                    a.eccentricity[k] = max(a.eccentricity.get(k, 0.0), e)
                break
        else:
            found.append(Attractor(r.motion, r.period, [r.index], r.points,
                                   dict(r.eccentricity)))
    found.sort(key=lambda a: -len(a.members))
    by_index = {r.index: r for r in outcomes}
    for a in found:
        if a.period is not None:
            a.hb = hb_correction(model, by_index[a.representative], options.harmonics)
    return found


def _text(x: Any) -> Any:
    return "" if x is None else x


@dataclass
class AttractorCensus:
    """A census at one speed: the starts' coordinates ``(N, 2 m)`` (``q_i / c_i``,
    ``v_i / (c_i Omega)``; a last column: the phase of the HB orbit the other DOFs start
    on, with ``around = "orbit"``), their outcomes and the attractors."""

    speed: float
    reference_speed: float | None
    options: Any
    coords: np.ndarray
    outcomes: list[Any]
    attractors: list[Attractor]
    elapsed_integration: float
    elapsed_hb: float

    @property
    def n_starts(self) -> int:
        return len(self.outcomes)

    @property
    def speed_ratio(self) -> float | None:
        return self.speed / self.reference_speed if self.reference_speed else None

    def fraction(self, a: Attractor) -> tuple[float, float]:
        """Basin fraction ``k / N`` and its binomial standard error."""
        p = len(a.members) / self.n_starts
        return p, float(np.sqrt(p * (1 - p) / self.n_starts))

    def labels(self) -> np.ndarray:
        """Attractor number (from 0) of every start."""
        out = np.zeros(self.n_starts, dtype=int)
        for i, a in enumerate(self.attractors):
            out[a.members] = i
        return out

    def rows(self, elements: list[str] | None = None) -> list[dict[str, Any]]:
        """One dict per attractor: the attractors.csv columns."""
        m = self.coords.shape[1] // 2
        names = elements or sorted({k for a in self.attractors for k in a.eccentricity})
        rows = []
        for i, a in enumerate(self.attractors):
            p, se = self.fraction(a)
            c = self.coords[a.representative]
            row: dict[str, Any] = {
                "speed_rad_s": self.speed, "speed_ratio": _text(self.speed_ratio),
                "attractor": i, "motion": a.motion, "period": _text(a.period),
                "starts": len(a.members), "basin_fraction": p, "basin_se": se,
                "start_index": a.representative}
            row.update({f"start_q{j + 1}": c[j] for j in range(m)})
            row.update({f"start_v{j + 1}": c[m + j] for j in range(m)})
            if c.size > 2 * m:
                row["start_orbit_phase"] = c[2 * m]
            row["poincare_points"] = "; ".join(" ".join(f"{x:.5g}" for x in pt)
                                               for pt in a.points[:16])
            row["periods_run_median"] = float(np.median(
                [self.outcomes[k].periods_run for k in a.members]))
            row.update({f"eps_max_{k}": _text(a.eccentricity.get(k)) for k in names})
            for key in ("step_check", "hb_residual", "hb_orbit_difference", "hb_max_multiplier",
                        "hb_stable", "hb_note"):
                row[key] = _text(a.hb.get(key))
            rows.append(row)
        return rows

    def summary_dict(self) -> dict[str, Any]:
        """summary.json's content."""
        return {"speed_rad_s": self.speed, "speed_ratio": self.speed_ratio,
                "reference_speed_rad_s": self.reference_speed,
                "settings": asdict(self.options), "n_starts": self.n_starts,
                "n_attractors": len(self.attractors),
                "elapsed_integration_s": self.elapsed_integration,
                "elapsed_hb_s": self.elapsed_hb,
                "periods_run_total": int(sum(r.periods_run for r in self.outcomes)),
                "attractors": self.rows()}

    def summary(self) -> str:
        """A few lines for the terminal."""
        head = (f"{self.n_starts} starts at {self.speed:.6g} rad/s"
                + (f" (speed ratio {self.speed_ratio:.5g})" if self.speed_ratio else "")
                + f": {len(self.attractors)} attractor(s), "
                  f"{self.elapsed_integration:.1f} s of integration")
        lines = [head]
        for i, a in enumerate(self.attractors):
            p, se = self.fraction(a)
            pt = " ".join(f"{x:+.3f}" for x in a.points[0]) if a.points.size else ""
            hb = ""
            if "hb_max_multiplier" in a.hb:
                hb = (f", HB |mu|max {a.hb['hb_max_multiplier']:.4f} "
                      f"({'stable' if a.hb['hb_stable'] else 'unstable'})")
            lines.append(f"  {i}: {a.motion}, basin {p:.3f} +- {se:.3f}, Poincare point "
                         f"({pt}){hb}")
        return "\n".join(lines)


#: what the two axes of basins.png are, unless the caller says
DEFAULT_COORDINATES = ["initial displacement of the element's first DOF (y) / clearance",
                       "initial displacement of its second DOF (z) / clearance"]


@dataclass
class CensusResult(Sequence):
    """The censuses of ``rotorsfd attractors`` (one per speed, a sequence of
    :class:`AttractorCensus`) on the result protocol: ``coordinate_names`` the two axes
    of the basin plot, ``title`` the run's."""

    censuses: list[AttractorCensus]
    coordinate_names: list[str] | None = None
    title: str = ""

    def __getitem__(self, i: Any) -> Any:
        return self.censuses[i]

    def __len__(self) -> int:
        return len(self.censuses)

    def summary(self) -> str:
        """Each census's lines."""
        return "\n".join(c.summary() for c in self.censuses)

    def summary_dict(self) -> dict[str, Any]:
        """summary.json's content."""
        return {"title": self.title, "censuses": [c.summary_dict() for c in self.censuses]}

    def plot(self) -> dict[str, Any]:
        """``basins.png``: the first census's starts coloured by attractor
        (:func:`rotorsfd.plots.basins.basin_figure`)."""
        from rotorsfd.plots.basins import basin_figure  # deferred: matplotlib

        if not self.censuses:
            return {}
        return {"basins.png": basin_figure(self.censuses[0],
                                           self.coordinate_names or DEFAULT_COORDINATES,
                                           self.title)}

    def to_dataset(self) -> Any:
        """Every start (dimension ``start``: its speed, coordinates, motion, attractor
        number and periods run) and every attractor (dimension ``attractor``: speed,
        motion, period (0: not periodic), basin fraction and its standard error)."""
        import xarray as xr  # deferred: xarray

        starts = [(c, r) for c in self.censuses for r in c.outcomes]
        labels = {id(c): c.labels() for c in self.censuses}
        atts = [(c, a) for c in self.censuses for a in c.attractors]
        width = max((c.coords.shape[1] for c in self.censuses), default=0)
        return xr.Dataset(
            {"start_speed": ("start", [c.speed for c, _ in starts], {"units": "rad/s"}),
             "start_coords": (("start", "coordinate"),
                              np.array([c.coords[r.index] for c, r in starts]).reshape(
                                  len(starts), width),
                              {"long_name": "q_i / c_i, v_i / (c_i Omega) of the start"}),
             "start_motion": ("start", [r.motion for _, r in starts]),
             "start_attractor": ("start", np.array([labels[id(c)][r.index]
                                                    for c, r in starts], dtype=np.int32)),
             "start_periods_run": ("start", np.array([r.periods_run for _, r in starts],
                                                     dtype=np.int32)),
             "attractor_speed": ("attractor", [c.speed for c, _ in atts],
                                 {"units": "rad/s"}),
             "attractor_motion": ("attractor", [a.motion for _, a in atts]),
             "attractor_period": ("attractor", np.array([a.period or 0 for _, a in atts],
                                                        dtype=np.int32)),
             "basin_fraction": ("attractor", [c.fraction(a)[0] for c, a in atts]),
             "basin_se": ("attractor", [c.fraction(a)[1] for c, a in atts])},
            attrs={"title": self.title})

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """attractors.csv (every census, a speed column), starts.csv, summary.json and
        (``plots``) basins.png (the first census) in ``directory``."""
        censuses = self.censuses
        out = Path(directory)
        out.mkdir(parents=True, exist_ok=True)
        names = sorted({k for c in censuses for a in c.attractors for k in a.eccentricity})
        rows = [r for c in censuses for r in c.rows(names)]
        header = list(rows[0]) if rows else ["speed_rad_s"]
        paths = {"attractors.csv": write_csv(out / "attractors.csv", header,
                                             [[r.get(h, "") for h in header]
                                              for r in rows])}
        start_rows = []
        for c in censuses:
            lab = c.labels()
            for r in c.outcomes:
                start_rows.append([c.speed, r.index, *c.coords[r.index], r.motion,
                                   int(lab[r.index]), r.periods_run])
        m = censuses[0].coords.shape[1] // 2
        cols = [f"q{j + 1}" for j in range(m)] + [f"v{j + 1}" for j in range(m)]
        cols += ["orbit_phase"] * (censuses[0].coords.shape[1] - 2 * m)
        paths["starts.csv"] = write_csv(out / "starts.csv",
                                        ["speed_rad_s", "start", *cols, "motion",
                                         "attractor", "periods_run"], start_rows)
        paths["summary.json"] = write_json(out / "summary.json", self.summary_dict())
        if plots:
            paths.update(save_figures(self.plot(), out))
        return paths


def write_census(censuses: Sequence[AttractorCensus], folder: str | Path,
                 coordinate_names: list[str] | None = None, title: str = "",
                 plots: bool = True) -> dict[str, Path]:
    """:meth:`CensusResult.write` of ``censuses``."""
    return CensusResult(list(censuses), coordinate_names, title).write(folder, plots)
