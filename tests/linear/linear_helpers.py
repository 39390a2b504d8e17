"""Shared helpers of the linear-analysis tests."""

from __future__ import annotations

import numpy as np

from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft

STEEL = Material(7810.0, 211e9, 81.783e9)
# Fitted by scripts/fit_paper_supports.py (centring spring at node 1, right support node 21)
PAPER_K1 = 1.032513e7
PAPER_K21 = 9.551305e6


class Constrained:
    """LinearDynamics wrapper removing fixed DOFs (exact pinned/clamped supports).

    Also shows that analyses take any object with ``n_dof`` and ``matrices(speed)``."""

    def __init__(self, system, fixed: list[int]) -> None:
        self.system = system
        self.free = np.setdiff1d(np.arange(system.n_dof), fixed)
        self.n_dof = self.free.size

    def matrices(self, speed: float):
        ix = np.ix_(self.free, self.free)
        return tuple(m[ix] for m in self.system.matrices(speed))

    def expand(self, q: np.ndarray) -> np.ndarray:
        full = np.zeros(self.system.n_dof, dtype=q.dtype)
        full[self.free] = q
        return full


def pinned_pinned(rotor: Rotor) -> Constrained:
    """y = z = 0 at the first and last nodes."""
    last = rotor.n_nodes
    fixed = [rotor.dof_index(n, d) for n in (1, last) for d in ("y", "z")]
    return Constrained(rotor, fixed)


def paper_rotor(k1: float = PAPER_K1, k21: float = PAPER_K21) -> Rotor:
    shaft = uniform_shaft(0.5994, 20, 20.65e-3, 30.15e-3, STEEL)
    disk = Disk.from_geometry(8, STEEL.density, 30.15e-3, 101.6e-3, 50.8e-3)
    return Rotor(shaft, disks=[disk],
                 supports=[LinearSupport.isotropic(1, k1), LinearSupport.isotropic(21, k21)])
