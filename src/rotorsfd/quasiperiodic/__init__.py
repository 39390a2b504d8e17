"""Quasi-periodic responses (tori) by two-frequency harmonic balance: a rotor spinning at
Omega on a base moving harmonically at w_b responds at every k1 Omega + k2 w_b
(docs/quasiperiodic.md).

``torus_fourier`` (truncation lattice, real packing, 2D AFT, grid rule), ``torus_linear``
(the coupled linear operator, exact condensation), ``torus_system`` (the torus problem of a
RotorSystem), ``torus_residual`` (condensed residual, exact Jacobians),
``torus_continuation`` (one torus, branches by arc length), ``torus_base_parameters`` (the
problem continued in w_b or a base law's amplitude).
"""

from rotorsfd.quasiperiodic.torus_base_parameters import base_parameter_problem
from rotorsfd.quasiperiodic.torus_continuation import (
    TorusBranch,
    TorusSolution,
    continue_torus,
    solve_torus,
)
from rotorsfd.quasiperiodic.torus_fourier import TorusLattice
from rotorsfd.quasiperiodic.torus_system import torus_problem

__all__ = ["TorusBranch", "TorusLattice", "TorusSolution", "base_parameter_problem",
           "continue_torus", "solve_torus", "torus_problem"]
