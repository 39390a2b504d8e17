"""The compiled kernel of the journal bearing element
(:class:`rotorsfd.elements.journal_bearing.JournalBearingElement`).

One sample: the short-bearing film of :func:`rotorsfd.model.sfd_kernels.sfd_sample` at the
velocity relative to the frame turning at half the journal speed (module doc of the
element)::

    F = F_film(q, w),   w = v - (Omega/2) J q,   J q = (-q_z, q_y)
    dF/dq = dF_film/dq + dF_film/dw (-(Omega/2) J),   dF/dv = dF_film/dw

Kept apart from the element and its config model so that loading a config does not load
numba.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rotorsfd.model.sfd_kernels import N_PARAMS, sfd_sample

__all__ = ["N_BEARING_PARAMS", "P_SPEED", "journal_bearing_kernel"]

#: Parameter vector: the film's (``N_PARAMS``), then the journal speed Omega [rad/s].
P_SPEED = N_PARAMS
N_BEARING_PARAMS = N_PARAMS + 1


@njit(cache=True)
def journal_bearing_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
                           dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """The film at ``w = v - (Omega/2) J q`` and the chain rule into ``dF/dq``."""
    half = 0.5 * params[P_SPEED]
    status = sfd_sample(q[0], q[1], v[0] + half * q[1], v[1] - half * q[0], params, F,
                        dFdq, dFdv)
    if status != 0:
        return status
    for i in range(2):
        dFdq[i, 0] -= half * dFdv[i, 1]
        dFdq[i, 1] += half * dFdv[i, 0]
    return 0
