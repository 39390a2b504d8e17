"""Floquet stability of periodic solutions and of linear time-periodic systems (generic:
no rotor knowledge).

- ``monodromy``: Newmark (average acceleration) monodromy with a low-rank update,
  Magnus-4 reference, ``floquet_multipliers`` (full = the paper's method, or reduced).
- ``reduction``: Craig-Bampton model keeping the nonlinear DOFs.
- ``hill``: Hill's method (symmetric-weight selection, Koopman-Hill projection).
- ``floquet``: result object, stability tolerance, crossing type, Liouville check.
- ``bifurcations``: test functions, detection along a branch, location by regula falsi.
- ``chart``: stability charts of LTP systems over two parameters.
- ``orbit``: multipliers of a harmonic-balance solution (Fourier coefficients).
"""

from rotorsfd.stability.bifurcations import (
    Bifurcation,
    BifurcationMonitor,
    Bracket,
    BranchSample,
    crossing_signs,
    detect,
    find_bifurcations,
    locate,
)
from rotorsfd.stability.chart import LTPSystem, StabilityChart, stability_chart
from rotorsfd.stability.floquet import (
    STABILITY_TOL,
    FloquetResult,
    multiplier_type,
    sort_multipliers,
)
from rotorsfd.stability.hill import fourier_coefficients, hill_floquet, hill_matrix
from rotorsfd.stability.monodromy import (
    floquet_multipliers,
    monodromy_magnus4,
    monodromy_newmark,
)
from rotorsfd.stability.orbit import orbit_floquet, orbit_samples
from rotorsfd.stability.reduction import ReducedModel, craig_bampton

__all__ = [
    "STABILITY_TOL",
    "Bifurcation",
    "BifurcationMonitor",
    "Bracket",
    "BranchSample",
    "FloquetResult",
    "LTPSystem",
    "ReducedModel",
    "StabilityChart",
    "craig_bampton",
    "crossing_signs",
    "detect",
    "find_bifurcations",
    "floquet_multipliers",
    "fourier_coefficients",
    "hill_floquet",
    "hill_matrix",
    "locate",
    "monodromy_magnus4",
    "monodromy_newmark",
    "multiplier_type",
    "orbit_floquet",
    "orbit_samples",
    "sort_multipliers",
    "stability_chart",
]
