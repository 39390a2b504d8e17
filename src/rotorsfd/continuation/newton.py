"""Newton corrector on an extended system and the tangent of a solution curve.

A *continuation system* is any object with

- ``n`` : number of unknowns besides the parameter; points are ``z = (x, lam)`` (n+1,),
  already scaled so that a unit change means the same in every component;
- ``evaluate(z) -> (R (n,), J (n, n+1))``: residual and exact Jacobian ``[dR/dx, dR/dlam]``;
  may raise ``FloatingPointError`` (e.g. ``rotorsfd.errors.JournalContactError``) where
  the residual is not defined;
- ``admissible(z) -> bool``: False where the state must not go (e.g. ``nl_limit >= 1``);
- optionally ``weights`` (n+1,) >= 0: the metric ``|v|_W^2 = sum w_i v_i^2`` in which arc
  length, tangents and their angles are measured (default: all ones).

The extended system is ``R(z) = 0, a . z - b = 0`` (pseudo arc-length: ``a`` the previous
tangent and ``b = a . z_prev + ds``; fixed parameter: ``a = e_lam``, ``b = lam``).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Protocol

import numpy as np
import scipy.sparse as sp
import scipy.sparse.linalg as spla
from numpy.typing import NDArray
from scipy.linalg import lapack

FloatArray = NDArray[np.float64]


class ContinuationSystem(Protocol):
    """Scaled nonlinear system ``R(x, lam) = 0`` (module docstring)."""

    n: int

    def evaluate(self, z: FloatArray) -> tuple[FloatArray, FloatArray]: ...

    def admissible(self, z: FloatArray) -> bool: ...


@dataclass
class NewtonResult:
    """Outcome of :func:`newton_extended`; ``J`` is the Jacobian (n, n+1) at ``z``."""

    z: FloatArray
    R: FloatArray | None
    J: FloatArray | None
    iterations: int
    converged: bool
    norm: float
    message: str


def _bordered_solve(J: FloatArray, a: FloatArray, rhs: FloatArray) -> FloatArray:
    """Solve ``[J; a^T] x = rhs`` (LAPACK gesv without numpy's per-call overhead, which
    dominates for the small condensed systems; SuperLU for a scipy.sparse J, the full
    HB of a large model; Woodbury for a sparse + low-rank J that has ``bordered_solve``,
    :class:`rotorsfd.model.lowrank.SparseLowRank`); LinAlgError if exactly singular."""
    if hasattr(J, "bordered_solve"):
        return J.bordered_solve(a, rhs)
    if sp.issparse(J):
        A = sp.vstack([J, sp.csr_matrix(np.asarray(a, dtype=float)[None, :])], format="csc")
        try:
            x = spla.splu(A).solve(np.asarray(rhs, dtype=float))
        except RuntimeError as err:      # SuperLU: "Factor is exactly singular"
            raise np.linalg.LinAlgError(str(err)) from err
        return x
    n = J.shape[0]
    A = np.empty((n + 1, n + 1))
    A[:n] = J
    A[n] = a
    x, info = lapack.dgesv(A, rhs, overwrite_a=True)[2:]
    if info != 0:
        raise np.linalg.LinAlgError("singular extended Jacobian")
    return x


def _safe_evaluate(system: ContinuationSystem, z: FloatArray
                   ) -> tuple[FloatArray, FloatArray] | str:
    """Evaluate if admissible; return the reason as a string otherwise."""
    if not system.admissible(z):
        return "state limit reached (nl_limit >= limit)"
    try:
        R, J = system.evaluate(z)
    except (FloatingPointError, np.linalg.LinAlgError, ZeroDivisionError) as err:
        return f"evaluation failed: {err}"
    finite = J.is_finite() if hasattr(J, "is_finite") else np.all(
        np.isfinite(J.data if sp.issparse(J) else J))
    if not (np.all(np.isfinite(R)) and finite):
        return "non-finite residual or Jacobian"
    return R, J


def newton_extended(system: ContinuationSystem, z0: FloatArray, a: FloatArray, b: float,
                    tol: float = 1e-6, max_iter: int = 10, max_halvings: int = 10
                    ) -> NewtonResult:
    """Solve ``R(z) = 0, a.z = b`` by Newton from z0, converged when
    ``||(R, a.z - b)||_2 <= tol``. A step that leaves the admissible set or where the
    residual cannot be evaluated is halved (damped) up to ``max_halvings`` times."""
    z = np.array(z0, dtype=float)
    ev = _safe_evaluate(system, z)
    if isinstance(ev, str):
        return NewtonResult(z, None, None, 0, False, np.inf, f"at the initial guess: {ev}")
    R, J = ev
    norm = np.inf
    Rext = np.empty(system.n + 1)
    for it in range(max_iter + 1):
        Rext[:-1] = R
        Rext[-1] = a @ z - b
        norm = float(np.sqrt(Rext @ Rext))
        if norm <= tol:
            return NewtonResult(z, R, J, it, True, norm, "converged")
        if it == max_iter:
            break
        try:
            dz = _bordered_solve(J, a, -Rext)
        except np.linalg.LinAlgError:
            return NewtonResult(z, R, J, it, False, norm, "singular extended Jacobian")
        alpha, reason = 1.0, ""
        for _ in range(max_halvings + 1):
            ev = _safe_evaluate(system, z + alpha * dz)
            if not isinstance(ev, str):
                break
            reason = ev
            alpha *= 0.5
        else:
            return NewtonResult(z, R, J, it + 1, False, norm,
                                f"Newton step damped {max_halvings} times: {reason}")
        z = z + alpha * dz
        R, J = ev
    return NewtonResult(z, R, J, max_iter, False, norm,
                        f"no convergence in {max_iter} iterations (residual {norm:.3g} > {tol:g})")


def metric(system: object) -> FloatArray:
    """Weights of the arc-length metric of a continuation system (ones by default)."""
    w = getattr(system, "weights", None)
    return np.ones(system.n + 1) if w is None else np.asarray(w, dtype=float)


#: Largest dense J whose bordered-determinant sign :func:`bordered_sign` takes (a sign per
#: accepted point of a branch costs one LU of the (n+1)-square bordered matrix).
SIGN_MAX = 512


def bordered_sign(J: FloatArray, t: FloatArray, weights: FloatArray | None = None) -> float:
    """``sign det [J; (W t)^T]``: the sign of the branch-point test function tau_BP
    (Allgower & Georg, *Numerical Continuation Methods*, 1990, sec. 8.1), which changes at
    a simple branch point and not at a fold (:mod:`rotorsfd.stability.branch_points`);
    NaN for a sparse J, one of more than :data:`SIGN_MAX` rows, or a singular matrix."""
    if not isinstance(J, np.ndarray) or J.shape[0] > SIGN_MAX:
        return float("nan")
    w = np.ones(J.shape[1]) if weights is None else weights
    sign, logdet = np.linalg.slogdet(np.vstack([J, w * t]))
    return float(sign) if sign != 0 and np.isfinite(logdet) else float("nan")


def tangent(J: FloatArray, t_prev: FloatArray, weights: FloatArray | None = None
            ) -> FloatArray:
    """Null vector t of J (n, n+1) of unit W-norm, oriented so that ``t.W.t_prev > 0``.

    Solves the bordered system ``[J; (W t_prev)^T] t = e_{n+1}``; falls back to the last
    right singular vector when that system is singular.
    """
    w = np.ones(J.shape[1]) if weights is None else weights
    n = J.shape[0]
    rhs = np.zeros(n + 1)
    rhs[-1] = 1.0
    row = w * t_prev if np.any(w * t_prev) else t_prev
    try:
        t = _bordered_solve(J, row, rhs)
        if not np.all(np.isfinite(t)):
            raise np.linalg.LinAlgError
    except np.linalg.LinAlgError:
        if sp.issparse(J) or hasattr(J, "bordered_solve"):
            raise
        t = np.linalg.svd(J)[2][-1]
    t = t / np.sqrt(t @ (w * t))
    return t if t @ (w * t_prev) >= 0 else -t
