"""The stepping of a census start (:mod:`~rotorsfd.analyses.attractors`), prepared once.

:func:`~rotorsfd.analyses.td_integration.integrate_periods` prepares the step (effective
matrix factorised, loads packed) and projects the final state back to physical
coordinates at every call, and records every coordinate of the recorded periods; a census
start calls it once per check chunk of ``check_periods`` periods. Here the
:class:`~rotorsfd.timedomain.step_records.PreparedSystem` is built once per batch of
starts on the grid ``t_k = k T / N`` from ``t = 0`` (every start begins there) and each
start's :class:`~rotorsfd.timedomain.step_records.StepState` is carried from chunk to
chunk in the stepped (reduced) coordinates ``p``: the same Newmark recursion

    p_{k+1} = step(p_k, v_k, F_nl(q_nl, v_nl), t_k)

with ``q = Psi p`` formed only for what the census reads (the nonlinear DOFs' Poincare
points ``q_nl(j T)``, every step of the last recorded periods, the final state). Chunk
boundaries change nothing but rounding (no restart from the projected state).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from rotorsfd.analyses.td_integration import TimeDomainInputs
from rotorsfd.errors import ConvergenceError
from rotorsfd.timedomain import newmark as nm
from rotorsfd.timedomain.integrate import MESSAGES, initial_state, prepare_system, run
from rotorsfd.timedomain.step_records import StepState


@dataclass
class Chunk:
    """What one chunk gives the census (physical nonlinear DOFs, columns ``nl_dofs``):
    the Poincare points of its periods ``(pt, pq, pv)``, every step of its last recorded
    periods ``(t, q, v)`` and the elements' diagnostics over them."""

    pt: np.ndarray
    pq: np.ndarray
    pv: np.ndarray
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    element_diagnostics: dict[str, float] = field(default_factory=dict)


class StartStepper:
    """The step of ``inputs`` at ``T / steps_per_period`` over ``horizon`` periods from
    ``t = 0``, for any number of starts (:meth:`start`, then :meth:`advance`)."""

    def __init__(self, inputs: TimeDomainInputs, steps_per_period: int, horizon: int
                 ) -> None:
        self.inputs = inputs
        self.spp = int(steps_per_period)
        self.red = inputs.reduction
        stepped = self.red.stepped(inputs) if self.red is not None else inputs
        self.ps = prepare_system(stepped, inputs.period / self.spp,
                                 self.spp * int(horizon), t0=0.0)
        self.nl = np.asarray(inputs.nl_dofs, dtype=np.int64)
        self.r = self.ps.n_dof
        # stepped coordinates recorded: all of them when reduced (q_nl = Psi[nl] p)
        self.rec = (np.arange(self.r, dtype=np.int64) if self.red is not None
                    else self.nl)

    def physical_nl(self, x: np.ndarray) -> np.ndarray:
        """``q_nl`` of recorded stepped samples ``x (samples, len(rec))``."""
        return x if self.red is None else self.red.physical(x, self.nl)

    def start(self, q0: np.ndarray, v0: np.ndarray) -> StepState:
        """The state at ``t = 0`` of the physical ``(q0, v0)``."""
        if self.red is None:
            return initial_state(self.ps, q0, v0)
        return initial_state(self.ps, self.red.reduce(q0), self.red.reduce(v0))

    def time(self, state: StepState) -> float:
        return self.ps.t0 + state.step * self.ps.ops.dt

    def final(self, state: StepState) -> tuple[np.ndarray, np.ndarray, float]:
        """The physical ``(q, v, t)`` of ``state``."""
        q, v = state.X[:self.r], state.X[self.r:2 * self.r]
        if self.red is not None:
            q, v = self.red.physical(q), self.red.physical(v)
        return q.copy(), v.copy(), self.time(state)

    def advance(self, state: StepState, periods: int, record_periods: int) -> Chunk:
        """Step ``state`` in place by ``periods`` periods; record every step of the last
        ``record_periods``. A state outside an element's law raises that element's
        contact error, another failure :class:`ConvergenceError`."""
        spp, k_a = self.spp, state.step
        k_b = k_a + periods * spp
        status, smp, info = run(self.ps, state, periods * spp, record_dofs=self.rec,
                                record_every=1, record_start=k_b - record_periods * spp,
                                poincare_every=spp, poincare_start=0)
        if status != nm.OK:
            step = int(info[nm.I_STEP]) + 1
            t = self.ps.t0 + step * self.ps.ops.dt
            where = (f"t={t:.6g} s, rotor period {(step - k_a) / spp:.2f} of {periods} "
                     f"(step {step - k_a})")
            elements = self.inputs.elements
            if status != nm.CONTACT or elements is None:
                raise ConvergenceError(f"time integration: {MESSAGES.get(status)} at "
                                       f"{where}")
            m = self.nl.size
            err = elements.located_contact(smp["fail"][:m], smp["fail"][m:2 * m], where +
                                           ": the step's Newton iterates left the "
                                           "element's force law (state of the last "
                                           "iterate)")
            err.time, err.period = t, step / spp
            raise err
        q, v = self.physical_nl(smp["q"]), self.physical_nl(smp["v"])
        elements = self.inputs.elements
        diag = (elements.diagnostics(q, v) if elements is not None and len(elements)
                and q.shape[0] else {})
        keep = smp["pt"] > self.time(state) - (periods - 0.5) * self.inputs.period
        return Chunk(smp["pt"][keep], self.physical_nl(smp["pq"][keep]),
                     self.physical_nl(smp["pv"][keep]), smp["t"], q, v, diag)
