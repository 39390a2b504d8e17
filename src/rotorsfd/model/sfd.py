"""Short-bearing, incompressible squeeze film damper (paper section 2.3), with exact Jacobian.

The force on the journal is computed in the base frame from the journal displacement
``(y, z)`` and velocity ``(vy, vz)`` at the SFD node (derivation: ``docs/sfd.md``)::

    F = -mu R L^3 int_film n n^T v / (C - q.n)^3 dphi,   n = (cos phi, sin phi)

With ``eps = e/C``, ``psi = atan2(z, y)``, ``theta`` from the line of centres as in the
paper (``h = C (1 + eps cos theta)``) and ``I1, I2, I3`` the Sommerfeld integrals over
the film arc::

    F_r = -(mu R L^3 / C^2) (eps psi' I1 + eps' I2)
    F_t = -(mu R L^3 / C^2) (eps' I1 + eps psi' I3)
    Fy = F_r cos psi - F_t sin psi,   Fz = F_r sin psi + F_t cos psi

Film (cavitation) models:

- ``"pi"``: half-Sommerfeld pi film, fixed arc theta in [pi, 2 pi] (paper eq. 11)::

      F_r = -(mu R L^3/C^2) [2 eps^2 psi'/(1-eps^2)^2 + pi (1+2 eps^2) eps'/(2 (1-eps^2)^(5/2))]
      F_t = -(mu R L^3/C^2) [pi eps psi'/(2 (1-eps^2)^(3/2)) + 2 eps eps'/(1-eps^2)^2]

- ``"none"``: uncavitated 2 pi film, ``I1 = 0``, ``I2, I3`` twice the pi film's.
- ``"guembel"``: the film is where the pressure is positive, ``eps' cos theta +
  eps psi' sin theta < 0``: the half circumference facing the velocity, whatever ``q``.

A centring spring is not part of this class: it is a linear support at the SFD node
(``LinearSupport``), added by the model layer.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rotorsfd.model.film_land import DEFAULT_EPS_MAX, FilmLand
from rotorsfd.model.sfd_kernels import (
    CAVITATION_CODES,
    N_PARAMS,
    P_CLEARANCE,
    P_CODE,
    P_EPS_MAX,
    P_LENGTH,
    P_RADIUS,
    P_VISCOSITY,
    sfd_batch,
    sfd_kernel,
    sfd_sample,
)

__all__ = ["DEFAULT_EPS_MAX", "SFD"]

_SCALARS = (float, int, np.floating, np.integer)


class SFD(FilmLand):
    """Short-bearing squeeze film damper with the pi, 2 pi (``"none"``) or Guembel film.

    Parameters
    ----------
    viscosity, radius, length, clearance
        Oil viscosity mu [Pa s], journal radius R [m], land length L [m], radial
        clearance C [m].
    cavitation
        ``"pi"`` (paper), ``"none"`` (2 pi film) or ``"guembel"``.
    eps_max
        Contact limit, ``0 < eps_max < 1``: ``force``/``jacobian`` raise
        :class:`~rotorsfd.errors.JournalContactError` when ``eps = sqrt(y^2+z^2)/C >=
        eps_max``; the compiled kernel returns 1 instead.

    ``force``, ``jacobian``, ... (:class:`~rotorsfd.model.film_land.FilmLand`) give
    ``F = -mu R L^3 int_film n n^T v / (C - q.n)^3 dphi`` in closed form (module doc),
    ``dF/dv = -mu R L^3 int_film n n^T / h^3 dphi`` and
    ``dF/dq = -3 mu R L^3 int_film (n.v) n n^T / h^4 dphi`` plus, for the pi film, the
    term of its ends turning with psi. Where the force is not differentiable the mean of
    the limiting Jacobians is returned: pi film at ``eps = 0`` exactly (``dF/dq = 0``),
    Guembel film at ``v = 0`` (``dF/dv`` = half the 2 pi film's).
    """

    label = "SFD"

    def __init__(self, viscosity: float, radius: float, length: float, clearance: float,
                 cavitation: str = "pi", eps_max: float = DEFAULT_EPS_MAX) -> None:
        super().__init__(viscosity, radius, length, clearance, cavitation, eps_max)
        params = np.empty(N_PARAMS)
        params[P_VISCOSITY] = self.viscosity
        params[P_RADIUS] = self.radius
        params[P_LENGTH] = self.length
        params[P_CLEARANCE] = self.clearance
        params[P_EPS_MAX] = self.eps_max
        params[P_CODE] = CAVITATION_CODES[cavitation]
        self._params = params

    def __repr__(self) -> str:
        return (f"SFD(viscosity={self.viscosity!r}, radius={self.radius!r}, "
                f"length={self.length!r}, clearance={self.clearance!r}, "
                f"cavitation={self.cavitation!r}, eps_max={self.eps_max!r})")

    @property
    def linear_damping(self) -> float:
        """Small-eps limit ``F -> -c v``: ``c = pi mu R L^3 / (2 C^3)`` for the pi and
        Guembel films, ``pi mu R L^3 / C^3`` for the 2 pi film [N s/m]."""
        full = math.pi * self.coefficient
        return full if self.cavitation == "none" else 0.5 * full

    @property
    def kernel_params(self) -> np.ndarray:
        """float64 vector ``[mu, R, L, C, eps_max, model code]`` for :attr:`numba_kernel`
        (codes: pi 0, none 1, guembel 2); a fresh writable copy (type ``float64[::1]``)."""
        return self._params.copy()

    @property
    def numba_kernel(self) -> Any:
        """``kernel(q, v, params, F, dFdq, dFdv) -> int64``: one sample, ``q = (y, z)``,
        ``v = (vy, vz)``; writes F (2,), dFdq, dFdv (2, 2); returns 0, or 1 on contact
        (``eps >= eps_max`` or a non-finite state), outputs then untouched."""
        return sfd_kernel

    def samples(self, y: Any, z: Any, vy: Any, vz: Any, want_jac: bool
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, ...]]:
        """Flat outputs ``F (n, 2)``, ``dFdq, dFdv (n, 2, 2)`` (``(1, 2, 2)`` scratch if
        not ``want_jac``) and the broadcast shape; raises on contact."""
        if all(isinstance(a, _SCALARS) for a in (y, z, vy, vz)):  # one sample: no broadcast
            F, dFdq, dFdv = np.empty((1, 2)), np.empty((1, 2, 2)), np.empty((1, 2, 2))
            yf, zf, vyf, vzf = float(y), float(z), float(vy), float(vz)
            if sfd_sample(yf, zf, vyf, vzf, self._params, F[0], dFdq[0], dFdv[0]) != 0:
                self.contact(yf, zf, vyf, vzf)
            return F, dFdq, dFdv, ()
        arrays = np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in (y, z, vy, vz)))
        shape = arrays[0].shape
        flat = [np.ascontiguousarray(a).ravel() for a in arrays]
        n = flat[0].size
        F = np.empty((n, 2))
        dFdq = np.empty((n, 2, 2)) if want_jac else np.empty((1, 2, 2))
        dFdv = np.empty((n, 2, 2)) if want_jac else np.empty((1, 2, 2))
        bad = sfd_batch(*flat, self._params, F, dFdq, dFdv, want_jac)
        if bad >= 0:
            self.contact(*(float(a[bad]) for a in flat))
        return F, dFdq, dFdv, shape

