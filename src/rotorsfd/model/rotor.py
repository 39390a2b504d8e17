"""Assembly of the finite-element rotor: shaft elements, disks, point masses, supports.

Global equation (docs/INTERFACES.md): ``M q'' + (C + Omega G) q' + K q = f`` with the DOF
order of :mod:`rotorsfd.model.dofs`. Element ``i`` (0-based in the list) joins nodes
``i + 1`` and ``i + 2``; its local DOFs are the global ``4 i ... 4 i + 7``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model import dofs
from rotorsfd.model.damping import ModalDamping, RayleighDamping
from rotorsfd.model.disk import Disk, PointMass
from rotorsfd.model.shaft import ShaftElement
from rotorsfd.model.supports import LinearSupport


class Rotor:
    """Finite-element rotor with global float matrices ``M, K, C, G`` (n_dof x n_dof).

    ``C`` = support damping + structural damping (``damping.matrix(M, K)``, computed on the
    supported non-rotating rotor); ``G`` is skew-symmetric and multiplies the speed.
    Satisfies the ``LinearDynamics`` protocol through :meth:`matrices`.
    """

    def __init__(
        self,
        shaft_elements: Sequence[ShaftElement],
        disks: Iterable[Disk] = (),
        point_masses: Iterable[PointMass] = (),
        supports: Iterable[LinearSupport] = (),
        damping: RayleighDamping | ModalDamping | None = None,
        x_start: float = 0.0,
    ) -> None:
        self.shaft_elements: tuple[ShaftElement, ...] = tuple(shaft_elements)
        if not self.shaft_elements:
            raise ConfigError("shaft_elements", [], "need at least one shaft element")
        self.disks: tuple[Disk, ...] = tuple(disks)
        self.point_masses: tuple[PointMass, ...] = tuple(point_masses)
        self.supports: tuple[LinearSupport, ...] = tuple(supports)
        self.damping = damping
        self.x_start = float(x_start)

        self.n_nodes: int = len(self.shaft_elements) + 1
        self.n_dof: int = dofs.n_dof(self.n_nodes)
        lengths = np.array([e.length for e in self.shaft_elements])
        self.node_x: np.ndarray = self.x_start + np.concatenate(([0.0], np.cumsum(lengths)))
        self.element_x: np.ndarray = self.node_x[:-1].copy()
        for kind, items in (("disk", self.disks), ("point_mass", self.point_masses),
                            ("support", self.supports)):
            for item in items:
                if not 1 <= item.node <= self.n_nodes:
                    raise ConfigError(f"{kind}.node", item.node,
                                      f"must be a node of the rotor, 1..{self.n_nodes}")
        self._assemble()

    # ---- assembly ---------------------------------------------------------------------
    def element_dofs(self, index: int) -> np.ndarray:
        """Global DOF indices of 0-based shaft element ``index`` (its 8 local DOFs)."""
        return np.arange(4 * index, 4 * index + 8)

    def _assemble(self) -> None:
        n = self.n_dof
        M, K, G, C = (np.zeros((n, n)) for _ in range(4))
        for i, el in enumerate(self.shaft_elements):
            idx = np.ix_(self.element_dofs(i), self.element_dofs(i))
            M[idx] += el.mass_matrix()
            K[idx] += el.stiffness_matrix()
            G[idx] += el.gyroscopic_matrix()
        for d in self.disks:
            y, z, ty, tz = dofs.node_dofs(d.node)
            M[y, y] += d.mass
            M[z, z] += d.mass
            M[ty, ty] += d.diametral_inertia
            M[tz, tz] += d.diametral_inertia
            G[ty, tz] += d.polar_inertia
            G[tz, ty] -= d.polar_inertia
        for p in self.point_masses:
            y, z = dofs.node_dofs(p.node)[:2]
            M[y, y] += p.mass
            M[z, z] += p.mass
        for s in self.supports:
            yz = np.ix_(dofs.node_dofs(s.node)[:2], dofs.node_dofs(s.node)[:2])
            K[yz] += s.stiffness
            C[yz] += s.damping
        if self.damping is not None:
            C += self.damping.matrix(M, K)
        self.M, self.K, self.C, self.G = M, K, C, G

    # ---- protocol and helpers ---------------------------------------------------------
    def dof_index(self, node: int, direction: str) -> int:
        """Global index of ``direction`` (y, z, ty, tz) at 1-based ``node``."""
        if not 1 <= node <= self.n_nodes:
            raise ConfigError("node", node, f"must be in 1..{self.n_nodes}")
        return dofs.dof_index(node, direction)

    def matrices(self, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(M, C + speed G, K) at spin speed ``speed`` [rad/s] (LinearDynamics protocol)."""
        return self.M, self.C + speed * self.G, self.K

    def with_supports(self, extra_supports: Iterable[LinearSupport]) -> Rotor:
        """A new rotor with the same shaft, disks, masses and damping, plus ``extra_supports``."""
        return Rotor(self.shaft_elements, self.disks, self.point_masses,
                     self.supports + tuple(extra_supports), self.damping, self.x_start)

    @property
    def total_mass(self) -> float:
        """Shaft + disks + point masses [kg]."""
        return (sum(e.mass for e in self.shaft_elements) + sum(d.mass for d in self.disks)
                + sum(p.mass for p in self.point_masses))

    def __repr__(self) -> str:
        return (f"Rotor(n_nodes={self.n_nodes}, disks={len(self.disks)}, "
                f"supports={len(self.supports)}, mass={self.total_mass:.4g} kg)")
