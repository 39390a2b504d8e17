"""Finite-length squeeze film damper: the Reynolds equation on a (theta, axial) grid, open
or sealed ends, the pi, 2 pi or Guembel film, with the exact Jacobian of the discrete force.

**Equation.** The journal does not spin; the film is incompressible and isoviscous. With
``x`` axial (``|x| <= L/2``), ``theta`` from the thickest film in the frame of the line of
centres (``h = C (1 + eps cos theta)``, ``phi = psi + pi + theta`` as in
:mod:`rotorsfd.model.sfd`) and ``dh/dt = w_r cos theta + w_t sin theta``,
``(w_r, w_t) = Rot(psi)^T v``, Reynolds' equation reads::

    (1/R^2) d/dtheta (h^3 dp/dtheta) + d/dx (h^3 dp/dx) = 12 mu dh/dt

Scaled by ``zeta = 2x/L``, ``H = h/C``, ``p = (3 mu L^2/C^3)(w_r Pi_r + w_t Pi_t)``::

    lam d/dtheta (H^3 dPi_k/dtheta) + d/dzeta (H^3 dPi_k/dzeta) = m_k(theta),
    lam = (L/D)^2,  m_r = cos theta,  m_t = sin theta

The right-hand side is linear in the velocity and the operator depends on ``eps`` only, so
the uncavitated pressure at any state is a combination of two basis solutions ``Pi_r,
Pi_t`` of ``eps``. As ``lam -> 0``, ``Pi_k = m_k (zeta^2 - 1) / (2 H^3)``: the short film.

**End seal.** At each end the flow through the seal per unit circumference is taken
proportional to the film pressure there, ``q_x = -h^3/(12 mu) dp/dx = c_e p`` (a linear
seal of end-flow coefficient ``c_e`` [m^2/(Pa s)]). Scaled by the axial conductance of the
centred half land, ``C^3/(6 mu L)``, with ``beta = 6 mu L c_e / C^3``::

    H^3 dPi/dzeta + beta Pi = 0   at zeta = +-1

``beta = inf``: open ends (``p = 0``); ``beta = 0``: a sealed land (no end flow; then the
film is the long bearing's, its constant pressure mode fixed by zero net end flow:
solved with ``beta = 1e-7``). The two ends are alike, so the film is symmetric about
mid-land and the half land is solved. At the centred position the solution is
``Pi = m_k f(zeta)``, ``f = A cosh(s zeta) - 1/lam``, ``s = sqrt(lam)``,
``A = beta / (lam (s sinh s + beta cosh s))``, which gives :attr:`FiniteSFD.linear_damping`.

**Cavitation** (the short film's three models, on the same two basis solutions):
``"pi"``: the half-Sommerfeld film of the paper, the fixed arc ``theta in [pi, 2 pi]``
(linear in ``v``, so the finite film compares with the paper's short film model for
model); ``"none"``: the 2 pi film; ``"guembel"``: the Guembel clamp ``p = max(p_full, 0)``
node by node (positive pressure everywhere and on any orbit, backward whirl included;
the short film's Guembel film as ``lam -> 0``). Elrod's mass-conserving model is not here.

**Force and Jacobian.** ``F = R Rot int int p m dx dtheta`` (``m = (cos, sin)``), by Simpson
in ``zeta`` and the periodic trapezoid in theta (Simpson on the pi arc): ``F = Rot G(eps,
w)``, ``G = kappa sum W chi p m``, ``kappa = 3 mu R L^3 / C^3``, ``chi`` the film's nodes.
With ``M = dG/dw`` (sums of ``chi Pi_k``) and ``dPi/deps = -A^-1 A' Pi`` (the discrete
operator differentiated, two more solves of the same factorisation)::

    dF/dv = Rot M Rot^T
    dF/dq = Rot dG/deps e_r^T / C + Rot (J G - M J w) e_t^T / e,  J = [[0, -1], [1, 0]]

exact for the discrete force (the Guembel clamp integrates the positive part of the
linear interpolant cell by cell, so its force is C1: a node changing sign moves nothing
abruptly; at ``e = 0`` the ``psi`` term is left out, as the short pi film does).

**Table.** With ``table = True`` (default) the film is tabulated over eps when it is
built and interpolated (:mod:`rotorsfd.model.film_finite_table`), its error against the
solver measured at every interval's midpoint (:attr:`FiniteSFD.table_error`): for the
pi and 2 pi films ``G = M(eps) w``, so ``M`` and ``dM/deps``; for the Guembel film the
two basis fields, clamped per sample.
Scheme and solver: :mod:`rotorsfd.model.film_finite_kernels`; derivation and measured
accuracy: ``docs/sfd.md``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model.film_land import DEFAULT_EPS_MAX, FilmLand

__all__ = ["DEFAULT_N_AXIAL", "DEFAULT_N_THETA", "FiniteSFD", "centred_damping_ratio"]

#: Default grid: theta nodes (a multiple of 4) and axial intervals of the half land (even).
DEFAULT_N_THETA = 48
DEFAULT_N_AXIAL = 4

_SCALARS = (float, int, np.floating, np.integer)


def centred_damping_ratio(length_to_diameter: float, end_flow: float = math.inf) -> float:
    """``c_finite / c_short`` at the centred position (exact for the continuous film)::

        c / c_short = -3 int_0^1 f dzeta = 3 (1/lam - A sinh(s)/s),
        A = beta / (lam (s sinh s + beta cosh s)),  s = sqrt(lam),  lam = (L/D)^2

    (open ends: ``3 (1 - tanh(s)/s) / lam -> 1`` as ``lam -> 0``; sealed: ``3 / lam``,
    the long bearing's ``c = 12 pi mu R^3 L / C^3`` (2 pi film))."""
    lam = float(length_to_diameter) ** 2
    s = math.sqrt(lam)
    if math.isinf(end_flow):
        return 3.0 * (1.0 - math.tanh(s) / s) / lam
    beta = float(end_flow)
    a_sinh = beta * math.tanh(s) / (lam * (s * math.tanh(s) + beta))  # A sinh(s)
    return 3.0 * (1.0 / lam - a_sinh / s)


class FiniteSFD(FilmLand):
    """Finite-length squeeze film damper (module doc) with the API of
    :class:`rotorsfd.model.sfd.SFD`.

    Parameters
    ----------
    viscosity, radius, length, clearance
        mu [Pa s], R [m], L [m], C [m].
    cavitation
        ``"pi"``, ``"none"`` or ``"guembel"``.
    end_flow
        Dimensionless end-flow coefficient ``beta = 6 mu L c_e / C^3`` of each end seal,
        ``>= 0``: ``inf`` open ends (default), ``0`` a sealed land.
    n_theta, n_axial
        Grid: theta nodes (a multiple of 4, >= 16) and axial intervals of the half land
        (even, >= 2).
    eps_max
        Contact limit on ``eps``, as :class:`~rotorsfd.model.sfd.SFD`.
    table
        Tabulate the film over eps (module doc).
    """

    label = "finite SFD"

    def __init__(self, viscosity: float, radius: float, length: float, clearance: float,
                 cavitation: str = "pi", end_flow: float = math.inf,
                 n_theta: int = DEFAULT_N_THETA, n_axial: int = DEFAULT_N_AXIAL,
                 eps_max: float = DEFAULT_EPS_MAX, table: bool = True) -> None:
        # deferred: model.film_finite_kernels (loads numba)
        from rotorsfd.model.film_finite_kernels import (
            CAVITATION_CODES,
            N_PARAMS,
            P_CLEARANCE,
            P_CODE,
            P_END_FLOW,
            P_EPS_MAX,
            P_LENGTH,
            P_N_AXIAL,
            P_N_THETA,
            P_RADIUS,
            P_VISCOSITY,
        )
        super().__init__(viscosity, radius, length, clearance, cavitation, eps_max)
        end_flow = float(end_flow)
        if not end_flow >= 0.0:
            raise ConfigError("end_flow", end_flow, "a number >= 0 (inf: open ends)")
        self.end_flow = end_flow
        if int(n_theta) != n_theta or n_theta < 16 or n_theta % 4:
            raise ConfigError("n_theta", n_theta, "a multiple of 4, at least 16")
        if int(n_axial) != n_axial or n_axial < 2 or n_axial % 2:
            raise ConfigError("n_axial", n_axial, "an even number, at least 2")
        self.n_theta, self.n_axial = int(n_theta), int(n_axial)
        params = np.zeros(N_PARAMS)
        params[P_VISCOSITY] = self.viscosity
        params[P_RADIUS] = self.radius
        params[P_LENGTH] = self.length
        params[P_CLEARANCE] = self.clearance
        params[P_EPS_MAX] = self.eps_max
        params[P_CODE] = CAVITATION_CODES[cavitation]
        params[P_N_THETA] = self.n_theta
        params[P_N_AXIAL] = self.n_axial
        params[P_END_FLOW] = end_flow
        self._params = params
        #: largest relative error of the table's M and dM/deps at the intervals'
        #: midpoints against the solver (0 without a table)
        self.table_error = (0.0, 0.0)
        if table:
            from rotorsfd.model.film_finite_build import field_table, matrix_table

            build = field_table if cavitation == "guembel" else matrix_table
            self._params, self.table_error = build(params)

    @property
    def tabulated(self) -> bool:
        """Whether the force comes from the eps table."""
        # deferred: model.film_finite_kernels (loads numba)
        from rotorsfd.model.film_finite_kernels import P_TABLE_N

        return self._params[P_TABLE_N] > 0

    def __repr__(self) -> str:
        return (f"FiniteSFD(viscosity={self.viscosity!r}, radius={self.radius!r}, "
                f"length={self.length!r}, clearance={self.clearance!r}, "
                f"cavitation={self.cavitation!r}, end_flow={self.end_flow!r}, "
                f"n_theta={self.n_theta}, n_axial={self.n_axial}, "
                f"table={self.tabulated})")

    @property
    def length_to_diameter(self) -> float:
        """L/D."""
        return self.length / (2.0 * self.radius)

    @property
    def pressure_scale(self) -> float:
        """``3 mu L^2 / C^3`` [Pa s/m]: ``p = pressure_scale (w_r Pi_r + w_t Pi_t)``."""
        return 3.0 * self.viscosity * self.length**2 / self.clearance**3

    @property
    def linear_damping(self) -> float:
        """Centred ``F = -c v`` of the continuous film: the short film's ``c`` times
        :func:`centred_damping_ratio` [N s/m]."""
        full = math.pi * self.coefficient * centred_damping_ratio(self.length_to_diameter,
                                                                  self.end_flow)
        return full if self.cavitation == "none" else 0.5 * full

    @property
    def kernel_params(self) -> np.ndarray:
        """float64 parameter vector of :attr:`numba_kernel` (layout
        :mod:`rotorsfd.model.film_finite_kernels`; housing offset 0), a fresh copy."""
        return self._params.copy()

    @property
    def numba_kernel(self) -> Any:
        """``kernel(q, v, params, F, dFdq, dFdv) -> int64`` of one sample (kernel contract);
        returns 1 on contact, outputs then untouched."""
        # deferred: model.film_finite_kernels (loads numba)
        from rotorsfd.model.film_finite_kernels import finite_kernel

        return finite_kernel

    def samples(self, y: Any, z: Any, vy: Any, vz: Any, want_jac: bool = True
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, tuple[int, ...]]:
        # deferred: model.film_finite_kernels (loads numba)
        from rotorsfd.model.film_finite_kernels import finite_batch

        scalar = all(isinstance(a, _SCALARS) for a in (y, z, vy, vz))
        arrays = np.broadcast_arrays(*(np.asarray(a, dtype=np.float64) for a in (y, z, vy, vz)))
        shape = () if scalar else arrays[0].shape
        flat = [np.ascontiguousarray(a).ravel() for a in arrays]
        n = flat[0].size
        F, dFdq, dFdv = np.empty((n, 2)), np.empty((n, 2, 2)), np.empty((n, 2, 2))
        bad = finite_batch(*flat, self._params, F, dFdq, dFdv)
        if bad >= 0:
            self.contact(*(float(a[bad]) for a in flat))
        return F, dFdq, dFdv, shape

    def pressure(self, y: float, z: float, vy: float, vz: float
                 ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
        """The film of one sample: ``(phi (n,), x (m+1,), p_full, p)`` with ``p_full`` the
        uncavitated pressure [Pa] on the half land (``x`` from mid-land to the end, ``phi``
        the absolute angle of each theta node) and ``p`` the model's (zero off the pi arc,
        clamped for Guembel)."""
        # deferred: model.film_finite_kernels (loads numba)
        from rotorsfd.model.film_finite_kernels import basis_fields

        e = math.hypot(y, z)
        eps = e / self.clearance
        if not eps < self.eps_max:
            self.contact(y, z, vy, vz)
        psi = math.atan2(z, y) if e > 0.0 else 0.0
        cp, sp = math.cos(psi), math.sin(psi)
        wr, wt = cp * vy + sp * vz, -sp * vy + cp * vz
        basis, _ = basis_fields(eps, self.length_to_diameter**2, self.n_theta, self.n_axial,
                                self.end_flow, False)
        p_full = self.pressure_scale * (wr * basis[..., 0] + wt * basis[..., 1])
        if p_full.shape[1] == self.n_axial:  # open end: p = 0 at the last node
            p_full = np.concatenate([p_full, np.zeros((self.n_theta, 1))], axis=1)
        theta = 2.0 * np.pi * np.arange(self.n_theta) / self.n_theta
        if self.cavitation == "pi":
            p = np.where((theta >= np.pi - 1e-12)[:, None] | (theta == 0.0)[:, None],
                         p_full, 0.0)
        elif self.cavitation == "guembel":
            p = np.maximum(p_full, 0.0)
        else:
            p = p_full
        phi = np.mod(psi + np.pi + theta, 2.0 * np.pi)
        x = 0.5 * self.length * np.linspace(0.0, 1.0, self.n_axial + 1)
        return phi, x, p_full, p
