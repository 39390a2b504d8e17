"""Linear bearing/support elements acting on the lateral DOFs (y, z) of one node."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotorsfd.errors import ConfigError


@dataclass(frozen=True)
class LinearSupport:
    """Linear support to ground at 1-based ``node``.

    Force on the rotor ``[Fy, Fz] = -K_b [y, z] - C_b [y', z']`` with
    ``K_b = [[kyy, kyz], [kzy, kzz]]`` and ``C_b = [[cyy, cyz], [czy, czz]]``.
    Cross-coupled terms may be unsymmetric (e.g. fluid-film bearings).
    """

    node: int
    kyy: float
    kzz: float
    kyz: float = 0.0
    kzy: float = 0.0
    cyy: float = 0.0
    czz: float = 0.0
    cyz: float = 0.0
    czy: float = 0.0

    def __post_init__(self) -> None:
        if self.node < 1:
            raise ConfigError("support.node", self.node, "node numbers start at 1")
        values = np.array(
            [self.kyy, self.kzz, self.kyz, self.kzy, self.cyy, self.czz, self.cyz, self.czy],
            dtype=float,
        )
        if not np.all(np.isfinite(values)):
            raise ConfigError("support", values.tolist(), "coefficients must be finite")

    @classmethod
    def isotropic(cls, node: int, stiffness: float, damping: float = 0.0) -> LinearSupport:
        """kyy = kzz = stiffness, cyy = czz = damping, no cross-coupling."""
        return cls(node, stiffness, stiffness, cyy=damping, czz=damping)

    @property
    def stiffness(self) -> np.ndarray:
        """K_b = [[kyy, kyz], [kzy, kzz]] (acts on [y, z])."""
        return np.array([[self.kyy, self.kyz], [self.kzy, self.kzz]])

    @property
    def damping(self) -> np.ndarray:
        """C_b = [[cyy, cyz], [czy, czz]] (acts on [y', z'])."""
        return np.array([[self.cyy, self.cyz], [self.czy, self.czz]])
