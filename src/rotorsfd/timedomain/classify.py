"""Motion classification: period-n, quasi-periodic or chaotic.

Decision, in this order:

1. period-n: the normalised Poincare points repeat with period ``n <= n_max``
   (``|P[k+n] - P[k]| <= rtol`` times the orbit's spread); when their differences over a
   divisor m of n shrink steadily through the window (a period-m orbit approached along a
   slowly damped spiral, :func:`~rotorsfd.timedomain.poincare.converging_period`), the
   class is period-m, not settled (``evidence["converging"]``); when they come back
   within rtol after n periods but drift on steadily through the window (more distinct
   points than n, the drift not shrinking: a torus with rotation number near 1/n,
   :func:`~rotorsfd.timedomain.poincare.steady_drift`), the motion is not periodic.
2. chaotic: a largest Lyapunov exponent above ``lyapunov_threshold`` per forcing period
   by more than its uncertainty (a :class:`LyapunovResult`'s ``half_spread``).
3. quasi-periodic: not periodic and a Lyapunov exponent at or below the threshold (within
   its uncertainty).
   Without a Lyapunov exponent (weaker): the strong spectral lines are combinations
   ``p w + r w2`` of the forcing and one incommensurate frequency (``two_frequency_min``
   of their power); without a spectrum, the Poincare points on a smooth closed curve.
4. otherwise chaotic; ``evidence["basis"]`` says which test decided.

A chaotic section may look like a thin curve (folded filaments); the Lyapunov exponent
is the decisive test, the others are evidence.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rotorsfd.timedomain.lyapunov import LyapunovResult
from rotorsfd.timedomain.poincare import (
    closed_curve_test,
    converging_period,
    correlation_dimension,
    distinct_points,
    normalise,
    poincare_period,
    steady_drift,
)
from rotorsfd.timedomain.spectrum import spectral_lines, two_frequency_fraction


@dataclass(frozen=True)
class MotionClass:
    """``motion``: ``"period-1"``, ``"period-<n>"``, ``"quasi-periodic"`` or
    ``"chaotic"``; ``evidence``: the measured quantities behind it."""

    motion: str
    evidence: dict[str, Any] = field(default_factory=dict)

    @property
    def period(self) -> int | None:
        """``n`` of a period-n motion, else ``None``."""
        return int(self.motion.split("-")[1]) if self.motion.startswith("period-") else None


def classify_motion(poincare: np.ndarray, signal: np.ndarray | None = None,
                    dt: float | None = None, omega: float | None = None,
                    lyapunov: LyapunovResult | float | None = None, *,
                    scale: np.ndarray | float | None = None, rtol: float = 1e-3,
                    n_max: int = 16, lyapunov_threshold: float = 0.01,
                    two_frequency_min: float = 0.99) -> MotionClass:
    """Classify from Poincare points ``(N, d)`` (once per forcing period, transient
    discarded), optionally a sampled ``signal (N_t,)`` or ``(N_t, d')`` with step ``dt``
    for the spectrum (first column) and the orbit's spread, the forcing ``omega``
    [rad/s] and a Lyapunov exponent (a :class:`LyapunovResult`, or a float per forcing
    period).

    ``scale`` (per coordinate of ``poincare``) defaults to the peak-to-peak of
    ``signal`` when it has as many columns as the points, else of the points.
    ``lyapunov_threshold`` is per forcing period.
    """
    P_raw = np.asarray(poincare, dtype=float)
    if P_raw.ndim == 1:
        P_raw = P_raw[:, None]
    if P_raw.shape[0] < 8:
        raise ValueError(f"need at least 8 Poincare points, got {P_raw.shape[0]}")
    if not np.all(np.isfinite(P_raw)):
        raise ValueError("non-finite Poincare points")
    sig = None if signal is None else np.asarray(signal, dtype=float)
    if sig is not None and sig.ndim == 1:
        sig = sig[:, None]
    if scale is None and sig is not None and sig.shape[1] == P_raw.shape[1]:
        scale = np.ptp(sig, axis=0)
    P = normalise(P_raw, scale)
    ev: dict[str, Any] = {"n_poincare": P.shape[0]}
    n = poincare_period(P, rtol=rtol, n_max=n_max)
    ev["n_distinct_poincare"] = distinct_points(P, tol=rtol).shape[0]
    ev["poincare_period"] = n

    spec = None
    if sig is not None and dt is not None and omega is not None and omega > 0:
        spec = spectral_lines(sig[:, 0], dt, omega)
        ev["spectral_lines"] = [(ln.frequency, ln.amplitude, ln.ratio) for ln in spec.lines]
        ev["frequency_ratios"] = [ln.ratio for ln in spec.lines]
        ev["incommensurate_ratios"] = [ln.ratio for ln in spec.incommensurate]
        ev["broadband_fraction"] = spec.broadband_fraction
    lam = None
    err = 0.0
    if isinstance(lyapunov, LyapunovResult):
        lam = lyapunov.per_period
        ev["lyapunov_exponent"] = lyapunov.exponent
        ev["lyapunov_half_spread"] = lyapunov.half_spread
        if lyapunov.exponent != 0.0 and math.isfinite(lyapunov.half_spread):
            err = abs(lyapunov.half_spread * lam / lyapunov.exponent)
    elif lyapunov is not None:
        lam = float(lyapunov)
    if lam is not None:
        ev["lyapunov_per_period"] = lam
        ev["lyapunov_uncertainty_per_period"] = err
    if n is not None:
        ev["basis"] = (f"the Poincare points repeat every {n} period"
                       + ("s" if n > 1 else "") + f" within {rtol:g} of the orbit's spread")
        conv = converging_period(P, n, rtol=rtol)
        if conv is not None:
            m, rate = conv
            ev.update(poincare_period=m, converging={"from_period": n, "to_period": m,
                                                     "shrink_per_period": rate},
                      basis=f"the Poincare points converge to a period-{m} orbit",
                      note=(f"the Poincare points look period-{n} but their differences "
                            f"shrink by {rate:.3g} per period: a transient spiralling into "
                            f"a period-{m} orbit (a slowly damped complex multiplier); "
                            "run more periods"))
            return MotionClass(f"period-{m}", ev)
        drift = steady_drift(P, n, ev["n_distinct_poincare"])
        if drift is None:
            return MotionClass(f"period-{n}", ev)
        # the points come back within rtol after n periods but move on steadily: a torus
        # whose rotation number is near 1/n (the non-periodic tests decide)
        ev.update(poincare_period=None, near_period=n, drift_per_cycle=drift,
                  note=(f"the Poincare points come back within {rtol:g} after {n} "
                        f"periods but drift on steadily ({drift:.2g} per {n} periods, not "
                        f"shrinking; {ev['n_distinct_poincare']} distinct points): not "
                        "periodic"))

    curve = closed_curve_test(P)
    ev["closed_curve"] = curve
    ev["correlation_dimension"] = correlation_dimension(P)
    frac = None
    if spec is not None:
        frac, w2 = two_frequency_fraction(spec, float(omega))
        ev["two_frequency_fraction"] = frac
        ev["second_frequency"] = w2
    if lam is not None and math.isfinite(lam):
        if lam - err > lyapunov_threshold:
            ev["basis"] = "positive Lyapunov exponent"
            if curve["passed"] and frac is not None and frac >= two_frequency_min:
                ev["note"] = ("closed-curve section and two-frequency spectrum: the positive "
                              "exponent may come from a weakly unstable torus or from a "
                              "neutral (undamped) direction of the model")
            return MotionClass("chaotic", ev)
        ev["basis"] = ("non-periodic, largest Lyapunov exponent not above "
                       f"{lyapunov_threshold:g} per period within its uncertainty")
        return MotionClass("quasi-periodic", ev)
    if frac is not None:
        if frac >= two_frequency_min:
            ev["basis"] = "spectral lines at combinations of two incommensurate frequencies"
            return MotionClass("quasi-periodic", ev)
        ev["basis"] = "spectral lines not explained by two frequencies"
        return MotionClass("chaotic", ev)
    if curve["passed"]:
        ev["basis"] = "Poincare points on a closed curve"
        return MotionClass("quasi-periodic", ev)
    ev["basis"] = "scattered Poincare points"
    return MotionClass("chaotic", ev)


def classify_result(result: Any, lyapunov: LyapunovResult | float | None = None, *,
                    columns: Any = None, **kwargs: Any) -> MotionClass:
    """:func:`classify_motion` on a :class:`~rotorsfd.timedomain.step_records.TimeResult`:
    Poincare points ``[q, v]`` of the recorded DOFs (``columns``: indices into
    ``result.dofs``, default all), scaled by the spread of the recorded signal; the
    spectrum of the first selected DOF. Record only the steady part (``record_start``)."""
    cols = np.arange(result.dofs.size) if columns is None else np.atleast_1d(columns)
    P = np.hstack([result.poincare_q[:, cols], result.poincare_v[:, cols]])
    sig = np.hstack([result.q[:, cols], result.v[:, cols]])
    dt_rec = float(np.median(np.diff(result.t))) if result.t.size > 1 else result.dt
    return classify_motion(P, sig, dt_rec, result.omega, lyapunov, **kwargs)
