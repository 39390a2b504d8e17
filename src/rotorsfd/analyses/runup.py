"""Integrator inputs and the run of a rotor under a speed law Omega(t) (run-up, coast-down).

    M q'' + (C + Omega(t) G + C_base(t)) q' + (K + K_base(t) - Omega'(t) P21) q
        = F_mu(t) + F_base(t) + F_nl

with ``P21 = (PS + PJ) / 2`` the polar-inertia pattern on (tz, ty) of
:mod:`rotorsfd.model.base_terms` (``-Ip Omega'`` at (tz, ty) for a disk) and the unbalance
at the rotor angle ``phi = theta(t) + eta``, ``theta = int Omega``
(:mod:`rotorsfd.timedomain.speed_law` derives both):

    F_y = U [A_y cos(phi) + B_y sin(phi)],  F_z = U [A_z sin(phi) - B_z cos(phi)]
    A_y = Omega^2 + 2 Omega wx + wx^2 + wz^2,  B_y = wx' + Omega' - wy wz
    A_z = Omega^2 + 2 Omega wx + wx^2 + wy^2,  B_z = wx' + Omega' + wy wz

The base terms are those of :func:`rotorsfd.model.base_terms.time_varying_terms` at
speed 0 plus their part linear in the speed at Omega(t): ``Omega wx (P11 + P22)`` in K and
``-Omega wz pty + Omega wy ptz`` in F. Above :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF`
DOFs every matrix stays in the band (CSR; a modal damping of a few modes as
:class:`~rotorsfd.model.lowrank.BandedLowRank`), no dense n x n array: the reduced step
(``reduction = "auto"``, :func:`~rotorsfd.analyses.td_integration.with_reduction`)
projects them term by term; only the full step (``"none"``) densifies them.
The step is ``dt = 2 pi / (Omega_max steps_per_period)`` with ``Omega_max`` the
highest speed of the run.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, replace
from typing import Any

import numpy as np

from rotorsfd.analyses.td_integration import TimeDomainInputs, integrate_periods, with_reduction
from rotorsfd.errors import ConfigError
from rotorsfd.model import dofs
from rotorsfd.model.base_terms import base_basis, keeps_band, time_varying_terms
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.time_terms import banded_rotor_terms
from rotorsfd.model.unbalance import unbalance_series_law
from rotorsfd.timedomain import Forcing, TimeVaryingMatrices
from rotorsfd.timedomain.speed_law import FIELD, SpeedLaw, speed_range


def speed_law_inputs(system: RotorSystem, law: SpeedLaw, t_end: float) -> TimeDomainInputs:
    """Integrator inputs of ``system`` under ``law`` on [0, t_end] (module docstring);
    ``speed`` of the result is the highest speed of the run (it sets the step)."""
    if not (math.isfinite(t_end) and t_end > 0.0):
        raise ConfigError(f"{FIELD}.duration", t_end, "the run must last > 0 s")
    if system.elements.depends_on("speed"):
        raise ConfigError(FIELD, "an element whose law depends on the speed",
                          "a speed law needs elements independent of the speed "
                          "(a journal bearing needs a constant speed)")
    _, w_max = speed_range(law, t_end)
    r = system.rotor
    el = system.elements_at(w_max)
    kernel, params = (el.kernel, el.kernel_params) if len(el) else (None, None)
    basis = base_basis(r)
    banded = banded_rotor_terms(r)          # above DENSE_MAX_DOF: CSR (+ low rank)
    sparse = banded is not None and keeps_band(r.n_dof)

    def pattern(name: str) -> Any:
        return basis.sparse_matrix(name) if sparse else basis.matrix(name)

    M, C, K, G = (np.asarray(r.M, float), np.asarray(r.C, float).copy(),
                  np.asarray(r.K, float).copy(), np.asarray(r.G, float)) \
        if banded is None else (banded[0], banded[1].copy(), banded[2].copy(), banded[3])
    P21 = 0.5 * (pattern("PS") + pattern("PJ"))
    damping: list[tuple[Any, Any]] = [(law.omega, G)]
    stiffness: list[tuple[Any, Any]] = []
    if (P21.count_nonzero() if sparse else np.count_nonzero(P21)):
        stiffness.append((lambda t: -law.domega(t), P21))
    series: list[tuple[Any, np.ndarray]] = []
    if not system.base.is_fixed:
        motion = system.base
        c_b, k_b, f_b = time_varying_terms(basis, motion, 0.0, sparse=sparse)
        damping += c_b
        stiffness += k_b

        def w(t, i):
            return np.broadcast_to(np.asarray(motion.state(t).w, float)[i],
                                   np.shape(t)) * law.omega(t)

        stiffness += [(lambda t: w(t, 0), pattern("P11") + pattern("P22"))]
        series += [*f_b, (lambda t: -w(t, 2), basis.vector("pty")),
                   (lambda t: w(t, 1), basis.vector("ptz"))]
    series += unbalance_series_law(system.unbalances, r.n_dof, law,
                                   None if system.base.is_fixed else system.base)
    forcing = Forcing(omega=w_max, series=series)
    tv = TimeVaryingMatrices(damping=damping, stiffness=stiffness)
    return TimeDomainInputs(M, C, K, system.nl_dofs, kernel, params, forcing, tv,
                            float(w_max), el)


@dataclass
class SpeedLawRun:
    """Every step of a run under a speed law: ``q``, ``v`` (nt, len(dofs)) at ``t`` with
    the speed ``omega`` and the rotor angle ``theta`` there."""

    t: np.ndarray
    omega: np.ndarray
    theta: np.ndarray
    q: np.ndarray
    v: np.ndarray
    dofs: np.ndarray
    q_final: np.ndarray
    v_final: np.ndarray
    max_eccentricity_run: float | None
    law: Any

    def radius(self, node: int) -> np.ndarray:
        """Orbit radius ``sqrt(y^2 + z^2)`` of a 1-based node against time."""
        cols = [int(np.flatnonzero(self.dofs == dofs.dof_index(node, d))[0])
                for d in ("y", "z")]
        return np.hypot(self.q[:, cols[0]], self.q[:, cols[1]])


def run_speed_law(system: RotorSystem | None, law: SpeedLaw, t_end: float, *,
                  steps_per_period: int, record_dofs: Sequence[int],
                  q0: Any = 0.0, v0: Any = 0.0, inputs: TimeDomainInputs | None = None,
                  method_options: dict[str, Any] | None = None,
                  reduction: str = "none") -> SpeedLawRun:
    """Integrate ``system`` (or the given ``inputs``) under ``law`` from ``(q0, v0)`` at
    t = 0 to ``t_end`` (rounded up to whole periods of the highest speed)."""
    if inputs is None:
        if system is None:
            raise ValueError("run_speed_law needs a system or inputs")
        inputs = speed_law_inputs(system, law, t_end)
    if reduction != "none":
        inputs = with_reduction(inputs, reduction)
    else:
        inputs = replace(inputs, reduction=None)
    periods = max(1, math.ceil(t_end / inputs.period - 1e-9))
    tr = integrate_periods(inputs, q0, v0, steps_per_period=steps_per_period,
                           periods=periods, record_dofs=record_dofs, record_periods=periods,
                           poincare_periods=1, method_options=method_options)
    return SpeedLawRun(tr.t, law.omega(tr.t), law.angle(tr.t), tr.q, tr.v, tr.dofs,
                       tr.q_final, tr.v_final, tr.max_eccentricity_run, law)
