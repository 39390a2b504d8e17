"""Periodic solutions by HB-AFT: one point (:func:`solve_periodic`) and branches by
pseudo arc-length continuation (:func:`continue_periodic`).

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
from rotorsfd.continuation.newton import NewtonResult, newton_extended, tangent
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.blas import single_threaded_blas
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import aliasing_error, choose_n_samples, to_real
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.residual import FullHB

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
EventHook = Callable[[BranchPoint], "bool | None"]


class HBSystem:
    """Scaled continuation system ``z = (x/c, lam/lam_scale)`` around an HB residual."""

    def __init__(self, problem: PeriodicProblem, H: int, N: int, condensed: bool,
                 lam_ref: float, lam_scale: float, limit_max: float = 1.0) -> None:
        self.problem, self.H, self.N, self.condensed = problem, H, N, condensed
        self.hb: CondensedHB | FullHB = (CondensedHB if condensed else FullHB)(problem, H, N)
        self.n = self.hb.n_unknowns
        self.lam_scale = float(lam_scale)
        self.limit_max = limit_max
        c = problem.dof_scale
        if condensed:
            self.cx = np.tile(c[problem.nl_dofs], 2 * H + 1)
            self.cr = self.cx
        else:
            kappa = np.abs(np.diag(problem.matrices(lam_ref)[2]))
            pos = kappa[kappa > 0]
            kappa = np.where(kappa > 0, kappa, pos.mean() if pos.size else 1.0)
            self.cx = np.tile(c, 2 * H + 1)
            self.cr = np.tile(c * kappa, 2 * H + 1)
        # arc length measured on the nonlinear DOFs and lam in both paths (same branch)
        self.weights = np.ones(self.n + 1)
        if not condensed:
            nl = np.zeros((2 * H + 1, problem.n_dof))
            nl[:, problem.nl_dofs] = 1.0
            self.weights[:-1] = nl.ravel()

    # scaling -----------------------------------------------------------------------------
    def to_z(self, x: FloatArray, lam: float) -> FloatArray:
        return np.append(np.ravel(x) / self.cx, lam / self.lam_scale)

    def from_z(self, z: FloatArray) -> tuple[FloatArray, float]:
        return z[:-1] * self.cx, float(z[-1]) * self.lam_scale

    # ContinuationSystem protocol ------------------------------------------------------------
    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        x, lam = self.from_z(z)
        R, J, dR = self.hb.residual(x, lam, jac=True)
        Jz = np.empty((self.n, self.n + 1))
        Jz[:, :-1] = J if self.condensed else J * (self.cx[None, :] / self.cr[:, None])
        Jz[:, -1] = dR * (self.lam_scale / self.cr)
        return R.ravel() / self.cr, Jz

    def admissible(self, z: FloatArray) -> bool:
        if self.problem.nl_limit is None:
            return True
        x, _ = self.from_z(z)
        val = self.problem.limit(self.hb.aft.E @ self.hb.nl_part(x))
        return bool(np.isfinite(val) and val < self.limit_max)

    # results -------------------------------------------------------------------------------
    def physical_jacobian(self, z: FloatArray, Jz: FloatArray) -> FloatArray:
        """[dR/dx, dR/dlam] in physical units (condensed: Schur form) at a solution z."""
        J = Jz[:, :-1] * (self.cr[:, None] / self.cx[None, :])
        dR = Jz[:, -1] * (self.cr / self.lam_scale)
        if isinstance(self.hb, CondensedHB):
            return self.hb.schur_jacobian(J, dR, self.from_z(z)[1])
        return np.column_stack([J, dR])

    def coefficients(self, z: FloatArray) -> ComplexArray:
        """Fourier coefficients of all DOFs (H+1, n_dof) at z."""
        x, lam = self.from_z(z)
        if isinstance(self.hb, CondensedHB):
            return self.hb.recover(x, lam)
        xr = x.reshape(2 * self.H + 1, self.problem.n_dof)
        X = np.empty((self.H + 1, self.problem.n_dof), dtype=complex)
        X[0] = xr[0]
        X[1:] = xr[1::2] + 1j * xr[2::2]
        return X

    def aliasing(self, z: FloatArray) -> float:
        x, lam = self.from_z(z)
        xs = self.hb.nl_part(x)
        if isinstance(self.hb, CondensedHB):
            return self.hb.aliasing(xs, lam)
        return aliasing_error(self.problem.nl_force, xs, self.problem.frequency(lam), self.N,
                              self.hb.last_G(xs, lam))


def _initial_guess(problem: PeriodicProblem, H: int, lam: float,
                   X0: ComplexArray | None) -> ComplexArray:
    """All-DOF start (H+1, n): X0, or the linear response with the nonlinearity replaced by
    its linearisation at rest (``u = Zt^-1 F``), shrunk until nl_limit < 1."""
    if X0 is not None:
        X0 = np.asarray(X0, dtype=complex)
        if X0.shape == (H + 1, problem.n_dof):
            return X0
        X = np.zeros((H + 1, problem.n_dof), dtype=complex)
        h = min(H, X0.shape[0] - 1)
        if X0.shape[1] == problem.n_dof:
            X[: h + 1] = X0[: h + 1]
            return X
        raise ValueError(f"X0 must have shape (H+1, n_dof)=({H + 1}, {problem.n_dof}); "
                         f"got {X0.shape}")
    cond = CondensedHB(problem, H, 4 * H + 4)
    cond.set_shift(np.zeros((2 * H + 1, problem.m)), lam)
    X = cond.condense(lam, deriv=False).u.copy()
    if problem.nl_limit is not None:
        E = cond.aft.E
        for _ in range(60):
            if problem.limit(E @ to_real(X[:, problem.nl_dofs])) < 0.9:
                break
            X[1:] *= 0.5
    return X


def _setup(problem: PeriodicProblem, H: int, lam: float, X0: ComplexArray | None,
           n_samples: int | None, condensed: bool, lam_scale: float, limit_max: float
           ) -> tuple[HBSystem, FloatArray]:
    Xg = _initial_guess(problem, H, lam, X0)
    xg = to_real(Xg)
    N = n_samples or choose_n_samples(problem.nl_force, xg[:, problem.nl_dofs],
                                      problem.frequency(lam))
    system = HBSystem(problem, H, N, condensed, lam, lam_scale, limit_max)
    if isinstance(system.hb, CondensedHB):
        system.hb.set_shift(xg[:, problem.nl_dofs], lam)
        z0 = system.to_z(xg[:, problem.nl_dofs], lam)
    else:
        z0 = system.to_z(xg, lam)
    return system, z0


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
    system, z0 = _setup(problem, H, lam, X0, n_samples, condensed,
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


@_one_blas_thread
def continue_periodic(problem: PeriodicProblem, lam_start: float, lam_end: float, H: int,
                      X0: ComplexArray | None = None, *, n_samples: int | None = None,
                      condensed: bool = True, tol: float = 1e-6, ds: float = 0.01,
                      ds_min: float = 1e-6, ds_max: float = 0.05, max_iter: int = 8,
                      max_points: int = 2000, max_angle_deg: float = 20.0,
                      lam_scale: float | None = None, limit_max: float = 1.0,
                      alias_tol: float = 1e-6, n_samples_max: int = 2048,
                      store_jacobians: bool | None = None, callback: EventHook | None = None
                      ) -> Branch:
    """Branch of periodic solutions from lam_start towards lam_end (pseudo arc-length).

    Steps ``ds, ds_min, ds_max`` are arc lengths in the scaled unknowns (module docstring).
    N_f: with ``n_samples=None`` the rule of :func:`~rotorsfd.harmonic.fourier.choose_n_samples`
    at the first point, then, at every converged point, if doubling N_f would change the
    nonlinear-force coefficients by more than ``alias_tol`` (relative), N_f is doubled
    (the rule again, up to ``n_samples_max``) and the point re-solved before going on.
    ``callback(point: BranchPoint)`` is called at every converged point (the first too);
    returning True stops the continuation there (success, message says so).
    ``store_jacobians`` (default: only when condensed) keeps ``Branch.jacobians``.
    Never raises on a failed step: returns the points so far with ``success = False`` and a
    message saying where (lam) and why. Raises ConvergenceError only if the first point
    cannot be found.
    """
    scale = lam_scale or (abs(lam_end - lam_start) or max(abs(lam_start), 1.0))
    first = solve_periodic.__wrapped__(problem, lam_start, H, X0, n_samples=n_samples,
                                       condensed=condensed, tol=tol, limit_max=limit_max)
    if store_jacobians is None:
        store_jacobians = condensed
    keys = ("lam", "X", "w", "t", "it", "ds", "J", "al", "N", "z", "sys")
    out: dict[str, list] = {k: [] for k in keys}
    state: dict = {"refine": False, "s": 0.0}
    opts = ArcLengthOptions(ds=ds, ds_min=ds_min, ds_max=ds_max, tol=tol, max_iter=max_iter,
                            max_points=max_points, max_angle=float(np.radians(max_angle_deg)))
    X_start, lam0, N, t_prev = first.X, lam_start, first.n_samples, None
    while True:
        system, res0 = _start_point(problem, H, lam0, X_start, N, condensed, scale,
                                    limit_max, tol, max_iter)

        def on_point(z: FloatArray, t: FloatArray, Jz: FloatArray, it: int, step: float,
                     system: HBSystem = system) -> bool:
            x, lam = system.from_z(z)
            X = system.coefficients(z)
            J = system.physical_jacobian(z, Jz) if store_jacobians or callback else None
            w = problem.frequency(lam)
            al = system.aliasing(z)
            if n_samples is None and al > alias_tol and system.N < n_samples_max:
                state.update(refine=True, X=X, lam=lam, t=t, step=step)
                return True
            step = step or state.pop("step", 0.0)
            state["s"] += step
            vals = (lam, X, w, t, it, step, J, al, system.N, z, system)
            for key, val in zip(out, vals, strict=True):
                out[key].append(val)
            if callback is None:
                return False
            point = BranchPoint(len(out["lam"]) - 1, lam, X, x, t, J, it, w, state["s"],
                                float(t[-1]) * scale)
            return bool(callback(point))

        opts.max_points = max_points - len(out["lam"])
        status = arclength(system, res0.z, res0.J, lam_end / scale, on_point, opts,
                           lam_physical=lambda lh: lh * scale, t_prev=t_prev,
                           lam_start=lam_start / scale)
        if not state["refine"]:
            break
        # aliasing too large: more samples (the rule at this point), re-solve, go on
        state["refine"] = False
        X_start, lam0, t_prev = state["X"], state["lam"], state["t"]
        xs = to_real(X_start)[:, problem.nl_dofs]
        N = choose_n_samples(problem.nl_force, xs, problem.frequency(lam0), tol=alias_tol / 100,
                             n_min=2 * system.N, n_max=n_samples_max)
        opts.ds = status.ds
    al = np.array(out["al"])
    msg = status.message
    if al.size and al.max() > alias_tol:
        msg += (f"; warning: aliasing up to {al.max():.2g} (N_f={system.N}); "
                "consider a larger n_samples")
    s_all = np.cumsum(out["ds"]) if out["ds"] else np.zeros(0)
    return Branch(
        lam=np.array(out["lam"]), X=np.array(out["X"]), frequency=np.array(out["w"]),
        tangents=np.array(out["t"]), iterations=np.array(out["it"], dtype=np.int64),
        ds=np.array(out["ds"]), s=s_all,
        jacobians=np.array(out["J"]) if store_jacobians else None, aliasing=al,
        success=status.success, message=msg, H=H, n_samples=system.N,
        nl_dofs=problem.nl_dofs.copy(), condensed=condensed, lam_scale=scale,
        info={"n_samples": np.array(out["N"], dtype=np.int64)},
        resolver=_Resolver(problem, out["z"], out["t"], s_all, out["sys"], tol, scale))


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


def _start_point(problem: PeriodicProblem, H: int, lam: float, X: ComplexArray, N: int,
                 condensed: bool, scale: float, limit_max: float, tol: float, max_iter: int
                 ) -> tuple[HBSystem, NewtonResult]:
    """Continuation system with N samples and the point at lam solved in it."""
    system, z0 = _setup(problem, H, lam, X, N, condensed, scale, limit_max)
    e = np.zeros(system.n + 1)
    e[-1] = 1.0
    res = newton_extended(system, z0, e, float(z0[-1]), tol, max(max_iter, 20))
    if not res.converged:
        raise ConvergenceError(f"{problem.name}: point lost at lam={lam:.8g} with "
                               f"N_f={N}: {res.message}")
    return system, res
