"""Pseudo arc-length continuation (generic): Newton corrector, tangent predictor, step
control, the Branch result. Periodic branches: :func:`rotorsfd.harmonic.continue_periodic`."""

from rotorsfd.continuation.arclength import ArcLengthOptions, ArcLengthStatus, arclength
from rotorsfd.continuation.branch import Branch, BranchPoint
from rotorsfd.continuation.newton import (
    ContinuationSystem,
    NewtonResult,
    metric,
    newton_extended,
    tangent,
)

__all__ = [
    "ArcLengthOptions",
    "ArcLengthStatus",
    "Branch",
    "BranchPoint",
    "ContinuationSystem",
    "NewtonResult",
    "arclength",
    "metric",
    "newton_extended",
    "tangent",
]
