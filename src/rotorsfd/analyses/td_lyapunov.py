"""The largest Lyapunov exponent of a simulated motion, with the neutral high modes apart.

The rotor model has no structural damping: a bending mode whose shape barely moves the
SFD journal is almost undamped, and Newmark average acceleration (non-dissipative) keeps
its free vibration. In the two-trajectory (Benettin) estimate such a direction neither
grows nor decays, so the estimate of a stable periodic orbit tends to 0 (+0.006 +/- 0.007
per period was reported for stable orbits) instead of ``ln |mu|max`` of its Floquet
multipliers. Here the exponent is measured twice from the final state:

- ``reduced``: the perturbation projected (M-orthogonally) on the Craig-Bampton basis of
  the SFD DOFs and the fixed-interface modes with ``omega <= 100 / T`` (the reduced model
  of the Floquet analysis at its default 400 intervals, ``omega_max = n_intervals / (4
  T)``) at the start and at every renormalisation: the high modes neither grow nor enter
  the separation. This is the exponent that classifies; on a stable period-1 orbit it is
  ``ln |mu|max`` per period;
- ``full``: the whole state (reported apart; about 0 whenever a neutral mode exists).

The exponent is the mean over the renormalisations after the first 20 % (the alignment of
the random start), its uncertainty the difference of the two halves' means
(``half_spread``).
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from rotorsfd.analyses.td_integration import TimeDomainInputs
from rotorsfd.errors import ConfigError
from rotorsfd.stability.reduction import craig_bampton
from rotorsfd.timedomain import LyapunovResult
from rotorsfd.timedomain.lyapunov import Projector, lyapunov_exponents, modal_projector

#: Kept fixed-interface modes: ``omega <= HIGH_MODE_LIMIT / T`` (Floquet's 400 / 4).
HIGH_MODE_LIMIT = 100.0


@dataclass(frozen=True)
class LyapunovPair:
    """The exponent with the high modes excluded (``reduced``) and of the whole state
    (``full``); ``omega_max`` [rad/s] the highest kept mode's limit, ``n_modes`` the
    kept fixed-interface modes (None: no reduction possible, ``reduced`` is ``full``)."""

    reduced: LyapunovResult
    full: LyapunovResult
    omega_max: float | None
    n_modes: int | None


def lyapunov_estimate(ly: LyapunovResult, period: float,
                      skip_fraction: float = 0.2) -> LyapunovResult:
    """The exponent over the renormalisations after the first ``skip_fraction``: the first
    intervals measure the alignment of the random initial perturbation (its high-mode
    content grows by orders of magnitude in the weighted norm within one period), a
    constant offset that decays only like 1/t in the running mean."""
    n = ly.history.size
    k = int(skip_fraction * n)
    if k < 1 or n - k < 2:
        return ly
    t_start = ly.times[0] - (ly.times[1] - ly.times[0])
    cum = ly.history * (ly.times - t_start)          # running sum of ln(d_j / d0)
    lam = float((cum[-1] - cum[k - 1]) / (ly.times[-1] - ly.times[k - 1]))
    mid = (k - 1 + n - 1) // 2
    first = (cum[mid] - cum[k - 1]) / (ly.times[mid] - ly.times[k - 1])
    second = (cum[-1] - cum[mid]) / (ly.times[-1] - ly.times[mid])
    return dataclasses.replace(ly, exponent=lam, per_period=lam * period,
                               half_spread=float(abs(second - first)))


def high_mode_projector(inputs: TimeDomainInputs) -> tuple[Projector, float, int] | None:
    """Projector on the Craig-Bampton basis (SFD DOFs + modes with ``omega <= 100 / T``),
    its ``omega_max`` and the number of kept modes; None without nonlinear DOFs or with
    a singular interior (nothing to exclude reliably)."""
    if inputs.nl_dofs.size == 0:
        return None
    omega_max = HIGH_MODE_LIMIT / inputs.period
    try:
        red = craig_bampton(inputs.M, inputs.D, inputs.K, inputs.nl_dofs,
                            omega_max=omega_max)
    except (ConfigError, np.linalg.LinAlgError):
        return None
    if red.basis.shape[1] >= inputs.M.shape[0]:
        return None
    return modal_projector(inputs.M, red.basis), omega_max, int(red.omegas.size)


def lyapunov_pair(inputs: TimeDomainInputs, state: tuple[np.ndarray, np.ndarray, float], *,
                  steps_per_period: int, periods: int) -> LyapunovPair:
    """Both exponents from ``state = (q, v, t)`` over ``periods`` periods (module
    docstring), the two perturbations around one reference trajectory (three
    trajectories in all). Contact or Newton failures propagate."""
    q0, v0, t0 = state
    T = inputs.period
    proj = high_mode_projector(inputs)
    projectors = (None,) if proj is None else (None, proj[0])
    found = lyapunov_exponents(inputs.M, inputs.D, inputs.K, inputs.nl_dofs, inputs.kernel,
                               inputs.params, inputs.forcing,
                               steps_per_period=steps_per_period, n_periods=periods, q0=q0,
                               v0=v0, t0=t0, time_varying=inputs.time_varying,
                               method="newmark", projectors=projectors,
                               inertial_kernel=None if inputs.elements is None
                               else inputs.elements.inertial_kernel)
    full = lyapunov_estimate(found[0], T)
    if proj is None:
        return LyapunovPair(full, full, None, None)
    return LyapunovPair(lyapunov_estimate(found[1], T), full, proj[1], proj[2])


def uncertainty_per_period(ly: LyapunovResult, period: float) -> float:
    """The exponent's uncertainty per period ``T`` (``half_spread`` times T)."""
    return float(ly.half_spread) * float(period)
