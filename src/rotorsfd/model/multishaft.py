"""Several coaxial shafts in one rotor system, each at its own speed (dual-spool engines).

Node numbering: global, in the order of the shafts. Shaft ``s`` with ``n_s`` nodes owns the
nodes ``o_s + 1 ... o_s + n_s`` with ``o_s = n_1 + ... + n_(s-1)``, so its DOFs are the
contiguous block ``4 o_s ... 4 (o_s + n_s) - 1`` (the order of :mod:`rotorsfd.model.dofs`).
Disks, point masses, supports, intershaft bearings, elements and unbalances all name global
nodes; node positions along x are per shaft (``x_start`` of each shaft), so the shafts may
overlap in x (coaxial placement).

Speeds: shaft ``s`` spins at ``Omega_s = r_s Omega`` with the fixed ``speed_ratio`` r_s
(the first shaft's ratio is 1, Omega the continuation speed). Its kinetic energy carries
the gyroscopic term ``Omega_s G_s q_s'`` (:mod:`rotorsfd.model.shaft`, disks: ``G[ty, tz] =
+Ip``), and the shafts share no inertia, so Lagrange's equations of the system are

    M q'' + (C + Omega sum_s r_s G_s) q' + K q = f,    G = sum_s r_s G_s

i.e. the single-speed form ``C + Omega G`` of every solver with the speed-weighted
gyroscopic matrix ``G`` (``G_csr``; the per-shaft ``G_s`` are kept in ``shaft_gyroscopic``
for the analyses against the speed of one spool). A single shaft (``r_1 = 1``) gives the
:class:`~rotorsfd.model.rotor.Rotor` matrices exactly.

Intershaft bearing between node ``a`` (inner shaft) and node ``b`` (outer shaft), on the
relative displacement ``d = q_a - q_b`` (y, z): force ``-K_b d - C_b d'`` on ``a`` and the
opposite on ``b``; with ``T = [I, -I]`` on ``(y_a, z_a, y_b, z_b)`` its blocks are
``T^T K_b T`` and ``T^T C_b T``. It does not rotate with either shaft (no speed terms).

Base motion (:mod:`rotorsfd.model.base_terms`): the translations and gravity act on every
slice of every shaft alike, and so do the base-rate terms free of the spin; the terms
``Ip Omega wx`` (stiffness) and ``Ip (Omega + wx) w`` (load) carry the spin of the slice,
which differs per shaft: with a rotating base and a speed ratio other than 1 they are not
one pattern times a scalar, so such a model is refused (:func:`check_base_motion`).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence
from dataclasses import dataclass

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model import dofs, sparse
from rotorsfd.model.base_terms import MATRIX_NAMES, BaseBasis, disk_basis, shaft_element_basis
from rotorsfd.model.damping import ModalDamping, RayleighDamping
from rotorsfd.model.disk import Disk, PointMass
from rotorsfd.model.rotor import Rotor, lumped_blocks
from rotorsfd.model.shaft import ShaftElement
from rotorsfd.model.supports import LinearSupport

__all__ = ["IntershaftBearing", "MultiShaftRotor", "Shaft", "SpoolSpeed", "check_base_motion"]


@dataclass(frozen=True)
class Shaft:
    """One shaft: its elements (left to right from ``x_start``), its disks, point masses and
    supports at *global* nodes (of this shaft), and its speed ratio ``r = Omega_s / Omega``."""

    name: str
    elements: tuple[ShaftElement, ...]
    speed_ratio: float = 1.0
    x_start: float = 0.0
    disks: tuple[Disk, ...] = ()
    point_masses: tuple[PointMass, ...] = ()
    supports: tuple[LinearSupport, ...] = ()

    def __post_init__(self) -> None:
        object.__setattr__(self, "elements", tuple(self.elements))
        for name in ("disks", "point_masses", "supports"):
            object.__setattr__(self, name, tuple(getattr(self, name)))
        if not self.elements:
            raise ConfigError(f"rotor.shafts.{self.name}.sections", [],
                              "need at least one shaft element")
        if not (np.isfinite(self.speed_ratio) and self.speed_ratio > 0.0):
            raise ConfigError(f"rotor.shafts.{self.name}.speed_ratio", self.speed_ratio,
                              "must be a finite number > 0")

    @property
    def n_nodes(self) -> int:
        return len(self.elements) + 1


@dataclass(frozen=True)
class IntershaftBearing:
    """Linear bearing between ``node`` (inner shaft) and ``outer_node`` (another shaft),
    acting on their relative displacement (module doc): ``K_b``, ``C_b`` as for
    :class:`~rotorsfd.model.supports.LinearSupport`."""

    node: int
    outer_node: int
    kyy: float
    kzz: float
    kyz: float = 0.0
    kzy: float = 0.0
    cyy: float = 0.0
    czz: float = 0.0
    cyz: float = 0.0
    czy: float = 0.0

    @property
    def stiffness(self) -> np.ndarray:
        return np.array([[self.kyy, self.kyz], [self.kzy, self.kzz]])

    @property
    def damping(self) -> np.ndarray:
        return np.array([[self.cyy, self.cyz], [self.czy, self.czz]])

    def dofs(self) -> np.ndarray:
        """``(y_a, z_a, y_b, z_b)`` global indices."""
        return np.concatenate([dofs.node_dofs(self.node)[:2], dofs.node_dofs(self.outer_node)[:2]])

    @staticmethod
    def relative_block(a: np.ndarray) -> np.ndarray:
        """``T^T a T`` with ``T = [I, -I]`` (4 x 4)."""
        t = np.hstack([np.eye(2), -np.eye(2)])
        return t.T @ np.asarray(a, dtype=float) @ t


class MultiShaftRotor(Rotor):
    """Coaxial shafts at fixed speed ratios, coupled by intershaft bearings (module doc).

    The :class:`Rotor` interface (``M, K, C, G`` and their CSR, ``node_x``, ``n_nodes``,
    ``matrices(speed)``, ``dof_index``) with ``G = sum_s r_s G_s``; plus ``shafts``,
    ``node_offsets``, ``shaft_of_node``, ``shaft_gyroscopic`` (the ``G_s``) and
    ``dof_names``. ``extra_supports`` are grounded supports at global nodes besides the
    shafts' own (the elements' linear parts).
    """

    def __init__(self, shafts: Sequence[Shaft], intershaft: Iterable[IntershaftBearing] = (),
                 damping: RayleighDamping | ModalDamping | None = None,
                 extra_supports: Iterable[LinearSupport] = (),
                 extra_disks: Iterable[Disk] = (),
                 extra_point_masses: Iterable[PointMass] = ()) -> None:
        self.shafts: tuple[Shaft, ...] = tuple(shafts)
        if not self.shafts:
            raise ConfigError("rotor.shafts", [], "need at least one shaft")
        names = [s.name for s in self.shafts]
        if len(set(names)) != len(names):
            raise ConfigError("rotor.shafts.name", names, "shaft names must be distinct")
        if self.shafts[0].speed_ratio != 1.0:
            raise ConfigError(f"rotor.shafts.{names[0]}.speed_ratio",
                              self.shafts[0].speed_ratio, "the first shaft's ratio must be 1 "
                              "(its speed is the continuation speed)")
        self.intershaft: tuple[IntershaftBearing, ...] = tuple(intershaft)
        self.extra_supports = tuple(extra_supports)
        self.extra_disks = tuple(extra_disks)
        self.extra_point_masses = tuple(extra_point_masses)
        counts = [s.n_nodes for s in self.shafts]
        self.node_offsets: tuple[int, ...] = tuple(int(v) for v in np.cumsum([0, *counts[:-1]]))
        self.n_nodes = int(sum(counts))
        self.n_dof = dofs.n_dof(self.n_nodes)
        #: 0-based shaft index of each 1-based node (entry node - 1)
        self.shaft_of_node = np.repeat(np.arange(len(self.shafts)), counts)
        xs, lefts = [], []
        for s, off in zip(self.shafts, self.node_offsets, strict=True):
            lengths = np.array([e.length for e in s.elements])
            xs.append(s.x_start + np.concatenate(([0.0], np.cumsum(lengths))))
            lefts.append(off + 1 + np.arange(len(s.elements)))
        self.node_x = np.concatenate(xs)
        #: global left node (1-based) of each shaft element, in the order of shaft_elements
        self.element_left_node = np.concatenate(lefts).astype(np.int64)
        self.element_x = self.node_x[self.element_left_node - 1].copy()
        self.shaft_elements = tuple(e for s in self.shafts for e in s.elements)
        self.disks = tuple(d for s in self.shafts for d in s.disks) + self.extra_disks
        self.point_masses = (tuple(p for s in self.shafts for p in s.point_masses)
                             + self.extra_point_masses)
        self.supports = tuple(b for s in self.shafts for b in s.supports) + self.extra_supports
        self.damping = damping
        self.x_start = float(self.node_x.min())
        self._check_nodes()
        self._assemble()

    # ---- checks ------------------------------------------------------------------------
    def shaft_index(self, node: int, field: str) -> int:
        """0-based shaft of global ``node``; ConfigError naming ``field`` if no node."""
        if not 1 <= node <= self.n_nodes:
            raise ConfigError(field, node, f"must be a node of the rotor, 1..{self.n_nodes}")
        return int(self.shaft_of_node[node - 1])

    def node_range(self, index: int) -> tuple[int, int]:
        """(first, last) global node of shaft ``index``."""
        off = self.node_offsets[index]
        return off + 1, off + self.shafts[index].n_nodes

    def _check_nodes(self) -> None:
        for k, s in enumerate(self.shafts):
            lo, hi = self.node_range(k)
            for kind, items in (("disks", s.disks), ("point_masses", s.point_masses),
                                ("supports", s.supports)):
                for item in items:
                    if not lo <= item.node <= hi:
                        raise ConfigError(f"rotor.shafts.{s.name}.{kind}.node", item.node,
                                          f"must be a node of shaft {s.name!r}, {lo}..{hi}")
        for kind, items in (("disks", self.extra_disks), ("point_masses",
                                                           self.extra_point_masses),
                            ("supports", self.extra_supports)):
            for item in items:
                self.shaft_index(item.node, f"rotor.{kind}.node")
        for b in self.intershaft:
            a = self.shaft_index(b.node, "rotor.intershaft.node")
            o = self.shaft_index(b.outer_node, "rotor.intershaft.outer_node")
            if a == o:
                raise ConfigError("rotor.intershaft.outer_node", b.outer_node,
                                  f"must be a node of another shaft than node {b.node} "
                                  f"(both on shaft {self.shafts[a].name!r})")

    # ---- assembly ----------------------------------------------------------------------
    def element_dofs(self, index: int) -> np.ndarray:
        """Global DOF indices of 0-based shaft element ``index`` (its 8 local DOFs)."""
        start = 4 * (int(self.element_left_node[index]) - 1)
        return np.arange(start, start + 8)

    def _assemble(self) -> None:
        """M, K, C, the per-shaft G_s and G = sum r_s G_s as CSR (module doc)."""
        n = self.n_dof
        idx = 4 * (self.element_left_node[:, None] - 1) + np.arange(8)[None, :]
        els = self.shaft_elements
        mass = [(idx, np.array([el.mass_matrix() for el in els]))]
        stiff = [(idx, np.array([el.stiffness_matrix() for el in els]))]
        ge = np.array([el.gyroscopic_matrix() for el in els])
        owner = self.shaft_of_node[self.element_left_node - 1]
        gyro: list[list] = [[(idx[owner == k], ge[owner == k])] for k in range(len(self.shafts))]
        damp: list = []
        for node, block in lumped_blocks(self.disks, self.point_masses, self.supports, mass,
                                         stiff, damp):
            gyro[self.shaft_of_node[node - 1]].append(block)
        for b in self.intershaft:
            stiff.append((b.dofs(), b.relative_block(b.stiffness)))
            damp.append((b.dofs(), b.relative_block(b.damping)))
        self.M_csr = sparse.assemble(n, mass)
        self.K_csr = sparse.assemble(n, stiff)
        #: G_s of each shaft (per unit speed of that shaft)
        self.shaft_gyroscopic = tuple(sparse.assemble(n, g) for g in gyro)
        G = self.shaft_gyroscopic[0]
        for s, g in zip(self.shafts[1:], self.shaft_gyroscopic[1:], strict=True):
            G = G + s.speed_ratio * g
        self.G_csr = sparse.as_csr(G)
        C = sparse.assemble(n, damp)
        if self.damping is not None:
            C = sparse.as_csr(C + self.damping.matrix(self.M_csr, self.K_csr))
        self.C_csr = C
        self.band = sparse.bandwidths((self.M_csr, self.K_csr, self.G_csr, self.C_csr))

    # ---- protocol and helpers ----------------------------------------------------------
    @property
    def speed_ratios(self) -> np.ndarray:
        return np.array([s.speed_ratio for s in self.shafts])

    def node_speed_ratio(self, node: int) -> float:
        """Speed ratio of the shaft of global ``node``."""
        return float(self.shafts[self.shaft_index(node, "node")].speed_ratio)

    def node_label(self, node: int) -> str:
        """``<shaft>:<local node>`` of global ``node`` (``hp:3``, as configs and results
        files name it)."""
        k = self.shaft_index(node, "node")
        return f"{self.shafts[k].name}:{node - self.node_offsets[k]}"

    @property
    def dof_names(self) -> list[str]:
        """``<direction>@<shaft>:<local node>`` per global DOF (``y@lp:3``)."""
        return [f"{d}@{self.node_label(n)}" for n in range(1, self.n_nodes + 1)
                for d in dofs.DIRECTIONS]

    def shaft_matrices(self, speeds: Sequence[float]
                       ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(M, C + sum_s Omega_s G_s, K) with every shaft's own speed ``speeds[s]`` [rad/s]
        (the speed ratios ignored): the Campbell diagram against one spool's speed."""
        if len(speeds) != len(self.shafts):
            raise ConfigError("speeds", list(speeds), f"need one speed per shaft "
                              f"({len(self.shafts)})")
        D = self.C_csr.toarray()
        for om, g in zip(speeds, self.shaft_gyroscopic, strict=True):
            D = D + float(om) * g.toarray()
        return self.M, D, self.K

    def with_supports(self, extra_supports: Iterable[LinearSupport]) -> MultiShaftRotor:
        return MultiShaftRotor(self.shafts, self.intershaft, self.damping,
                               self.extra_supports + tuple(extra_supports),
                               self.extra_disks, self.extra_point_masses)

    def imported_base_basis(self):
        """The base-motion basis with the elements at their global DOFs (base_basis chains
        element i on DOFs 4 i ... 4 i + 7, a single shaft's numbering)."""
        n = self.n_dof
        blocks: list[list] = [[] for _ in MATRIX_NAMES]
        vecs = np.zeros((8, n))
        for i, el in enumerate(self.shaft_elements):
            idx = self.element_dofs(i)
            me, ve = shaft_element_basis(el, float(self.element_x[i]))
            for b, mb in zip(blocks, me, strict=True):
                b.append((idx, mb))
            vecs[:, idx] += ve
        lumped = [(d.node, d.mass, d.polar_inertia, d.diametral_inertia) for d in self.disks]
        lumped += [(p.node, p.mass, 0.0, 0.0) for p in self.point_masses]
        for node, m, ip, idi in lumped:
            idx = dofs.node_dofs(node)
            me, ve = disk_basis(m, ip, idi, float(self.node_x[node - 1]))
            for b, mb in zip(blocks, me, strict=True):
                b.append((idx, mb))
            vecs[:, idx] += ve
        return BaseBasis([sparse.assemble(n, b) for b in blocks], vecs)

    def __repr__(self) -> str:
        return (f"MultiShaftRotor(shafts={[s.name for s in self.shafts]}, "
                f"ratios={self.speed_ratios.tolist()}, n_nodes={self.n_nodes}, "
                f"intershaft={len(self.intershaft)}, mass={self.total_mass:.4g} kg)")


class SpoolSpeed:
    """The ``LinearDynamics`` view of a multi-shaft ``rotor`` against the speed of one
    spool: ``matrices(speed)`` with shaft ``spool`` at ``speed`` and every shaft ``k`` at
    ``speed r_k / r_spool`` (the fixed ratios), i.e. ``rotor.matrices(speed / r_spool)``.
    A Campbell diagram or critical speeds of this view are against that spool's speed; the
    excitation line of shaft ``k``'s unbalance is ``w = (r_k / r_spool) speed``
    (:meth:`harmonic`)."""

    def __init__(self, rotor: MultiShaftRotor, spool: str | int) -> None:
        names = [s.name for s in rotor.shafts]
        if isinstance(spool, str):
            if spool not in names:
                raise ConfigError("spool", spool, "must name a shaft: " + ", ".join(names))
            spool = names.index(spool)
        self.rotor = rotor
        self.index = int(spool)
        self.ratio = float(rotor.shafts[self.index].speed_ratio)
        self.n_dof = rotor.n_dof

    def matrices(self, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        return self.rotor.matrices(float(speed) / self.ratio)

    def harmonic(self, shaft: str | int) -> float:
        """The slope of shaft ``shaft``'s unbalance line against this spool's speed."""
        k = SpoolSpeed(self.rotor, shaft).index
        return self.rotor.shafts[k].speed_ratio / self.ratio


def check_base_motion(rotor: Rotor, base) -> None:
    """ConfigError if ``base`` rotates (a rate law not 'off') while a shaft of ``rotor``
    spins at a ratio other than 1 (module doc: the spin terms of the base differ per
    shaft)."""
    ratios = getattr(rotor, "speed_ratios", None)
    if ratios is None or np.all(ratios == 1.0):
        return
    for name, law in zip(("rolling", "pitching", "yawing"), base.rotation, strict=True):
        if not law.is_zero:
            raise ConfigError(f"base.{name}.law", law.kind, "a rotating base with shafts at "
                              "different speeds is not supported yet (the base's spin "
                              "terms differ per shaft); translations and gravity are")
