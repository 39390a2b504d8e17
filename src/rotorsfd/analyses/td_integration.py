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

from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.model.system import RotorSystem
from rotorsfd.second_order import SecondOrderSystem
from rotorsfd.timedomain import newmark as nm
from rotorsfd.timedomain.integrate import MESSAGES, initial_state, prepare_system, run
from rotorsfd.timedomain.reduced import reduce_system

FIELD = "analysis.simulate"
DIRECTIONS = ("y", "z")


# ---- inputs of the integrator ------------------------------------------------------------


TimeDomainInputs = SecondOrderSystem
"""The integrator's inputs at one rotor speed: the solvers' record
:class:`~rotorsfd.second_order.SecondOrderSystem` (``RotorSystem.second_order(speed)``,
with ``reduction`` the Craig-Bampton model the step runs on)."""


REDUCTIONS = ("auto", "none")
REDUCTION_CUTOFF = 40.0
"""Default cutoff of the reduced step, ``omega_max = REDUCTION_CUTOFF Omega``
(``analysis.simulate.reduction_cutoff``; see :func:`with_reduction`)."""


def refuse_large_full_step(n_dof: int) -> None:
    """ConfigError for ``reduction = "none"`` on a model above
    :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs: the full step forms the dense
    n x 2n step operator ``K_eff^-1 [-2K, 4/h M]`` (O(n^3) to prepare, O(n^2) a step:
    hours and GiB at 5000 DOFs), and no banded full step exists."""
    if n_dof > DENSE_MAX_DOF:
        raise ConfigError(f"{FIELD}.reduction", "none",
                          f'the full step (a dense n x 2n step operator) is allowed up to '
                          f'{DENSE_MAX_DOF} DOFs and this model has {n_dof}: use "auto"')


def with_reduction(inputs: TimeDomainInputs, reduction: str = "auto",
                   cutoff: float = REDUCTION_CUTOFF) -> TimeDomainInputs:
    """``inputs`` with the reduced step of ``reduction``: ``"auto"`` the Craig-Bampton
    model on the nonlinear DOFs and the fixed-interface modes with
    ``omega <= cutoff Omega`` when it has fewer coordinates than the model (and the
    interior is restrained once the nonlinear DOFs are fixed: no fixed-interface mode
    below ``1e-6`` of the cutoff), else the full step;
    ``"none"`` the full step. The full step is refused above ``DENSE_MAX_DOF`` DOFs
    (:func:`refuse_large_full_step`; for ``"auto"`` without a Craig-Bampton model too)."""
    if reduction not in REDUCTIONS:
        raise ConfigError(f"{FIELD}.reduction", reduction, '"auto" or "none"')
    if not cutoff > 0.0:
        raise ConfigError(f"{FIELD}.reduction_cutoff", cutoff, "must be > 0")
    if reduction == "none":
        refuse_large_full_step(inputs.n_dof)
        return replace(inputs, reduction=None)
    try:
        red = reduce_system(inputs, cutoff * inputs.speed)
    except (ConfigError, np.linalg.LinAlgError):  # a free interior: no Craig-Bampton model
        return _full_step_instead(inputs, "it fails")
    omegas = red.model.omegas
    mechanism = (omegas.size and omegas[0] < 1e-6 * red.omega_max) or not np.all(
        np.isfinite(red.basis))                        # a (nearly) free interior
    if mechanism:
        return _full_step_instead(inputs, "the interior is free once the nonlinear DOFs "
                                          "are fixed")
    return replace(inputs, reduction=red if red.n_dof < inputs.n_dof else None)


def _full_step_instead(inputs: TimeDomainInputs, why: str) -> TimeDomainInputs:
    """The full step where ``"auto"`` has no Craig-Bampton model (``why``); ConfigError
    above ``DENSE_MAX_DOF`` DOFs, where the full step is refused
    (:func:`refuse_large_full_step`)."""
    if inputs.n_dof > DENSE_MAX_DOF:
        raise ConfigError(f"{FIELD}.reduction", "auto",
                          f"no Craig-Bampton model of this {inputs.n_dof}-DOF model ({why}), "
                          f"and the full step is allowed up to {DENSE_MAX_DOF} DOFs")
    return replace(inputs, reduction=None)


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
    return red.stepped(inputs), (red.reduce(q), red.reduce(v), t)


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
    # read at call time, so that a patched reduced.DENSE_MAX (tests) applies
    from rotorsfd.timedomain.reduced import DENSE_MAX

    red = inputs.reduction
    if red is None:
        return {}
    full = replace(inputs, reduction=None)
    if inputs.n_dof <= DENSE_MAX:
        ref, label = full, "full step"
    else:
        factor = CHECK_FACTOR * red.omega_max / inputs.speed
        try:
            ref = with_reduction(full, "auto", factor)
        except ConfigError:                # never the dense full step of a large model
            return {}
        if ref.reduction is None:
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


def time_domain_inputs(system: RotorSystem, speed: float, *,
                       horizon: float | None = None) -> TimeDomainInputs:
    """Integrator inputs of ``system`` at rotor speed ``speed`` [rad/s]:
    :meth:`RotorSystem.second_order <rotorsfd.model.system.RotorSystem.second_order>`
    (``horizon`` [s], default 1000 rotor periods: the interval on which a base
    coefficient must be constant to be folded into the constant matrices)."""
    return system.second_order(speed, horizon=horizon)


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
    ended: Exception | None = None    #: the contact error that ended the run early


def integrate_periods(inputs: TimeDomainInputs, q0: Any, v0: Any, *, steps_per_period: int,
                      periods: int, record_dofs: Sequence[int], record_periods: int,
                      poincare_periods: int, method_options: dict[str, Any] | None = None,
                      chunk_periods: int | None = None, progress: Any = None,
                      t0: float = 0.0, snapshot_period: int | None = None,
                      on_contact: str = "raise") -> Trajectory:
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

    ``on_contact="end"``: a state outside an element's law ends the run as a result
    (issue 22): the Trajectory holds the recorded periods up to the last converged step
    (every step of at most the last ``max(record_periods, poincare_periods)`` periods
    before it, with their Poincare points), its state there as the final state, and the
    element's contact error in ``ended``: the state at the start of every chunk is kept
    (a copy of the step state, nothing recorded), and the periods before the contact are
    integrated again from the one that starts them (the same arithmetic, the same values).

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
        stepped = inputs
        x0, xv0 = q0, v0
        rec_all = rows

        def out(x: np.ndarray, cols: np.ndarray | None = None) -> np.ndarray:
            return x if cols is None else x[..., cols]
    else:
        stepped = red.stepped(inputs)
        x0, xv0 = red.reduce(q0), red.reduce(v0)
        rec_all = np.arange(red.n_dof, dtype=np.int64)          # every reduced coordinate

        def out(x: np.ndarray, cols: np.ndarray | None = None) -> np.ndarray:
            return red.physical(x, None if cols is None else rows[cols])
    ps = prepare_system(stepped, dt, n_steps, t0=t0, options=method_options)
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
    if on_contact not in ("raise", "end"):
        raise ValueError(f"on_contact must be 'raise' or 'end', got {on_contact!r}")
    tail = on_contact == "end"     # keep the chunk starts: the periods before a contact
    ended = None
    starts: list[Any] = []
    while done < periods:
        k = min(chunk, periods - done)
        if snap is not None and done < snap:
            k = min(k, snap - done)
        # a chunk before the kept windows records only the elements' DOFs (for the limit)
        window = (done + k) * spp >= first_kept
        if tail:
            starts.append(state.copy())
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
            if status != nm.CONTACT or elements is None:
                raise ConvergenceError(f"time integration: {MESSAGES.get(status)} at "
                                       f"{where}")
            m = nl.size
            f_q, f_v = smp["fail"][:m], smp["fail"][m:2 * m]   # the last iterate
            where += (": the step's Newton iterates left the element's force law "
                      "(state of the last iterate)")
            err = elements.located_contact(f_q, f_v, where)
            err.time, err.period = t, step / spp
            if not tail:
                raise err
            ended = err
            parts = _before_contact(ps, starts, state.step, rec_all, spp,
                                    max(record_periods, poincare_periods) * spp)
            break
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
    if ended is not None:
        parts = _kept_tail(parts, out, c_rd, c_nl, ps.t0 + state.step * dt, dt,
                           record_periods * spp, (poincare_periods - 1) * spp)
    cat = {k: np.concatenate(v) if v else np.zeros((0, rd.size)) for k, v in parts.items()}
    cat["t"], cat["pt"] = cat["t"].reshape(-1), cat["pt"].reshape(-1)
    q_end, v_end = out(state.X[:r]).copy(), out(state.X[r:2 * r]).copy()
    return Trajectory(cat["t"], cat["q"], cat["v"], cat["pt"], cat["pq"], cat["pv"], rd,
                      q_end, v_end, ps.t0 + state.step * dt,
                      eps_max if limited else None, newton_max, snapshot,
                      elements.diagnostics(cat["qn"], cat["vn"])
                      if elements is not None and len(elements) and cat["qn"].shape[0] else {},
                      ended)


def _before_contact(ps: Any, starts: list[Any], last: int, rows: np.ndarray, spp: int,
                    n_keep: int) -> dict[str, list[np.ndarray]]:
    """The raw samples (every step, Poincare points every ``spp``) of the columns ``rows``
    from the latest kept chunk start at least ``n_keep`` steps before step ``last`` (the
    last converged one) up to it: integrated again from that start's copied state."""
    first = next((st for st in reversed(starts) if st.step <= last - n_keep), starts[0])
    st = first.copy()
    _, smp, _ = run(ps, st, last - st.step, record_dofs=rows, record_every=1,
                    record_start=0, poincare_every=spp, poincare_start=0)
    return {k: [smp[key]] for k, key in (("t", "t"), ("q", "q"), ("v", "v"), ("pt", "pt"),
                                         ("pq", "pq"), ("pv", "pv"))}


def _kept_tail(raw: dict[str, list[np.ndarray]], out: Any, c_rd: np.ndarray,
               c_nl: np.ndarray, t_end: float, dt: float, n_record: int, n_poincare: int
               ) -> dict[str, list[np.ndarray]]:
    """The samples of an ``on_contact="end"`` run before its contact as the Trajectory's
    parts: every step of the last ``n_record`` steps before ``t_end`` and the Poincare
    points from ``n_poincare`` steps before it, in physical rows."""
    parts: dict[str, list[np.ndarray]] = {k: [] for k in ("t", "q", "v", "pt", "pq", "pv",
                                                          "qn", "vn")}
    for t, q, v, pt, pq, pv in zip(*(raw[k] for k in ("t", "q", "v", "pt", "pq", "pv")),
                                   strict=True):
        keep = t >= t_end - (n_record + 0.5) * dt
        parts["t"].append(t[keep])
        parts["q"].append(out(q[keep], c_rd))
        parts["v"].append(out(v[keep], c_rd))
        parts["qn"].append(out(q[keep], c_nl))
        parts["vn"].append(out(v[keep], c_nl))
        keep = pt >= t_end - (n_poincare + 0.5) * dt
        parts["pt"].append(pt[keep])
        parts["pq"].append(out(pq[keep], c_rd))
        parts["pv"].append(out(pv[keep], c_rd))
    return parts
