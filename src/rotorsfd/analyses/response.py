"""Nonlinear periodic response of the rotor and its elements: a branch of HB-AFT solutions
continued in the rotor speed (or a base rate, or the unbalance), its table, files and plots.

``run_response(system, settings) -> ResponseResult`` (or ``run_response(config)``: the same
code, :mod:`rotorsfd.analyses.response_inputs`) reads ``[analysis.response]``; the result holds
the :class:`~rotorsfd.continuation.branch.Branch` and writes ``branch.nc`` (every Fourier
coefficient), ``branch.csv`` (the paper's quantities per point) and the frequency-response
plots. Quantities per point, for an output node n and direction d in (y, z)::

    static_<n>_<d>    = X_0                    [m]   (zero-order term)
    amp_<n>_<d>_h<k>  = |X_k|                  [m]   (half peak-to-peak of harmonic k)
    defl_<n>          = max_t sqrt(y^2 + z^2) / C    (the paper's r~, C the smallest
                                                      clearance of the elements)

and per nonlinear element e its orbit diagnostics ``<key>_<e>`` (an SFD's ``eps_max_<e>``,
the largest eccentricity ratio over the period; :meth:`ResponseResult.element_columns`).

Per-point stability (``stable``, ``max_multiplier``, ``multipliers``) and the located
bifurcations: computed after the branch by
:func:`~rotorsfd.stability.branch_stability.branch_stability` when
``[analysis.stability].enabled`` (or ``stability_options`` is given); alternatively a
``stability`` hook called at every converged point fills them, or
:meth:`ResponseResult.with_stability` adds them afterwards; they are written when present,
with ``multipliers.png`` (the multipliers of one point against the unit circle,
:meth:`ResponseResult.plot_multipliers`).
"""

from __future__ import annotations

import dataclasses
import sys
import time
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.context import RunContext
from rotorsfd.analyses.dual_spool_response import dual_spool, run_dual_spool_response
from rotorsfd.analyses.response_inputs import ResponseInputs
from rotorsfd.analyses.response_result import PointStability, ResponseResult, StabilityHook
from rotorsfd.analyses.response_words import (
    PARAMETER_UNITS,
    column_slug,
    start_failure,
    system_parameter,
)
from rotorsfd.analyses.torus_response import harmonic_base, run_torus_response
from rotorsfd.continuation.branch import Branch, BranchPoint
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.harmonic.synthesis import max_radius, orbit_samples
from rotorsfd.model.system import RotorSystem

if TYPE_CHECKING:
    from rotorsfd.io.schema import Config, ResponseAnalysis
    from rotorsfd.stability.branch_stability import StabilityOptions

__all__ = ["PARAMETER_UNITS", "PointStability", "ResponseInputs", "ResponseResult",
           "column_slug", "max_radius", "orbit_samples", "response_branch", "run_response",
           "system_parameter"]

FloatArray = NDArray[np.float64]

# ---- running ------------------------------------------------------------------------------


class _Progress:
    """tqdm bar on stderr: percent of the parameter range reached, points, position."""

    def __init__(self, start: float, stop: float, enabled: bool, label: str,
                 scale: float, unit: str) -> None:
        # deferred: tqdm is heavy (loaded only when this runs)
        from tqdm import tqdm

        self.start, self.span = start, (stop - start) or 1.0
        self.scale, self.unit, self.done, self.label = scale, unit, 0, label
        self.bar = tqdm(total=100, desc=label, disable=not enabled, file=sys.stderr,
                        dynamic_ncols=True, leave=False,
                        bar_format="{desc} {percentage:3.0f}%|{bar}| [{elapsed}]")

    def update(self, point: BranchPoint) -> None:
        frac = min(max((point.lam - self.start) / self.span, 0.0), 1.0)
        new = int(100 * frac)
        if new > self.done:
            self.bar.update(new - self.done)
            self.done = new
        self.bar.set_description_str(f"{self.label}: {point.index + 1} points, at "
                                     f"{point.lam / self.scale:.4g}{self.unit}",
                                     refresh=False)

    def close(self) -> None:
        self.bar.close()


def run_response(config_or_system: Config | RotorSystem,
                 settings: ResponseAnalysis | None = None, *,
                 context: RunContext | None = None, search_path: Path | None = None,
                 parameter: str | None = None, start: float | None = None,
                 stop: float | None = None, speed: float | None = None,
                 reference_speed: float | None = None, harmonics: int | None = None,
                 nodes: Sequence[int] | None = None, directions: Sequence[str] | None = None,
                 X0: Any = None, progress: bool = True,
                 stability: StabilityHook | None = None,
                 stability_options: StabilityOptions | bool | None = None,
                 callback: Callable[[BranchPoint], bool | None] | None = None,
                 title: str | None = None, from_orbit: Any = None,
                 closure_tol: float | None = None, **options: Any) -> ResponseResult:
    """Continue periodic solutions and return a :class:`ResponseResult`.

    The inputs are resolved once by :class:`~rotorsfd.analyses.response_inputs.
    ResponseInputs`: from a :class:`RotorSystem` with ``settings`` (an
    ``[analysis.response]`` section; default the context's, by default
    ``ResponseAnalysis()``: speeds 0.5 to 1.6 x Omega_ref, H 'auto' from 3) and
    ``context`` (:class:`RunContext`: the reference speed, default the first forward
    critical speed; ``[analysis.stability]``, default on; the title); from a Config, its
    system (one ``build``), ``[analysis.response]`` and context, through the same code,
    so ``run_response(config)`` is ``run_response(build(config),
    config.analysis.response, context=config_context(...))``. Keyword arguments override
    the section (``start, stop`` in SI; a given H is fixed). ``options`` go to
    :func:`~rotorsfd.harmonic.periodic.continue_periodic`.
    ``stability(point)`` may return a :class:`PointStability` per point; otherwise
    ``stability_options`` (None: as ``[analysis.stability].enabled``; True: on, with that
    section's options; False: off; or a StabilityOptions) computes the multipliers of
    every point and the located bifurcations after the branch. ``callback(point)``
    returning True stops the branch. A failed step never raises: the result then has
    ``success`` False and the points so far.

    A Config whose base law is harmonic gets the quasi-periodic response instead (a
    :class:`~rotorsfd.analyses.torus_response.TorusResponseResult`, the torus branch in the
    speed: :func:`~rotorsfd.analyses.torus_response.run_torus_response`).

    ``from_orbit`` (a simulate ``timeseries.nc``, its directory, or a SimulationResult;
    speed parameter only): the branch starts at the orbit's speed from the Fourier
    coefficients of its last period, Newton-corrected (``info["orbit_difference"]``: the
    largest difference over the period between that HB orbit and the recorded one, in
    clearances), and is continued in both directions, stopping when it closes on itself
    (an isola, ``info["closed"]``; ``closure_tol`` see
    :func:`~rotorsfd.analyses.orbit_branch.continue_both_ways`).
    """
    over: dict[str, Any] = {"parameter": parameter, "start": start, "stop": stop,
                            "speed": speed, "harmonics": harmonics, "nodes": nodes,
                            "directions": directions, "title": title,
                            "stability_options": stability_options}
    if isinstance(config_or_system, RotorSystem):
        inputs = ResponseInputs.from_system(config_or_system, settings, context,
                                            reference_speed=reference_speed, **over)
    else:       # a harmonic base law or two spools' unbalances: a torus
        if settings is not None or context is not None:
            raise TypeError("settings and context go with a RotorSystem; a Config gives "
                            "its own [analysis.response] and context")
        if dual_spool(config_or_system):     # unbalances on two spools: two frequencies
            return run_dual_spool_response(config_or_system, search_path=search_path,
                                           progress=progress, from_orbit=from_orbit,
                                           callback=callback)
        if harmonic_base(config_or_system):
            return run_torus_response(config_or_system, search_path=search_path,
                                      progress=progress, from_orbit=from_orbit,
                                      callback=callback)
        inputs = ResponseInputs.from_config(config_or_system, search_path,
                                            reference_speed=reference_speed, **over)
    return response_branch(inputs, X0=X0, progress=progress, stability=stability,
                           callback=callback, from_orbit=from_orbit,
                           closure_tol=closure_tol, **options)


def response_branch(inputs: ResponseInputs, *, X0: Any = None, progress: bool = True,
                    stability: StabilityHook | None = None,
                    callback: Callable[[BranchPoint], bool | None] | None = None,
                    from_orbit: Any = None, closure_tol: float | None = None,
                    **options: Any) -> ResponseResult:
    """The branch of resolved ``inputs`` (:func:`run_response`): HB-AFT continuation of
    ``R(X, lam) = 0`` from ``inputs.start`` to ``inputs.stop``, then the Floquet stability
    of every point when ``inputs.stability`` is set (and no ``stability`` hook)."""
    system, sys_param, ref = inputs.system, inputs.parameter, inputs.reference_speed
    start, stop, H = inputs.start, inputs.stop, inputs.harmonics
    opts = {**inputs.options, **options}
    problem = system.periodic_problem(sys_param, inputs.speed)
    scale, unit = ((ref, " x ref") if sys_param == "speed"
                   else (1.0, f" {PARAMETER_UNITS[sys_param]}"))
    bar = _Progress(start, stop, progress, "response", scale, unit)
    data: dict[int, PointStability] = {}

    def hook(point: BranchPoint) -> bool:
        bar.update(point)
        stop_now = False
        if stability is not None:
            ps = stability(point)
            if ps is not None:
                data[point.index] = ps
                stop_now = ps.stop
        if callback is not None:
            stop_now = bool(callback(point)) or stop_now
        return stop_now

    t0 = time.perf_counter()
    orbit_info: dict[str, Any] = {}
    try:
        if from_orbit is not None:
            branch, orbit_info = _branch_from_orbit(problem, sys_param, from_orbit, H,
                                                    start, stop, hook, closure_tol, opts)
        else:
            try:
                branch = continue_periodic(problem, start, stop, H, X0, callback=hook, **opts)
            except ConvergenceError as exc:   # only the first point raises
                raise ConvergenceError(start_failure(system, inputs.path, start, ref,
                                                     opts.get("limit_max"), str(exc))) from None
    finally:
        bar.close()
    result = ResponseResult(branch, system, ref, inputs.nodes, inputs.directions or ("y", "z"),
                            inputs.path, inputs.speed, inputs.title,
                            time.perf_counter() - t0)
    result.info.update(orbit_info)
    if inputs.config_toml:
        result.info["config_toml"] = inputs.config_toml
    if "limit_max" in opts:
        result.info["limit_max"] = float(opts["limit_max"])
    if data and len(data) >= branch.n_points:
        pts = [data[i] for i in range(branch.n_points)]
        mu = None
        if all(p.multipliers is not None for p in pts):
            mu = np.array([np.asarray(p.multipliers, dtype=complex) for p in pts])
        result = result.with_stability([p.stable for p in pts],
                                       [p.max_multiplier for p in pts], mu)
    elif stability is None and inputs.stability is not None and branch.n_points:
        result = _with_branch_stability(result, problem, inputs.stability, progress)
    return result


def _branch_from_orbit(problem: Any, sys_param: str, from_orbit: Any, H: int,
                       start: float, stop: float, hook: Any, closure_tol: float | None,
                       opts: dict[str, Any]) -> tuple[Branch, dict[str, Any]]:
    """The branch through a time-domain orbit (see :func:`run_response`) and its info."""
    # deferred: analyses.orbit_branch (loads 18 more rotorsfd modules, needed only here)
    from rotorsfd.analyses.orbit_branch import CLOSURE_TOL, continue_both_ways, orbit_start

    if sys_param != "speed":
        raise ConfigError("from_orbit", sys_param, "a branch from a time-domain orbit is "
                          "continued in the rotor speed")
    solve = {k: opts[k] for k in ("n_samples", "tol") if k in opts}
    sol, fit, diff = orbit_start(problem, from_orbit, H, **solve)
    branch = continue_both_ways(problem, fit.speed, sol.X, H, min(start, stop),
                                max(start, stop), callback=hook,
                                closure_tol=closure_tol or CLOSURE_TOL, **opts)
    info = {"from_orbit": fit.source, "orbit_speed": fit.speed,
            "orbit_difference": diff, "orbit_fit_truncation": fit.difference(),
            "closed": bool(branch.info.get("closed")),
            "start_index": int(branch.info.get("start_index", 0))}
    return branch, info


def _with_branch_stability(result: ResponseResult, problem: Any,
                           options: StabilityOptions, progress: bool) -> ResponseResult:
    """The result with the multipliers of every point and the located bifurcations."""
    # deferred: tqdm is heavy; the Floquet stability modules load only when it is on
    from tqdm import tqdm

    from rotorsfd.stability.branch_stability import FloquetEvaluator, branch_stability

    # deferred: stability.fold_points (loads 17 more rotorsfd modules, needed only here)
    from rotorsfd.stability.fold_points import with_fold_points

    n = result.branch.n_points
    bar = tqdm(total=n, desc="stability", disable=not progress, file=sys.stderr,
               dynamic_ncols=True, leave=False)

    def step(i: int, total: int) -> None:
        bar.update(i - bar.n)

    try:
        st = branch_stability(result.branch, problem, options, progress=step)
        if options.check and st.bifurcations:
            # deferred: stability.bifurcation_check (loads 18 more modules)
            from rotorsfd.stability.bifurcation_check import checks_as_configured

            bar.set_description_str("checking bifurcations", refresh=True)
            st.checks = checks_as_configured(result.branch, problem, st, options)
        branch, st, added = with_fold_points(result.branch, st,
                                             FloquetEvaluator(problem, options))
        st.messages.extend(added)
    finally:
        bar.close()
    result = dataclasses.replace(result, branch=branch)
    out = result.with_stability(st.stable, st.max_multiplier, st.multipliers,
                                st.rows(result.reference_speed, problem.frequency))
    out.info.update(stability=st, stability_options=options, n_multipliers=st.n_multipliers,
                    stability_elapsed=st.elapsed, floquet_intervals=st.n_intervals)
    if st.multiplier_error is not None:
        out.info["multiplier_error"] = st.multiplier_error
    out.info.update(floquet_basis=st.basis, floquet_modes=st.n_modes,
                    max_multiplier_outside=st.max_multiplier_outside)
    return out
