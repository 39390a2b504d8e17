"""Tori by two-frequency HB-AFT: one point (:func:`solve_torus`) and branches in a parameter
by the generic pseudo arc-length continuation (:func:`continue_torus`).

Scaling as in :mod:`rotorsfd.harmonic.periodic`: Newton unknowns ``xs / c`` (c the
nonlinear DOFs' length scales, e.g. the SFD clearance) and ``lam / lam_scale``; the
condensed residual (a length) over c; a point is converged when the 2-norm of the scaled
extended residual is <= tol. The elements' validity measure (an SFD's eccentricity ratio)
must stay below ``limit_max`` at every grid point of the torus: a step that crosses it is
halved, and the branch ends there with the corrector's message, as a periodic branch does.
The grid N1 x N2 starts at the one-dimensional floor per direction
(``default_min_samples(H1) x default_min_samples(H2)``). The sampling error of every point
is measured in the units of the Newton test, as the periodic "adaptive" rule does: the
change of the scaled condensed residual ``|Ht (G_2N - G_N)| / c`` when N1 or N2 doubles;
where it exceeds ``alias_tol`` (default: the Newton tolerance) in a direction, that
direction's N doubles and the point is solved again (the grid only grows along a branch).
The error is stored per point; the message warns if it stayed above ``alias_tol`` at
``grid_max``. A given ``grid`` is used as it is.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.arclength import ArcLengthOptions, arclength
from rotorsfd.continuation.newton import newton_extended
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.fourier import default_min_samples, to_real
from rotorsfd.quasiperiodic.torus_fourier import (
    TorusAFT,
    TorusLattice,
    synthesize,
)
from rotorsfd.quasiperiodic.torus_linear import TorusProblem
from rotorsfd.quasiperiodic.torus_residual import TorusHB, torus_force

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


class TorusSystem:
    """Scaled continuation system ``z = (xs / c, lam / lam_scale)`` around :class:`TorusHB`
    (the :class:`~rotorsfd.continuation.newton.ContinuationSystem` protocol)."""

    def __init__(self, problem: TorusProblem, lattice: TorusLattice, grid: tuple[int, int],
                 lam_scale: float, limit_max: float = 1.0) -> None:
        self.problem, self.lattice, self.grid = problem, lattice, tuple(grid)
        self.hb = TorusHB(problem, lattice, *grid)
        self.n = self.hb.n_unknowns
        self.lam_scale = float(lam_scale)
        self.limit_max = limit_max
        self.cx = np.tile(problem.dof_scale[problem.nl_dofs], lattice.n_real)

    def to_z(self, xs: FloatArray, lam: float) -> FloatArray:
        return np.append(np.ravel(xs) / self.cx, lam / self.lam_scale)

    def from_z(self, z: FloatArray) -> tuple[FloatArray, float]:
        xs = (z[:-1] * self.cx).reshape(self.lattice.n_real, self.problem.m)
        return xs, float(z[-1]) * self.lam_scale

    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]:
        xs, lam = self.from_z(z)
        R, J, dR = self.hb.residual(xs, lam, jac=True)
        Jz = np.empty((self.n, self.n + 1))
        Jz[:, :-1] = J * (self.cx[None, :] / self.cx[:, None])
        Jz[:, -1] = dR * (self.lam_scale / self.cx)
        return R.ravel() / self.cx, Jz

    def admissible(self, z: FloatArray) -> bool:
        if self.problem.elements is None or not self.problem.m:
            return True
        xs, _ = self.from_z(z)
        val = self.problem.limit(self.hb.aft.sample(xs))
        return bool(np.isfinite(val) and val < self.limit_max)

    def coefficients(self, z: FloatArray) -> ComplexArray:
        xs, lam = self.from_z(z)
        return self.hb.coefficients(xs, lam)

    def aliasing(self, z: FloatArray) -> float:
        """Sampling error at z: the larger of :meth:`aliasing_axes`."""
        return max(self.aliasing_axes(z))

    def aliasing_axes(self, z: FloatArray, grid: tuple[int, int] | None = None
                      ) -> tuple[float, float]:
        """Sampling error of each torus direction on ``grid`` (default: this one), in the
        units of the Newton test: ``|Ht (G_2N - G_N)|_2 / c`` when N1 (N2) doubles, the
        change of the scaled condensed residual (0 without elements)."""
        if not self.problem.m:
            return 0.0, 0.0
        xs, lam = self.from_z(z)
        N1, N2 = grid or self.grid
        Ht = self.hb.condenser.condense(lam, deriv=False).Ht
        G = [torus_force(self.problem, TorusAFT(self.lattice, *g), xs, lam, jac=False).G
             for g in ((N1, N2), (2 * N1, N2), (N1, 2 * N2))]
        e = [float(np.linalg.norm(Ht @ (Gd - G[0]).ravel() / self.cx)) for Gd in G[1:]]
        return e[0], e[1]

    def finer_grid(self, z: FloatArray, tol: float, n_max: int) -> tuple[int, int]:
        """This grid with N1 and N2 doubled while their sampling error at z exceeds tol
        (up to n_max per direction)."""
        grid = self.grid
        for _ in range(8):
            err = self.aliasing_axes(z, grid)
            finer = tuple(N * 2 if e > tol and N < n_max else N
                          for e, N in zip(err, grid, strict=True))
            if finer == grid:
                break
            grid = finer
        return grid

    def with_grid(self, grid: tuple[int, int]) -> TorusSystem:
        """The same system on another grid (sharing the condensed linear operators)."""
        other = TorusSystem(self.problem, self.lattice, grid, self.lam_scale,
                            self.limit_max)
        other.hb.condenser = self.hb.condenser
        return other


def initial_guess(problem: TorusProblem, lattice: TorusLattice, lam: float,
                  X0: ComplexArray | None, grid: tuple[int, int]) -> FloatArray:
    """Nonlinear-DOF unknowns (n_real, m) to start from: X0's (all DOFs, (nk, n)), or
    the linear response with the elements replaced by their linearisation at rest,
    halved until the validity measure is below 0.9."""
    if X0 is not None:
        return to_real(np.asarray(X0)[:, problem.nl_dofs])
    hb = TorusHB(problem, lattice, *grid)
    zero = np.zeros((lattice.n_real, problem.m))
    hb.set_shift(zero, lam)
    G = torus_force(problem, hb.aft, zero, lam, jac=False).G
    cond = hb.condenser.condense(lam, deriv=False)
    X = hb.condenser.recover(cond, zero, G)
    xs = to_real(X[:, problem.nl_dofs])
    for _ in range(60):
        if problem.limit(hb.aft.sample(xs)) < 0.9:
            break
        xs = 0.5 * xs
    return xs


def torus_system(problem: TorusProblem, lattice: TorusLattice, lam: float,
                 X0: ComplexArray | None, grid: tuple[int, int] | None, lam_scale: float,
                 limit_max: float) -> tuple[TorusSystem, FloatArray]:
    """The scaled system at lam on ``grid`` (default: ``default_min_samples`` of H1 and
    of h(0), the one-dimensional floor per direction), its shift Delta set at the first
    unknowns, and those unknowns."""
    if grid is None:
        grid = (default_min_samples(lattice.H1), default_min_samples(lattice.h(0)))
    xs = initial_guess(problem, lattice, lam, X0, grid)
    system = TorusSystem(problem, lattice, grid, lam_scale, limit_max)
    system.hb.set_shift(xs, lam)
    return system, system.to_z(xs, lam)


@dataclass
class TorusSolution:
    """One torus: one-sided coefficients X (nk, n) on the lattice's half lattice."""

    lam: float
    X: ComplexArray
    omega: float
    wb: float
    lattice: TorusLattice
    grid: tuple[int, int]
    iterations: int
    residual_norm: float
    aliasing: float

    def time_series(self, t: FloatArray) -> FloatArray:
        """q(t) (nt, n) on the torus started at phases (0, 0)."""
        return synthesize(self.lattice, self.X, self.omega, self.wb, t)


def solve_torus(problem: TorusProblem, lam: float, lattice: TorusLattice,
                X0: ComplexArray | None = None, *, grid: tuple[int, int] | None = None,
                tol: float = 1e-8, max_iter: int = 50, limit_max: float = 1.0,
                alias_tol: float | None = None, grid_max: int = 512) -> TorusSolution:
    """The torus at fixed lam by Newton on the condensed equations (ConvergenceError on
    failure, saying where and why). Without ``grid`` the solution is refined: N1, N2
    double while their sampling error exceeds ``alias_tol`` (default tol) and the torus
    is solved again."""
    system, z = torus_system(problem, lattice, lam, X0, grid, max(abs(lam), 1.0),
                             limit_max)
    e = np.zeros(system.n + 1)
    e[-1] = 1.0
    it, norm = 0, 0.0
    for _ in range(8 if system.n else 0):
        res = newton_extended(system, z, e, float(z[-1]), tol, max_iter)
        if not res.converged:
            raise ConvergenceError(f"{problem.name}: no torus at lam={lam:.8g} "
                                   f"({lattice}, grid {system.grid}): {res.message}")
        z, it, norm = res.z, it + res.iterations, res.norm
        finer = system.grid if grid else system.finer_grid(
            z, tol if alias_tol is None else alias_tol, grid_max)
        if finer == system.grid:
            break
        system = system.with_grid(finer)
    om, wb = problem.frequencies(lam)
    return TorusSolution(lam, system.coefficients(z), om, wb, lattice, system.grid, it,
                         norm, system.aliasing(z))


@dataclass
class TorusBranch:
    """A branch of tori: ``lam`` (n_points,), ``X`` (n_points, nk, n) one-sided
    coefficients, ``omega`` and ``wb`` the two base frequencies at each point, the arc
    length ``s``, tangents, Newton iterations, the sampling error per point, the outcome."""

    lam: FloatArray
    X: ComplexArray
    omega: FloatArray
    wb: FloatArray
    lattice: TorusLattice
    grid: tuple[int, int]
    s: FloatArray
    tangents: FloatArray
    iterations: NDArray[np.int64]
    aliasing: FloatArray
    limit: FloatArray
    success: bool
    message: str
    info: dict = field(default_factory=dict)

    @property
    def n_points(self) -> int:
        return int(self.lam.size)

    def amplitude(self, dof: int, k1: int, k2: int) -> FloatArray:
        """|X_(k1, k2)| of one DOF along the branch (half peak-to-peak of that line)."""
        return np.abs(self.X[:, self.lattice.index(k1, k2), dof])

    def time_series(self, index: int, t: FloatArray) -> FloatArray:
        """q(t) (nt, n) at point ``index``, torus phases (0, 0) at t = 0."""
        return synthesize(self.lattice, self.X[index], self.omega[index], self.wb[index], t)


def continue_torus(problem: TorusProblem, lam_start: float, lam_end: float,
                   lattice: TorusLattice, X0: ComplexArray | None = None, *,
                   grid: tuple[int, int] | None = None, tol: float = 1e-6,
                   ds: float = 0.01, ds_min: float = 1e-6, ds_max: float = 0.05,
                   max_iter: int = 8, max_points: int = 500, max_angle_deg: float = 20.0,
                   lam_scale: float | None = None, limit_max: float = 1.0,
                   alias_tol: float | None = None, grid_max: int = 512,
                   callback: Callable[[int, float, ComplexArray], bool | None] | None = None
                   ) -> TorusBranch:
    """Branch of tori from lam_start towards lam_end by pseudo arc-length
    (:func:`~rotorsfd.continuation.arclength.arclength`; steps in the scaled unknowns,
    module docstring). ``callback(index, lam, X) -> stop``. The branch ends with
    ``success = False`` and the continuation's message where the corrector fails (the
    validity limit of an element, no convergence) or the branch turns back; raises
    ConvergenceError only if the first point cannot be found.

    The grid: ``grid`` as given, or adapted (module docstring; ``alias_tol`` default
    tol)."""
    scale = lam_scale or (abs(lam_end - lam_start) or max(abs(lam_start), 1.0))
    alias_tol = tol if alias_tol is None else alias_tol
    system, z0 = torus_system(problem, lattice, lam_start, X0, grid, scale, limit_max)
    e = np.zeros(system.n + 1)
    e[-1] = 1.0
    first = newton_extended(system, z0, e, float(z0[-1]), tol, 50)
    if not first.converged:
        raise ConvergenceError(f"{problem.name}: no torus at lam={lam_start:.8g} "
                               f"({lattice}, grid {system.grid}): {first.message}")
    out: dict[str, list] = {k: [] for k in ("lam", "X", "om", "wb", "t", "it", "ds", "al",
                                            "lim")}
    state: dict = {"refine": None, "carry": 0.0}

    def on_point(z: FloatArray, t: FloatArray, J: FloatArray, it: int, step: float) -> bool:
        err = system.aliasing_axes(z)
        finer = tuple(N * 2 if e > alias_tol and N < grid_max else N
                      for e, N in zip(err, system.grid, strict=True))
        if finer != system.grid and grid is None:     # solve this point on a finer grid
            state["refine"] = (z, t, finer, step)
            return True
        xs, lam = system.from_z(z)
        om, wb = problem.frequencies(lam)
        lim = problem.limit(system.hb.aft.sample(xs)) if problem.m else 0.0
        step = step or state["carry"]
        state["carry"] = 0.0
        vals = (lam, system.coefficients(z), om, wb, t, it, step, max(err), lim)
        for key, val in zip(out, vals, strict=True):
            out[key].append(val)
        return bool(callback(len(out["lam"]) - 1, lam, vals[1])) if callback else False

    opts = ArcLengthOptions(ds=ds, ds_min=ds_min, ds_max=ds_max, tol=tol, max_iter=max_iter,
                            max_points=max_points, max_angle=float(np.radians(max_angle_deg)))
    z, J, t_prev = first.z, first.J, None
    while True:
        opts.max_points = max(1, max_points - len(out["lam"]))
        status = arclength(system, z, J, lam_end / scale, on_point, opts,
                           lam_physical=lambda v: v * scale, t_prev=t_prev,
                           lam_start=lam_start / scale)
        if state["refine"] is None:
            break
        z_old, t_prev, finer, step = state["refine"]
        state["refine"], state["carry"] = None, step
        lam = system.from_z(z_old)[1]
        system = system.with_grid(finer)
        e = np.zeros(system.n + 1)
        e[-1] = 1.0
        again = newton_extended(system, z_old, e, float(z_old[-1]), tol, 20)
        if not again.converged:
            status.success = False
            status.message = (f"re-solve on the grid {finer[0]} x {finer[1]} (sampling "
                              f"error) failed at lam={lam:.8g}: {again.message}")
            break
        z, J = again.z, again.J
        opts.ds = status.ds or opts.ds
    al = np.array(out["al"])
    msg = status.message
    if al.size and al.max() > alias_tol:
        msg += (f"; warning: sampling error up to {al.max():.2g} on the grid "
                f"{system.grid[0]} x {system.grid[1]}: pass a finer grid")
    return TorusBranch(
        lam=np.array(out["lam"]), X=np.array(out["X"]), omega=np.array(out["om"]),
        wb=np.array(out["wb"]), lattice=lattice, grid=system.grid,
        s=np.cumsum(out["ds"]), tangents=np.array(out["t"]),
        iterations=np.array(out["it"], dtype=np.int64), aliasing=al,
        limit=np.array(out["lim"]), success=status.success, message=msg,
        info={"lam_scale": scale, "tol": tol, "limit_max": limit_max,
              "alias_tol": alias_tol})
