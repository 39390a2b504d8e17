"""Static deflection of a linear rotor."""

from __future__ import annotations

import warnings

import numpy as np
import scipy.linalg

from rotorsfd.errors import ConvergenceError
from rotorsfd.linear.modal import LinearDynamics


def static_deflection(system: LinearDynamics, force: np.ndarray, speed: float = 0.0) -> np.ndarray:
    """q = K(speed)^-1 f, with K the stiffness returned by ``system.matrices(speed)``
    (including any base-motion stiffness). Raises ConvergenceError if K is singular."""
    _, _, k = system.matrices(speed)
    f = np.asarray(force, dtype=float)
    if f.shape[0] != k.shape[0]:
        raise ValueError(f"force has {f.shape[0]} entries, system has {k.shape[0]} DOFs")
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", scipy.linalg.LinAlgWarning)
            lu = scipy.linalg.lu_factor(k, check_finite=True)
    except (np.linalg.LinAlgError, ValueError) as exc:
        raise ConvergenceError(f"stiffness matrix not factorisable: {exc}") from None
    rcond = 1.0 / max(np.linalg.cond(k, 1), 1.0)
    if not rcond > 1e-14 or np.any(np.abs(np.diag(lu[0])) == 0.0):
        raise ConvergenceError(
            f"stiffness matrix is singular (rcond={rcond:.3g}): is the rotor supported?"
        )
    q = scipy.linalg.lu_solve(lu, f)
    if not np.all(np.isfinite(q)):
        raise ConvergenceError("static deflection is not finite")
    return q
