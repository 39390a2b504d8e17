"""Branch points of a branch of periodic solutions: the bordered-determinant test, their
location and type, and the tangent of the second branch.

Along a branch ``R(z) = 0`` (``z = (x, lam)`` scaled, ``J = [R_x, R_lam]`` of size
n x (n+1), ``t`` the unit tangent oriented continuously, ``t . t_prev > 0``) the standard
test functions (Allgower & Georg, *Numerical Continuation Methods*, 1990, sec. 8.1;
Kuznetsov, *Elements of Applied Bifurcation Theory*, 3rd ed., sec. 10.2) are::

    fold (turning point)   tau_F  = t_lam                  (changes sign, A regular)
    branch point           tau_BP = det A,  A = [J; t^T]   (changes sign, not at a fold)

Why: A is regular wherever ``J`` has full rank n (the fold included: there ``R_x`` is
singular but ``R_lam`` is not in its range); at a simple branch point rank J = n - 1 and
the continuously oriented tangent of the followed branch passes through the
two-dimensional kernel, so det A goes through zero with a sign change. A Floquet multiplier
through +1 where the branch does not turn is a branch point when tau_BP changes sign
there too; without that it is no branch point of the HB equations (a truncation artefact
of the Floquet step, or two crossings).

Location: Brent in the arc length on ``sign(det A) sigma_min(A)`` (continuous, zero at the
branch point), each value on a re-solved point (``Branch.point_at``).

Second tangent (the algebraic branching equation, Keller 1977; Kuznetsov sec. 10.2.2): at
the branch point ``z*`` take the kernel basis ``{t1, e}`` with ``t1`` the followed branch's
tangent and ``e = (v, 0)``, ``v`` the null vector of ``R_x``, and ``psi`` the left null
vector of ``R_x``. Tangents ``alpha t1 + beta e`` of solution curves satisfy::

    a11 alpha^2 + 2 a12 alpha beta + a22 beta^2 = 0,   a_ij = psi . R''[p_i, p_j]

with ``a11 = 0`` (t1 is a solution curve's tangent: ``R''[t1, t1] + J z'' = 0``), so the
second root is ``t2 ~ a22 t1 - 2 a12 e`` (needs ``a12 != 0``: a simple branch point),
oriented towards larger lam (a pitchfork's: its largest component positive).
``R''[u, w]`` by central differences of J: ``(J(z + h u) - J(z - h u)) w / 2h``.
Type: ``symmetry-breaking pitchfork`` when the second branch does not cross the parameter
(``|t2_lam| <= PITCHFORK_TOL |t1_lam|``: a22 = 0, as a Z2 symmetry forces), else
``transcritical``.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray
from scipy.optimize import brentq

from rotorsfd.continuation.branch import Branch
from rotorsfd.continuation.newton import metric, newton_extended
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.harmonic.hb_system import HBSystem, hb_system
from rotorsfd.harmonic.periodic import BORDERED, continue_periodic
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.truncation import convert_tangent

FloatArray = NDArray[np.float64]

#: A branch point is a symmetry-breaking pitchfork when the second tangent's parameter
#: component is at most this fraction of the first one's (a22 / a12 at the round-off of
#: the finite differences: measured 1e-9 on the pumped Mathieu oscillator).
PITCHFORK_TOL = 1e-3
#: Step of the central differences of J for the branching coefficients (scaled units).
FD_STEP = 1e-5
#: Largest unknowns of a (dense) bordered-determinant test.
MAX_DENSE = 3000


@dataclass
class LocatedBranchPoint:
    """A branch point of the HB equations: ``lam`` and arc length ``s`` on the branch,
    ``kind`` (``symmetry-breaking pitchfork`` or ``transcritical``), the scaled point
    ``z`` and the tangents ``t1`` (followed branch) and ``t2`` (second branch) in the
    layout of ``system``, the branching coefficients ``a = (a11, a12, a22)``, the test
    function's bracket ``bracket`` (computed points i, i+1)."""

    lam: float
    s: float
    kind: str
    z: FloatArray
    t1: FloatArray
    t2: FloatArray
    coefficients: tuple[float, float, float]
    system: HBSystem = field(repr=False)
    bracket: tuple[int, int] = (0, 0)

    @property
    def X(self) -> NDArray[np.complex128]:
        """Fourier coefficients (H+1, n_dof) at the branch point."""
        return self.system.coefficients(self.z)

    @property
    def second_slope(self) -> float:
        """``|t2_lam| / |t1_lam|``: 0 for a pitchfork."""
        return abs(float(self.t2[-1])) / max(abs(float(self.t1[-1])), np.finfo(float).tiny)


def bordered_test(system: Any, z: FloatArray, t: FloatArray, sign_only: bool = False
                  ) -> float:
    """``sign(det A) sigma_min(A)``, ``A = [J(z); (W t)^T]`` (module docstring): changes
    sign at a branch point, not at a fold; ``sign_only``: ``sign(det A)`` (no SVD)."""
    _, J = system.evaluate(z)
    if sp.issparse(J) or hasattr(J, "toarray"):   # CSR or sparse + low-rank
        if J.shape[0] > MAX_DENSE:
            raise ValueError(f"bordered test: {J.shape[0]} unknowns, more than {MAX_DENSE}")
        J = J.toarray()
    A = np.vstack([J, metric(system) * t])
    sign, _ = np.linalg.slogdet(A)
    if sign_only:
        return float(sign)
    return float(sign * np.linalg.svd(A, compute_uv=False)[-1])


def stored_signs(branch: Branch) -> tuple[FloatArray, NDArray[np.int64]] | None:
    """The signs of the bordered test the continuation took at the branch's points
    (``Branch.info["bordered_sign"]``, NaN where it did not) and the index of the HB
    system of each (two signs compare only within one system); a point whose stored
    ``bordered_lam`` or tangent direction is not its own (points inserted, reordered or
    reversed since) gets NaN; None without such columns."""
    info, n = branch.info, branch.n_points
    cols = [info.get(k) for k in BORDERED]
    if any(c is None or np.shape(c) != (n,) for c in cols) or branch.tangents.shape[0] != n:
        return None
    sign, system, lam, direction = (np.asarray(c) for c in cols)
    own = (lam == branch.lam) & (direction == np.sign(branch.tangents[:, -1]))
    return np.where(own, sign, np.nan), system.astype(np.int64)


def harmonics_of(branch: Branch) -> NDArray[np.int64]:
    """H of every computed point (adaptive H: ``info['harmonics']``, else ``branch.H``)."""
    Hs = branch.info.get("harmonics")
    if Hs is not None and len(Hs) == branch.n_points:
        return np.asarray(Hs, dtype=np.int64)
    return np.full(branch.n_points, branch.H, dtype=np.int64)


def samples_of(branch: Branch) -> NDArray[np.int64]:
    """N_f of every computed point (adaptive N_f: ``info['n_samples']``, else
    ``branch.n_samples``)."""
    Ns = branch.info.get("n_samples")
    if Ns is not None and np.shape(Ns) == (branch.n_points,):
        return np.asarray(Ns, dtype=np.int64)
    return np.full(branch.n_points, branch.n_samples, dtype=np.int64)


def branch_system(problem: PeriodicProblem, branch: Branch, index: int = 0,
                  H: int | None = None, limit_max: float = 1.0) -> HBSystem:
    """An HB system of the branch's scaling with the N_f of point ``index`` (the one its
    point was solved with) and H harmonics (default that point's H too; its condensation
    shift fixed at that point), in which points of the branch are evaluated. Needs a
    condensed branch (ValueError otherwise)."""
    if not branch.condensed:
        raise ValueError("branch points are tested on condensed branches")
    H = int(harmonics_of(branch)[index]) if H is None else int(H)
    system, _ = hb_system(problem, H, float(branch.lam[index]), branch.X[index][: H + 1],
                          int(samples_of(branch)[index]), True, branch.lam_scale, limit_max)
    return system


def point_z(system: HBSystem, problem: PeriodicProblem, lam: float,
            X: NDArray[np.complex128]) -> FloatArray:
    """Scaled unknowns of a branch point (its nonlinear DOFs' real coefficients up to the
    system's H, zero-padded, and lam)."""
    X = np.asarray(X)
    Xs = np.zeros((system.H + 1, problem.m), dtype=complex)
    h = min(system.H, X.shape[0] - 1)
    Xs[: h + 1] = X[: h + 1][:, problem.nl_dofs]
    return system.to_z(to_real(Xs), lam)


def point_tangent(system: HBSystem, problem: PeriodicProblem, t: FloatArray) -> FloatArray:
    """A stored tangent in the layout of the system's H (harmonics padded or cut)."""
    return convert_tangent(np.asarray(t, dtype=float), system.H, problem.m)


def point_test(system: HBSystem, problem: PeriodicProblem, branch: Branch, i: int) -> float:
    """The sign of ``bordered_test`` at computed point i, in ``system``."""
    return bordered_test(system, point_z(system, problem, float(branch.lam[i]), branch.X[i]),
                         point_tangent(system, problem, branch.tangents[i]), True)


def bordered_tests(system: HBSystem, problem: PeriodicProblem, branch: Branch) -> FloatArray:
    """The sign of ``bordered_test`` at every computed point of the branch, in one system."""
    return np.array([point_test(system, problem, branch, i) for i in range(branch.n_points)])


def branch_point_intervals(branch: Branch, tests: FloatArray) -> list[int]:
    """Indices i where the bordered test changes sign between points i and i+1 and the
    branch does not turn there (dlam/ds of one sign)."""
    t = np.sign(branch.tangents[:, -1])
    return [i for i in range(branch.n_points - 1)
            if tests[i] * tests[i + 1] < 0 and t[i] * t[i + 1] > 0]


def second_tangent(system: HBSystem, z: FloatArray, t1: FloatArray, h: float = FD_STEP
                   ) -> tuple[FloatArray, tuple[float, float, float]]:
    """The second branch's unit tangent at the branch point z (followed tangent t1) and
    the branching coefficients (a11, a12, a22) (module docstring)."""
    W = metric(system)
    _, J = system.evaluate(z)
    J = J.toarray() if hasattr(J, "toarray") else J
    U, _, Vt = np.linalg.svd(J[:, :-1])
    psi, v = U[:, -1], Vt[-1]
    e = np.append(v, 0.0)
    t1 = t1 / np.sqrt(t1 @ (W * t1))

    def d2(u: FloatArray) -> FloatArray:     # R''[u, .] as a matrix (n, n+1)
        Jp, Jm = (system.evaluate(z + sgn * h * u)[1] for sgn in (1.0, -1.0))
        Jp, Jm = (a.toarray() if hasattr(a, "toarray") else a for a in (Jp, Jm))
        return (Jp - Jm) / (2 * h)

    D1, De = d2(t1), d2(e)
    a11 = float(psi @ (D1 @ t1))
    a12 = float(psi @ (D1 @ e))
    a22 = float(psi @ (De @ e))
    if a12 == 0.0:
        raise ConvergenceError("branch point not simple: the branching coefficient a12 "
                               "is zero")
    t2 = a22 * t1 - 2.0 * a12 * e
    t2 = t2 / np.sqrt(t2 @ (W * t2))
    # the sign of (psi, v) is the SVD's: orient t2 towards larger lam (transcritical), or
    # its largest component positive (pitchfork, t2_lam ~ 0), the same in any system
    lead = -1 if abs(t2[-1]) > PITCHFORK_TOL * abs(t1[-1]) else int(np.argmax(np.abs(t2)))
    return (t2 if t2[lead] >= 0 else -t2), (a11, a12, a22)


def locate_branch_point(problem: PeriodicProblem, branch: Branch, i: int,
                        system: HBSystem | None = None, xtol: float = 1e-12
                        ) -> LocatedBranchPoint:
    """The branch point between computed points i and i+1 (a sign change of the bordered
    test there), located by Brent in s, with its second tangent and type; ``system``: of
    the H and N_f of point i+1 (the ones ``Branch.point_at`` re-solves in between)."""
    system = system or branch_system(problem, branch, i + 1)
    cache: dict[float, Any] = {}

    def f(s: float) -> float:
        p = branch.point_at(s)
        cache[s] = p
        return bordered_test(system, point_z(system, problem, p.lam, p.X),
                             point_tangent(system, problem, p.tangent))

    a, b = float(branch.s[i]), float(branch.s[i + 1])
    tol = xtol * max(1.0, abs(b))
    s_star = float(brentq(f, a, b, xtol=tol, rtol=4 * np.finfo(float).eps))
    p = cache.get(s_star) or branch.point_at(s_star)
    z = point_z(system, problem, p.lam, p.X)
    t1 = point_tangent(system, problem, p.tangent)
    t2, coef = second_tangent(system, z, t1)
    ratio = abs(t2[-1]) / max(abs(t1[-1]), np.finfo(float).tiny)
    kind = "symmetry-breaking pitchfork" if ratio <= PITCHFORK_TOL else "transcritical"
    return LocatedBranchPoint(float(p.lam), s_star, kind, z, t1, t2, coef, system, (i, i + 1))


@dataclass
class BranchPointSwitch:
    """The second branch at a branch point: ``legs`` continued from ``z* +- delta t2``
    along ``+t2`` and ``-t2`` (the two halves of the second branch; mirror images under
    the broken symmetry at a pitchfork), ``point`` the located branch point."""

    point: LocatedBranchPoint
    legs: list[Branch]
    delta: float
    message: str = ""


def switch_branch_point(problem: PeriodicProblem, point: LocatedBranchPoint,
                        lam_range: tuple[float, float], *, delta: float = 0.02,
                        **continue_kw: Any) -> BranchPointSwitch:
    """Continue the second branch at a located branch point both ways: each leg starts
    on the plane normal to ``t2`` through ``z* +- delta t2`` (scaled units) and follows
    ``+-t2`` (:func:`~rotorsfd.harmonic.periodic.continue_periodic` with
    ``start_tangent``) within ``lam_range``; ``continue_kw`` go to it."""
    system = point.system
    lo, hi = sorted(lam_range)
    H = system.H
    kw = {"n_samples": system.N, "lam_scale": system.lam_scale, "ds": delta,
          "ds_max": 2 * delta, **continue_kw}
    legs, words = [], []
    for sign in (1.0, -1.0):
        t = sign * point.t2
        z = point.z + delta * t
        a = metric(system) * t
        first = newton_extended(system, z, a, float(a @ z), 1e-10, 30)
        if first.converged:
            z = first.z
        X = system.coefficients(z)
        lam = system.from_z(z)[1]
        # the end the leg heads for: along t2's lam part, or for a pitchfork (t2_lam = 0)
        # to the side of lam* its first point lies on
        ahead = float(t[-1]) if point.kind == "transcritical" else lam - point.lam
        end = hi if ahead >= 0 else lo
        try:
            leg = continue_periodic(problem, lam, end, H, X, start_tangent=t, **kw)
        except ConvergenceError as exc:
            words.append(f"leg {'+-'[sign < 0]}t2: {exc}")
            continue
        legs.append(leg)
        words.append(f"leg {'+-'[sign < 0]}t2: {leg.n_points} points, lam "
                     f"{leg.lam.min():.8g} .. {leg.lam.max():.8g}: {leg.message}")
    if not legs:
        raise ConvergenceError(f"{problem.name}: no second branch at the branch point "
                               f"lam={point.lam:.9g}: " + "; ".join(words))
    msg = f"second branch at the {point.kind} at lam={point.lam:.9g}: " + "; ".join(words)
    return BranchPointSwitch(point, legs, delta, msg)
