"""The branches of a census' periodic attractors: each period-1 attractor's HB-corrected
orbit continued both ways in the rotor speed (the ``--from-orbit`` algorithm,
:func:`~rotorsfd.harmonic.orbit_branch.continue_both_ways`: it stops when the branch
closes on itself, an isola), with its Floquet stability.

Attractors on one branch (two stable parts of an S-curve between its folds) are traced
once (:func:`~rotorsfd.harmonic.orbit_branch.on_branch`): the branch of attractor ``i``
is crossed at the census speed ``Omega_c`` between points ``j, j + 1``
(``lam_j <= Omega_c <= lam_{j+1}`` or reverse); there the HB equations are solved at
``Omega_c`` from the coefficients interpolated linearly in lam, and the solution compared
with attractor ``k``'s on the nonlinear DOFs, ``max |X_i(Omega_c) - X_k| / c <``
:data:`~rotorsfd.harmonic.orbit_branch.SAME_TOL` on the length scales ``c``: then ``k`` is
``on_branch_of`` ``i``. Over several census speeds (``--speed-ratio A --to B --stride S``)
each branch is traced once too: an attractor at a later speed that lies on a branch
traced at an earlier one (the same test at its own speed, the same H) takes that branch,
its stability and its note (``info["traced_at"]``: the census speed it was traced from)
instead of tracing it again (:func:`trace_census_branches`). Period-n attractors (n > 1)
are not traced (the branch of a period-n orbit in the speed needs the subharmonic
problem's continuation: not yet).
"""

from __future__ import annotations

import dataclasses
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.analyses.attractors_result import AttractorCensus
from rotorsfd.continuation.branch import Branch
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.harmonic.orbit_branch import continue_both_ways, on_branch
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.io.atomic import save_figures, write_csv

__all__ = ["AttractorBranch", "AttractorBranches", "run_attractor_branches",
           "trace_attractor_branches", "trace_census_branches"]


@dataclass
class AttractorBranch:
    """The branch of census attractor ``attractor`` (None and ``note`` if not traced),
    ``closed`` an isola, ``stable`` per point (None: stability off), ``on_branch_of`` the
    attractor whose branch it lies on (itself when traced)."""

    attractor: int
    on_branch_of: int
    branch: Branch | None = None
    closed: bool = False
    stable: np.ndarray | None = None
    max_multiplier: np.ndarray | None = None
    note: str = ""
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def traced(self) -> bool:
        return self.branch is not None and self.on_branch_of == self.attractor

    def speed_range(self) -> tuple[float, float] | None:
        if self.branch is None:
            return None
        return float(self.branch.lam.min()), float(self.branch.lam.max())


def trace_attractor_branches(problem: PeriodicProblem | None, census: AttractorCensus,
                             lo: float, hi: float, *, stability: Any = True,
                             known: Sequence[AttractorBranch] = (),
                             **continue_kw: Any) -> list[AttractorBranch]:
    """One :class:`AttractorBranch` per attractor of ``census`` (the HB ``problem`` of its
    model, speed-parameter; None: nothing traced): each period-1 attractor with an HB
    correction continued within ``(lo, hi)`` rad/s, unless it lies on an earlier
    attractor's branch or on one of ``known`` (traced branches of other census speeds
    over the same range: taken as they are; module docstring); ``stability`` True
    (default options), a :class:`~rotorsfd.stability.branch_options.StabilityOptions` or
    False; ``continue_kw`` go to ``continue_both_ways``."""
    speed = census.speed
    if not lo < speed < hi:
        raise ConfigError("branches", (lo, hi), f"the speed range must contain the census "
                          f"speed {speed:.6g} rad/s")
    out: list[AttractorBranch] = []
    for i, a in enumerate(census.attractors):
        X = a.hb.get("hb_X")
        if a.period != 1 or X is None or problem is None:
            why = (f"a period-{a.period} attractor: its branch is not traced"
                   if a.period not in (None, 1) else a.hb.get("hb_note")
                   or f"a {a.motion} attractor has no periodic branch")
            out.append(AttractorBranch(i, i, note=why))
            continue
        home = next((b.attractor for b in out if b.traced
                     and on_branch(problem, b.branch, speed, X)), None)
        if home is not None:
            first = out[home]
            out.append(AttractorBranch(i, home, first.branch, first.closed, first.stable,
                                       first.max_multiplier,
                                       note=f"on the branch of attractor {home}"))
            continue
        seen = next((b for b in known if b.traced and b.branch.H == X.shape[0] - 1
                     and on_branch(problem, b.branch, speed, X)), None)
        if seen is not None:
            out.append(dataclasses.replace(seen, attractor=i, on_branch_of=i,
                                           info={**seen.info}))
            continue
        try:
            branch = continue_both_ways(problem, speed, X, X.shape[0] - 1, lo, hi,
                                        **continue_kw)
        except ConvergenceError as exc:
            out.append(AttractorBranch(i, i, note=" ".join(str(exc).split())[:200]))
            continue
        item = AttractorBranch(i, i, branch, bool(branch.info.get("closed")),
                               info={"traced_at": speed})
        if stability is not False:
            # deferred: stability.branch_options, stability.branch_stability (loads scipy)
            from rotorsfd.stability.branch_options import StabilityOptions
            from rotorsfd.stability.branch_stability import branch_stability

            options = stability if isinstance(stability, StabilityOptions) else None
            st = branch_stability(branch, problem, options)
            item.stable, item.max_multiplier = st.stable, st.max_multiplier
        item.note = ("an isola (closed on itself)" if item.closed
                     else f"open: {branch.message}")
        out.append(item)
    return out


def trace_census_branches(problem: PeriodicProblem | None,
                          censuses: Sequence[AttractorCensus], lo: float, hi: float, *,
                          stability: Any = True,
                          **continue_kw: Any) -> list[list[AttractorBranch]]:
    """:func:`trace_attractor_branches` of every census in turn, each knowing the
    branches traced at the speeds before it (a branch is traced once over the stride)."""
    out: list[list[AttractorBranch]] = []
    for c in censuses:
        known = [b for bs in out for b in bs if b.traced]
        out.append(trace_attractor_branches(problem, c, lo, hi, stability=stability,
                                            known=known, **continue_kw))
    return out


@dataclass
class AttractorBranches:
    """The traced branches of every census of a :class:`CensusResult` (``censuses[k]``
    with ``branches[k]``); ``reference_speed`` for the speed ratios."""

    censuses: list[AttractorCensus]
    branches: list[list[AttractorBranch]]
    nl_dofs: np.ndarray
    dof_scale: np.ndarray
    reference_speed: float | None = None
    title: str = ""

    @property
    def traces(self) -> int:
        """How many branches were continued (a branch taken at several census speeds
        counts once)."""
        return len({id(b.branch) for bs in self.branches for b in bs if b.traced})

    def rows(self) -> list[list[Any]]:
        """attractor_branches.csv: one row per attractor and census speed."""
        out = []
        for c, bs in zip(self.censuses, self.branches, strict=True):
            for b in bs:
                rng = b.speed_range() or ("", "")
                n = b.branch.n_points if b.branch is not None else 0
                folds = b.branch.folds().size if b.branch is not None else ""
                out.append([c.speed, b.attractor, b.on_branch_of,
                            "isola" if b.closed else "open" if b.branch is not None
                            else "", *rng, n, folds, b.note])
        return out

    def summary(self) -> str:
        """One line per attractor, in words."""
        lines = []
        ref = self.reference_speed
        for c, bs in zip(self.censuses, self.branches, strict=True):
            for b in bs:
                head = f"motion {b.attractor + 1} at {c.speed:.6g} rad/s"
                if b.branch is None:
                    lines.append(f"{head}: no branch ({b.note})")
                elif not b.traced:
                    lines.append(f"{head}: on the branch of motion {b.on_branch_of + 1}")
                else:
                    lo, hi = b.speed_range()
                    span = (f"Omega~ {lo / ref:.4g}-{hi / ref:.4g}" if ref
                            else f"{lo:.6g}-{hi:.6g} rad/s")
                    kind = "an isola" if b.closed else "an open branch"
                    at = b.info.get("traced_at", c.speed)
                    again = ("" if at == c.speed
                             else f" (traced from the census at {at:.6g} rad/s)")
                    lines.append(f"{head}: {kind} over {span}, {b.branch.n_points} points, "
                                 f"{b.branch.folds().size} folds{again}")
        return "\n".join(lines)

    def plot(self) -> dict[str, Any]:
        """``attractor_branches.png``
        (:func:`rotorsfd.plots.attractor_branches.branches_figure`)."""
        # deferred: plots.attractor_branches (loads matplotlib)
        from rotorsfd.plots.attractor_branches import branches_figure

        return {"attractor_branches.png": branches_figure(self)}

    def write(self, directory: Any, plots: bool = True) -> dict[str, Any]:
        """attractor_branches.csv, one ``branch_motion<k>.csv`` per traced branch (speed,
        the 1X amplitude of each nonlinear DOF over its length scale, ``|mu|max``,
        stable) and (``plots``) attractor_branches.png in ``directory``."""
        out = Path(directory)
        out.mkdir(parents=True, exist_ok=True)
        paths = {"attractor_branches.csv": write_csv(
            out / "attractor_branches.csv",
            ["speed_rad_s", "attractor", "on_branch_of", "branch", "speed_min_rad_s",
             "speed_max_rad_s", "points", "folds", "note"], self.rows())}
        for k, bs in enumerate(self.branches):
            for b in bs:
                if not b.traced:
                    continue
                amp = [b.branch.amplitude(int(d)) / s
                       for d, s in zip(self.nl_dofs, self.dof_scale, strict=True)]
                mu = b.max_multiplier if b.max_multiplier is not None else [""] * len(amp[0])
                st = b.stable if b.stable is not None else [""] * len(amp[0])
                tag = f"branch_motion{b.attractor + 1}" + (f"_speed{k}"
                                                           if len(self.censuses) > 1 else "")
                paths[f"{tag}.csv"] = write_csv(
                    out / f"{tag}.csv",
                    ["speed_rad_s", *[f"amplitude_1x_dof{int(d)}" for d in self.nl_dofs],
                     "max_multiplier", "stable"],
                    [[float(x), *[float(a[i]) for a in amp],
                      "" if mu[i] == "" else float(mu[i]),
                      "" if st[i] == "" else bool(st[i])]
                     for i, x in enumerate(b.branch.lam)])
        if plots:
            paths.update(save_figures(self.plot(), out))
        return paths


def run_attractor_branches(config_or_system: Any, result: Any, *, settings: Any = None,
                           stability: Any = None,
                           search_path: Any = None) -> AttractorBranches:
    """:class:`AttractorBranches` of a :class:`CensusResult`: the branches within
    ``settings.speed_range`` (an ``[analysis.response]`` section) with the options of
    ``stability`` (an ``[analysis.stability]`` section; off when it is off).
    ``run_attractor_branches(system, result, settings=..., stability=...)``, defaults: an
    empty configuration's sections; ``run_attractor_branches(config, result)`` is that
    call with ``build(config)`` and the config's two sections."""
    # deferred: analyses.context, stability.branch_options (loads scipy, pydantic)
    from rotorsfd.analyses.context import build
    from rotorsfd.io.schema import Config, ResponseAnalysis, StabilityAnalysis
    from rotorsfd.stability.branch_options import StabilityOptions

    if isinstance(config_or_system, Config):
        config = config_or_system
        return run_attractor_branches(
            build(config, search_path), result,
            settings=config.analysis.response if settings is None else settings,
            stability=config.analysis.stability if stability is None else stability)
    system = config_or_system
    settings = settings if settings is not None else ResponseAnalysis()
    st = stability if stability is not None else StabilityAnalysis()
    problem = system.periodic_problem() if system.base.is_constant else None
    ref = result.censuses[0].reference_speed if result.censuses else None
    lo, hi = settings.speed_range.bounds(ref or 0.0)
    options = StabilityOptions.from_section(st) if st.enabled else False
    branches = trace_census_branches(problem, result.censuses, lo, hi, stability=options)
    dofs = np.asarray(problem.nl_dofs if problem is not None else [], dtype=np.int64)
    scale = (np.asarray(problem.dof_scale, float)[dofs] if problem is not None
             else np.zeros(0))
    return AttractorBranches(list(result.censuses), branches, dofs, scale, ref,
                             getattr(result, "title", ""))
