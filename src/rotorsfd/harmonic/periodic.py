"""Periodic solutions by HB-AFT: one point (:func:`solve_periodic`) and branches by
pseudo arc-length continuation (:func:`continue_periodic`), on the scaled system of
:mod:`rotorsfd.harmonic.hb_system`.

Scaling (so that the threshold ``tol = 1e-6`` means the same in any units): with the
per-DOF length scale c of the problem and ``lam_scale`` (default: the range
``|lam_end - lam_start|``), the Newton unknowns are ``x/c`` and ``lam/lam_scale``;
the condensed residual (units of length) is divided by c; the full residual (forces) by
``c_i kappa_i`` with ``kappa_i = |K_ii|`` at the first lam (a force that would move DOF i
by c_i). A point is converged when the 2-norm of the scaled extended residual is <= tol.
Arc length, tangents and their angles are measured on the scaled nonlinear-DOF unknowns and
lam in both paths (the full path weights the other DOFs 0), so condensed and full trace
the same points.
"""

from __future__ import annotations

import functools
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.arclength import ArcLengthOptions, arclength
from rotorsfd.continuation.branch import Branch, BranchPoint
from rotorsfd.continuation.newton import (
    NewtonResult,
    bordered_sign,
    metric,
    newton_extended,
    tangent,
)
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.blas import single_threaded_blas
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import choose_n_samples, default_min_samples, to_real
from rotorsfd.harmonic.hb_system import HBSystem, hb_system, initial_guess
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.truncation import (
    convert_tangent,
    estimate_condenser,
    harmonic_norms,
    pad_coefficients,
    tail_norms,
    truncation_error,
)

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
EventHook = Callable[[BranchPoint], "bool | None"]


def _one_blas_thread(func):
    """Run ``func`` with BLAS limited to one thread (see :mod:`rotorsfd.harmonic.blas`)."""

    @functools.wraps(func)
    def wrapper(*args, **kwargs):
        with single_threaded_blas():
            return func(*args, **kwargs)

    return wrapper


@dataclass
class PeriodicSolution:
    """One periodic solution: coefficients X (H+1, n_dof), the parameter, iterations,
    the scaled residual norm, the Jacobian [dR/dx, dR/dlam] (physical units; condensed:
    Schur form), N_f used and the aliasing estimate."""

    lam: float
    X: ComplexArray
    frequency: float
    iterations: int
    residual_norm: float
    jacobian: FloatArray
    n_samples: int
    aliasing: float
    condensed: bool


@_one_blas_thread
def solve_periodic(problem: PeriodicProblem, lam: float, H: int,
                   X0: ComplexArray | None = None, *, n_samples: int | None = None,
                   condensed: bool = True, tol: float = 1e-6, max_iter: int = 50,
                   limit_max: float = 1.0) -> PeriodicSolution:
    """Periodic solution at fixed lam by Newton on the HB-AFT equations.

    ``X0`` (H+1, n_dof) complex start (default: linearised response, see module);
    ``n_samples`` N_f (default: :func:`~rotorsfd.harmonic.fourier.choose_n_samples` at X0).
    Raises :class:`rotorsfd.errors.ConvergenceError` saying where and why on failure.
    """
    system, z0 = hb_system(problem, H, lam, X0, n_samples, condensed,
                        max(abs(lam), 1.0), limit_max)
    e = np.zeros(system.n + 1)
    e[-1] = 1.0
    res = newton_extended(system, z0, e, float(z0[-1]), tol, max_iter)
    if not res.converged:
        raise ConvergenceError(
            f"{problem.name}: no periodic solution at lam={lam:.8g} (H={H}, "
            f"N_f={system.N}, condensed={condensed}): {res.message}")
    return PeriodicSolution(lam, system.coefficients(res.z), problem.frequency(lam),
                            res.iterations, res.norm, system.physical_jacobian(res.z, res.J),
                            system.N, system.aliasing(res.z), condensed)


#: N_f rules of :func:`continue_periodic` (``n_samples_rule``).
N_SAMPLES_RULES = ("adaptive", "grow")
#: The adaptive rule halves N_f only when the halved count's sampling error is below this
#: fraction of ``alias_tol`` (doubling is at ``alias_tol``): the band is the hysteresis.
COARSEN_FRACTION = 0.1
#: Default ``harmonics_tol`` of :func:`continue_periodic`: the truncation-error estimate
#: (solution change in the Newton test's length scales, e.g. SFD clearances) allowed.
TRUNCATION_TOL = 1e-3


@_one_blas_thread
def continue_periodic(problem: PeriodicProblem, lam_start: float, lam_end: float, H: int,
                      X0: ComplexArray | None = None, *, n_samples: int | None = None,
                      condensed: bool = True, tol: float = 1e-6, ds: float = 0.01,
                      ds_min: float = 1e-6, ds_max: float = 0.05, max_iter: int = 8,
                      max_points: int = 2000, max_angle_deg: float = 20.0,
                      lam_scale: float | None = None, limit_max: float = 1.0,
                      alias_tol: float | None = None, n_samples_max: int = 2048,
                      n_samples_rule: str = "adaptive",
                      store_jacobians: bool | None = None, callback: EventHook | None = None,
                      harmonics_tol: float | None = TRUNCATION_TOL,
                      adaptive_harmonics: bool = False, H_min: int = 1, H_max: int = 32,
                      start_tangent: FloatArray | None = None) -> Branch:
    """Branch of periodic solutions from lam_start towards lam_end (pseudo arc-length).

    Steps ``ds, ds_min, ds_max`` are arc lengths in the scaled unknowns (module docstring).
    N_f: a given ``n_samples`` is used throughout. With ``n_samples=None`` the first point
    uses the rule of :func:`~rotorsfd.harmonic.fourier.choose_n_samples`, then, at every
    converged point, ``n_samples_rule``:

    - ``"adaptive"`` (default): the sampling error is the 2-norm of the change of the
      scaled residual (the quantity the Newton test bounds by ``tol``) if N_f doubled:
      ``|Ht_k (G_k(2N) - G_k(N))| / c`` condensed (the force error of the retained
      harmonics as the displacement it causes, over the length scale), ``|G(2N) - G(N)| /
      (c kappa)`` at nl_dofs for the full residual. Above ``alias_tol`` (default ``tol``:
      aliasing moves the residual no more than the convergence test allows) N_f becomes
      the smallest power of two (<= ``n_samples_max``) whose error is <= alias_tol there
      and the point is re-solved; when the error of N_f/2 (against N_f) is below
      ``COARSEN_FRACTION * alias_tol``, N_f is halved (repeatedly, not below
      ``default_min_samples(H)``) and the branch goes on from the same point.
    - ``"grow"`` (the rule before the adaptive one, kept for comparison): if doubling N_f
      changes the force coefficients by more than ``alias_tol`` (default 1e-6) relative
      to the largest (:func:`~rotorsfd.harmonic.fourier.aliasing_error`), N_f is re-chosen
      by ``choose_n_samples`` at ``alias_tol / 100`` (at least doubled) and the point
      re-solved; N_f never comes down.

    A re-solved point keeps its lam, or near a fold (``|dlam/ds|`` small in the scaled
    unknowns) its position along the tangent. ``Branch.aliasing`` holds the rule's error
    estimate at every point (with a given n_samples too), ``Branch.info["n_samples"]``
    N_f.
    ``callback(point: BranchPoint)`` is called at every converged point (the first too);
    returning True stops the continuation there (success, message says so).
    ``store_jacobians`` (default: only when condensed) keeps ``Branch.jacobians``.

    Harmonics: at every converged point the truncation error is estimated
    (:func:`~rotorsfd.harmonic.truncation.truncation_error`, the change of the solution if
    about 1.5 H harmonics were kept, in the length scales of the Newton test: for an SFD,
    clearances) and stored in ``Branch.info["truncation_error"]`` (``harmonics_tol=None``
    skips it). With ``adaptive_harmonics`` H starts at ``H`` and follows the branch: above
    ``harmonics_tol`` it is raised (to where the estimate's dropped content falls below
    half the tolerance, at most ``H_max``) and the point re-solved; where the content of
    the top harmonics plus the estimate is below ``COARSEN_FRACTION * harmonics_tol`` it
    is lowered (not below ``H_min``). ``Branch.info["harmonics"]`` holds H per point,
    ``Branch.H`` the largest (``X`` is zero-padded to it; ``jacobians`` is then None). A
    fixed H whose estimate exceeds ``harmonics_tol`` adds a warning to the message.

    ``start_tangent`` (scaled unknowns of the layout of X0, e.g. a tangent of another
    branch at X0): the first point is solved on the plane through ``(X0, lam_start)``
    normal to it instead of at fixed lam (well conditioned near a fold, where a fixed-lam
    Newton from a perturbed start may fail or jump to another solution), and the branch
    follows its direction (``lam_end`` then only bounds the range, as far behind the start
    as ahead of it).
    Never raises on a failed step: returns the points so far with ``success = False`` and a
    message saying where (lam) and why; this includes the re-solve of a point after N_f
    changed ("re-solve at N_f=... failed at lam=..."). Raises ConvergenceError only if the
    first point cannot be found.
    """
    if n_samples_rule not in N_SAMPLES_RULES:
        raise ValueError(f"n_samples_rule must be one of {N_SAMPLES_RULES}, "
                         f"got {n_samples_rule!r}")
    adaptive = n_samples is None and n_samples_rule == "adaptive"
    grow = n_samples is None and n_samples_rule == "grow"
    if alias_tol is None:
        alias_tol = tol if n_samples_rule == "adaptive" else 1e-6
    n_floor = min(default_min_samples(H), n_samples_max)
    scale = lam_scale or (abs(lam_end - lam_start) or max(abs(lam_start), 1.0))
    width = problem.m if condensed else problem.n_dof     # unknowns per harmonic
    if start_tangent is None:
        first = solve_periodic.__wrapped__(problem, lam_start, H, X0, n_samples=n_samples,
                                           condensed=condensed, tol=tol,
                                           limit_max=limit_max)
        X_start, N, t_prev, plane = first.X, first.n_samples, None, False
    else:
        X_start = initial_guess(problem, H, lam_start, X0)
        xs = to_real(X_start)[:, problem.nl_dofs]
        N = n_samples or choose_n_samples(problem.law(lam_start).force, xs,
                                          problem.frequency(lam_start))
        t_prev, plane = convert_tangent(start_tangent, H, width), True
    if store_jacobians is None:
        store_jacobians = condensed
    keys = ("lam", "X", "w", "t", "it", "ds", "J", "al", "N", "z", "sys", "H", "te", "bp")
    out: dict[str, list] = {k: [] for k in keys}
    state: dict = {"refine": False, "coarsen": False, "skip": False, "s": 0.0}
    condensers: dict[int, CondensedHB] = {}   # of the truncation estimate, by H
    opts = ArcLengthOptions(ds=ds, ds_min=ds_min, ds_max=ds_max, tol=tol, max_iter=max_iter,
                            max_points=max_points, max_angle=float(np.radians(max_angle_deg)))
    lam0 = lam_start
    try:
        system, res0 = _start_point(problem, H, lam0, X_start, N, condensed, scale,
                                    limit_max, tol, max_iter, t_prev, plane)
    except ConvergenceError:
        if not plane:
            raise
        raise ConvergenceError(f"{problem.name}: no periodic solution near lam="
                               f"{lam_start:.8g} (H={H}, N_f={N}) on the plane normal to "
                               "the start tangent") from None
    lam_first = lam_start
    if plane:   # the range reaches as far behind the start as ahead of it
        lam_first = system.from_z(res0.z)[1]
        lam_first -= lam_end - lam_first
    failed: str | None = None
    while True:

        def on_point(z: FloatArray, t: FloatArray, Jz: FloatArray, it: int, step: float,
                     system: HBSystem = system) -> bool:
            if state["skip"]:   # restart after N_f was halved: this point is stored already
                state["skip"] = False
                return False
            x, lam = system.from_z(z)
            if n_samples_rule == "adaptive":
                al = system.sampling_error(z, system.N)[0]
                if adaptive and al > alias_tol and system.N < n_samples_max:
                    N_up = system.smallest_n_samples(z, 2 * system.N, n_samples_max,
                                                     alias_tol)
                    state.update(refine=True, X=system.coefficients(z), lam=lam, t=t,
                                 step=step, N=N_up)
                    return True
            else:
                al = system.aliasing(z)
                if grow and al > alias_tol and system.N < n_samples_max:
                    state.update(refine=True, X=system.coefficients(z), lam=lam, t=t,
                                 step=step, N=None)
                    return True
            te, H_down = np.nan, system.H
            if harmonics_tol is not None:
                if system.H not in condensers:
                    condensers[system.H] = estimate_condenser(problem, system.H)
                est = truncation_error(problem, system.hb.nl_part(x), lam,
                                       tangent=system.nl_tangent(t), lam_scale=scale,
                                       condenser=condensers[system.H],
                                       point=system.hb if condensed else None)
                te = est.error
                if adaptive_harmonics and te > harmonics_tol and system.H < H_max:
                    H_up = min(H_max, max(system.H + 1,
                                          est.harmonics_needed(0.5 * harmonics_tol)))
                    state.update(refine=True, X=system.coefficients(z), lam=lam, t=t,
                                 step=step, N=max(system.N, default_min_samples(H_up)),
                                 H=H_up)
                    return True
                if adaptive_harmonics and system.H > H_min:
                    H_down = _coarser_harmonics(system, x, te, H_min,
                                                COARSEN_FRACTION * harmonics_tol)
            X = system.coefficients(z)
            J = system.physical_jacobian(z, Jz) if store_jacobians or callback else None
            w = problem.frequency(lam)
            step = step or state.pop("step", 0.0)
            state["s"] += step
            # the branch-point test's sign in this system, for the scan after Floquet
            # (which tests condensed branches only)
            bp = bordered_sign(Jz, t, metric(system)) if condensed else np.nan
            vals = (lam, X, w, t, it, step, J, al, system.N, z, system, system.H, te, bp)
            for key, val in zip(out, vals, strict=True):
                out[key].append(val)
            stop = False
            if callback is not None:
                point = BranchPoint(len(out["lam"]) - 1, lam, X, x, t, J, it, w, state["s"],
                                    float(t[-1]) * scale)
                stop = bool(callback(point))
            N_down = system.N
            if adaptive and not stop and system.N > n_floor:
                N_down = system.coarser_n_samples(z, n_floor, COARSEN_FRACTION * alias_tol)
            if not stop and (N_down < system.N or H_down < system.H):
                if H_down < system.H:
                    N_down = max(min(N_down, system.N), min(default_min_samples(H_down),
                                                            n_samples_max))
                state.update(coarsen=True, X=X, lam=lam, t=t, N=N_down, H=H_down)
                return True
            return stop

        opts.max_points = max_points - len(out["lam"]) + (1 if state["skip"] else 0)
        status = arclength(system, res0.z, res0.J, lam_end / scale, on_point, opts,
                           lam_physical=lambda lh: lh * scale, t_prev=t_prev,
                           lam_start=lam_first / scale)
        state["skip"] = False
        H_next = state.pop("H", system.H)
        if state["refine"]:
            # sampling or truncation error too large: more samples or harmonics, re-solve
            # this point, go on
            state["refine"] = False
            X_start, lam0, t_prev, N = state["X"], state["lam"], state["t"], state["N"]
            if N is None:   # the "grow" rule
                xs = to_real(X_start)[:, problem.nl_dofs]
                N = choose_n_samples(problem.law(lam0).force, xs, problem.frequency(lam0),
                                     tol=alias_tol / 100, n_min=2 * system.N,
                                     n_max=n_samples_max)
        elif state["coarsen"]:
            # fewer samples suffice: go on from the stored point (unless the range ended)
            state["coarsen"] = False
            if not status.message.startswith("stopped by the callback"):
                break
            X_start, lam0, t_prev, N = state["X"], state["lam"], state["t"], state["N"]
            state["skip"] = True
        else:
            break
        opts.ds = status.ds
        if H_next != system.H:
            why = f"H {'raised for the truncation error' if H_next > system.H else 'lowered'}"
            why += f" from {system.H} to {H_next}"
        else:
            why = ("N_f raised for the sampling error" if N > system.N else "N_f lowered")
            why += f" from {system.N}"
        t_prev = convert_tangent(t_prev, H_next, width)
        try:
            system, res0 = _start_point(problem, H_next, lam0, X_start, N, condensed, scale,
                                        limit_max, tol, max_iter, t_prev)
        except ConvergenceError as exc:
            # keep the promise: a failed step ends the branch, it does not raise
            at = f"N_f={N}" if H_next == system.H else f"H={H_next}, N_f={N}"
            failed = (f"re-solve at {at} failed at lam={lam0:.8g} ({why}; the branch ends "
                      f"at the last point with N_f={system.N}"
                      + ("" if H_next == system.H else f", H={system.H}")
                      + f"): {' '.join(str(exc).split())}")
            break
    al = np.array(out["al"])
    msg = status.message if failed is None else failed
    if al.size and al.max() > alias_tol:
        msg += (f"; warning: aliasing up to {al.max():.2g} (N_f={system.N}); "
                "consider a larger n_samples")
    Hs = np.array(out["H"], dtype=np.int64)
    te = np.array(out["te"], dtype=float)
    H_top = int(Hs.max()) if Hs.size else H
    msg += _truncation_warning(te, Hs, np.array(out["lam"]), harmonics_tol,
                               adaptive_harmonics, H_max)
    s_all = np.cumsum(out["ds"]) if out["ds"] else np.zeros(0)
    uniform = bool(Hs.size == 0 or np.all(Hs == H_top))
    return Branch(
        lam=np.array(out["lam"]), X=np.array([pad_coefficients(X, H_top) for X in out["X"]]),
        frequency=np.array(out["w"]),
        tangents=np.array([convert_tangent(t, H_top, width) for t in out["t"]]),
        iterations=np.array(out["it"], dtype=np.int64),
        ds=np.array(out["ds"]), s=s_all,
        jacobians=np.array(out["J"]) if store_jacobians and uniform else None, aliasing=al,
        success=status.success and failed is None, message=msg, H=H_top,
        n_samples=system.N, nl_dofs=problem.nl_dofs.copy(), condensed=condensed,
        lam_scale=scale,
        info={"n_samples": np.array(out["N"], dtype=np.int64),
              "n_samples_rule": n_samples_rule,
              "alias_tol": alias_tol, "harmonics": Hs, "truncation_error": te,
              "harmonics_tol": harmonics_tol, "adaptive_harmonics": adaptive_harmonics,
              **bordered_info(out["bp"], out["sys"], out["lam"], out["t"])},
        resolver=_Resolver(problem, out["z"], out["t"], s_all, out["sys"], tol, scale))



#: Per-point columns of ``Branch.info`` (one entry per computed point) that follow the
#: points when branches are joined or points inserted (the branch-point signs apart:
#: :data:`BORDERED`).
POINT_COLUMNS = ("n_samples", "harmonics", "truncation_error")

#: The ``Branch.info`` columns of :func:`bordered_info`.
BORDERED = ("bordered_sign", "bordered_system", "bordered_lam", "bordered_dir")


def bordered_info(signs: list[float], systems: list[HBSystem], lam: list[float],
                  tangents: list[FloatArray]) -> dict[str, NDArray[np.generic]]:
    """``Branch.info`` columns of the branch-point test at every point: its sign
    (``bordered_sign``, NaN where not taken), the index of the HB system it was taken in
    (``bordered_system``: signs compare only within one system; a new one at every change
    of H or N_f) and, to recognise the point it belongs to, its ``bordered_lam`` and the
    sign of its tangent's lam component (``bordered_dir``: a reversed branch does not
    match)."""
    ids: dict[int, int] = {}
    return {"bordered_sign": np.array(signs, dtype=float),
            "bordered_system": np.array([ids.setdefault(id(s), len(ids)) for s in systems],
                                        dtype=np.int64),
            "bordered_lam": np.array(lam, dtype=float),
            "bordered_dir": np.array([np.sign(t[-1]) for t in tangents], dtype=float)}


def _coarser_harmonics(system: HBSystem, x: FloatArray, error: float, H_min: int,
                       target: float) -> int:
    """The smallest H' in [H_min, H] for which the content of the harmonics above H' (in
    the length scales c, first order: what truncating them drops) plus the current
    estimate ``error`` is <= target."""
    c = system.problem.dof_scale[system.problem.nl_dofs]
    tail = tail_norms(harmonic_norms(system.hb.nl_part(x) / c[None, :]))  # tail[k] = |k..H|
    for h in range(H_min, system.H):
        if tail[h + 1] + error <= target:
            return h
    return system.H


def _truncation_warning(te: FloatArray, Hs: NDArray[np.int64], lam: FloatArray,
                        tol: float | None, adaptive: bool, H_max: int) -> str:
    """'; warning: ...' where the truncation estimate exceeds tol ('' if nowhere)."""
    if tol is None or not te.size:
        return ""
    bad = np.nan_to_num(te, nan=0.0) > tol
    if not bad.any():
        return ""
    i = int(np.argmax(np.where(bad, te, -np.inf)))
    where = (f"at {int(bad.sum())} of {te.size} points, up to {te[i]:.2g} at "
             f"lam={lam[i]:.8g} (H={int(Hs[i])})")
    if adaptive:
        return (f"; warning: HB truncation error above {tol:g} {where} with H at its "
                f"maximum {H_max}: raise harmonics_max")
    return (f"; warning: HB truncation error above {tol:g} {where}: the response, its "
            "folds and bifurcations are not converged in H; raise H or use "
            "harmonics = 'auto'")


class _Resolver:
    """Re-solves a branch at arc length s between its points (for locating events):
    Newton on ``R = 0, t_i . (z - z_i) = s - s_i`` from ``z_i + (s - s_i) t_i``."""

    def __init__(self, problem, zs, ts, s, systems, tol, scale) -> None:
        self.problem, self.zs, self.ts, self.s = problem, zs, ts, s
        self.systems, self.tol, self.scale = systems, tol, scale

    @_one_blas_thread
    def __call__(self, s: float) -> BranchPoint:
        if not len(self.s):
            raise ConvergenceError("empty branch: nothing to re-solve")
        i = int(np.clip(np.searchsorted(self.s, s, side="right") - 1, 0, len(self.s) - 1))
        system = self.systems[min(i + 1, len(self.s) - 1)]
        z_i, t_i = self.zs[i], self.ts[i]
        if self.systems[i].H != system.H:   # H changed between the two points: z_i, t_i
            m = system.n // (2 * system.H + 1)  # in the layout of the system used
            z_i = convert_tangent(z_i, system.H, m)
            t_i = convert_tangent(t_i, system.H, m)
            t_i = t_i / max(float(np.linalg.norm(t_i)), np.finfo(float).tiny)
        W = system.weights
        d = float(s - self.s[i])
        res = newton_extended(system, z_i + d * t_i, W * t_i, float((W * t_i) @ z_i) + d,
                              min(self.tol, 1e-8), 30)
        if not res.converged:
            raise ConvergenceError(f"{self.problem.name}: re-solving the branch at s={s:.6g} "
                                   f"(near lam={self.zs[i][-1] * self.scale:.8g}) failed: "
                                   f"{res.message}")
        x, lam = system.from_z(res.z)
        t = tangent(res.J, t_i, W)
        return BranchPoint(-1, lam, system.coefficients(res.z), x, t,
                           system.physical_jacobian(res.z, res.J), res.iterations,
                           self.problem.frequency(lam), float(s), float(t[-1]) * self.scale)


#: A re-solved point keeps its lam unless the scaled tangent's lam component is below this
#: (near a fold, where fixed lam is singular): then it stays on the plane normal to t.
FOLD_TANGENT = 0.1


def _start_point(problem: PeriodicProblem, H: int, lam: float, X: ComplexArray, N: int,
                 condensed: bool, scale: float, limit_max: float, tol: float, max_iter: int,
                 t: FloatArray | None = None, plane: bool = False
                 ) -> tuple[HBSystem, NewtonResult]:
    """Continuation system with N samples and the point at lam solved in it (at fixed lam,
    or on the plane through it normal to the tangent t near a fold or with ``plane``)."""
    system, z0 = hb_system(problem, H, lam, X, N, condensed, scale, limit_max)
    a = np.zeros(system.n + 1)
    a[-1] = 1.0
    if t is not None and (plane or abs(t[-1]) < FOLD_TANGENT):
        a = system.weights * t
    res = newton_extended(system, z0, a, float(a @ z0), tol, max(max_iter, 20))
    if not res.converged:
        raise ConvergenceError(f"{problem.name}: point lost at lam={lam:.8g} with "
                               f"N_f={N}: {res.message}")
    return system, res
