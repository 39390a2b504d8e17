"""Unbalance force in the base frame, with the base-rotation terms (paper eqs. 5-6).

A mass m_u at eccentricity e (``magnitude = m_u e`` [kg m]) on the disk at ``node``, at the
angle ``theta = Omega t + eta`` from +y towards +z (Omega: spin relative to the base).
Its absolute acceleration relative to the disk centre, in base components, is
rho'' + 2 w x rho' + w' x rho + w x (w x rho) with rho = e (0, cos theta, sin theta); the
force on the rotor is minus m_u times it (derived in ``derivations/base_motion.py``):

    F_y = m_u e [ (Omega^2 + 2 Omega wx + wx^2 + wz^2) cos(theta) + (wx' - wy wz) sin(theta) ]
    F_z = m_u e [ (Omega^2 + 2 Omega wx + wx^2 + wy^2) sin(theta) - (wx' + wy wz) cos(theta) ]

Terms of order m_u e q (the eccentric mass moving with the tilts) and m_u e^2 are dropped,
as usual. For constant rates ``F = F_c cos(Omega t) + F_s sin(Omega t)`` (eq. 5) with

    F_c(y) = U [A_y cos(eta) + B_y sin(eta)],   F_s(y) = U [B_y cos(eta) - A_y sin(eta)]
    F_c(z) = U [A_z sin(eta) - B_z cos(eta)],   F_s(z) = U [A_z cos(eta) + B_z sin(eta)]

where U = m_u e, A_y = Omega^2 + 2 Omega wx + wx^2 + wz^2, B_y = wx' - wy wz,
A_z = Omega^2 + 2 Omega wx + wx^2 + wy^2, B_z = wx' + wy wz.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model import dofs
from rotorsfd.model.base_motion import BaseState


@dataclass(frozen=True)
class Unbalance:
    """Unbalance ``magnitude`` = m_u e [kg m] at 1-based ``node``, phase eta [rad]; in the
    time domain it acts from ``start`` [s] on (0: always; later: a sudden unbalance, a
    blade loss, appearing at the rotor angle of that instant), growing to its magnitude
    over ``rise_time`` as ``(1 - cos(pi s / rise_time)) / 2`` (0: a step, which a fixed
    time step resolves to first order only: the step's trapezoidal impulse is off by up to
    half a step's). Steady-state analyses see every unbalance (the rotor after its
    events)."""

    node: int
    magnitude: float
    phase: float = 0.0
    start: float = 0.0
    rise_time: float = 0.0

    def __post_init__(self) -> None:
        if self.node < 1:
            raise ConfigError("unbalance.node", self.node, "node numbers start at 1")
        if not np.isfinite(self.magnitude) or self.magnitude < 0.0:
            raise ConfigError("unbalance.magnitude", self.magnitude, "must be finite, >= 0")
        if not (np.isfinite(self.start) and self.start >= 0.0):
            raise ConfigError("unbalance.start", self.start, "must be finite, >= 0 s")
        if not (np.isfinite(self.rise_time) and self.rise_time >= 0.0):
            raise ConfigError("unbalance.rise_time", self.rise_time, "must be finite, >= 0 s")

    def on(self, t: np.ndarray) -> np.ndarray | float:
        """The share of the magnitude acting at t: 0 before ``start``, the half-cosine
        rise over ``rise_time``, then 1."""
        if self.start == 0.0 and self.rise_time == 0.0:
            return 1.0
        s = np.asarray(t, dtype=float) - self.start
        if self.rise_time == 0.0:
            return (s >= 0.0).astype(float)
        x = np.clip(s / self.rise_time, 0.0, 1.0)
        return 0.5 * (1.0 - np.cos(np.pi * x))


def _state_or_fixed(state: BaseState | None) -> BaseState:
    return BaseState.fixed() if state is None else state


def _factors(speed: float, state: BaseState) -> tuple[np.ndarray, ...]:
    """(A_y, B_y, A_z, B_z) of the module docstring."""
    wx, wy, wz = np.asarray(state.w, dtype=float)
    dwx = np.asarray(state.dw, dtype=float)[0]
    common = speed**2 + 2.0 * speed * wx + wx**2
    return common + wz**2, dwx - wy * wz, common + wy**2, dwx + wy * wz


def unbalance_force(unbalances: Sequence[Unbalance], rotor, speed: float,
                    state: BaseState | None, t: float | np.ndarray) -> np.ndarray:
    """Global unbalance force at time(s) t, shape (n_dof,) or (n_dof, nt).

    ``state`` may be time-vectorised with the same t (e.g. ``motion.state(t)``); rates and
    their derivatives are taken at t (general time-varying rates).
    """
    st = _state_or_fixed(state)
    t = np.asarray(t, dtype=float)
    ay, by, az, bz = _factors(speed, st)
    F = np.zeros((rotor.n_dof, *t.shape))
    for u in unbalances:
        theta = speed * t + u.phase
        c, s = np.cos(theta), np.sin(theta)
        iy, iz = dofs.dof_index(u.node, "y"), dofs.dof_index(u.node, "z")
        F[iy] += u.magnitude * (ay * c + by * s)
        F[iz] += u.magnitude * (az * s - bz * c)
    return F


def _harmonic_vectors(unbalances: Sequence[Unbalance], n_dof: int, ay: float, by: float,
                      az: float, bz: float) -> tuple[np.ndarray, np.ndarray]:
    Fc, Fs = np.zeros(n_dof), np.zeros(n_dof)
    for u in unbalances:
        ce, se = np.cos(u.phase), np.sin(u.phase)
        iy, iz = dofs.dof_index(u.node, "y"), dofs.dof_index(u.node, "z")
        U = u.magnitude
        Fc[iy] += U * (ay * ce + by * se)
        Fs[iy] += U * (by * ce - ay * se)
        Fc[iz] += U * (az * se - bz * ce)
        Fs[iz] += U * (az * ce + bz * se)
    return Fc, Fs


def unbalance_harmonics(unbalances: Sequence[Unbalance], rotor, speed: float,
                        state: BaseState | None = None) -> tuple[np.ndarray, np.ndarray]:
    """(F_c, F_s) with F = F_c cos(Omega t) + F_s sin(Omega t), for constant rates (eq. 5-6).

    ``state.dw`` is used as given (zero for constant rates).
    """
    st = _state_or_fixed(state)
    ay, by, az, bz = (float(v) for v in _factors(speed, st))
    return _harmonic_vectors(unbalances, rotor.n_dof, ay, by, az, bz)


def unbalance_harmonics_derivatives(
    unbalances: Sequence[Unbalance], rotor, speed: float, state: BaseState | None = None,
    only: str | None = None,
) -> dict[str, tuple[np.ndarray, np.ndarray]]:
    """d(F_c, F_s)/dp for p in ("speed", "wx", "wy", "wz", "dwx") (``only``: that p alone,
    the HB's dforcing needs one per call); F_c, F_s are linear in (A_y, B_y, A_z, B_z), so
    each derivative is the same map of their derivatives."""
    st = _state_or_fixed(state)
    wx, wy, wz = (float(v) for v in np.asarray(st.w, dtype=float))
    om = float(speed)
    dA = 2.0 * om + 2.0 * wx  # d(common)/d(speed) ... and d/d(wx) = 2 Omega + 2 wx too
    partials = {
        "speed": (dA, 0.0, dA, 0.0),
        "wx": (2.0 * om + 2.0 * wx, 0.0, 2.0 * om + 2.0 * wx, 0.0),
        "wy": (0.0, -wz, 2.0 * wy, wz),
        "wz": (2.0 * wz, -wy, 0.0, wy),
        "dwx": (0.0, 1.0, 0.0, 1.0),
    }
    keys = partials if only is None else (only,)
    return {k: _harmonic_vectors(unbalances, rotor.n_dof, *partials[k]) for k in keys}


@dataclass(frozen=True)
class _SteadySpeed:
    """Omega(t) = speed (the speed-law protocol of :mod:`rotorsfd.timedomain.speed_law`)."""

    speed: float

    def omega(self, t: np.ndarray) -> np.ndarray:
        return np.full(np.shape(t), float(self.speed))

    def domega(self, t: np.ndarray) -> np.ndarray:
        return np.zeros(np.shape(t))

    def angle(self, t: np.ndarray) -> np.ndarray:
        return float(self.speed) * np.asarray(t, dtype=float)


def unbalance_series(unbalances: Sequence[Unbalance], rotor, speed: float,
                     motion=None) -> list[tuple]:
    """F_mu(t) as ``(coefficient(t), vector)`` pairs (``timedomain.forcing.Forcing.series``):
    per unbalance, ``U (A_y cos + B_y sin)`` on y and ``U (A_z sin - B_z cos)`` on z, with the
    rates of ``motion`` (a BaseMotion; None: fixed base) evaluated at t: the speed law
    form below at a constant speed."""
    return unbalance_series_law(unbalances, rotor.n_dof, _SteadySpeed(speed), motion)


def unbalance_series_law(unbalances: Sequence[Unbalance], n_dof: int, law: Any,
                         motion: Any = None) -> list[tuple]:
    """``(coefficient(t), vector)`` pairs of F_mu under a speed law Omega(t) (``law``:
    ``omega``, ``domega``, ``angle`` of :mod:`rotorsfd.timedomain.speed_law`), the rotor
    angle ``theta = int Omega`` and ``Omega'`` in place of ``Omega t`` and 0 (the
    tangential term, derived there), with the rates of ``motion`` (a BaseMotion; None: a
    fixed base)."""
    out: list[tuple] = []

    def factors(t: np.ndarray) -> tuple[np.ndarray, ...]:
        t = np.asarray(t, dtype=float)
        st = BaseState.fixed() if motion is None else motion.state(t)
        wx, wy, wz = (np.broadcast_to(v, t.shape) for v in np.asarray(st.w, dtype=float))
        dwx = np.broadcast_to(np.asarray(st.dw, dtype=float)[0], t.shape)
        om, dom = law.omega(t), law.domega(t)
        common = om**2 + 2.0 * om * wx + wx**2
        return (common + wz**2, dwx + dom - wy * wz, common + wy**2, dwx + dom + wy * wz,
                law.angle(t))

    for u in unbalances:
        ey, ez = np.zeros(n_dof), np.zeros(n_dof)
        ey[dofs.dof_index(u.node, "y")] = u.magnitude
        ez[dofs.dof_index(u.node, "z")] = u.magnitude

        def cy(t, u=u):
            ay, by, _, _, th = factors(t)
            return (ay * np.cos(th + u.phase) + by * np.sin(th + u.phase)) * u.on(t)

        def cz(t, u=u):
            _, _, az, bz, th = factors(t)
            return (az * np.sin(th + u.phase) - bz * np.cos(th + u.phase)) * u.on(t)

        out += [(cy, ey), (cz, ez)]
    return out
