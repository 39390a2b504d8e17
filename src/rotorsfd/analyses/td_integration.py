"""Inputs of the time integrator at one rotor speed, and the chunked integration over
whole rotor periods that :mod:`~rotorsfd.analyses.simulate`,
:mod:`~rotorsfd.analyses.step_control` and :mod:`~rotorsfd.analyses.bifurcation_diagram`
run.

    M q'' + (C + Omega G + C_base(t)) q' + (K + K_base(t)) q = F_mu(t) + F_base(t) + F_sfd

stepped by :func:`rotorsfd.timedomain.integrate` with ``dt = T / steps_per_period``,
``T = 2 pi / Omega``; Poincare points once per rotor period at ``t = t0 + k T``.

With ``reduction = "auto"`` (:func:`with_reduction`) the step runs on the Craig-Bampton
model of :mod:`rotorsfd.timedomain.reduced` (the nonlinear DOFs plus the fixed-interface
modes up to ``omega_max = cutoff Omega``): states enter by its projector and the outputs
(recorded DOFs, Poincare points, final state) come back as ``q = Psi p``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np

from rotorsfd.elements.composite import ElementSet
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.model.system import RotorSystem
from rotorsfd.timedomain import Forcing, HarmonicLoad, TimeVaryingMatrices
from rotorsfd.timedomain import newmark as nm
from rotorsfd.timedomain.integrate import MESSAGES, initial_state, prepare, run
from rotorsfd.timedomain.reduced import ReducedStep, reduce_step

FIELD = "analysis.simulate"
DIRECTIONS = ("y", "z")


# ---- inputs of the integrator ------------------------------------------------------------


@dataclass
class TimeDomainInputs:
    """Everything :func:`rotorsfd.timedomain.integrate` takes, for one rotor speed."""

    M: np.ndarray
    D: np.ndarray
    K: np.ndarray
    nl_dofs: np.ndarray
    kernel: Any
    params: np.ndarray | None
    forcing: Forcing
    time_varying: TimeVaryingMatrices | None
    speed: float
    elements: ElementSet | None = None
    reduction: ReducedStep | None = None

    @property
    def period(self) -> float:
        """Rotor period T = 2 pi / Omega [s]."""
        return 2.0 * math.pi / self.speed

    @property
    def n_dof(self) -> int:
        """Physical DOFs."""
        return self.M.shape[0]


REDUCTIONS = ("auto", "none")
REDUCTION_CUTOFF = 40.0
"""Default cutoff of the reduced step, ``omega_max = REDUCTION_CUTOFF Omega``
(``analysis.simulate.reduction_cutoff``; see :func:`with_reduction`)."""


def with_reduction(inputs: TimeDomainInputs, reduction: str = "auto",
                   cutoff: float = REDUCTION_CUTOFF) -> TimeDomainInputs:
    """``inputs`` with the reduced step of ``reduction``: ``"auto"`` the Craig-Bampton
    model on the nonlinear DOFs and the fixed-interface modes with
    ``omega <= cutoff Omega`` when it has fewer coordinates than the model (and the
    interior is restrained once the nonlinear DOFs are fixed: no fixed-interface mode
    below ``1e-6`` of the cutoff), else the full step;
    ``"none"`` the full step."""
    if reduction not in REDUCTIONS:
        raise ConfigError(f"{FIELD}.reduction", reduction, '"auto" or "none"')
    if not cutoff > 0.0:
        raise ConfigError(f"{FIELD}.reduction_cutoff", cutoff, "must be > 0")
    if reduction == "none":
        return replace(inputs, reduction=None)
    try:
        red = reduce_step(inputs.M, inputs.D, inputs.K, inputs.nl_dofs, inputs.forcing,
                          inputs.time_varying, cutoff * inputs.speed)
    except (ConfigError, np.linalg.LinAlgError):  # a free interior: no Craig-Bampton model
        return replace(inputs, reduction=None)
    omegas = red.model.omegas
    mechanism = (omegas.size and omegas[0] < 1e-6 * red.omega_max) or not np.all(
        np.isfinite(red.basis))                        # a (nearly) free interior
    useful = red.n_dof < inputs.n_dof and not mechanism
    return replace(inputs, reduction=red if useful else None)


def stepped_system(inputs: TimeDomainInputs, state: tuple[np.ndarray, np.ndarray, float]
                   ) -> tuple[TimeDomainInputs, tuple[np.ndarray, np.ndarray, float]]:
    """The model the step integrates and a physical ``state = (q, v, t)`` in its
    coordinates: with a reduction the Craig-Bampton model as plain inputs (nonlinear DOFs
    ``0..m-1``) and ``(P q, P v, t)``; without, ``inputs`` and ``state`` themselves. For
    analyses that integrate the stepped model directly (the Lyapunov run)."""
    red = inputs.reduction
    if red is None:
        return inputs, state
    q, v, t = state
    plain = TimeDomainInputs(red.model.M, red.model.D, red.model.K, red.nl_dofs,
                             inputs.kernel, inputs.params, red.forcing, red.time_varying,
                             inputs.speed, inputs.elements)
    return plain, (red.reduce(q), red.reduce(v), t)


CHECK_FACTOR = 4.0
"""Above :data:`~rotorsfd.timedomain.reduced.DENSE_MAX` DOFs the reduction check's
reference is the reduced step at this multiple of the cutoff (the full step's ``prepare``
is O(n^3) there)."""


def reduction_check(inputs: TimeDomainInputs, state: tuple[np.ndarray, np.ndarray, float],
                    *, steps_per_period: int, periods: int, record_dofs: Sequence[int],
                    scale: float | None) -> dict[str, Any]:
    """The reduced step against a reference over ``periods`` periods from the physical
    ``state = (q, v, t)`` (a state of the reduced run, so both start alike): the full step
    for models up to ``DENSE_MAX`` DOFs, else the reduced step at :data:`CHECK_FACTOR`
    times the cutoff. ``reduction_check`` is the largest difference of the ``record_dofs``
    columns over the window in units of ``scale`` (None: of the reference's largest
    value there). An upper estimate: the reference starts from a state without the
    dynamic part of the modes it adds and keeps their free vibration (paper rotor:
    1.3e-5 C, where the two settled orbits differ by 7e-7 C)."""
    from rotorsfd.timedomain.reduced import DENSE_MAX

    red = inputs.reduction
    if red is None:
        return {}
    full = replace(inputs, reduction=None)
    if inputs.n_dof <= DENSE_MAX:
        ref, label = full, "full step"
    else:
        factor = CHECK_FACTOR * red.omega_max / inputs.speed
        ref = with_reduction(full, "auto", factor)
        if ref.reduction is None:          # never the dense full step of a large model
            return {}
        label = f"reduced step at {factor:g} x Omega ({ref.reduction.n_dof} coordinates)"
    q, v, t = state
    runs = [integrate_periods(x, q, v, steps_per_period=steps_per_period, periods=periods,
                              record_dofs=record_dofs, record_periods=periods,
                              poincare_periods=periods, t0=t) for x in (inputs, ref)]
    unit = scale or float(np.max(np.abs(runs[1].q))) or 1.0
    return {"reduction_check": float(np.max(np.abs(runs[0].q - runs[1].q))) / unit,
            "reduction_check_reference": label, "reduction_check_periods": int(periods)}


def reduction_summary(inputs: TimeDomainInputs, cutoff: float | None = None
                      ) -> dict[str, Any]:
    """What the run integrated, for the summary: the reduction, its cutoff, the kept
    coordinates and the highest kept mode."""
    red = inputs.reduction
    if red is None:
        return {"reduction": "none", "reduced_dof": inputs.n_dof,
                "reduction_cutoff": cutoff, "reduction_omega_max_rad_s": None,
                "reduction_modes": None}
    top = float(red.model.omegas.max()) if red.n_modes else None
    return {"reduction": "craig-bampton", "reduced_dof": red.n_dof,
            "reduction_cutoff": red.omega_max / inputs.speed,
            "reduction_omega_max_rad_s": red.omega_max, "reduction_modes": red.n_modes,
            "reduction_highest_mode_rad_s": top}


def _fold_constant(pairs: Sequence[tuple[Any, np.ndarray]], probe: np.ndarray
                   ) -> tuple[list[tuple[Any, np.ndarray]], np.ndarray | None]:
    """Split ``(coefficient, array)`` pairs into time-varying ones and the sum of those
    whose coefficient is constant on ``probe`` (that sum, or None)."""
    varying: list[tuple[Any, np.ndarray]] = []
    const = None
    for c, X in pairs:
        values = np.broadcast_to(np.asarray(c(probe), dtype=float), probe.shape)
        if np.ptp(values) == 0.0:
            term = float(values[0]) * np.asarray(X, dtype=float)
            const = term if const is None else const + term
        else:
            varying.append((c, X))
    return varying, const


def time_domain_inputs(system: RotorSystem, speed: float, *,
                       horizon: float | None = None) -> TimeDomainInputs:
    """Integrator inputs of ``system`` at rotor speed ``speed`` [rad/s].

    Constant base (``system.base.is_constant``): ``matrices(speed)``, the constant force
    ``static_force(speed)`` and the unbalance harmonics at ``Omega``. Otherwise
    ``M, C + Omega G, K`` plus the base terms as time-varying matrices and series loads;
    ``horizon`` [s] (default 1000 rotor periods) is the interval on which a coefficient
    must be constant to be folded into the constant matrices.
    """
    if not speed > 0.0:
        raise ConfigError(f"{FIELD}.speed", speed, "the rotor speed must be > 0 rad/s")
    r = system.rotor
    nl = system.nl_dofs
    el = system.elements_at(speed)   # a law of the speed (journal bearing) set to it
    kernel, params = (el.kernel, el.kernel_params) if len(el) else (None, None)
    events = any(u.start > 0.0 for u in system.unbalances)   # a sudden unbalance: series
    if system.base.is_constant and not events:
        M, D, K = system.matrices(speed)
        Fc, Fs = system.unbalance_harmonics(speed)
        harm = [HarmonicLoad(1.0, Fc, Fs)] if system.unbalances else []
        forcing = Forcing(omega=speed, constant=system.static_force(speed), harmonics=harm)
        return TimeDomainInputs(M, D.copy(), K.copy(), nl, kernel, params, forcing, None,
                                float(speed), el)
    from rotorsfd.model.base_terms import time_varying_terms
    from rotorsfd.model.unbalance import unbalance_series

    T = 2.0 * math.pi / speed
    span = horizon if horizon is not None else 1000.0 * T
    probe = np.concatenate([np.linspace(0.0, span, 257),
                            span * (np.arange(1, 64) * math.sqrt(2.0) % 1.0),
                            system.base.support_times()])   # where a pulse or record acts
    damping, stiffness, force = time_varying_terms(system.basis, system.base, speed)
    damping, dC = _fold_constant(damping, probe)
    stiffness, dK = _fold_constant(stiffness, probe)
    force, f0 = _fold_constant(force, probe)
    D = r.C + speed * r.G + (dC if dC is not None else 0.0)
    K = r.K + (dK if dK is not None else 0.0)
    series = list(force) + unbalance_series(system.unbalances, r, speed, system.base)
    forcing = Forcing(omega=speed, constant=f0, series=series)
    tv = TimeVaryingMatrices(damping=damping, stiffness=stiffness) \
        if damping or stiffness else None
    return TimeDomainInputs(r.M, np.asarray(D, float), np.asarray(K, float), nl, kernel,
                            params, forcing, tv, float(speed), el)


def scheme_options(scheme: str, alpha: float) -> dict[str, Any]:
    """``integrate`` keywords of ``[analysis.simulate] scheme, alpha``: HHT ``alpha``
    (either sign convention: |alpha| <= 1/3), generalized-alpha ``rho_inf = alpha``."""
    if scheme == "newmark":
        return {"method": "newmark"}
    if scheme == "hht":
        a = abs(float(alpha))
        if a > 1.0 / 3.0:
            raise ConfigError(f"{FIELD}.alpha", alpha, "HHT needs |alpha| <= 1/3")
        return {"method": "hht", "alpha": a}
    if scheme == "generalized-alpha":
        if not 0.0 <= alpha <= 1.0:
            raise ConfigError(f"{FIELD}.alpha", alpha, "generalized-alpha takes the "
                              "spectral radius rho_inf = alpha in [0, 1]")
        return {"method": "generalized-alpha", "rho_inf": float(alpha)}
    raise ConfigError(f"{FIELD}.scheme", scheme, "newmark, hht or generalized-alpha")


# ---- chunked integration ---------------------------------------------------------------------


@dataclass
class Trajectory:
    """Samples of a chunked run: every step of the last ``record_periods`` and the
    Poincare points of the last ``poincare_periods`` (columns = ``dofs``)."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    poincare_t: np.ndarray
    poincare_q: np.ndarray
    poincare_v: np.ndarray
    dofs: np.ndarray
    q_final: np.ndarray
    v_final: np.ndarray
    t_final: float
    max_eccentricity_run: float | None
    newton_iterations_max: int = 0
    snapshot: tuple[np.ndarray, np.ndarray, float] | None = None
    element_diagnostics: dict[str, float] = field(default_factory=dict)


def integrate_periods(inputs: TimeDomainInputs, q0: Any, v0: Any, *, steps_per_period: int,
                      periods: int, record_dofs: Sequence[int], record_periods: int,
                      poincare_periods: int, method_options: dict[str, Any] | None = None,
                      chunk_periods: int | None = None, progress: Any = None,
                      t0: float = 0.0,
                      snapshot_period: int | None = None) -> Trajectory:
    """Integrate ``periods`` rotor periods in chunks from ``(q0, v0)`` at ``t0``.

    ``snapshot_period`` (0 < p < periods): a chunk ends after p periods and the full state
    there is kept (``Trajectory.snapshot = (q, v, t)``, the start of the step check).

    ``progress(periods_done)`` is called after each chunk. A state outside an element's
    law raises that element's contact error (an SFD's
    :class:`~rotorsfd.errors.JournalContactError`, with the time and rotor period in its
    ``where``); other failures :class:`ConvergenceError`. ``max_eccentricity_run`` is the
    largest validity measure of the elements over the run (None if none has one),
    ``element_diagnostics`` every element's orbit diagnostics over the recorded periods
    (``eps_max_<name>``, :meth:`~rotorsfd.elements.ElementSet.diagnostics`).

    With ``inputs.reduction`` the run steps the reduced coordinates ``p`` from
    ``p0 = P q0``; every output (the columns of ``record_dofs``, the elements' DOFs, the
    final state and the snapshot) is the physical ``Psi p`` of the rows it needs.
    """
    spp = int(steps_per_period)
    n_steps = spp * int(periods)
    dt = inputs.period / spp
    red = inputs.reduction
    rd = np.asarray(record_dofs, dtype=np.int64)
    rows = np.concatenate([rd, inputs.nl_dofs]).astype(np.int64)  # physical rows kept
    if red is None:
        M, D, K, forcing, tv = inputs.M, inputs.D, inputs.K, inputs.forcing, \
            inputs.time_varying
        nl_step = inputs.nl_dofs
        x0, xv0 = q0, v0
        rec_all = rows

        def out(x: np.ndarray, cols: np.ndarray | None = None) -> np.ndarray:
            return x if cols is None else x[..., cols]
    else:
        M, D, K = red.model.M, red.model.D, red.model.K
        forcing, tv, nl_step = red.forcing, red.time_varying, red.nl_dofs
        x0, xv0 = red.reduce(q0), red.reduce(v0)
        rec_all = np.arange(red.n_dof, dtype=np.int64)          # every reduced coordinate

        def out(x: np.ndarray, cols: np.ndarray | None = None) -> np.ndarray:
            return red.physical(x, None if cols is None else rows[cols])
    ps = prepare(M, D, K, nl_step, inputs.kernel, inputs.params, forcing, dt, n_steps, t0=t0,
                 time_varying=tv, **(method_options or {}),
                 inertial_kernel=None if inputs.elements is None
                 else inputs.elements.inertial_kernel)
    r = ps.n_dof
    nl = ps.nl
    elements = inputs.elements
    limited = elements is not None and any(e.limit_label is not None for e in elements)
    c_rd = np.arange(rd.size)
    c_nl = np.arange(rd.size, rows.size)
    rec_start = (periods - record_periods) * spp
    pc_start = (periods - poincare_periods + 1) * spp
    first_kept = min(rec_start, pc_start)
    state = initial_state(ps, x0, xv0)
    chunk = max(1, chunk_periods or math.ceil(periods / 100))
    parts: dict[str, list[np.ndarray]] = {k: [] for k in ("t", "q", "v", "pt", "pq", "pv",
                                                          "qn", "vn")}
    eps_max = 0.0
    newton_max = 0
    done = 0
    snapshot = None
    snap = snapshot_period if snapshot_period and 0 < snapshot_period < periods else None
    while done < periods:
        k = min(chunk, periods - done)
        if snap is not None and done < snap:
            k = min(k, snap - done)
        # a chunk before the kept windows records only the elements' DOFs (for the limit)
        window = (done + k) * spp >= first_kept
        rec = rec_all if window else (nl if limited else nl[:0])
        status, smp, info = run(ps, state, k * spp, record_dofs=rec, record_every=1,
                                record_start=0, poincare_every=spp if window else 0,
                                poincare_start=0, record_initial=(done == 0))
        newton_max = max(newton_max, int(info[nm.I_NEWTON_MAX]))
        q_nl = out(smp["q"], c_nl) if window else smp["q"]
        if limited and q_nl.shape[0]:
            eps_max = max(eps_max, elements.limit(q_nl))
        if status != nm.OK:
            step = int(info[nm.I_STEP]) + 1
            t = ps.t0 + step * dt
            where = (f"t={t:.6g} s, rotor period {step / spp:.2f} of {periods} "
                     f"(step {step})")
            if status == nm.CONTACT and elements is not None:
                m = nl.size
                f_q, f_v = smp["fail"][:m], smp["fail"][m:2 * m]   # the last iterate
                where += (": the step's Newton iterates left the element's force law "
                          "(state of the last iterate)")
                err = elements.located_contact(f_q, f_v, where)
                err.time, err.period = t, step / spp
                raise err
            raise ConvergenceError(f"time integration: {MESSAGES.get(status)} at {where}")
        done += k
        if done == snap:
            snapshot = (out(state.X[:r]).copy(), out(state.X[r:2 * r]).copy(),
                        ps.t0 + state.step * dt)
        if progress is not None:
            progress(done)
        if not window:
            continue
        keep = smp["t"] >= ps.t0 + (rec_start - 0.5) * dt
        parts["t"].append(smp["t"][keep])
        parts["q"].append(out(smp["q"][keep], c_rd))
        parts["v"].append(out(smp["v"][keep], c_rd))
        parts["qn"].append(q_nl[keep])
        parts["vn"].append(out(smp["v"][keep], c_nl))
        keep = smp["pt"] >= ps.t0 + (pc_start - 0.5) * dt
        parts["pt"].append(smp["pt"][keep])
        parts["pq"].append(out(smp["pq"][keep], c_rd))
        parts["pv"].append(out(smp["pv"][keep], c_rd))
    cat = {k: np.concatenate(v) for k, v in parts.items()}
    q_end, v_end = out(state.X[:r]).copy(), out(state.X[r:2 * r]).copy()
    return Trajectory(cat["t"], cat["q"], cat["v"], cat["pt"], cat["pq"], cat["pv"], rd,
                      q_end, v_end, ps.t0 + state.step * dt,
                      eps_max if limited else None, newton_max, snapshot,
                      elements.diagnostics(cat["qn"], cat["vn"])
                      if elements is not None and len(elements) and cat["qn"].shape[0] else {})
