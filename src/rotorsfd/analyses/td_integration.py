"""Inputs of the time integrator at one rotor speed, and the chunked integration over
whole rotor periods that :mod:`~rotorsfd.analyses.simulate`,
:mod:`~rotorsfd.analyses.step_control` and :mod:`~rotorsfd.analyses.bifurcation_diagram`
run.

    M q'' + (C + Omega G + C_base(t)) q' + (K + K_base(t)) q = F_mu(t) + F_base(t) + F_sfd

stepped by :func:`rotorsfd.timedomain.integrate` with ``dt = T / steps_per_period``,
``T = 2 pi / Omega``; Poincare points once per rotor period at ``t = t0 + k T``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rotorsfd.elements.composite import ElementSet
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.model.system import RotorSystem
from rotorsfd.timedomain import Forcing, HarmonicLoad, TimeVaryingMatrices
from rotorsfd.timedomain import newmark as nm
from rotorsfd.timedomain.integrate import MESSAGES, initial_state, prepare, run

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

    @property
    def period(self) -> float:
        """Rotor period T = 2 pi / Omega [s]."""
        return 2.0 * math.pi / self.speed


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
    el = system.elements
    kernel, params = (el.kernel, el.kernel_params) if len(el) else (None, None)
    if system.base.is_constant:
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
                            span * (np.arange(1, 64) * math.sqrt(2.0) % 1.0)])
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
    """
    spp = int(steps_per_period)
    n_steps = spp * int(periods)
    dt = inputs.period / spp
    ps = prepare(inputs.M, inputs.D, inputs.K, inputs.nl_dofs, inputs.kernel, inputs.params,
                 inputs.forcing, dt, n_steps, t0=t0, time_varying=inputs.time_varying,
                 **(method_options or {}))
    nl = ps.nl
    elements = inputs.elements
    limited = elements is not None and any(e.limit_label is not None for e in elements)
    rd = np.asarray(record_dofs, dtype=np.int64)
    rec_all = np.concatenate([rd, nl]).astype(np.int64)
    rec_start = (periods - record_periods) * spp
    pc_start = (periods - poincare_periods + 1) * spp
    state = initial_state(ps, q0, v0)
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
        status, smp, info = run(ps, state, k * spp, record_dofs=rec_all, record_every=1,
                                record_start=0, poincare_every=spp, poincare_start=0,
                                record_initial=(done == 0))
        newton_max = max(newton_max, int(info[nm.I_NEWTON_MAX]))
        if limited and smp["q"].shape[0]:
            eps_max = max(eps_max, elements.limit(smp["q"][:, rd.size:]))
        if status != nm.OK:
            step = int(info[nm.I_STEP]) + 1
            t = ps.t0 + step * dt
            where = (f"t={t:.6g} s, rotor period {step / spp:.2f} of {periods} "
                     f"(step {step})")
            if status == nm.CONTACT and elements is not None:
                m = nl.size
                q_nl, v_nl = smp["fail"][:m], smp["fail"][m:2 * m]   # the last iterate
                where += (": the step's Newton iterates left the element's force law "
                          "(state of the last iterate)")
                err = elements.located_contact(q_nl, v_nl, where)
                err.time, err.period = t, step / spp
                raise err
            raise ConvergenceError(f"time integration: {MESSAGES.get(status)} at {where}")
        keep = smp["t"] >= ps.t0 + (rec_start - 0.5) * dt
        parts["t"].append(smp["t"][keep])
        parts["q"].append(smp["q"][keep, :rd.size])
        parts["v"].append(smp["v"][keep, :rd.size])
        parts["qn"].append(smp["q"][keep, rd.size:])
        parts["vn"].append(smp["v"][keep, rd.size:])
        keep = smp["pt"] >= ps.t0 + (pc_start - 0.5) * dt
        parts["pt"].append(smp["pt"][keep])
        parts["pq"].append(smp["pq"][keep, :rd.size])
        parts["pv"].append(smp["pv"][keep, :rd.size])
        done += k
        if done == snap:
            snapshot = (state.X[:ps.n_dof].copy(), state.X[ps.n_dof:2 * ps.n_dof].copy(),
                        ps.t0 + state.step * dt)
        if progress is not None:
            progress(done)
    n = ps.n_dof
    cat = {k: np.concatenate(v) for k, v in parts.items()}
    return Trajectory(cat["t"], cat["q"], cat["v"], cat["pt"], cat["pq"], cat["pv"], rd,
                      state.X[:n].copy(), state.X[n:2 * n].copy(), ps.t0 + state.step * dt,
                      eps_max if limited else None, newton_max, snapshot,
                      elements.diagnostics(cat["qn"], cat["vn"])
                      if elements is not None and len(elements) and cat["qn"].shape[0] else {})

