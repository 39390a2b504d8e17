"""Degree-of-freedom ordering of the finite-element rotor.

Every node carries four DOFs, in the base frame of the paper (x along the shaft axis,
y horizontal, z vertical)::

    q[4*(node-1) + 0] = y      lateral displacement along y        [m]
    q[4*(node-1) + 1] = z      lateral displacement along z        [m]
    q[4*(node-1) + 2] = ty     rotation about y (theta_y ~ -dz/dx) [rad]
    q[4*(node-1) + 3] = tz     rotation about z (theta_z ~ +dy/dx) [rad]

Nodes are numbered from 1, as in the paper and in the configuration files.
"""

from __future__ import annotations

import numpy as np

DOFS_PER_NODE = 4
DIRECTIONS: tuple[str, ...] = ("y", "z", "ty", "tz")
_OFFSET = {name: k for k, name in enumerate(DIRECTIONS)}


def dof_index(node: int, direction: str) -> int:
    """Global index of DOF ``direction`` (one of ``y, z, ty, tz``) at 1-based ``node``."""
    if node < 1:
        raise ValueError(f"node numbers start at 1, got {node}")
    try:
        return DOFS_PER_NODE * (node - 1) + _OFFSET[direction]
    except KeyError:
        raise ValueError(
            f"direction must be one of {', '.join(DIRECTIONS)}, got {direction!r}"
        ) from None


def node_dofs(node: int) -> np.ndarray:
    """The four global indices ``[y, z, ty, tz]`` of 1-based ``node``."""
    start = dof_index(node, "y")
    return np.arange(start, start + DOFS_PER_NODE)


def n_dof(n_nodes: int) -> int:
    """Number of DOFs of a rotor with ``n_nodes`` nodes."""
    return DOFS_PER_NODE * n_nodes
