"""The compiled kernel of the intershaft SFD
(:class:`rotorsfd.elements.intershaft_sfd.IntershaftSFDElement`).

One sample on ``(y_a, z_a, y_b, z_b)``: the short film on the relative state
``d = q_a - q_b - o``, ``d' = q_a' - q_b'``, force ``+f`` on node a, ``-f`` on node b::

    F = T^T f(T q - o, T v),   dF/dq = T^T (df/dd) T,   dF/dv = T^T (df/dd') T,   T = [I, -I]

with ``f`` the kernel :func:`rotorsfd.model.sfd_kernels.sfd_sample` and the parameter vector
of :func:`rotorsfd.elements.sfd_kernel.sfd_element_kernel` (the film's, then the offset).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rotorsfd.elements.sfd_kernel import P_OFFSET_Y, P_OFFSET_Z
from rotorsfd.model.sfd_kernels import sfd_sample

__all__ = ["intershaft_sfd_kernel"]


@njit(cache=True)
def intershaft_sfd_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
                          dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """The film of one sample on the relative state of the two nodes (module doc)."""
    f = np.empty(2)
    jq = np.empty((2, 2))
    jv = np.empty((2, 2))
    rc = sfd_sample(q[0] - q[2] - params[P_OFFSET_Y], q[1] - q[3] - params[P_OFFSET_Z],
                    v[0] - v[2], v[1] - v[3], params, f, jq, jv)
    if rc != 0:
        return rc
    for i in range(2):
        F[i] = f[i]
        F[i + 2] = -f[i]
        for j in range(2):
            dFdq[i, j] = jq[i, j]
            dFdq[i, j + 2] = -jq[i, j]
            dFdq[i + 2, j] = -jq[i, j]
            dFdq[i + 2, j + 2] = jq[i, j]
            dFdv[i, j] = jv[i, j]
            dFdv[i, j + 2] = -jv[i, j]
            dFdv[i + 2, j] = -jv[i, j]
            dFdv[i + 2, j + 2] = jv[i, j]
    return 0
