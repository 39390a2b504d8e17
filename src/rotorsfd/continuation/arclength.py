"""Pseudo arc-length continuation (Keller) with tangent predictor and step control.

From a converged point z_i with unit tangent t_i (null vector of ``J = [dR/dx, dR/dlam]``,
oriented by ``t_i . t_{i-1} > 0``, so turning points are passed in both directions):

- predictor ``z = z_i + ds t_i``;
- corrector: Newton on ``R(z) = 0, t_i . W (z - z_i) - ds = 0`` (:func:`newton_extended`;
  W the system's optional arc-length metric ``weights``, identity by default),
  converged when the 2-norm of the scaled extended residual is <= tol;
- step control: reject and halve ds if the corrector fails (no convergence, state limit,
  contact) or if the new tangent turns by more than ``max_angle`` (folds are not jumped);
  grow ds by ``grow`` after an easy convergence (<= ``easy_iter`` iterations), shrink it by
  0.7 after a hard one (and, with a finite ``angle_aim``, keep it at most ``angle_aim
  max_angle / angle`` times the step just taken: aimed below the cap instead of grown into
  it and halved); ``ds_min <= ds <= ds_max``. Below ds_min the branch stops with
  ``success = False`` and a message that says where and why.

The continuation works on a scaled :class:`~rotorsfd.continuation.newton.ContinuationSystem`
and knows nothing of harmonic balance.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.newton import (
    ContinuationSystem,
    metric,
    newton_extended,
    tangent,
)

FloatArray = NDArray[np.float64]

#: ``on_point(z, t, J, iterations, ds) -> stop``, called at every accepted point.
PointHandler = Callable[[FloatArray, FloatArray, FloatArray, int, float], bool]


@dataclass
class ArcLengthOptions:
    """Step control of :func:`arclength` (lengths in scaled units)."""

    ds: float = 0.01
    ds_min: float = 1e-6
    ds_max: float = 0.05
    tol: float = 1e-6
    max_iter: int = 8
    max_points: int = 2000
    max_angle: float = float(np.radians(20.0))
    grow: float = 1.5
    shrink: float = 0.5
    easy_iter: int = 3
    max_halvings: int = 10
    #: the next step is at most this fraction of the one that turns the tangent by
    #: max_angle (the turn taken as proportional to the step); off (inf) by default: at
    #: 0.7 it cut the paper run's CPU by 7-18 % but its points missed the narrow
    #: period-doubling pair of tests/elements/test_journal_bearing_rotor.py (measured
    #: 2026-12-04, benchmarks/README.md)
    angle_aim: float = float("inf")


@dataclass
class ArcLengthStatus:
    """How the continuation ended."""

    success: bool
    message: str
    n_points: int
    ds: float = 0.0  #: the step length in use when it ended


def arclength(system: ContinuationSystem, z0: FloatArray, J0: FloatArray, lam_end: float,
              on_point: PointHandler, options: ArcLengthOptions | None = None,
              lam_physical: Callable[[float], float] = float,
              t_prev: FloatArray | None = None, lam_start: float | None = None
              ) -> ArcLengthStatus:
    """Continue the converged point z0 (Jacobian J0) towards ``z[-1] = lam_end``.

    The first tangent is oriented along ``t_prev`` if given (a restart inside a branch),
    else towards lam_end; ``lam_start`` (default z0[-1]) is the start of the range, for
    the test "turned back": the branch stops when it goes back past lam_start (after a
    fold), and the message says so.
    Ends with success when lam_end is reached (the last point solved at lam_end exactly),
    or when ``on_point`` returns True; ends with ``success = False`` when the corrector
    fails below ds_min, when the branch turns back out of the range, or at max_points.
    """
    o = options or ArcLengthOptions()
    lam0 = float(z0[-1])
    lam_first = lam0 if lam_start is None else lam_start
    direction = 1.0 if lam_end >= lam_first else -1.0
    e = np.zeros(system.n + 1)
    e[-1] = 1.0
    z = np.asarray(z0, dtype=float)
    W = metric(system)
    t = tangent(J0, direction * e if t_prev is None else t_prev, W)
    n_points = 1

    def at(zz: FloatArray) -> str:
        return f"lam={lam_physical(float(zz[-1])):.8g}"

    if on_point(z, t, J0, 0, 0.0):
        return ArcLengthStatus(True, f"stopped by the callback at {at(z)}", n_points, o.ds)
    if lam0 == lam_end:
        return ArcLengthStatus(True, f"reached the end of the range, {at(z)}", n_points, o.ds)
    ds = o.ds
    while n_points < o.max_points:
        res = newton_extended(system, z + ds * t, W * t, float((W * t) @ z) + ds, o.tol,
                              o.max_iter,
                              o.max_halvings)
        if res.converged:
            t_new = tangent(res.J, t, W)
            angle = float(np.arccos(np.clip(t_new @ (W * t), -1.0, 1.0)))
            if angle > o.max_angle and ds > o.ds_min:
                ds = max(ds * o.shrink, o.ds_min)
                continue
        else:
            if ds <= o.ds_min:
                return ArcLengthStatus(
                    False, f"corrector failed after the point at {at(z)} with the minimum "
                    f"step ds={ds:.3g}: {res.message}", n_points, ds)
            ds = max(ds * o.shrink, o.ds_min)
            continue
        lam_new = float(res.z[-1])
        if (lam_new - lam_end) * direction >= 0.0:
            frac = (lam_end - z[-1]) / (lam_new - z[-1])
            fin = newton_extended(system, z + frac * (res.z - z), e, lam_end, o.tol,
                                  o.max_iter, o.max_halvings)
            if fin.converged:
                on_point(fin.z, tangent(fin.J, t_new, W), fin.J, fin.iterations,
                         float(np.sqrt((fin.z - z) @ (W * (fin.z - z)))))
                return ArcLengthStatus(True, f"reached the end of the range, {at(fin.z)}",
                                       n_points + 1)
            on_point(res.z, t_new, res.J, res.iterations, ds)
            return ArcLengthStatus(True, f"passed the end of the range at {at(res.z)}",
                                   n_points + 1)
        stop = on_point(res.z, t_new, res.J, res.iterations, ds)
        n_points += 1
        z, t = res.z, t_new
        if stop:
            return ArcLengthStatus(True, f"stopped by the callback at {at(z)}", n_points, ds)
        if (lam_new - lam_first) * direction < 0.0:
            side = "below" if direction > 0 else "above"
            return ArcLengthStatus(
                False, f"the branch turned back and went {side} the start of its "
                f"range lam={lam_physical(lam_first):.8g} (towards "
                f"lam={lam_physical(lam_end):.8g}) at {at(z)}", n_points, ds)
        used = ds
        if res.iterations <= o.easy_iter:
            ds = min(ds * o.grow, o.ds_max)
        else:
            ds = max(ds * 0.7, o.ds_min)
        if angle > 0.0:   # aim below the angle cap (a step past it is solved twice)
            ds = max(min(ds, used * o.angle_aim * o.max_angle / angle), o.ds_min)
    return ArcLengthStatus(False, f"max_points reached at {at(z)}", n_points, ds)
