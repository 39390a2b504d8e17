"""Linear analyses of rotors: complex modes, Campbell diagram, critical speeds, statics.

Every function takes any ``LinearDynamics`` system (``n_dof``, ``matrices(speed)``).
"""

from rotorsfd.linear.campbell import CampbellResult, campbell
from rotorsfd.linear.critical import CriticalSpeed, branch_frequency, critical_speeds
from rotorsfd.linear.modal import (
    LinearDynamics,
    ModalResult,
    eigen,
    log_decrement,
    mac,
    mode_shapes,
    whirl_direction,
)
from rotorsfd.linear.static import static_deflection

__all__ = [
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
    "static_deflection",
    "whirl_direction",
]
