"""Two-parameter continuation of folds (saddle-nodes) and their cusps.

A *two-parameter system* is any object with ``n`` (number of state unknowns x) and

- ``evaluate(z) -> (R (n,), J (n, n+2))`` at ``z = (x, lam1, lam2)`` (scaled), with the
  exact ``J = [R_x, R_lam1, R_lam2]``; ``admissible(z) -> bool``.

Fold of ``R(x, lam1) = 0`` at fixed lam2 (minimally extended system, Govaerts 2000)::

    [A  b] [v]   [0]          [A^T c] [w]   [0]
    [c^T 0] [g] = [1],         [b^T 0] [h] = [1],        A = R_x,

g(x, lam1, lam2) vanishes exactly where A is singular (v, w: right and left null
vectors); b, c are the left and right null vectors of A at the last accepted point
(so the bordered matrix stays well conditioned). The fold curve is the solution set of

    F(x, lam1, lam2) = [R; g] = 0          (n + 1 equations, n + 2 unknowns),

continued by pseudo arc-length (:func:`~rotorsfd.continuation.arclength.arclength`,
parameter lam2). Derivatives: ``dg/dy = -w^T (dA/dy) v`` for y in (x, lam1, lam2), i.e.
``dg/dz = -w^T D_v J`` with ``D_v J`` the directional derivative of the full Jacobian
``[R_x, R_lam1, R_lam2]`` along (v, 0, 0) (mixed partials commute:
``(d R_x / dlam) v = D_v R_lam``). R and g are exact; ``D_v J`` is the only approximate
quantity: a central difference ``(J(x + h v) - J(x - h v)) / 2h`` with ``|h v| = 1e-5``
in scaled unknowns (error O(h^2) ~ 1e-10, it only affects the Newton rate, not the
converged fold, since g itself is exact).

Cusp: along the fold curve, ``(dlam1, dlam2)`` is orthogonal to ``(w.R_lam1, w.R_lam2)``,
so at a nondegenerate fold (``w.R_lam1 != 0``) ``dlam2/ds = 0`` forces ``dlam1/ds = 0``:
the curve turns back in lam2 exactly at a cusp, where the two folds of a pair meet. It is
located by the Illinois method on ``dlam2/ds`` (the tangent's last entry) along the arc.

The condensed HB-AFT residual in this form (exact ``R_lam1`` and ``R_lam2``) is
:class:`rotorsfd.harmonic.fold_curve.TwoParameterHB`; this module knows no HB.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, Protocol

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.arclength import ArcLengthOptions, arclength
from rotorsfd.continuation.branch import Branch, BranchPoint
from rotorsfd.continuation.newton import metric, newton_extended, tangent
from rotorsfd.errors import ConvergenceError

FloatArray = NDArray[np.float64]

#: Step of the central difference of the Jacobian along v (scaled unknowns).
FD_STEP = 1e-5


class TwoParameterSystem(Protocol):
    """Scaled ``R(x, lam1, lam2) = 0`` with exact ``[R_x, R_lam1, R_lam2]`` (module doc)."""

    n: int

    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]: ...

    def admissible(self, z: FloatArray) -> bool: ...


def bordered(A: NDArray, b: NDArray, c: NDArray) -> tuple[NDArray, float | complex]:
    """Solve ``[A b; c^T 0] [v; g] = [0; 1]`` (real, or complex for a complex A)."""
    n = A.shape[0]
    dtype = np.result_type(A, b, c)
    B = np.zeros((n + 1, n + 1), dtype=dtype)
    B[:n, :n], B[:n, n], B[n, :n] = A, b, c
    rhs = np.zeros(n + 1, dtype=dtype)
    rhs[n] = 1.0
    sol = np.linalg.solve(B, rhs)
    return sol[:n], (complex(sol[n]) if np.iscomplexobj(sol) else float(sol[n]))


def bordered_null_vectors(A: NDArray, b: NDArray, c: NDArray
                          ) -> tuple[NDArray, NDArray, float | complex]:
    """(v, w, g): the right and left null-vector approximations of the bordered systems
    ``[A b; c^T 0] [v; g] = [0; 1]`` and ``[A^T c; b^T 0] [w; h] = [0; 1]``, and g."""
    v, g = bordered(A, b, c)
    w, _ = bordered(A.T, c, b)
    return v, w, g


def unit_borders(v: NDArray, w: NDArray) -> tuple[NDArray, NDArray] | None:
    """The borders (c, b) = (conj(v) / |v|, conj(w) / |w|) from the null vectors v, w of
    :func:`bordered_null_vectors`, or None if either is not finite. ``bordered`` pairs a
    border with a vector by the bilinear ``c^T v``: conjugated, ``c^T v = |v|``; for a
    complex v, v itself can give ``v^T v ~ 0``, a near-singular bordered matrix (the
    paper's C/R = 0.728 % Neimark-Sacker start went to another solution so). For real
    vectors the conjugate is the vector."""
    if not (np.all(np.isfinite(v)) and np.all(np.isfinite(w))):
        return None
    return np.conj(v) / np.linalg.norm(v), np.conj(w) / np.linalg.norm(w)


def null_vectors(A: FloatArray) -> tuple[FloatArray, FloatArray]:
    """Unit right and left singular vectors of the smallest singular value of A."""
    U, _, Vt = np.linalg.svd(A)
    return Vt[-1].copy(), U[:, -1].copy()


class FoldSystem:
    """The fold-augmented system ``F = [R; g]`` in ``z = (x, lam1, lam2)`` (module doc);
    a :class:`~rotorsfd.continuation.newton.ContinuationSystem` with parameter lam2."""

    def __init__(self, base: TwoParameterSystem, z0: FloatArray, fd_step: float = FD_STEP
                 ) -> None:
        self.base = base
        self.n = base.n + 1
        self.fd_step = fd_step
        w = getattr(base, "weights", None)
        self.weights = None if w is None else np.asarray(w, dtype=float)
        _, J = base.evaluate(np.asarray(z0, dtype=float))
        self.c, self.b = null_vectors(J[:, : base.n])

    def admissible(self, z: FloatArray) -> bool:
        return self.base.admissible(z)

    def null_vectors(self, A: FloatArray) -> tuple[FloatArray, FloatArray, float]:
        """(v, w, g) of the bordered systems at A = R_x."""
        return bordered_null_vectors(A, self.b, self.c)

    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        n = self.base.n
        R, J = self.base.evaluate(z)
        v, w, g = self.null_vectors(J[:, :n])
        h = self.fd_step / max(float(np.linalg.norm(v)), 1e-300)
        dz = np.zeros_like(z)
        dz[:n] = h * v
        Jp = self.base.evaluate(z + dz)[1]
        Jm = self.base.evaluate(z - dz)[1]
        dg = -(w @ (Jp - Jm)) / (2.0 * h)
        return np.append(R, g), np.vstack([J, dg])

    def update_border(self, z: FloatArray) -> None:
        """b, c <- the unit left and right null vectors w, v at z (after a point)."""
        _, J = self.base.evaluate(z)
        borders = unit_borders(*self.null_vectors(J[:, : self.base.n])[:2])
        if borders is not None:
            self.c, self.b = borders


@dataclass
class Cusp:
    """A turning point of the fold curve in lam2 (where a fold pair meets): its index in
    the curve's points (the point itself is stored there) and arc length."""

    index: int
    s: float
    z: FloatArray


@dataclass
class FoldBranch:
    """Points of a fold curve in scaled unknowns ``z = (x, lam1, lam2)``.

    ``segment`` counts the turns in lam2 passed so far (a new segment after each cusp, so
    each segment is one fold of a pair, lam1 a function of lam2 on it); ``s`` arc length;
    ``cusps`` the located turns (their points are in ``z`` too).
    """

    z: FloatArray
    tangents: FloatArray
    s: FloatArray
    segment: NDArray[np.int64]
    cusps: list[Cusp]
    success: bool
    message: str
    system: FoldSystem = field(repr=False)
    #: the event (index into ``continue_folds``' ``events``) whose zero ended the curve
    #: (the located zero is the last point), None if none did
    ended_at: int | None = None

    @property
    def n_points(self) -> int:
        return int(self.s.size)

    def solve_at(self, lam2: float, tol: float = 1e-10) -> list[FloatArray]:
        """Points of the curve at the scaled ``lam2``: Newton at fixed lam2 from the linear
        interpolation of every pair of consecutive points that brackets it."""
        out: list[FloatArray] = []
        e = np.zeros(self.system.n + 1)
        e[-1] = 1.0
        l2 = self.z[:, -1]
        for i in range(self.n_points - 1):
            a, b = l2[i] - lam2, l2[i + 1] - lam2
            if a * b > 0 or (b == 0 and i + 1 < self.n_points - 1) or a == b:
                continue
            z0 = self.z[i] + (self.z[i + 1] - self.z[i]) * (a / (a - b))
            res = newton_extended(self.system, z0, e, lam2, tol, 30)
            if not res.converged:
                raise ConvergenceError(f"fold curve: re-solving at lam2={lam2:.8g} failed: "
                                       f"{res.message}")
            out.append(res.z)
        return out


@dataclass
class FoldOptions:
    """Steps of the fold-curve continuation (scaled units) and the cusp tolerance:
    the turn is located until |dlam2/ds| <= ``turn_tol``."""

    ds: float = 0.02
    ds_min: float = 1e-6
    ds_max: float = 0.05
    tol: float = 1e-8
    max_iter: int = 10
    max_points: int = 1000
    max_angle_deg: float = 20.0
    max_turns: int = 20
    turn_tol: float = 1e-9


def _illinois(g: Callable[[float], tuple[float, Any]], a: float, fa: float, b: float,
              fb: float, done: Callable[[float, float, float, float], bool],
              max_iter: int) -> tuple[float, Any]:
    """Root of a sign-changing f on [a, b] by regula falsi with the Illinois modification.

    ``g(x) -> (f(x), payload)`` (the payload is what the caller wants at the root);
    ``done(x, f, a, b)`` says when to stop. Returns (x, payload) of the last evaluation.
    """
    side = 0
    x, payload = b, None
    for _ in range(max_iter):
        x = (a * fb - b * fa) / (fb - fa)
        f, payload = g(x)
        if done(x, f, a, b):
            break
        if f * fb < 0:
            a, fa = b, fb
            b, fb = x, f
            side = 0
        else:
            b, fb = x, f
            if side == -1:
                fa *= 0.5
            side = -1
    return x, payload


def locate_on_curve(system: Any, z: FloatArray, t: FloatArray, z1: FloatArray,
                    test: Callable[[FloatArray, FloatArray], float], fa: float, fb: float,
                    tol: float, *, ftol: float = 0.0, xtol: float = 1e-10,
                    max_iter: int = 60) -> tuple[FloatArray, FloatArray, float, float]:
    """Zero of ``test(z, t)`` (z a point of the curve of ``system``, t its tangent) between
    the curve's points z (tangent t, ``test = fa``) and z1 (``test = fb``, of the other
    sign), by the Illinois method on the arc distance d from z: each trial point solves
    the curve's equations with the pseudo arc-length condition ``t.W (z' - z) = d``.
    Stops when ``|test| <= ftol`` or the bracket is below ``xtol`` (scaled arc length;
    the located unknowns, parameters included, are then within ``xtol`` of the zero).
    Returns (z, t, d, test) at the last trial point."""
    W = metric(system)

    def g(d: float) -> tuple[float, tuple[FloatArray, FloatArray]]:
        res = newton_extended(system, z + d * t, W * t, float((W * t) @ z) + d, tol, 30)
        if not res.converged:
            raise ConvergenceError(f"locating a zero along the curve failed: {res.message}")
        tc = tangent(res.J, t, W)
        return float(test(res.z, tc)), (res.z, tc)

    def done(d: float, f: float, a: float, b: float) -> bool:
        return abs(f) <= ftol or abs(b - a) <= xtol

    state = {"f": fb}

    def g_kept(d: float):
        f, payload = g(d)
        state["f"] = f
        return f, payload

    d, (zc, tc) = _illinois(g_kept, 0.0, fa, float(t @ (W * (z1 - z))), fb, done, max_iter)
    return zc, tc, d, state["f"]


def _locate_turn(fold: FoldSystem, z: FloatArray, t: FloatArray, z1: FloatArray,
                 t1: FloatArray, tol: float, turn_tol: float
                 ) -> tuple[FloatArray, FloatArray, float]:
    """Point between z (tangent t) and z1 where the tangent's lam2 entry vanishes
    (:func:`locate_on_curve` on ``dlam2/ds``); returns (z, t, d)."""
    zc, tc, d, _ = locate_on_curve(fold, z, t, z1, lambda z_, t_: float(t_[-1]),
                                   float(t[-1]), float(t1[-1]), tol, ftol=turn_tol,
                                   xtol=1e-14)
    return zc, tc, d


def continue_folds(base: TwoParameterSystem, z0: FloatArray, lam2_range: tuple[float, float],
                   options: FoldOptions | None = None,
                   on_point: Callable[[FloatArray, int], None] | None = None,
                   lam_physical: Callable[[float], float] = float,
                   augmented: Callable[[TwoParameterSystem, FloatArray], Any] | None = None,
                   events: Sequence[Callable[[FloatArray], float]] = (),
                   event_xtol: float = 1e-10) -> FoldBranch:
    """Continue the fold near z0 (scaled ``(x, lam1, lam2)``) in lam2 over ``lam2_range``
    (scaled), from ``z0[-1]`` towards ``lam2_range[1]``.

    z0 is first corrected at fixed lam2 (Newton on ``[R; g] = 0``). Each time the curve
    turns back in lam2 (``dlam2/ds`` changes sign: a cusp), the turn is located, stored as
    a :class:`Cusp`, and the continuation goes on towards the other end of the range
    (at most ``max_turns`` times). ``on_point(z, segment)`` is called at every point;
    ``lam_physical(lam2)`` converts the scaled lam2 for messages.
    Never raises after the first point: ``success`` False and a message on failure.
    ``augmented(base, z0)`` builds another singularity's augmented system with the
    interface of :class:`FoldSystem` (default: the fold's; a period doubling's:
    :class:`rotorsfd.harmonic.pd_curve.PeriodDoublingSystem`).
    ``events``: functions of a point whose sign change between two points ends the curve
    there: the zero is located along the arc (:func:`locate_on_curve`, to ``event_xtol``
    in scaled arc length), stored as the last point, and ``ended_at`` names the event
    (e.g. a Neimark-Sacker curve reaching theta = 1/2).
    """
    o = options or FoldOptions()
    z0 = np.asarray(z0, dtype=float)
    fold = FoldSystem(base, z0) if augmented is None else augmented(base, z0)
    e = np.zeros(fold.n + 1)
    e[-1] = 1.0
    first = newton_extended(fold, z0, e, float(z0[-1]), o.tol, 30)
    if not first.converged:
        raise ConvergenceError(f"fold curve: no fold near the start point: {first.message}")
    fold.update_border(first.z)
    first = newton_extended(fold, first.z, e, float(first.z[-1]), o.tol, 30)
    zs: list[FloatArray] = []
    ts: list[FloatArray] = []
    ss: list[float] = []
    seg: list[int] = []
    cusps: list[Cusp] = []
    state: dict[str, Any] = {"segment": 0, "turned": False, "ended": None}
    ev_prev: list[float] = []

    def record(z: FloatArray, t: FloatArray, step: float) -> None:
        zs.append(z.copy())
        ts.append(t.copy())
        ss.append((ss[-1] if ss else 0.0) + step)
        seg.append(state["segment"])
        fold.update_border(z)
        if on_point is not None:
            on_point(z, state["segment"])

    def handler(z: FloatArray, t: FloatArray, J: FloatArray, it: int, step: float) -> bool:
        if state["ended"] is not None:
            return True
        values = [float(f(z)) for f in events]
        for k, (fa, fb) in enumerate(zip(ev_prev, values, strict=False)):
            if fa * fb < 0 or (fb == 0.0 and fa != 0.0):
                zc, tc, d, _ = locate_on_curve(fold, zs[-1], ts[-1], z,
                                               lambda z_, t_, f=events[k]: float(f(z_)),
                                               fa, fb, o.tol, xtol=event_xtol)
                record(zc, tc, d)
                state["ended"] = k
                return True
        ev_prev[:] = values
        if ts and ts[-1][-1] * t[-1] < 0:
            zc, tc, d = _locate_turn(fold, zs[-1], ts[-1], z, t, o.tol, o.turn_tol)
            record(zc, tc, d)
            cusps.append(Cusp(len(zs) - 1, ss[-1], zc))
            state["segment"] += 1
            state["turned"] = True
            record(z, t, max(step - d, 0.0))
            return True
        record(z, t, step)
        return False

    opts = ArcLengthOptions(ds=o.ds, ds_min=o.ds_min, ds_max=o.ds_max, tol=o.tol,
                            max_iter=o.max_iter, max_points=o.max_points,
                            max_angle=float(np.radians(o.max_angle_deg)))
    z, J, t_prev = first.z, first.J, None
    ends = [float(lam2_range[1]), float(lam2_range[0])]
    target = 0
    while True:
        state["turned"] = False
        restart = bool(zs)
        opts.max_points = o.max_points - len(zs) + int(restart)
        status = arclength(fold, z, J, ends[target],
                           _skip_first(handler) if restart else handler, opts,
                           lam_physical=lam_physical, t_prev=t_prev)
        if state["ended"] is not None:
            res = _result(zs, ts, ss, seg, cusps, True, f"ended at event {state['ended']} "
                          f"(lam={lam_physical(float(zs[-1][-1])):.8g})", fold)
            res.ended_at = int(state["ended"])
            return res
        if not state["turned"]:
            return _result(zs, ts, ss, seg, cusps, status.success, status.message, fold)
        if len(cusps) > o.max_turns:
            return _result(zs, ts, ss, seg, cusps, False,
                           f"stopped after {len(cusps)} turns in lam2 (max_turns)", fold)
        target = 1 - target
        z, t_prev = zs[-1], ts[-1]
        J = fold.evaluate(z)[1]
        opts.ds = status.ds or o.ds


def _skip_first(handler):
    """The handler, skipping the first call of a restart (the last recorded point)."""
    seen = {"first": True}

    def wrapped(z, t, J, it, step):
        if seen["first"]:
            seen["first"] = False
            return False
        return handler(z, t, J, it, step)

    return wrapped


def _result(zs, ts, ss, seg, cusps, success, message, fold) -> FoldBranch:
    return FoldBranch(np.array(zs), np.array(ts), np.array(ss),
                      np.array(seg, dtype=np.int64), cusps, success, message, fold)


# ---- folds of one-parameter branches -----------------------------------------------------


def locate_branch_fold(branch: Branch, i: int, rtol: float = 1e-10,
                       max_iter: int = 60) -> BranchPoint:
    """The turning point ``dlam/ds = 0`` of a one-parameter branch between its points i and
    i+1 (``Branch.folds()``), by the Illinois method on dlam/ds(s) with
    ``Branch.point_at``; stops when the step in s is below ``rtol`` times the bracket."""
    a, b = float(branch.s[i]), float(branch.s[i + 1])
    fa, fb = float(branch.dlam_ds[i]), float(branch.dlam_ds[i + 1])
    if fa * fb > 0:
        raise ValueError(f"no sign change of dlam/ds between points {i} and {i + 1}")
    width = b - a

    def g(s: float) -> tuple[float, BranchPoint]:
        p = branch.point_at(s)
        return p.dlam_ds, p

    def done(s: float, f: float, a: float, b: float) -> bool:
        return f == 0.0 or min(abs(s - a), abs(s - b)) <= rtol * width

    return _illinois(g, a, fa, b, fb, done, max_iter)[1]
