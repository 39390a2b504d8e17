"""A periodic branch started from an orbit: the Fourier fit of one sampled period, its
Newton correction on the HB equations, and the continuation both ways that stops when
the branch closes on itself (an isola).

1. :func:`fit_samples`: ``X_k = (2/N) sum_j x(t_j) exp(-i k Omega t_j)`` (``X_0`` the
   mean) of the last period of evenly sampled DOFs, in the HB convention
   ``q(t) = Re sum_k X_k exp(i k Omega t)`` with the absolute time, so the phase relative
   to the forcing is kept (:class:`OrbitFit`, with the difference of an HB orbit to the
   samples).
2. :func:`correct_orbit`: Newton on the HB equations at that speed from the fit
   (:func:`~rotorsfd.harmonic.periodic.solve_periodic`, condensed unknowns: the nonlinear
   DOFs must be among the samples).
3. :func:`continue_both_ways`: continuation from that point towards the upper end of the
   range; it stops when the branch closes on itself (the parameter comes back across the
   start within ``closure_tol`` of the start point, on the nonlinear DOFs' coefficients
   over their length scale), otherwise the other direction is continued too and the two
   legs joined into one branch (lower end first, :func:`join_segments`).

:mod:`rotorsfd.analyses.orbit_branch` reads the orbit of a time-domain run and calls these.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rotorsfd.continuation.branch import Branch, BranchPoint
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.harmonic.periodic import (
    BORDERED,
    POINT_COLUMNS,
    PeriodicSolution,
    continue_periodic,
    solve_periodic,
)
from rotorsfd.harmonic.problem import PeriodicProblem

__all__ = ["CLOSURE_TOL", "SAME_TOL", "OrbitFit", "continue_both_ways", "correct_orbit",
           "crossings", "fit_samples", "join_segments", "on_branch", "problem_lam"]

#: Default closure tolerance of :func:`continue_both_ways` (units of the length scale).
CLOSURE_TOL = 0.02

#: Largest coefficient difference (length scales) of one orbit seen on another's branch
#: (:func:`on_branch`): two Newton solutions of one orbit differ by the solver's tolerance
#: (1e-6 scaled, more at a poorly conditioned unstable orbit), distinct orbits at one speed
#: by O(0.1).
SAME_TOL = 1e-3


@dataclass
class OrbitFit:
    """Fourier coefficients of the last recorded period of a time-domain orbit.

    ``X`` (H+1, n_dof): the recorded nodes' y, z filled, the rest 0; ``t`` (N,) the
    sample times (one period, absolute), ``samples`` {dof: x(t_j)}; ``speed`` [rad/s].
    """

    X: np.ndarray
    speed: float
    t: np.ndarray
    samples: dict[int, np.ndarray]
    clearance: float | None = None
    source: str = ""
    info: dict[str, Any] = field(default_factory=dict)

    @property
    def H(self) -> int:
        return self.X.shape[0] - 1

    def evaluate(self, X: np.ndarray, dof: int) -> np.ndarray:
        """``Re sum_k X_k exp(i k Omega t_j)`` of ``dof`` at the sample times."""
        k = np.arange(X.shape[0])
        return (np.exp(1j * self.speed * np.outer(self.t, k)) @ X[:, dof]).real

    def difference(self, X: np.ndarray | None = None) -> float:
        """Largest |q_HB(t_j) - q(t_j)| over the period and the recorded DOFs, over the
        clearance (or in m without one); ``X`` default: the fit itself (its truncation)."""
        X = self.X if X is None else X
        err = max(float(np.max(np.abs(self.evaluate(X, d) - x)))
                  for d, x in self.samples.items())
        return err / (self.clearance or 1.0)


def fit_samples(t: np.ndarray, samples: dict[int, np.ndarray], speed: float, H: int,
                n_dof: int, clearance: float | None = None, source: str = "") -> OrbitFit:
    """:class:`OrbitFit` of the last period of evenly sampled ``samples`` {dof: x(t)}
    (t the absolute time, including the period's end point or not)."""
    t = np.asarray(t, float)
    T = 2 * math.pi / speed
    keep = t > t[-1] - T * (1 - 1e-9)      # the last whole period (N equal steps)
    if keep.sum() < 2 * H + 2:
        raise ConfigError("from_orbit", source, f"{int(keep.sum())} samples in the last "
                          f"period: too few for H = {H} (record at least one period)")
    ts = t[keep]
    dt = np.diff(ts)
    if np.ptp(dt) > 1e-6 * dt.mean() or abs(ts[-1] - ts[0] + dt.mean() - T) > 1e-6 * T:
        raise ConfigError("from_orbit", source, "the last period is not sampled evenly")
    N = ts.size
    E = np.exp(-1j * speed * np.outer(np.arange(H + 1), ts)) / N       # (H+1, N)
    X = np.zeros((H + 1, n_dof), dtype=complex)
    kept: dict[int, np.ndarray] = {}
    for dof, x in samples.items():
        xs = np.asarray(x, float)[keep]
        c = E @ xs
        X[:, dof] = 2 * c
        X[0, dof] = c[0].real
        kept[int(dof)] = xs.copy()
    return OrbitFit(X, float(speed), ts, kept, float(clearance) if clearance else None,
                    source, {"samples_per_period": N})


def correct_orbit(problem: PeriodicProblem, fit: OrbitFit, H: int | None = None,
                  **options: Any) -> PeriodicSolution:
    """The HB solution at the orbit's speed, Newton from the fit (condensed unknowns);
    ``options`` go to :func:`~rotorsfd.harmonic.periodic.solve_periodic`."""
    missing = [int(d) for d in problem.nl_dofs if int(d) not in fit.samples]
    if missing:
        raise ConfigError("from_orbit", fit.source, f"the orbit does not record the "
                          f"nonlinear DOFs {missing} (record the SFD node)")
    H = H or fit.H
    X0 = np.zeros((H + 1, problem.n_dof), dtype=complex)
    h = min(H, fit.H)
    X0[: h + 1] = fit.X[: h + 1, : problem.n_dof]
    options.setdefault("condensed", True)
    return solve_periodic(problem, problem_lam(problem, fit.speed), H, X0, **options)


def problem_lam(problem: PeriodicProblem, speed: float) -> float:
    """lam of a speed-parameter problem at ``speed`` (its frequency is lam)."""
    if not math.isclose(problem.frequency(speed), speed, rel_tol=1e-12):
        raise ConfigError("from_orbit", speed, "a branch from an orbit needs the rotor "
                          "speed as the continuation parameter")
    return float(speed)


class _Closure:
    """Callback: stops when lam crosses ``lam0`` again near the start point."""

    def __init__(self, problem: PeriodicProblem, lam0: float, X0: np.ndarray, tol: float,
                 inner: Any = None) -> None:
        self.nl = np.asarray(problem.nl_dofs)
        self.c = np.asarray(problem.dof_scale)[self.nl]
        self.lam0, self.X0, self.tol, self.inner = lam0, X0[:, self.nl], tol, inner
        self.prev: tuple[float, np.ndarray] | None = None
        self.n = 0
        self.closed = False
        self.distance = math.inf

    def __call__(self, point: BranchPoint) -> bool:
        stop = bool(self.inner(point)) if self.inner is not None else False
        Xn = point.X[:, self.nl]
        if self.prev is not None and self.n >= 3:
            lp, Xp = self.prev
            a, b = lp - self.lam0, point.lam - self.lam0
            if a * b <= 0 and a != b:
                w = a / (a - b)
                Xc = Xp + w * (Xn - Xp)
                d = float(np.max(np.abs(Xc - self.X0) / self.c))
                if d < self.tol:
                    self.closed, self.distance = True, d
                    return True
        self.prev = (point.lam, Xn)
        self.n += 1
        return stop


#: Most legs of one direction in :func:`continue_both_ways` (a leg ends where the branch
#: turns back past the parameter it started from; the next leg goes on from there).
MAX_LEGS = 12


def _direction(problem: PeriodicProblem, lam0: float, X0: np.ndarray, H: int, end: float,
               other: float, closure: _Closure, options: dict[str, Any]
               ) -> tuple[list[Branch], str, bool]:
    """Legs from (lam0, X0) towards ``end``: whenever the branch turns back past the
    start of a leg (after a fold), a new leg starts at that point towards the other end
    of the range. Returns the legs, the last message and whether the range end was
    reached."""
    legs: list[Branch] = []
    lam, X, target = lam0, X0, end
    for _ in range(MAX_LEGS):
        leg = continue_periodic(problem, lam, target, H, X, callback=closure, **options)
        legs.append(leg)
        if closure.closed or leg.success or "turned back" not in leg.message \
                or leg.n_points < 2:
            return legs, leg.message, bool(leg.success and not closure.closed)
        lam, X = float(leg.lam[-1]), leg.X[-1]
        target = other if target == end else end
    return legs, f"{MAX_LEGS} legs without closing or reaching the end", False


def continue_both_ways(problem: PeriodicProblem, lam0: float, X0: np.ndarray | None,
                       H: int,
                       lo: float, hi: float, *, closure_tol: float = CLOSURE_TOL,
                       callback: Any = None, **options: Any) -> Branch:
    """Branch through ``(lam0, X0)``: towards ``hi`` (past folds: a leg that turns back
    past its start is followed by a leg the other way, see :data:`MAX_LEGS`), stopping
    if it closes on itself (``info["closed"]``); otherwise also towards ``lo``, the two
    directions joined lower end first (``info["start_index"]``: the start point).
    ``callback`` is called at every point (True stops the leg); ``options`` go to
    :func:`~rotorsfd.harmonic.periodic.continue_periodic`."""
    if not lo < lam0 < hi:
        raise ConfigError("from_orbit", lam0, f"the orbit's parameter must lie inside the "
                          f"range ({lo:.6g}, {hi:.6g})")
    options.setdefault("lam_scale", hi - lo)
    if X0 is None:
        X0 = solve_periodic(problem, lam0, H, n_samples=options.get("n_samples")).X
    up_cb = _Closure(problem, lam0, X0, closure_tol, callback)
    up, up_msg, _ = _direction(problem, lam0, X0, H, hi, lo, up_cb, options)
    if up_cb.closed:
        out = join_segments([(leg, False) for leg in up])
        out.message = (f"closed on itself (an isola) after {out.n_points} points: back at "
                       f"the start parameter within {up_cb.distance:.2g} of the start "
                       "point")
        out.success = True
        out.info.update(closed=True, closure_distance=up_cb.distance, start_index=0)
        return out
    down_cb = _Closure(problem, lam0, X0, closure_tol, callback)
    down, down_msg, _ = _direction(problem, lam0, X0, H, lo, hi, down_cb, options)
    out = join_segments([(leg, True) for leg in reversed(down)]
                        + [(leg, False) for leg in up])
    n_down = sum(leg.n_points - 1 for leg in down)
    out.info.update(closed=down_cb.closed, start_index=n_down)
    if down_cb.closed:
        out.info["closure_distance"] = down_cb.distance
    out.message = (f"towards {hi:.6g}: {up_msg}; towards {lo:.6g}: {down_msg}"
                   + ("; closed on itself (an isola)" if down_cb.closed else ""))
    out.success = bool(up[-1].success and (down[-1].success or down_cb.closed))
    return out


def join_segments(segments: list[tuple[Branch, bool]]) -> Branch:
    """One branch from legs ``(branch, reversed)`` in order, where each joins the next at
    a shared point (a reversed leg: its first point; a forward leg after a forward leg:
    its first point is the previous leg's last). Reversed legs have their tangents and
    dlam/ds negated; the arc length runs over the whole chain and ``point_at`` re-solves
    in the leg it falls in. All legs need the same ``lam_scale``."""
    scale = segments[0][0].lam_scale
    if any(not math.isclose(b.lam_scale, scale, rel_tol=1e-12) for b, _ in segments):
        raise ValueError("join_segments: the legs have different lam_scale")
    idx: list[tuple[int, np.ndarray, bool]] = []     # (segment, point indices, reversed)
    s_parts, spans = [], []
    offset = 0.0
    prev_rev = None
    for i, (b, rev) in enumerate(segments):
        n = b.n_points
        order = np.arange(n)[::-1] if rev else np.arange(n)
        L = float(b.s[-1]) if n else 0.0
        u = (L - b.s[order]) if rev else b.s[order]
        if rev:
            keep = slice(0, n - 1) if i < len(segments) - 1 else slice(None)
        else:
            keep = slice(1, None) if (i > 0 and prev_rev is False) else slice(None)
        idx.append((i, order[keep], rev))
        s_parts.append(offset + u[keep])
        spans.append((offset, L, rev, b))
        offset += L
        prev_rev = rev

    def cat(get: Any) -> np.ndarray:
        return np.concatenate([get(segments[i][0])[k] for i, k, _ in idx])

    sign = np.concatenate([np.full(k.size, -1.0 if r else 1.0) for _, k, r in idx])
    s = np.concatenate(s_parts)
    jac = None
    if all(b.jacobians is not None for b, _ in segments):
        jac = cat(lambda b: b.jacobians)
    info = dict(segments[-1][0].info)
    for key in POINT_COLUMNS:   # per-point columns: the legs' joined, else none
        info.pop(key, None)
        if all(np.shape(b.info.get(key)) == (b.n_points,) for b, _ in segments):
            info[key] = cat(lambda b, key=key: np.asarray(b.info[key]))
    for key in BORDERED:
        info.pop(key, None)
    if all(np.shape(b.info.get(key)) == (b.n_points,) for b, _ in segments
           for key in BORDERED):   # a reversed leg: its tangents, so the sign, negated
        info["bordered_sign"] = cat(lambda b: b.info["bordered_sign"]) * sign
        info["bordered_dir"] = cat(lambda b: b.info["bordered_dir"]) * sign
        info["bordered_lam"] = cat(lambda b: b.info["bordered_lam"])
        info["bordered_system"] = np.concatenate(   # the legs' systems are their own
            [np.asarray(segments[i][0].info["bordered_system"])[k] * len(segments) + i
             for i, k, _ in idx])

    def resolver(s_: float) -> BranchPoint:
        for off, L, rev, b in spans:
            if s_ <= off + L or (off, L, rev, b) == spans[-1]:
                u = s_ - off
                p = b.point_at(L - u if rev else u)
                f = -1.0 if rev else 1.0
                return BranchPoint(-1, p.lam, p.X, p.xs, f * p.tangent, p.jacobian,
                                   p.iterations, p.frequency, float(s_), f * p.dlam_ds)
        raise AssertionError("unreachable")

    first = segments[0][0]
    return Branch(
        lam=cat(lambda b: b.lam), X=cat(lambda b: b.X),
        frequency=cat(lambda b: b.frequency),
        tangents=cat(lambda b: b.tangents) * sign[:, None],
        iterations=cat(lambda b: b.iterations),
        ds=np.concatenate([[0.0], np.diff(s)]), s=s, jacobians=jac,
        aliasing=cat(lambda b: b.aliasing),
        success=all(b.success for b, _ in segments), message="", H=first.H,
        n_samples=max(b.n_samples for b, _ in segments), nl_dofs=first.nl_dofs,
        condensed=first.condensed, lam_scale=scale, info=info, resolver=resolver)


def crossings(problem: PeriodicProblem, branch: Branch, speed: float) -> list[np.ndarray]:
    """The HB solutions ``X`` (H+1, n_dof) where ``branch`` crosses ``speed``: Newton at
    that speed from the coefficients interpolated linearly in lam between the two points
    around each crossing (module docstring); a crossing whose Newton fails is left out."""
    lam = branch.lam
    out = []
    for j in range(lam.size - 1):
        a, b = lam[j] - speed, lam[j + 1] - speed
        if a == 0.0 or a * b < 0.0:
            w = 0.0 if a == 0.0 else a / (a - b)
            X0 = (1 - w) * branch.X[j] + w * branch.X[j + 1]
            try:
                out.append(solve_periodic(problem, speed, branch.H, X0,
                                          condensed=branch.condensed).X)
            except ConvergenceError:
                continue
    return out


def on_branch(problem: PeriodicProblem, branch: Branch, speed: float, X: np.ndarray,
              tol: float = SAME_TOL) -> bool:
    """Whether the orbit ``X`` (H+1, n_dof) at ``speed`` lies on ``branch``: one of its
    :func:`crossings` within ``tol`` length scales on the nonlinear DOFs."""
    dofs = np.asarray(problem.nl_dofs, dtype=np.int64)
    scale = np.asarray(problem.dof_scale, float)[dofs]
    H = min(branch.H, X.shape[0] - 1)
    target = X[: H + 1][:, dofs] / scale
    return any(np.max(np.abs(Xc[: H + 1][:, dofs] / scale - target)) < tol
               for Xc in crossings(problem, branch, speed))
