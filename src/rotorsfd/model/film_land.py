"""The land of a film (a squeeze film damper or a journal bearing): the oil viscosity mu,
journal radius R, land length L, radial clearance C, the film model and the contact limit
on the eccentricity ratio, checked once for every film law (the short-bearing
:class:`~rotorsfd.model.sfd.SFD`, the finite-length
:class:`~rotorsfd.model.film_finite.FiniteSFD`). No numba here: the laws' kernels live in
their own modules."""

from __future__ import annotations

import math
from typing import Any, NoReturn

import numpy as np

from rotorsfd.errors import ConfigError, JournalContactError

__all__ = ["DEFAULT_EPS_MAX", "FILM_MODELS", "FilmLand", "positive"]

#: Default contact limit on the eccentricity ratio: the force grows like (1 - eps)^(-5/2)
#: and the Jacobian like (1 - eps)^(-7/2); at 0.999 that is a factor ~1e7 above eps = 0.
DEFAULT_EPS_MAX = 0.999
#: the film (cavitation) models: half-Sommerfeld pi film, full 2 pi film, Guembel film
FILM_MODELS = ("pi", "none", "guembel")


def positive(field: str, value: float) -> float:
    """``value`` as a float; ConfigError naming ``field`` unless finite and > 0."""
    value = float(value)
    if not (math.isfinite(value) and value > 0.0):
        raise ConfigError(field, value, "a finite positive number (SI units)")
    return value


class FilmLand:
    """mu [Pa s], R, L, C [m], the film model (:data:`FILM_MODELS`) and ``0 < eps_max < 1``,
    validated; the force law's public forms (``force``, ``jacobian``, ...) over the law's
    :meth:`samples`."""

    #: how the law names itself in its contact errors
    label = "film"

    def __init__(self, viscosity: float, radius: float, length: float, clearance: float,
                 cavitation: str = "pi", eps_max: float = DEFAULT_EPS_MAX) -> None:
        self.viscosity = positive("viscosity", viscosity)
        self.radius = positive("radius", radius)
        self.length = positive("length", length)
        self.clearance = positive("clearance", clearance)
        if cavitation not in FILM_MODELS:
            raise ConfigError("cavitation", cavitation, "one of 'pi', 'none', 'guembel'")
        self.cavitation = cavitation
        eps_max = float(eps_max)
        if not 0.0 < eps_max < 1.0:
            raise ConfigError("eps_max", eps_max, "a number with 0 < eps_max < 1")
        self.eps_max = eps_max

    @classmethod
    def from_ratios(cls, viscosity: float, clearance: float, clearance_ratio: float,
                    length_to_diameter: float, cavitation: str = "pi", **kwargs: Any
                    ) -> Any:
        """From ``C``, ``C/R`` and ``L/D`` as the paper gives them: ``R = C / (C/R)``,
        ``L = (L/D) 2 R`` (``clearance_ratio`` as a fraction, 0.00485); ``kwargs`` go to the
        law's constructor."""
        clearance = positive("clearance", clearance)
        radius = clearance / positive("clearance_ratio", clearance_ratio)
        length = positive("length_to_diameter", length_to_diameter) * 2.0 * radius
        return cls(viscosity, radius, length, clearance, cavitation, **kwargs)

    @property
    def coefficient(self) -> float:
        """``K = mu R L^3 / C^3`` [N s/m], the scale of every short-bearing force term."""
        return self.viscosity * self.radius * self.length**3 / self.clearance**3

    # ---- the law's forms, over its samples ------------------------------------------------
    def samples(self, y: Any, z: Any, vy: Any, vz: Any, want_jac: bool
                ) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, ...]]:
        """Flat ``F (n, 2)``, ``dFdq, dFdv (n, 2, 2)`` (scratch if not ``want_jac``) of the
        broadcast samples and their shape; :meth:`contact` outside the law's domain."""
        raise NotImplementedError

    def contact(self, y: float, z: float, vy: float, vz: float) -> NoReturn:
        """Raise for a sample the law rejects: ValueError for a non-finite state, else
        JournalContactError (``eps >= eps_max``)."""
        if not all(math.isfinite(a) for a in (y, z, vy, vz)):
            raise ValueError(f"SFD state is not finite: y={y}, z={z}, vy={vy}, vz={vz}")
        raise JournalContactError(math.hypot(y, z) / self.clearance, y, z, vy, vz,
                                  where=f"{self.label} ({self.cavitation} film, eps_max="
                                        f"{self.eps_max:g})")

    def force(self, y: Any, z: Any, vy: Any, vz: Any) -> tuple[Any, Any]:
        """Film force ``(Fy, Fz)`` [N] on the journal, broadcasting over numpy arrays.
        Raises ``JournalContactError`` if ``eps >= eps_max`` anywhere (with the state of
        the first such sample) and ``ValueError`` on a non-finite state."""
        F, _, _, shape = self.samples(y, z, vy, vz, want_jac=False)
        return F[:, 0].reshape(shape)[()], F[:, 1].reshape(shape)[()]

    def jacobian(self, y: Any, z: Any, vy: Any, vz: Any) -> tuple[np.ndarray, np.ndarray]:
        """Exact ``(dF/dq, dF/dv)``, each of shape ``(..., 2, 2)``: rows (Fy, Fz),
        columns (y, z) resp. (vy, vz). Raises like :meth:`force`."""
        _, dFdq, dFdv, shape = self.samples(y, z, vy, vz, want_jac=True)
        return dFdq.reshape((*shape, 2, 2)), dFdv.reshape((*shape, 2, 2))

    def force_and_jacobian(self, y: Any, z: Any, vy: Any, vz: Any
                           ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """``(F, dF/dq, dF/dv)`` in one pass; ``F`` of shape ``(..., 2)``."""
        F, dFdq, dFdv, shape = self.samples(y, z, vy, vz, want_jac=True)
        return (F.reshape((*shape, 2)), dFdq.reshape((*shape, 2, 2)),
                dFdv.reshape((*shape, 2, 2)))

    def nl_force(self, q: Any, v: Any) -> np.ndarray:
        """Generic-solver form (``docs/INTERFACES.md``): ``q = (..., 2)`` displacements
        ``(y, z)``, ``v = (..., 2)`` velocities; returns ``F (..., 2)``."""
        q, v = np.asarray(q, dtype=np.float64), np.asarray(v, dtype=np.float64)
        F, _, _, shape = self.samples(q[..., 0], q[..., 1], v[..., 0], v[..., 1],
                                      want_jac=False)
        return F.reshape((*shape, 2))

    def nl_jacobian(self, q: Any, v: Any) -> tuple[np.ndarray, np.ndarray]:
        """Generic-solver form of :meth:`jacobian`: ``(dF/dq, dF/dv)``, each ``(..., 2, 2)``."""
        q, v = np.asarray(q, dtype=np.float64), np.asarray(v, dtype=np.float64)
        return self.jacobian(q[..., 0], q[..., 1], v[..., 0], v[..., 1])
