"""Assembly of the finite-element rotor: shaft elements, disks, point masses, supports.

Global equation (docs/INTERFACES.md): ``M q'' + (C + Omega G) q' + K q = f`` with the DOF
order of :mod:`rotorsfd.model.dofs`. Element ``i`` (0-based in the list) joins nodes
``i + 1`` and ``i + 2``; its local DOFs are the global ``4 i ... 4 i + 7``.
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from functools import cached_property
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model import dofs, sparse
from rotorsfd.model.damping import ModalDamping, RayleighDamping
from rotorsfd.model.disk import Disk, PointMass
from rotorsfd.model.lowrank import with_lowrank
from rotorsfd.model.shaft import ShaftElement
from rotorsfd.model.supports import LinearSupport


def lumped_blocks(disks: Sequence[Disk], point_masses: Sequence[PointMass],
                  supports: Sequence[LinearSupport], mass: list, stiff: list, damp: list
                  ) -> list[tuple[int, tuple[np.ndarray, np.ndarray]]]:
    """Append the lumped parts' assembly blocks (:func:`rotorsfd.model.sparse.assemble`)
    to ``mass``, ``stiff``, ``damp``: a disk's ``diag(m, m, Id, Id)``, a point mass's ``m``
    on (y, z), a support's K_b and C_b on (y, z); return each disk's gyroscopic block
    ``[[0, Ip], [-Ip, 0]]`` on its (ty, tz) with its node, for the caller to place."""
    gyro = []
    for d in disks:
        idx = dofs.node_dofs(d.node)
        mass.append((idx, np.diag([d.mass, d.mass, d.diametral_inertia,
                                   d.diametral_inertia])))
        gyro.append((d.node, (idx[2:], np.array([[0.0, d.polar_inertia],
                                                  [-d.polar_inertia, 0.0]]))))
    for p in point_masses:
        mass.append((dofs.node_dofs(p.node)[:2], p.mass * np.eye(2)))
    for s in supports:
        yz = dofs.node_dofs(s.node)[:2]
        stiff.append((yz, s.stiffness))
        damp.append((yz, s.damping))
    return gyro


class LinearRotor:
    """What every linear rotor gives over its ``n_nodes`` and matrices ``M, C, G, K``: the
    DOF of a node and direction, and the ``LinearDynamics`` protocol."""

    def dof_index(self, node: int, direction: str) -> int:
        """Global index of ``direction`` (y, z, ty, tz) at 1-based ``node``."""
        if not 1 <= node <= self.n_nodes:
            raise ConfigError("node", node, f"must be in 1..{self.n_nodes}")
        return dofs.dof_index(node, direction)

    def matrices(self, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(M, C + speed G, K) at spin speed ``speed`` [rad/s] (LinearDynamics protocol)."""
        return self.M, self.C + speed * self.G, self.K


class Rotor(LinearRotor):
    """Finite-element rotor with global float matrices ``M, K, C, G`` (n_dof x n_dof),
    stored sparse (``M_csr, K_csr, C_csr, G_csr``, scipy CSR, half bandwidth 7: see
    :mod:`rotorsfd.model.sparse`); the dense ``M, K, C, G`` are built on first use.

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
        """M, K, G, C as CSR from the element blocks (:func:`rotorsfd.model.sparse.assemble`,
        no dense n x n array); the dense M, K, C, G are built from them on first use."""
        n = self.n_dof
        ne = len(self.shaft_elements)
        idx = 4 * np.arange(ne)[:, None] + np.arange(8)[None, :]    # element_dofs, stacked
        els = self.shaft_elements
        mass = [(idx, np.array([el.mass_matrix() for el in els]))]
        stiff = [(idx, np.array([el.stiffness_matrix() for el in els]))]
        gyro = [(idx, np.array([el.gyroscopic_matrix() for el in els]))]
        damp: list = []
        disk_gyro = lumped_blocks(self.disks, self.point_masses, self.supports, mass, stiff,
                                  damp)
        gyro += [block for _, block in disk_gyro]
        self.M_csr = sparse.assemble(n, mass)
        self.K_csr = sparse.assemble(n, stiff)
        self.G_csr = sparse.assemble(n, gyro)
        C = sparse.assemble(n, damp)
        #: a structural damping ``U diag(c) U^T`` of the lowest modes, as its factors
        #: (U, c) (ModalDamping with ``modes``): C_csr = C_band_csr + U diag(c) U^T
        self.damping_lowrank: tuple[np.ndarray, np.ndarray] | None = None
        if isinstance(self.damping, ModalDamping) and self.damping.modes is not None:
            self.damping_lowrank = self.damping.factors(self.M_csr, self.K_csr)
        elif self.damping is not None:
            C = sparse.as_csr(C + self.damping.matrix(self.M_csr, self.K_csr))
        #: the damping without the low-rank modal term (all of it without one)
        self.C_band_csr = C
        #: (kl, ku) of M, C, G, K together (7, 7 for a beam rotor; n - 1 with modal
        #: damping of every mode; that of the banded part with a low-rank one)
        self.band: tuple[int, int] = sparse.bandwidths(
            (self.M_csr, self.K_csr, self.G_csr, self.C_band_csr))

    @cached_property
    def C_csr(self):
        """Damping matrix (supports + structural damping) as CSR; with a low-rank modal
        term a full matrix, formed on first use (the HB solvers use its factors)."""
        if self.damping_lowrank is None:
            return self.C_band_csr
        u, c = self.damping_lowrank
        full = (u * c) @ u.T
        return sparse.as_csr(self.C_band_csr + 0.5 * (full + full.T))

    def split_matrices(self, speed: float) -> tuple[Any, Any, Any]:
        """(M, C + speed G, K) as CSR without a dense n x n array; the damping a
        :class:`~rotorsfd.model.lowrank.BandedLowRank` with modal damping of a few modes."""
        lowrank = getattr(self, "damping_lowrank", None)   # a subclass may assemble its own
        C = self.C_csr if lowrank is None else self.C_band_csr
        return self.M_csr, with_lowrank(sparse.as_csr(C + speed * self.G_csr), lowrank), \
            self.K_csr

    @cached_property
    def M(self) -> np.ndarray:
        """Mass matrix, dense (built from ``M_csr`` on first use)."""
        return self.M_csr.toarray()

    @cached_property
    def K(self) -> np.ndarray:
        """Stiffness matrix (shaft + supports), dense (from ``K_csr``)."""
        return self.K_csr.toarray()

    @cached_property
    def C(self) -> np.ndarray:
        """Damping matrix (supports + structural damping), dense (from ``C_csr``)."""
        return self.C_csr.toarray()

    @cached_property
    def G(self) -> np.ndarray:
        """Gyroscopic matrix per unit speed (skew-symmetric), dense (from ``G_csr``)."""
        return self.G_csr.toarray()

    # ---- protocol and helpers ---------------------------------------------------------
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
