"""The quantities ``rotorsfd calibrate`` fits, with their derivatives in config fields.

Critical speed (exact derivative). Omega_c is a root of ``g(Omega, p) = w_i(Omega, p) -
h Omega`` with ``w_i = Im lambda_i`` the i-th damped frequency of its whirl
(:mod:`rotorsfd.linear.critical`). For a simple eigenvalue of the state matrix
``A = [[0, I], [-M^-1 K, -M^-1 D]]`` with right/left eigenvectors ``x``, ``y``::

    dlambda/dq = y^H A_q x / (y^H x),
    A_q = [[0, 0], [-M^-1 (K_q - M_q M^-1 K), -M^-1 (D_q - M_q M^-1 D)]],

and by the implicit-function theorem on g::

    dOmega_c/dp = -Im(dlambda/dp) / (Im(dlambda/dOmega) - h).

``M_p, D_p, K_p`` are central differences of the assembled matrices of the config with the
field moved by +-1e-4 of its value; the eigen-derivative is exact given them (and the
differences are exact to rounding for fields the matrices are linear in, a stiffness or a
damping coefficient). ``M_Omega`` etc. likewise in the speed (D is linear in it). After the
first bracketing search the critical speeds are followed by Newton's method on g with
this derivative (the same g, the same branch index), falling back to the search if Newton
leaves the range or does not converge.

Response quantities (derivatives by central finite differences on rebuilt configs): the
located saddle-node speeds of the speed branch (``locate_branch_fold``), the speed of a
located bifurcation (``[analysis.stability]`` on) and the peak of r = max_t sqrt(y^2 +
z^2) at a node [m], located between the branch points around the largest one by a bounded
scalar search over the arc length.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
import scipy.linalg
from scipy.optimize import minimize_scalar

from rotorsfd.continuation.folds import locate_branch_fold
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.linear.critical import critical_speeds
from rotorsfd.linear.modal import DENSE_MAX_DOF, dense_eigen, state_matrix
from rotorsfd.model import dofs

Matrices = tuple[np.ndarray, np.ndarray, np.ndarray]


def branch_eigenvalue(system: Any, speed: float, mode: int, whirl: str,
                      n_modes: int) -> complex:
    """lambda of the ``mode``-th (1-based) mode of ``whirl`` at ``speed`` (dense)."""
    res = dense_eigen(system, speed, n_modes)
    lam = res.eigenvalues if whirl == "any" else res.eigenvalues[res.whirl == whirl]
    if lam.size < mode:
        raise ConvergenceError(f"fewer than {mode} {whirl} modes among {n_modes} at "
                               f"{speed:g} rad/s")
    return complex(lam[mode - 1])


def eigen_derivatives(mats: Matrices, dmats: Sequence[Matrices], lam: complex
                      ) -> tuple[complex, np.ndarray]:
    """The eigenvalue of the state matrix of ``mats`` nearest ``lam`` and its derivatives
    dlambda/dq_j for each ``dmats[j] = (M_q, D_q, K_q)`` (module docstring)."""
    mass, damping, stiffness = (np.asarray(m, dtype=float) for m in mats)
    n = mass.shape[0]
    vals, left, right = scipy.linalg.eig(state_matrix(mass, damping, stiffness),
                                         left=True, right=True)
    k = int(np.argmin(np.abs(vals - lam)))
    x, y = right[:, k], left[:, k]
    norm = y.conj() @ x
    factor = scipy.linalg.cho_factor(mass)
    minv_k = scipy.linalg.cho_solve(factor, stiffness)
    minv_d = scipy.linalg.cho_solve(factor, damping)
    out = np.empty(len(dmats), dtype=complex)
    for j, (m_q, d_q, k_q) in enumerate(dmats):
        a_k = scipy.linalg.cho_solve(factor, k_q - m_q @ minv_k)
        a_d = scipy.linalg.cho_solve(factor, d_q - m_q @ minv_d)
        # y^H A_q x with A_q = [[0, 0], [-a_k, -a_d]]
        out[j] = -(y[n:].conj() @ (a_k @ x[:n] + a_d @ x[n:])) / norm
    return complex(vals[k]), out


def difference(f: Callable[[float], Matrices], value: float, rel: float = 1e-4
               ) -> Matrices:
    """Central difference (M, D, K)' of ``f`` at ``value`` (step rel * |value|, or rel)."""
    h = rel * abs(value) if value != 0.0 else rel
    lo, hi = f(value - h), f(value + h)
    return tuple((np.asarray(b, dtype=float) - np.asarray(a, dtype=float)) / (2 * h)
                 for a, b in zip(lo, hi, strict=True))  # type: ignore[return-value]


class CriticalSpeedTracker:
    """Critical speeds of ``modes`` (1-based, of one whirl) and their exact derivatives in
    the fields ``paths``, for configs rebuilt by ``system_of(values)``."""

    def __init__(self, system_of: Callable[[Sequence[float]], Any], modes: Sequence[int],
                 whirl: str, speed_max: float, harmonic: float = 1.0) -> None:
        self.system_of, self.modes, self.whirl = system_of, list(modes), whirl
        self.speed_max, self.harmonic = float(speed_max), float(harmonic)
        self.last: np.ndarray | None = None
        self.branches: list[int] = []
        self.lams: list[complex] = []
        self.last_p = b""

    def n_modes(self) -> int:
        return 4 * max(self.modes) + 8

    def search(self, system: Any) -> np.ndarray:
        """The bracketing search of :func:`critical_speeds` (ConvergenceError if a critical
        speed asked for is not below ``speed_max``)."""
        n = max(self.modes)
        found = {c.mode: c.speed_rad_s for c in critical_speeds(
            system, n=n, whirl=self.whirl, harmonic=self.harmonic,
            speed_range=(0.0, self.speed_max), n_modes=self.n_modes())}
        ordered = sorted(found.values())
        if len(ordered) < n:
            raise ConvergenceError(f"only {len(ordered)} {self.whirl} critical speeds below "
                                   f"{self.speed_max:g} rad/s; {n} needed")
        return np.array([ordered[m - 1] for m in self.modes])

    def newton(self, system: Any, mode: int, start: float) -> tuple[float, complex]:
        """(Omega_c, lambda) of branch ``mode`` by Newton's method on g from ``start``; the
        eigenvalue is followed by its first-order prediction and checked at the end to be
        the ``mode``-th of its whirl (ConvergenceError otherwise)."""
        speed = start
        guess = branch_eigenvalue(system, speed, mode, self.whirl, self.n_modes())
        for _ in range(30):
            lam, (dlam,) = eigen_derivatives(system.matrices(speed),
                                             [difference(system.matrices, speed)], guess)
            step = -(lam.imag - self.harmonic * speed) / (dlam.imag - self.harmonic)
            speed += step
            guess = lam + dlam * step
            if not 0.0 < speed < self.speed_max:
                break
            if abs(step) <= 1e-12 * abs(speed):
                check = branch_eigenvalue(system, speed, mode, self.whirl, self.n_modes())
                if abs(check - guess) <= 1e-6 * abs(guess):
                    return speed, check
                break
        raise ConvergenceError(f"Newton on critical speed {mode} did not converge")

    def values(self, p: Sequence[float]) -> np.ndarray:
        """The critical speeds [rad/s] at field values ``p`` (the last ones again if ``p``
        is the last point)."""
        key = np.asarray(p, dtype=float).tobytes()
        if self.last is not None and key == self.last_p:
            return self.last.copy()
        system = self.system_of(p)
        if system.n_dof > DENSE_MAX_DOF:
            raise ConfigError("--target", "critical_speed",
                              f"exact derivatives need the dense eigensolver (<= "
                              f"{DENSE_MAX_DOF} DOF, the rotor has {system.n_dof})")
        out = None
        if self.last is not None:
            try:
                # the branch index is the one critical_speeds numbers modes by (mode b of
                # the sorted branch list); Newton keeps the branch it starts on
                pairs = [self.newton(system, b, s)
                         for b, s in zip(self.branches, self.last, strict=True)]
                out = np.array([sp for sp, _ in pairs])
                self.lams = [lam for _, lam in pairs]
            except ConvergenceError:
                out = None
        if out is None:
            out = self.search(system)
            self.branches = [self.branch_of(system, s) for s in out]
            self.lams = [branch_eigenvalue(system, s, b, self.whirl, self.n_modes())
                         for s, b in zip(out, self.branches, strict=True)]
        self.last, self.last_p = out, key
        return out.copy()

    def branch_of(self, system: Any, speed: float) -> int:
        """The branch (1-based mode of its whirl) whose frequency crosses h Omega at
        ``speed``."""
        res = dense_eigen(system, speed, self.n_modes())
        freq = res.frequencies if self.whirl == "any" else \
            res.frequencies[res.whirl == self.whirl]
        return int(np.argmin(np.abs(freq - self.harmonic * speed))) + 1

    def jacobian(self, p: Sequence[float], field_system: Callable[[int, float], Any]
                 ) -> np.ndarray:
        """dOmega_c,i / dp_j (module docstring); ``field_system(j, value)`` is the linear
        system with field j at ``value`` (the others at ``p``)."""
        speeds = self.values(p)
        system = self.system_of(p)
        shifted = []
        for j, value in enumerate(p):
            h = 1e-4 * abs(value) if value != 0.0 else 1e-4
            shifted.append((field_system(j, value - h), field_system(j, value + h), h))
        jac = np.empty((len(speeds), len(p)))
        for i, (speed, lam) in enumerate(zip(speeds, self.lams, strict=True)):
            dmats = [difference(system.matrices, speed)]
            for lo, hi, h in shifted:
                dmats.append(tuple((np.asarray(b, dtype=float) - np.asarray(a, dtype=float))
                                   / (2 * h) for a, b in zip(lo.matrices(speed),
                                                             hi.matrices(speed),
                                                             strict=True)))
            _, dlam = eigen_derivatives(system.matrices(speed), dmats, lam)
            jac[i] = -dlam[1:].imag / (dlam[0].imag - self.harmonic)
        return jac


# ---- response quantities ----------------------------------------------------------------


def fold_speeds(result: Any) -> np.ndarray:
    """The located saddle-node speeds [rad/s] of a speed branch, ascending."""
    b = result.branch
    return np.sort([float(locate_branch_fold(b, int(i)).frequency) for i in b.folds()])


def peak_amplitude(result: Any, node: int) -> float:
    """max over the branch of r = max_t sqrt(y^2 + z^2) at ``node`` [m], located between
    the points around the largest computed one (bounded search in arc length)."""
    # deferred: harmonic.synthesis (loads numba, threadpoolctl)
    from rotorsfd.harmonic.synthesis import max_radius

    b = result.branch
    iy, iz = dofs.dof_index(node, "y"), dofs.dof_index(node, "z")
    r = max_radius(b.X[:, :, iy], b.X[:, :, iz])
    k = int(np.argmax(r))
    if k == 0 or k == b.n_points - 1 or b.resolver is None:
        return float(r[k])

    def minus_r(s: float) -> float:
        pt = b.point_at(s)
        return -float(max_radius(pt.X[None, :, iy], pt.X[None, :, iz])[0])

    sol = minimize_scalar(minus_r, bounds=(float(b.s[k - 1]), float(b.s[k + 1])),
                          method="bounded", options={"xatol": 1e-10 * float(b.s[-1])})
    return max(float(-sol.fun), float(r[k]))


def bifurcation_speed(result: Any, selector: str) -> float:
    """speed_rad_s of the located bifurcation ``selector``: its 1-based row number, or the
    first row of that type (e.g. 'period-doubling')."""
    rows = result.bifurcations or []
    if selector.isdigit():
        i = int(selector)
        if not 1 <= i <= len(rows):
            raise ConvergenceError(f"bifurcation {i} asked for, the branch has {len(rows)}")
        return float(rows[i - 1]["speed_rad_s"])
    for row in rows:
        if row["type"] == selector:
            return float(row["speed_rad_s"])
    raise ConvergenceError(f"no {selector} bifurcation located on the branch")


# ---- fold speeds: exact derivatives from the fold-augmented system ----------------------


def fold_points(result: Any) -> list[tuple[Any, int]]:
    """(located saddle-node, index of the branch point before it), ascending in speed."""
    b = result.branch
    pts = [(locate_branch_fold(b, int(i)), int(i)) for i in b.folds()]
    return sorted(pts, key=lambda pi: float(pi[0].frequency))


def fold_speed_derivative(result: Any, point: Any, index: int, parameter: str,
                          value: float) -> float:
    """dOmega_fold/dp at a located saddle-node of a speed branch for a registered
    continuation parameter ``p`` (:mod:`rotorsfd.model.parameters`) at ``value``.

    On the fold curve ``R(x, Omega, p) = 0`` with ``R_x`` singular (left null vector
    ``w``), differentiating along it and projecting on ``w``::

        w^T R_Omega dOmega + w^T R_p dp = 0   =>   dOmega/dp = -(w^T R_p) / (w^T R_Omega),

    with R_Omega and R_p exact (:class:`~rotorsfd.harmonic.fold_curve.TwoParameterHB`, the
    residual of ``rotorsfd fold-curve``) at the fold's H and N_f; ``w`` from the SVD of R_x.
    """
    # deferred: harmonic.fold_curve (loads numba, threadpoolctl)
    from rotorsfd.harmonic.fold_curve import TwoParameterHB

    family = result.system.two_parameter_problem(parameter)
    b = result.branch
    m = family.first(value).m
    H = (np.size(point.xs) // m - 1) // 2
    n_samples = b.info.get("n_samples")
    N = int(max(n_samples[index], n_samples[min(index + 1, len(n_samples) - 1)])) \
        if n_samples is not None and np.size(n_samples) else int(b.n_samples)
    hb = TwoParameterHB(family, H, N, (1.0, 1.0), point.xs, (point.lam, value))
    _, jac = hb.evaluate(hb.to_z(point.xs, point.lam, value))
    n = hb.n
    w = scipy.linalg.svd(jac[:, :n])[0][:, -1]
    return float(-(w @ jac[:, n + 1]) / (w @ jac[:, n]))
