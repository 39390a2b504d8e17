"""The compiled kernel of the SFD element (:class:`rotorsfd.elements.sfd.SFDElement`).

One sample of the film relative to the housing centre ``o = (o_y, o_z)``::

    F = F_film(q - o, v),   dF/dq = dF_film/dq (q - o, v),   dF/dv = dF_film/dv (q - o, v)

with ``F_film`` the short-bearing kernel :func:`rotorsfd.model.sfd_kernels.sfd_sample`
(``docs/sfd.md``). Kept apart from the element and its config model so that loading a
config does not load numba: the element imports this module when its ``kernel`` is first
asked for.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rotorsfd.model.sfd_kernels import N_PARAMS, sfd_sample

__all__ = ["N_ELEMENT_PARAMS", "P_OFFSET_Y", "P_OFFSET_Z", "sfd_element_kernel"]

#: Parameter vector of :func:`sfd_element_kernel`: the film's (``N_PARAMS``), then the
#: housing offset.
P_OFFSET_Y, P_OFFSET_Z = N_PARAMS, N_PARAMS + 1
N_ELEMENT_PARAMS = N_PARAMS + 2


@njit(cache=True)
def sfd_element_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
                       dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """The film of one sample relative to the housing centre: ``F_film(q - o, v)``."""
    return sfd_sample(q[0] - params[P_OFFSET_Y], q[1] - params[P_OFFSET_Z], v[0], v[1],
                      params, F, dFdq, dFdv)
