"""Harmonic balance with AFT: Fourier matrices, problem definition, residuals with exact
Jacobians, exact condensation onto the nonlinear DOFs, periodic solutions and branches.

Usage::

    from rotorsfd.harmonic import PeriodicProblem, solve_periodic, continue_periodic
    sol = solve_periodic(problem, lam=850.0, H=3)            # PeriodicSolution, .X (H+1, n)
    branch = continue_periodic(problem, 490.0, 1220.0, H=8,  # Branch, scipy-style outcome
                               callback=lambda point: None)  # event hook at every point
    branch.lam, branch.X, branch.amplitude(dof=0), branch.folds(), branch.point_at(s)

Modules: ``fourier`` (real DFT matrices, N_f rule), ``problem`` (PeriodicProblem),
``residual`` (full HB residual and Jacobians), ``condensation`` (exact condensation),
``banded`` and ``aft_kernels`` (its compiled loops: banded LU of all harmonics, AFT and
assembly), ``periodic`` (solvers), ``examples`` (Duffing, Jeffcott, 84-DOF beam rotor,
test chain).
"""

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
