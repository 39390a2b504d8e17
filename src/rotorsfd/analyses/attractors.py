"""Attractor census at one rotor speed: many time integrations from sampled initial
states, each stopped once its orbit has settled, classified and grouped into attractors.

Initial states: ``n_starts`` points ``u`` of the unit cube ``[0, 1]^(2 m)`` (a Latin
hypercube, :class:`scipy.stats.qmc.LatinHypercube`, or a grid with ``ceil(n^(1/2m))``
levels per coordinate) over the ``m`` nonlinear DOFs' states:

    q_i = a c_i (2 u_i - 1),   v_i = a c_i Omega (2 u_{m+i} - 1)

(``a`` the ``displacement_fraction``, ``c_i`` the DOF's length scale: the SFD clearance).
The other DOFs follow quasi-statically, ``q_o = -K_oo^-1 K_on q_n`` (same for ``v``), so
a start does not load the shaft with an arbitrary elastic strain.

Each start is integrated in chunks of ``check_periods`` rotor periods (one fixed step
``T / steps_per_period``, prepared once per batch of starts and its state carried from
chunk to chunk: :mod:`~rotorsfd.analyses.attractors_step`); after each chunk the
Poincare points ``P_k`` (the nonlinear DOFs' displacements at ``t = k T`` over ``c_i``)
are tested for a period-n orbit, the smallest ``n <= n_max`` with

    max_{k in last repeats * n} |P_{k+n} - P_k|_inf <= settle_tol,

and the run stops there, unless the returns of a divisor ``m`` of n still shrink
(:func:`~rotorsfd.timedomain.poincare.converging_period`: a transient spiralling into a
period-m orbit whose multiplier's angle is near ``2 pi / n`` passes the period-n test
first). A start is *captured* earlier (``capture_tol > 0``) when its last
``repeats * n`` returns lie within ``capture_tol`` of the cycle of a period-n orbit another
start of the same batch (a worker's share, run in order) has already settled on, in
phase, and still contract (the largest ``|P_{k+n} - P_k|`` over the last ``repeats * n``
returns below that over the ``repeats * n`` before): it is then in that stable orbit's
basin, and the rest of its transient (from ``capture_tol`` down to ``settle_tol``) is not
integrated. The first member of every attractor is a start settled
by the test above (the one the HB correction starts from). Not settled after
``max_periods``: ``classify_periods`` more
periods are recorded and classified as ``rotorsfd simulate`` does
(:func:`~rotorsfd.analyses.simulate.classify`, spectral and section tests; no Lyapunov
run). A state outside an element's law is ``contact``. Grouping, HB correction and the
table: :mod:`~rotorsfd.analyses.attractors_result`.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from scipy.stats import qmc

from rotorsfd.analyses.attractors_result import AttractorCensus, group
from rotorsfd.analyses.attractors_step import StartStepper
from rotorsfd.analyses.td_integration import TimeDomainInputs, integrate_periods
from rotorsfd.errors import ConfigError, ConvergenceError, ElementDomainError
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.model.lowrank import dense
from rotorsfd.timedomain.poincare import converging_period

FIELD = "attractors"
SAMPLINGS = ("lhs", "grid")
AROUND = ("rest", "orbit")
DEFAULT_STEPS = 400
"""Steps per period when neither the options nor the config give an integer."""
DEFAULT_HARMONICS = 8


@dataclass(frozen=True)
class CensusOptions:
    """Settings of a census (see the module docstring for the symbols)."""

    n_starts: int = 64
    sampling: str = "lhs"
    displacement_fraction: float = 0.5
    velocity_fraction: float = 0.5
    steps_per_period: int | None = None
    check_periods: int = 10
    max_periods: int = 600
    classify_periods: int = 100
    settle_tol: float = 1e-4
    repeats: int = 3
    n_max: int = 8
    cluster_tol: float = 1e-2
    capture_tol: float = 5e-3
    harmonics: int | None = None
    seed: int = 0
    around: str = "rest"

    def validate(self) -> CensusOptions:
        """Itself, or a ConfigError naming the field."""
        checks = [("n_starts", self.n_starts >= 1, ">= 1"),
                  ("sampling", self.sampling in SAMPLINGS, "lhs or grid"),
                  ("around", self.around in AROUND, "rest or orbit"),
                  ("displacement_fraction", 0.0 < self.displacement_fraction < 1.0,
                   "in (0, 1)"),
                  ("velocity_fraction", self.velocity_fraction >= 0.0, ">= 0"),
                  ("steps_per_period", (self.steps_per_period or 8) >= 8, ">= 8"),
                  ("check_periods", self.check_periods >= 2, ">= 2"),
                  ("max_periods", self.max_periods >= self.check_periods,
                   ">= check_periods"),
                  ("classify_periods", self.classify_periods >= 16, ">= 16"),
                  ("settle_tol", self.settle_tol > 0.0, "> 0"),
                  ("repeats", self.repeats >= 1, ">= 1"),
                  ("n_max", 1 <= self.n_max <= self.check_periods, "1..check_periods"),
                  ("cluster_tol", self.cluster_tol > self.settle_tol, "> settle_tol"),
                  ("capture_tol", 0.0 <= self.capture_tol < self.cluster_tol,
                   ">= 0 (0: off) and < cluster_tol"),
                  ("harmonics", (self.harmonics or 1) >= 1, ">= 1")]
        for name, ok, allowed in checks:
            if not ok:
                raise ConfigError(f"{FIELD}.{name}", getattr(self, name), allowed)
        return self

    def resolved(self) -> CensusOptions:
        """Itself with the defaults of the step and H filled in."""
        return replace(self, steps_per_period=self.steps_per_period or DEFAULT_STEPS,
                       harmonics=self.harmonics or DEFAULT_HARMONICS)


@dataclass
class CensusModel:
    """What a census integrates: the integrator inputs at one speed, the nonlinear DOFs'
    length scales ``scale`` [m], and the HB problem (None: no HB correction)."""

    inputs: TimeDomainInputs
    scale: np.ndarray
    problem: Any = None
    reference_speed: float | None = None
    orbit: np.ndarray | None = None

    @property
    def speed(self) -> float:
        return self.inputs.speed

    @property
    def nl_dofs(self) -> np.ndarray:
        return np.asarray(self.inputs.nl_dofs, dtype=np.int64)


def unit_samples(n: int, dim: int, sampling: str = "lhs", seed: int = 0) -> np.ndarray:
    """``(n', dim)`` points of the unit cube: a Latin hypercube of n points, or the grid
    of ``ceil(n^(1/dim))`` cell centres per coordinate (``n'`` may exceed n)."""
    if sampling == "lhs":
        return qmc.LatinHypercube(d=dim, seed=seed).random(n)
    levels = max(2, math.ceil(n ** (1.0 / dim) - 1e-9))
    g = (np.arange(levels) + 0.5) / levels
    return np.stack(np.meshgrid(*[g] * dim, indexing="ij"), -1).reshape(-1, dim)


def start_states(model: CensusModel, u: np.ndarray, options: CensusOptions
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """``(coords (n, 2m), q0 (n, n_dof), v0 (n, n_dof))`` of unit samples ``u``: coords
    are the nonlinear DOFs' ``q_i / c_i`` and ``v_i / (c_i Omega)``."""
    m = model.nl_dofs.size
    a = options.displacement_fraction
    coords = np.hstack([a * (2 * u[:, :m] - 1),
                        options.velocity_fraction * (2 * u[:, m:2 * m] - 1), u[:, 2 * m:]])
    n = model.inputs.n_dof
    nl = model.nl_dofs
    other = np.setdiff1d(np.arange(n), nl)
    K = dense(model.inputs.K)              # CSR above DENSE_MAX_DOF DOFs
    try:
        G = -np.linalg.solve(K[np.ix_(other, other)], K[np.ix_(other, nl)]) \
            if other.size else np.zeros((0, m))
    except np.linalg.LinAlgError:
        G = np.zeros((other.size, m))
    q0 = np.zeros((u.shape[0], n))
    v0 = np.zeros((u.shape[0], n))
    qn = coords[:, :m] * model.scale
    vn = coords[:, m:2 * m] * model.scale * model.speed
    q0[:, nl], v0[:, nl] = qn, vn
    q0[:, other], v0[:, other] = qn @ G.T, vn @ G.T
    if options.around == "orbit":
        # deferred: analyses.simulate (loads 19 more rotorsfd modules, needed only here)
        from rotorsfd.analyses.simulate import hb_state, shift_phase

        X = orbit_coefficients(model, options)
        for i, p in enumerate(u[:, 2 * m]):
            qh, vh = hb_state(shift_phase(X, p), model.speed)
            q0[i, other] += qh[other] - G @ qh[nl]
            v0[i, other] += vh[other] - G @ vh[nl]
    return coords, q0, v0


def orbit_coefficients(model: CensusModel, options: CensusOptions) -> np.ndarray:
    """HB coefficients ``X (H+1, n_dof)`` of the periodic solution at the model's speed
    (Newton from the linear response; if that fails, continued from half the speed),
    computed once (``model.orbit``)."""
    if model.orbit is not None:
        return model.orbit
    if model.problem is None:
        raise ConfigError(f"{FIELD}.around", "orbit", "needs a constant base motion (an "
                          "HB problem at the speed)")
    H = options.harmonics or DEFAULT_HARMONICS
    try:
        X = solve_periodic(model.problem, model.speed, H).X
    except ConvergenceError:
        b = continue_periodic(model.problem, 0.5 * model.speed, model.speed, H,
                              limit_max=0.999)
        if not (b.n_points and abs(b.lam[-1] - model.speed) <= 1e-9 * model.speed):
            raise
        X = b.X[-1]
    model.orbit = X
    return X


def settled_period(P: np.ndarray, tol: float, repeats: int, n_max: int) -> int | None:
    """Smallest ``n <= n_max`` whose last ``repeats * n`` returns repeat within ``tol``
    (inf-norm of ``P[k+n] - P[k]``), None if none does."""
    N = P.shape[0]
    for n in range(1, n_max + 1):
        w = repeats * n
        if N < w + n:
            return None
        d = np.abs(P[N - w:] - P[N - w - n:N - n])
        if float(np.max(d)) <= tol:
            return n
    return None


def settled(P: np.ndarray, options: CensusOptions) -> int | None:
    """:func:`settled_period` of the returns ``P``, None if a divisor's returns still
    shrink (a spiral into a period-m orbit, m | n, passes the period-n test first) or if
    the n points lie within ``cluster_tol`` of each other (a period-1 orbit, unsettled)."""
    o = options
    n = settled_period(P, o.settle_tol, o.repeats, o.n_max)
    if n is None or n == 1:
        return n
    if converging_period(P[-max(4 * n + 8, 40):], n, rtol=o.settle_tol) is not None:
        return None
    if float(np.max(np.ptp(P[-n:], axis=0))) <= o.cluster_tol:
        return None      # n points within the grouping tolerance: a period-1 orbit not yet
    return n             # settled (a slow spiral), not a period-n one


def captured(P: np.ndarray, known: Sequence[tuple[int, int, np.ndarray]],
             options: CensusOptions) -> int | None:
    """Start number of the settled orbit ``(index, n, cycle points (n, m))`` of ``known``
    that the returns ``P`` are captured by (module docstring), None if none."""
    o = options
    if o.capture_tol <= 0.0:
        return None
    for index, n, cycle in known:
        w = o.repeats * n
        if P.shape[0] < 2 * w + n:
            continue
        s = int(np.argmin(np.max(np.abs(cycle - P[-1]), axis=1)))
        phase = (s - np.arange(w)[::-1] + n * w) % n         # cycle point of P[-w:]
        if float(np.max(np.abs(P[-w:] - cycle[phase]))) > o.capture_tol:
            continue
        d = np.max(np.abs(P[n:] - P[:-n]), axis=1)          # returns' changes, lag n
        if float(d[-w:].max()) < float(d[-2 * w:-w].max()):
            return index
    return None


@dataclass
class StartOutcome:
    """One start: the class (``period-n``, ``quasi-periodic``, ``chaotic``,
    ``contact``, ``failed``), the periods integrated, the last Poincare points (in
    length scales), the recorded last ``n`` periods of the nonlinear DOFs ``(t, q)``,
    and the largest validity measure (eccentricity) per element over the last chunk;
    ``cpu`` the process CPU time it took [s]."""

    index: int
    motion: str
    period: int | None
    periods_run: int
    points: np.ndarray
    t: np.ndarray = field(default_factory=lambda: np.zeros(0))
    q: np.ndarray = field(default_factory=lambda: np.zeros((0, 0)))
    eccentricity: dict[str, float] = field(default_factory=dict)
    note: str = ""
    final: tuple[np.ndarray, np.ndarray, float] | None = None
    cpu: float = 0.0


def _chunk(inputs: TimeDomainInputs, q: np.ndarray, v: np.ndarray, t0: float, spp: int,
           periods: int, record: int) -> Any:
    nl = np.asarray(inputs.nl_dofs)
    return integrate_periods(inputs, q, v, steps_per_period=spp, periods=periods,
                             record_dofs=nl, record_periods=record,
                             poincare_periods=periods, t0=t0, chunk_periods=periods)


def _ecc(chunk: Any) -> dict[str, float]:
    return {k.removeprefix("eps_max_"): float(v) for k, v in
            chunk.element_diagnostics.items() if k.startswith("eps_max")}


def stepper_of(model: CensusModel, options: CensusOptions) -> StartStepper:
    """The step of the census starts, prepared once (:mod:`.attractors_step`)."""
    o = options
    return StartStepper(model.inputs, o.steps_per_period or DEFAULT_STEPS,
                        o.max_periods + o.classify_periods)


def run_start(model: CensusModel, index: int, q0: np.ndarray, v0: np.ndarray,
              options: CensusOptions,
              known: Sequence[tuple[int, int, np.ndarray]] = (),
              stepper: StartStepper | None = None) -> StartOutcome:
    """Integrate one start until it settles or is captured by a ``known`` orbit
    (``(start, n, cycle points)``, module docstring); ``stepper``: the prepared step
    (:func:`stepper_of`, built here if None)."""
    o = options
    st = stepper if stepper is not None else stepper_of(model, o)
    T = model.inputs.period
    pts: list[np.ndarray] = []
    done = 0
    try:
        state = st.start(np.asarray(q0, float), np.asarray(v0, float))
        while done < o.max_periods:
            k = min(o.check_periods, o.max_periods - done)
            ch = st.advance(state, k, min(k, o.n_max))
            pts.append(ch.pq / model.scale)
            t = st.time(state)
            done += k
            P = np.concatenate(pts)
            n = settled(P, o)
            j = None if n is not None or not known else captured(P, known, o)
            if j is not None:
                n = next(k for i, k, _ in known if i == j)
            if n is not None:
                sel = ch.t > t - n * T * (1 + 1e-9)
                return StartOutcome(index, f"period-{n}", n, done, P[-n:], ch.t[sel],
                                    ch.q[sel], _ecc(ch), "" if j is None else
                                    f"captured by the orbit of start {j}", st.final(state))
        ch = st.advance(state, o.classify_periods, o.classify_periods)
    except ElementDomainError as exc:
        P = np.concatenate(pts) if pts else np.zeros((0, model.nl_dofs.size))
        return StartOutcome(index, "contact", None, done, P[-1:], note=" ".join(
            str(exc).split())[:200])
    except ConvergenceError as exc:
        return StartOutcome(index, "failed", None, done,
                            np.zeros((0, model.nl_dofs.size)),
                            note=" ".join(str(exc).split())[:200])
    # deferred: analyses.simulate (loads 19 more rotorsfd modules, needed only here)
    from rotorsfd.analyses.simulate import classify

    P = ch.pq / model.scale
    mc = classify(ch.pq, ch.pv, ch.q, ch.v, T / st.spp, model.speed)
    motion = mc.motion if mc is not None else "chaotic"
    n = mc.period if mc is not None else None
    done += o.classify_periods
    final = st.final(state)
    if n is not None:
        sel = ch.t > final[2] - n * T * (1 + 1e-9)
        return StartOutcome(index, motion, n, done, P[-n:], ch.t[sel], ch.q[sel],
                            _ecc(ch), "settled only by the classifier's tolerance", final)
    return StartOutcome(index, motion, None, done, P, eccentricity=_ecc(ch), final=final)


def step_check(model: CensusModel, outcome: StartOutcome, options: CensusOptions
               ) -> float | None:
    """The step's effect on a settled orbit: from its final state, ``check_periods``
    periods at ``T / steps_per_period`` and at half that step; the largest difference
    of their Poincare points (length scales). None without a final state or if a run
    fails."""
    if outcome.final is None:
        return None
    q, v, t = outcome.final
    k = options.check_periods
    try:
        runs = [_chunk(model.inputs, q, v, t, s, k, 1) for s in
                (options.steps_per_period, 2 * options.steps_per_period)]
    except (ElementDomainError, ConvergenceError):
        return None
    a, b = (r.poincare_q[r.poincare_t > t + 0.5 * model.inputs.period] for r in runs)
    return float(np.max(np.abs(a - b) / model.scale))


def run_batch(model: CensusModel, indices: np.ndarray, q0: np.ndarray, v0: np.ndarray,
              options: CensusOptions, progress: Any = None) -> list[StartOutcome]:
    """:func:`run_start` of the rows of ``q0, v0`` (start numbers ``indices``) in order,
    each captured by the orbits the earlier ones settled on (module docstring)."""
    known: list[tuple[int, int, np.ndarray]] = []
    out = []
    stepper = stepper_of(model, options)
    for i, q, v in zip(indices, q0, v0, strict=True):
        tic = time.process_time()
        r = run_start(model, int(i), q, v, options, known, stepper)
        r.cpu = time.process_time() - tic
        if r.period is not None and not r.note:        # settled by the test itself
            if not any(_near(r.points, c, options.cluster_tol) for _, _, c in known):
                known.append((r.index, r.period, r.points))
        out.append(r)
        if progress is not None:
            progress(len(out))
    return out


def _near(points: np.ndarray, cycle: np.ndarray, tol: float) -> bool:
    """True when every point lies within tol of a point of the cycle (same period)."""
    return points.shape == cycle.shape and all(
        float(np.min(np.max(np.abs(cycle - p), axis=1))) <= tol for p in points)


def preload_workers() -> None:
    """Have the forkserver import this module before it forks a process pool's workers:
    each then starts with numpy, numba and the step loaded (about 1.5 s CPU per worker
    otherwise). No effect once the forkserver runs, or without one."""
    # deferred: multiprocessing is heavy (loaded only when this runs)
    import multiprocessing

    if "forkserver" in multiprocessing.get_all_start_methods():
        multiprocessing.get_context("forkserver").set_forkserver_preload(
            ["__main__", __name__])


def run_starts(model: CensusModel, q0: np.ndarray, v0: np.ndarray, options: CensusOptions,
               executor: Any = None, progress: Any = None) -> list[StartOutcome]:
    """:func:`run_start` of every row, on ``executor`` (a
    :func:`~rotorsfd.studies.executors.make_executor`; None: in this process)."""
    if executor is None:
        return run_batch(model, np.arange(q0.shape[0]), q0, v0, options, progress)
    # the workers get the integrator inputs only (the HB problem holds closures, 0.3 MB
    # pickled in 4 ms), in batches of starts (four per worker)
    preload_workers()
    lite = executor.share(replace(model, problem=None))
    n = q0.shape[0]
    batches = np.array_split(np.arange(n), min(n, 4 * max(1, executor.workers)))
    futures = [executor.submit(run_batch, lite, b, q0[b], v0[b], options)
               for b in batches if b.size]
    out = []
    for fut in executor.as_completed(futures):
        out.extend(fut.result())
        if progress is not None:
            progress(len(out))
    return sorted(out, key=lambda r: r.index)


def census(model: CensusModel, options: CensusOptions | None = None, *,
           executor: Any = None, progress: Any = None) -> Any:
    """The census at the model's speed: an
    :class:`~rotorsfd.analyses.attractors_result.AttractorCensus`."""
    o = (options or CensusOptions()).validate().resolved()
    tic = time.perf_counter()
    dim = 2 * model.nl_dofs.size + (o.around == "orbit")
    u = unit_samples(o.n_starts, dim, o.sampling, o.seed)
    coords, q0, v0 = start_states(model, u, o)
    outcomes = run_starts(model, q0, v0, o, executor, progress)
    elapsed = time.perf_counter() - tic
    attractors = group(model, outcomes, coords, o)
    for a in attractors:
        if a.motion not in ("contact", "failed"):
            a.hb["step_check"] = step_check(model, outcomes[a.representative], o)
    return AttractorCensus(model.speed, model.reference_speed, o, coords, outcomes,
                           attractors, elapsed, time.perf_counter() - tic - elapsed)


def census_map(models: Sequence[CensusModel], options: CensusOptions | None = None, *,
               executor: Any = None, progress: Any = None) -> list[Any]:
    """:func:`census` at each model's speed (a map of coexisting solutions)."""
    return [census(m, options, executor=executor, progress=progress) for m in models]

