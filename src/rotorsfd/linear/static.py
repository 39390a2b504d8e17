"""Static deflection of a linear rotor: ``q = K(speed)^-1 f``.

Small models: dense LU (LAPACK) with the 1-norm condition number. Models with more than
:data:`rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs whose system gives ``sparse_matrices``:
sparse LU (SuperLU) of the CSR stiffness, no dense n x n array, with the 1-norm condition
estimated as ``||K||_1 ||K^-1||_1`` (Hager-Higham estimate of the inverse's norm from a few
solves, ``scipy.sparse.linalg.onenormest``).
"""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg

from rotorsfd.errors import ConvergenceError
from rotorsfd.linear.modal import LinearDynamics
from rotorsfd.model.sparse import DENSE_MAX_DOF

RCOND_MIN = 1e-14   # below: the stiffness is taken as singular (an unsupported rotor)


def static_deflection(system: LinearDynamics, force: np.ndarray, speed: float = 0.0) -> np.ndarray:
    """q = K(speed)^-1 f, with K the stiffness returned by ``system.matrices(speed)``
    (including any base-motion stiffness). Raises ConvergenceError if K is singular."""
    f = np.asarray(force, dtype=float)
    sparse = getattr(system, "split_matrices", None) or getattr(system, "sparse_matrices",
                                                                  None)
    if sparse is not None and system.n_dof > DENSE_MAX_DOF:
        return _sparse_deflection(sparse(speed)[2], f)
    _, _, k = system.matrices(speed)
    _check_size(f, k.shape[0])
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            lu = scipy.linalg.lu_factor(k, check_finite=True)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ConvergenceError(f"stiffness matrix not factorisable: {exc}") from None
    rcond = 1.0 / max(np.linalg.cond(k, 1), 1.0)
    if not rcond > RCOND_MIN or np.any(np.abs(np.diag(lu[0])) == 0.0):
        _singular(rcond)
    return _finite(scipy.linalg.lu_solve(lu, f))


def _sparse_deflection(k, f: np.ndarray) -> np.ndarray:
    """Sparse-LU form of :func:`static_deflection` for the CSR stiffness k."""
    # deferred: scipy.sparse.linalg (only for a sparse model)
    import scipy.sparse.linalg as spla

    _check_size(f, k.shape[0])
    kc = k.tocsc()
    if not np.all(np.isfinite(kc.data)):
        raise ConvergenceError("stiffness matrix not factorisable: non-finite entries")
    try:
        lu = spla.splu(kc)
    except RuntimeError:          # SuperLU: "Factor is exactly singular"
        _singular(0.0)
    n = k.shape[0]
    inv = spla.LinearOperator((n, n), matvec=lu.solve, rmatvec=lambda x: lu.solve(x, "T"),
                              dtype=float)
    norm = float(abs(kc).sum(axis=0).max())
    rcond = 1.0 / max(norm * float(spla.onenormest(inv)), 1.0)
    if not rcond > RCOND_MIN:
        _singular(rcond)
    return _finite(lu.solve(f))


def _check_size(f: np.ndarray, n: int) -> None:
    if f.shape[0] != n:
        raise ValueError(f"force has {f.shape[0]} entries, system has {n} DOFs")


def _singular(rcond: float) -> None:
    raise ConvergenceError(
        f"stiffness matrix is singular (rcond={rcond:.3g}): is the rotor supported?")


def _finite(q: np.ndarray) -> np.ndarray:
    if not np.all(np.isfinite(q)):
        raise ConvergenceError("static deflection is not finite")
    return q
