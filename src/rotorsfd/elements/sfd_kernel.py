"""The compiled kernel of the SFD element (:class:`rotorsfd.elements.sfd.SFDElement`).

One sample of the film relative to the housing centre ``o = (o_y, o_z)``::

    F = F_film(q - o, v),   dF/dq = dF_film/dq (q - o, v),   dF/dv = dF_film/dv (q - o, v)

with ``F_film`` the short-bearing kernel :func:`rotorsfd.model.sfd_kernels.sfd_sample`
(``docs/sfd.md``). With an oil density ``rho`` (last parameter) the inertial kernel adds
the fluid inertia force of :func:`rotorsfd.model.film_inertia.film_inertia_sample` and
its acceleration Jacobian (the inertial kernel contract of :mod:`rotorsfd.kernels`)::

    F = F_film(q - o, v) + F_in(q - o, v, a)

Kept apart from the element and its config model so that loading a
config does not load numba: the element imports this module when its ``kernel`` is first
asked for.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from rotorsfd.model.film_inertia import film_inertia_sample
from rotorsfd.model.sfd_kernels import (
    N_PARAMS,
    P_CLEARANCE,
    P_CODE,
    P_LENGTH,
    P_RADIUS,
    sfd_sample,
)

__all__ = ["N_ELEMENT_PARAMS", "P_DENSITY", "P_OFFSET_Y", "P_OFFSET_Z",
           "sfd_element_kernel", "sfd_inertial_batch", "sfd_inertial_kernel"]

#: Parameter vector of :func:`sfd_element_kernel`: the film's (``N_PARAMS``), then the
#: housing offset and the oil density of the inertia force (0: none).
P_OFFSET_Y, P_OFFSET_Z, P_DENSITY = N_PARAMS, N_PARAMS + 1, N_PARAMS + 2
N_ELEMENT_PARAMS = N_PARAMS + 3


@njit(cache=True)
def sfd_element_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
                       dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """The film of one sample relative to the housing centre: ``F_film(q - o, v)``."""
    return sfd_sample(q[0] - params[P_OFFSET_Y], q[1] - params[P_OFFSET_Z], v[0], v[1],
                      params, F, dFdq, dFdv)


@njit(cache=True)
def sfd_inertial_kernel(q: np.ndarray, v: np.ndarray, a: np.ndarray, params: np.ndarray,
                        F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray,
                        dFda: np.ndarray) -> int:
    """The film with its fluid inertia, ``F(q - o, v, a)`` and ``dF/dq, dF/dv, dF/da``
    (the inertial kernel of :mod:`rotorsfd.kernels`); returns 0, or 1 on contact."""
    y = q[0] - params[P_OFFSET_Y]
    z = q[1] - params[P_OFFSET_Z]
    status = sfd_sample(y, z, v[0], v[1], params, F, dFdq, dFdv)
    if status != 0:
        return status
    if not (np.isfinite(a[0]) and np.isfinite(a[1])):
        return 1
    film_inertia_sample(y, z, v[0], v[1], a[0], a[1], params[P_DENSITY], params[P_RADIUS],
                        params[P_LENGTH], params[P_CLEARANCE], int(params[P_CODE]), F,
                        dFdq, dFdv, dFda)
    return 0


@njit(cache=True)
def sfd_inertial_batch(q: np.ndarray, v: np.ndarray, a: np.ndarray, params: np.ndarray,
                       F: np.ndarray, dFdq: np.ndarray, dFdv: np.ndarray,
                       dFda: np.ndarray) -> int:
    """:func:`sfd_inertial_kernel` over samples ``(n, 2)``; -1 if all are fine, else the
    index of the first one in contact."""
    for i in range(q.shape[0]):
        if sfd_inertial_kernel(q[i], v[i], a[i], params, F[i], dFdq[i], dFdv[i],
                               dFda[i]) != 0:
            return i
    return -1
