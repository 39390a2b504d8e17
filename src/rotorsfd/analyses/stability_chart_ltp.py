"""The linear time-periodic (LTP) system of a rotor under base rotation, and the modal
basis of its monodromy, for the stability chart.

The linear rotor (film off, supports and centring spring on: the model's linear part,
:func:`rotorsfd.model.time_terms.linear_part`) in the base frame::

    M q'' + (C + Omega G + sum_i c_i(t) B_i) q' + (K + sum_i k_i(t) B_i) q = f(t)

with the 12 constant base matrices ``B_i`` of :func:`rotorsfd.model.base_terms.base_basis`
and their coefficients from :class:`rotorsfd.analyses.stability_chart_rates.ChartParams`.
The forcing f does not change the stability and is left out. The Galerkin basis is the
lowest undamped modes of ``(K + constant base terms, M)``: every mode below a cutoff (the
chart takes ``MODE_CUTOFF`` times the highest of 2 w_b and Omega over the grid), at
least ``MIN_MODES``, which holds the combination resonances ``omega_i + omega_j = k w_b``
with ``k <= 2`` that the chart can show.

Above :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs the system keeps the band (the
record's CSR matrices, a modal damping of a few modes as
:class:`~rotorsfd.model.lowrank.BandedLowRank`, the CSR base patterns) and the modes come
from the sparse shift-invert eigensolver: no dense n x n array.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.linalg as sla
from numpy.typing import NDArray

from rotorsfd.analyses.stability_chart_rates import ChartParams, CoefficientCache
from rotorsfd.model.base_terms import MATRIX_NAMES, keeps_band
from rotorsfd.model.time_terms import linear_part
from rotorsfd.stability.chart import LTPSystem, lowest_modes

if TYPE_CHECKING:
    from rotorsfd.model.system import RotorSystem

__all__ = ["MIN_MODES", "MODE_CUTOFF", "modal_basis", "rotor_ltp_system"]

MODE_CUTOFF: float = 3.0
MIN_MODES: int = 4
_PROBE_T = np.sqrt(2.0) * np.arange(1, 8)[:, None] / 3.7  # irrational sample times [s]


def rotor_ltp_system(system: RotorSystem, params: ChartParams, p1_probe: NDArray,
                     p2_probe: NDArray) -> LTPSystem:
    """The LTPSystem of the linear part of ``system`` under the base rates of ``params``.

    ``M``, ``D = C + Omega G`` and ``K`` (and ``G`` for a speed axis) are the model's
    record of the linear part with the rates off
    (``linear_part(system, rates=0).second_order(Omega)``); the base terms are the 12
    matrices of the system's basis (those the record's time-varying terms are made of)
    with the chart coefficients. Base terms whose coefficient is zero at every probe
    point (``p1_probe`` x ``p2_probe`` x a few times) are dropped; those constant there
    are folded into the constant matrices.
    """
    speed_is_axis = (params.p1 is not None and params.p1[0] < 0) or \
        (params.p2 is not None and params.p2[0] < 0)
    at = 1.0 if speed_is_axis else float(params.speed)
    record = linear_part(system, rates=(0.0, 0.0, 0.0)).second_order(at)
    basis = system.basis
    cache = CoefficientCache(params)
    large = keeps_band(system.n_dof)    # CSR (+ low-rank modal damping), no n x n array
    if large:
        M, const = record.M, [record.D, record.K]
        patterns: Sequence[Any] = basis.sparse_matrices
        G = record.gyroscopic
    else:
        M = np.asarray(record.M, float)
        const = [np.array(record.D, float), np.array(record.K, float)]
        patterns = basis.matrices
        G = np.asarray(record.gyroscopic, float) if speed_is_axis else None
    d_terms: list[tuple[Any, Any]] = []
    k_terms: list[tuple[Any, Any]] = []
    if speed_is_axis:   # D(Omega) = D(1) + (Omega - 1) G
        which = 1 if params.p1 is not None and params.p1[0] < 0 else 2
        d_terms.append((G, (lambda t, a, b: a - at + 0.0 * t) if which == 1 else
                        (lambda t, a, b: b - at + 0.0 * t)))
    probes = [params.coefficients(_PROBE_T, float(a), np.asarray(p2_probe)[None, :])
              for a in np.atleast_1d(p1_probe)]
    for which, terms in enumerate((d_terms, k_terms)):
        values = np.concatenate([p[which].reshape(12, -1) for p in probes], axis=1)
        for i in range(len(MATRIX_NAMES)):
            v = values[i]
            if np.all(v == 0.0):
                continue
            if np.all(v == v[0]):
                const[which] = const[which] + v[0] * patterns[i]
            else:
                terms.append((patterns[i], cache.term(which, i)))
    return LTPSystem(M, [(const[0], None), *d_terms], [(const[1], None), *k_terms],
                     params.period)


def modal_basis(system: LTPSystem, cutoff: float, n_modes: int | None = None) -> NDArray:
    """Lowest undamped modes of (constant K, M): ``n_modes`` of them, or all below
    ``cutoff`` [rad/s] (at least MIN_MODES, degenerate partners kept together). Dense
    ``eigh`` up to ``DENSE_MAX_DOF`` DOFs; above, shift-invert Lanczos
    (:func:`~rotorsfd.stability.chart.lowest_modes`), the count doubled until a mode above
    the cutoff (and not degenerate with the last kept one) is found."""
    if system.is_large:
        return _sparse_modal_basis(system, cutoff, n_modes)
    K0 = system.constant_stiffness()
    K0 = 0.5 * (K0 + K0.T)
    lam, V = sla.eigh(K0, 0.5 * (system.M + system.M.T))
    if n_modes is None:
        n_modes = _kept(np.sqrt(np.abs(lam)), cutoff)
    return V[:, :n_modes]


def _kept(w: NDArray, cutoff: float) -> int:
    """Modes kept of the ascending frequencies ``w``: those below ``cutoff``, at least
    MIN_MODES, and the degenerate partners of the last one."""
    n_modes = max(min(MIN_MODES, w.size), int(np.sum(w < cutoff)))
    while n_modes < w.size and abs(w[n_modes] - w[n_modes - 1]) <= 1e-6 * w[n_modes]:
        n_modes += 1
    return n_modes


def _sparse_modal_basis(system: LTPSystem, cutoff: float, n_modes: int | None) -> NDArray:
    K0 = system.constant_stiffness()
    top = system.n_dof - 2
    k = min(top, n_modes if n_modes is not None else 4 * MIN_MODES)
    while True:
        lam, V = lowest_modes(K0, system.M, k)
        if n_modes is not None:
            return V[:, :n_modes]
        kept = _kept(np.sqrt(np.abs(lam)), cutoff)
        if kept < k or k >= top:   # a mode above the cutoff, not a partner, was found
            return V[:, :kept]
        k = min(top, 2 * k)
