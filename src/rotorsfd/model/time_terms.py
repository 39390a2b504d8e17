"""The rotor system at one speed as the solvers' :class:`~rotorsfd.second_order.
SecondOrderSystem` (what :meth:`rotorsfd.model.system.RotorSystem.second_order` returns).

    M q'' + (C + Omega G + C_base(t)) q' + (K + K_base(t)) q = F_mu(t) + F_base(t) + F_nl

A constant base (and no unbalance that starts later: a sudden unbalance is a series load)
gives constant matrices ``matrices(speed)`` (above
:data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs ``split_matrices(speed)``: CSR, a modal
damping of a few modes as :class:`~rotorsfd.model.lowrank.BandedLowRank`, the record's
``gyroscopic`` G as CSR, no dense n x n array; the full step densifies them, the reduced
step projects them), the constant load
``static_force(speed)`` and the unbalance harmonics at Omega; a harmonic, callable, pulse
or recorded base gives the base terms as time-varying matrices and series loads
(:func:`~rotorsfd.model.base_terms.time_varying_terms`,
:func:`~rotorsfd.model.unbalance.unbalance_series`), a coefficient that stays constant
over the run folded into the constant matrices.

:func:`linear_part` is the system's linear variant: the same rotor and base rotation
without the nonlinear elements and the loads, whose ``second_order(speed)`` is the record
without the nonlinear elements (what the linear time-periodic stability chart takes) and
whose ``matrices(speed)`` are that record's ``(M, D, K)`` at every speed for constant
rates (the ``LinearDynamics`` of the modal analyses).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import scipy.sparse as sp

from rotorsfd.errors import ConfigError
from rotorsfd.model.base_motion import BaseMotion, Constant
from rotorsfd.model.base_terms import time_varying_terms
from rotorsfd.model.lowrank import with_lowrank
from rotorsfd.model.multishaft_loads import other_spool_harmonics, split_unbalances
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.model.unbalance import unbalance_harmonics, unbalance_series
from rotorsfd.second_order import SecondOrderSystem
from rotorsfd.timedomain.forcing import Forcing, HarmonicLoad, TimeVaryingMatrices

__all__ = ["banded_rotor_terms", "fold_constant", "linear_part", "second_order_system"]


def banded_rotor_terms(rotor: Any) -> tuple[Any, Any, Any, Any] | None:
    """``(M, C, K, G)`` of ``rotor`` without a dense n x n array when it has more than
    :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs: CSR, the damping a
    :class:`~rotorsfd.model.lowrank.BandedLowRank` with modal damping of a few modes;
    None for a smaller (or matrix-free) rotor, whose dense matrices the callers take."""
    if rotor.n_dof <= DENSE_MAX_DOF or not hasattr(rotor, "G_csr"):
        return None
    lowrank = getattr(rotor, "damping_lowrank", None)
    C = rotor.C_csr if lowrank is None else rotor.C_band_csr
    return rotor.M_csr, with_lowrank(C, lowrank), rotor.K_csr, rotor.G_csr


def fold_constant(pairs: Sequence[tuple[Any, np.ndarray]], probe: np.ndarray
                  ) -> tuple[list[tuple[Any, np.ndarray]], np.ndarray | None]:
    """Split ``(coefficient, array)`` pairs into time-varying ones and the sum of those
    whose coefficient is constant on ``probe`` (that sum, or None)."""
    varying: list[tuple[Any, np.ndarray]] = []
    const = None
    for c, X in pairs:
        values = np.broadcast_to(np.asarray(c(probe), dtype=float), probe.shape)
        if np.ptp(values) == 0.0:                  # X dense or CSR (a large model)
            term = float(values[0]) * (X if sp.issparse(X) else np.asarray(X, dtype=float))
            const = term if const is None else const + term
        else:
            varying.append((c, X))
    return varying, const


def second_order_system(system: Any, speed: float, *,
                        horizon: float | None = None) -> SecondOrderSystem:
    """``system`` (a :class:`~rotorsfd.model.system.RotorSystem`, which calls this from
    its ``second_order``) at rotor speed ``speed`` [rad/s] (module docstring); ``horizon`` [s]
    (default 1000 rotor periods) is the interval on which a coefficient must be constant
    to be folded into the constant matrices."""
    if not speed > 0.0:
        raise ConfigError("analysis.simulate.speed", speed,
                          "the rotor speed must be > 0 rad/s")
    r = system.rotor
    nl = system.nl_dofs
    el = system.elements_at(speed)   # a law of the speed (journal bearing) set to it
    kernel, params = (el.kernel, el.kernel_params) if len(el) else (None, None)
    events = any(u.start > 0.0 for u in system.unbalances)   # a sudden unbalance: series
    own, other = split_unbalances(r, system.unbalances)   # each at its own shaft's speed
    if system.base.is_constant and not events:
        split = getattr(system, "split_matrices", None)
        if split is not None and system.n_dof > DENSE_MAX_DOF:
            M, D, K = split(speed)       # CSR, a modal damping as banded + low-rank
            G = r.G_csr if hasattr(r, "G_csr") else r.G   # dD/dOmega CSR too: no n x n
        else:
            M, D, K = system.matrices(speed)
            G = r.G
        Fc, Fs = unbalance_harmonics(own, r, speed, system.constant_base_state())
        harm = ([HarmonicLoad(1.0, Fc, Fs)] if own else []) + [
            HarmonicLoad(k, fc, fs) for k, fc, fs in other_spool_harmonics(
                r, system.unbalances, speed)]
        forcing = Forcing(omega=speed, constant=system.static_force(speed), harmonics=harm)
        return SecondOrderSystem(M, D.copy(), K.copy(), nl, kernel, params, forcing, None,
                                 float(speed), el, gyroscopic=G)
    T = 2.0 * math.pi / speed
    span = horizon if horizon is not None else 1000.0 * T
    probe = np.concatenate([np.linspace(0.0, span, 257),
                            span * (np.arange(1, 64) * math.sqrt(2.0) % 1.0),
                            system.base.support_times()])   # where a pulse or record acts
    damping, stiffness, force = time_varying_terms(system.basis, system.base, speed)
    damping, dC = fold_constant(damping, probe)
    stiffness, dK = fold_constant(stiffness, probe)
    force, f0 = fold_constant(force, probe)
    banded = banded_rotor_terms(r)     # above DENSE_MAX_DOF: the band, no n x n array
    M0, C0, K0, G0 = (r.M, r.C, r.K, r.G) if banded is None else banded
    D = C0 + speed * G0
    K = K0
    if dC is not None:
        D = D + dC
    if dK is not None:
        K = K + dK
    series = list(force) + unbalance_series(own, r, speed, system.base)
    for k, us in other.items():     # a second spool's unbalances at its speed k Omega
        series += unbalance_series(us, r, k * speed, system.base)
    forcing = Forcing(omega=speed, constant=f0, series=series)
    tv = TimeVaryingMatrices(damping=damping, stiffness=stiffness) \
        if damping or stiffness else None
    if banded is None:
        D, K = np.asarray(D, float), np.asarray(K, float)
    return SecondOrderSystem(M0, D, K, nl, kernel, params, forcing, tv, float(speed), el,
                             gyroscopic=G0)


def linear_part(system: Any, rates: Sequence[float] | None = None) -> Any:
    """The linear variant of ``system`` (a :class:`~rotorsfd.model.system.RotorSystem`):
    its rotor (with the elements' linear parts, such as an SFD's centring spring) on its
    base rotation, without the nonlinear elements and the loads (unbalance, base
    translation, gravity: they load the rotor, the matrices are free of them). Its
    ``second_order(speed)`` is the record of ``system`` without the nonlinear elements
    and the forcing; with constant rates its ``matrices(speed)`` (and
    ``sparse_matrices``) are that record's ``(M, D, K)`` at every speed. ``rates`` [rad/s]:
    constant rotation rates instead of the base's laws."""
    laws = system.base.rotation if rates is None else tuple(Constant(float(w))
                                                            for w in rates)
    return type(system)(system.rotor, base=BaseMotion(wx=laws[0], wy=laws[1], wz=laws[2]))
