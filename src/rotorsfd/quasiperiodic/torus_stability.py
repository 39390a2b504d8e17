"""Stability of a torus by its largest Lyapunov exponent: a short time integration
started on the HB torus (issue 19 item 4, the Lyapunov route).

From the torus' state at t = 0 (phases (0, 0)),

    q(0) = Re sum_k X_k,   q'(0) = Re sum_k i omega_k X_k,

the compiled Newmark code (which runs the harmonic base law) integrates the rotor and two
nearby trajectories (Benettin et al. 1980; :func:`~rotorsfd.analyses.td_lyapunov.
lyapunov_pair`): the exponent with the neutral, undamped high modes projected out
(``reduced``, the one that classifies, as for simulated motions) and that of the whole
state (``full``). A torus is stable when the reduced exponent plus its uncertainty is
below zero; on a stable torus it is the decay rate of the least damped perturbation.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.td_integration import time_domain_inputs
from rotorsfd.analyses.td_lyapunov import LyapunovPair, lyapunov_pair
from rotorsfd.model.system import RotorSystem
from rotorsfd.quasiperiodic.torus_continuation import TorusBranch
from rotorsfd.quasiperiodic.torus_fourier import TorusLattice

FloatArray = NDArray[np.float64]


def torus_state(lattice: TorusLattice, X: NDArray[np.complex128], omega: float, wb: float
                ) -> tuple[FloatArray, FloatArray]:
    """(q(0), q'(0)) of the torus at phases (0, 0), all DOFs."""
    w = lattice.frequencies(omega, wb)
    return X.sum(axis=0).real, (1j * w[:, None] * X).sum(axis=0).real


@dataclass(frozen=True)
class TorusLyapunov:
    """The exponents [1/s] of one torus (``pair``), per rotor period ``T = 2 pi / Omega``
    (``per_period``, reduced) with its uncertainty, and the verdict."""

    pair: LyapunovPair
    per_period: float
    uncertainty: float

    @property
    def stable(self) -> bool:
        return self.per_period + self.uncertainty < 0.0


def torus_lyapunov(system: RotorSystem, lattice: TorusLattice, X: NDArray[np.complex128],
                   omega: float, wb: float, *, steps_per_period: int = 200,
                   periods: int = 200) -> TorusLyapunov:
    """The largest Lyapunov exponent of the motion started on the torus X (nk, n) at the
    speed ``omega`` (the system's base law at ``wb``), over ``periods`` rotor periods."""
    inputs = time_domain_inputs(system, float(omega))
    q0, v0 = torus_state(lattice, X, omega, wb)
    pair = lyapunov_pair(inputs, (q0, v0, 0.0), steps_per_period=steps_per_period,
                         periods=periods)
    T = inputs.period
    return TorusLyapunov(pair, float(pair.reduced.exponent) * T,
                         float(pair.reduced.half_spread) * T)


def branch_lyapunov(system: RotorSystem, branch: TorusBranch, *, stride: int = 1,
                    steps_per_period: int = 200, periods: int = 200
                    ) -> dict[int, TorusLyapunov]:
    """:func:`torus_lyapunov` at every ``stride``-th point of a speed branch (and its last
    point), keyed by the point's index."""
    idx = sorted(set(range(0, branch.n_points, max(1, int(stride)))) | {branch.n_points - 1})
    return {i: torus_lyapunov(system, branch.lattice, branch.X[i], float(branch.omega[i]),
                              float(branch.wb[i]), steps_per_period=steps_per_period,
                              periods=periods) for i in idx}
