"""Linear analyses of rotors: complex modes, Campbell diagram, critical speeds, statics.

Every function takes any ``LinearDynamics`` system (``n_dof``, ``matrices(speed)``).
Up to ``DENSE_MAX_DOF`` DOF every root of the 2n state matrix is computed (dense); above,
the lowest modes by shift-invert Arnoldi (``sparse_modes``) and the Campbell diagram from
a reduced model with its measured error (``reduced``); ``method=`` chooses explicitly.
"""

from rotorsfd.linear.campbell import CampbellResult, campbell
from rotorsfd.linear.critical import CriticalSpeed, branch_frequency, critical_speeds
from rotorsfd.linear.modal import (
    DENSE_MAX_DOF,
    LinearDynamics,
    ModalResult,
    eigen,
    log_decrement,
    mac,
    mode_shapes,
    whirl_direction,
)
from rotorsfd.linear.sparse_modes import sparse_eigen
from rotorsfd.linear.static import static_deflection

__all__ = [
    "DENSE_MAX_DOF",
    "CampbellResult",
    "CriticalSpeed",
    "LinearDynamics",
    "ModalResult",
    "branch_frequency",
    "campbell",
    "critical_speeds",
    "eigen",
    "log_decrement",
    "mac",
    "mode_shapes",
    "sparse_eigen",
    "static_deflection",
    "whirl_direction",
]
