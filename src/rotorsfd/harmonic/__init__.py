"""Harmonic balance with AFT: Fourier matrices, problem definition, residuals with exact
Jacobians, exact condensation onto the nonlinear DOFs, periodic solutions and branches."""

from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import (
    aft_matrices,
    aliasing_error,
    choose_n_samples,
    default_min_samples,
    to_complex,
    to_real,
)
from rotorsfd.harmonic.periodic import (
    HBSystem,
    PeriodicSolution,
    continue_periodic,
    solve_periodic,
)
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.residual import FullHB

__all__ = [
    "CondensedHB",
    "FullHB",
    "HBSystem",
    "PeriodicProblem",
    "PeriodicSolution",
    "aft_matrices",
    "aliasing_error",
    "choose_n_samples",
    "continue_periodic",
    "default_min_samples",
    "solve_periodic",
    "to_complex",
    "to_real",
]
