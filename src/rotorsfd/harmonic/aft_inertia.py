"""Compiled AFT of a force that depends on the acceleration too (a film's fluid inertia).

The loops of :mod:`rotorsfd.harmonic.aft_kernels` with the acceleration samples: with
``E`` the sampling matrix, the second derivative in ``tau = w t`` of harmonic ``k``'s
columns is ``-k^2`` times them, so::

    a_n = w^2 Edd[n] xs,   Edd[n, b] = -k_b^2 E[n, b]

(``v`` scales with ``k w``, ``a`` with ``-(k w)^2``). The force ``F(q_n, v_n, a_n)`` of the
inertial kernel (``kernel(q, v, a, params, F, dFdq, dFdv, dFda) -> int``,
:mod:`rotorsfd.kernels`) gives::

    dG[a,i,b,j] = sum_n P[a,n] (dfq E[n,b] + w dfv Ed[n,b] + w^2 dfa Edd[n,b])[i,j]
    dG/dw       = P (dfv . q'_tau + 2 w dfa . q''_tau)

and the condensed assembly is unchanged (the force acts on, and depends on, the nonlinear
DOFs only).
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import njit

from rotorsfd.harmonic.aft_kernels import (
    KernelRef,
    as_kernel_cfunc,
    condensed_assembly,
    project_forces,
)
from rotorsfd.harmonic.aft_kernels import condensed_residual as plain_condensed_residual
from rotorsfd.harmonic.aft_kernels import force_coefficients as plain_force_coefficients
from rotorsfd.kernels import INERTIAL_SIGNATURE, INERTIAL_TYPE, as_inertial_cfunc

__all__ = ["InertialKernelRef", "as_inertial_kernel_ref", "condensed_residual",
           "condensed_residual_inertial", "force_coefficients", "force_coefficients_inertial",
           "hb_kernel"]


class InertialKernelRef(KernelRef):
    """A compiled inertial kernel as a first-class function argument of the loops below
    (its numba type attached, as :class:`rotorsfd.harmonic.aft_kernels.KernelRef`)."""

    _numba_type_ = INERTIAL_TYPE
    kernel_signature = INERTIAL_SIGNATURE
    compile = staticmethod(as_inertial_cfunc)


def as_inertial_kernel_ref(kernel: Any) -> InertialKernelRef:
    """First-class compiled version of an inertial kernel; memoised per kernel."""
    return InertialKernelRef.of(kernel)


@njit(cache=True)
def _harmonic_squares(nh: int) -> np.ndarray:
    """``k_b^2`` of the real-layout columns ``[0, 1, 1, 2, 2, ...]``."""
    k2 = np.empty(nh)
    for b in range(nh):
        k = (b + 1) // 2
        k2[b] = k * k
    return k2


@njit(cache=True)
def sample_states_inertial(xs: np.ndarray, w: float, E: np.ndarray, Ed: np.ndarray,
                           q: np.ndarray, dq: np.ndarray, v: np.ndarray, ddq: np.ndarray,
                           acc: np.ndarray) -> None:
    """``q = E xs``, ``dq = Ed xs``, ``v = w dq``, ``ddq = Edd xs``, ``acc = w^2 ddq``."""
    N, nh = E.shape
    m = xs.shape[1]
    k2 = _harmonic_squares(nh)
    for n in range(N):
        for i in range(m):
            a = 0.0
            b = 0.0
            c = 0.0
            for h in range(nh):
                x = xs[h, i]
                a += E[n, h] * x
                b += Ed[n, h] * x
                c -= k2[h] * E[n, h] * x
            q[n, i] = a
            dq[n, i] = b
            v[n, i] = w * b
            ddq[n, i] = c
            acc[n, i] = w * w * c


@njit(cache=True)
def force_samples_inertial(kernel: Any, params: np.ndarray, q: np.ndarray, v: np.ndarray,
                           acc: np.ndarray, f: np.ndarray, dfq: np.ndarray, dfv: np.ndarray,
                           dfa: np.ndarray) -> int:
    """The inertial kernel at every sample; 0, or n + 1 for the first it rejects."""
    for n in range(q.shape[0]):
        if kernel(q[n], v[n], acc[n], params, f[n], dfq[n], dfv[n], dfa[n]) != 0:
            return n + 1
    return 0


@njit(cache=True)
def project_inertial(P: np.ndarray, E: np.ndarray, Ed: np.ndarray, w: float,
                     f: np.ndarray, dfq: np.ndarray, dfv: np.ndarray, dfa: np.ndarray,
                     dq: np.ndarray, ddq: np.ndarray, jac: bool, G: np.ndarray,
                     dG: np.ndarray, dGdw: np.ndarray) -> bool:
    """G, and with jac dG, dG/dw with the acceleration terms (module doc). False if G
    is not finite."""
    if not project_forces(P, f, G):
        return False
    if not jac:
        return True
    nh, N = P.shape
    m = f.shape[1]
    k2 = _harmonic_squares(nh)
    dG[:] = 0.0
    dGdw[:] = 0.0
    T = np.empty((m, nh, m))
    g = np.empty(m)
    w2 = w * w
    for n in range(N):
        for i in range(m):
            acc = 0.0
            for j in range(m):
                acc += dfv[n, i, j] * dq[n, j] + 2.0 * w * dfa[n, i, j] * ddq[n, j]
            g[i] = acc
            for b in range(nh):
                e = E[n, b]
                ed = w * Ed[n, b]
                edd = -w2 * k2[b] * e
                for j in range(m):
                    T[i, b, j] = dfq[n, i, j] * e + dfv[n, i, j] * ed + dfa[n, i, j] * edd
        for a in range(nh):
            pa = P[a, n]
            if pa == 0.0:
                continue
            for i in range(m):
                dGdw[a, i] += pa * g[i]
                for b in range(nh):
                    for j in range(m):
                        dG[a, i, b, j] += pa * T[i, b, j]
    return True


@njit(cache=True)
def sampled_forces_inertial(kernel: Any, params: np.ndarray, xs: np.ndarray, w: float,
                            E: np.ndarray, Ed: np.ndarray, q: np.ndarray, dq: np.ndarray,
                            v: np.ndarray, f: np.ndarray, dfq: np.ndarray,
                            dfv: np.ndarray) -> tuple[int, np.ndarray, np.ndarray]:
    """The states at the samples and the inertial kernel at each (into q, dq, v, f, dfq,
    dfv); returns (like :func:`force_samples_inertial`, ``Edd xs``, ``dF/da``), the last
    two allocated here."""
    N, m = q.shape
    ddq = np.empty((N, m))
    acc = np.empty((N, m))
    dfa = np.empty((N, m, m))
    sample_states_inertial(xs, w, E, Ed, q, dq, v, ddq, acc)
    bad = force_samples_inertial(kernel, params, q, v, acc, f, dfq, dfv, dfa)
    return bad, ddq, dfa


@njit(cache=True)
def condensed_residual_inertial(kernel: Any, params: np.ndarray, xs: np.ndarray, w: float,
                                dw: float, E: np.ndarray, Ed: np.ndarray, P: np.ndarray,
                                delta: np.ndarray, delta_real: np.ndarray, Ht: np.ndarray,
                                Pt: np.ndarray, dHt: np.ndarray, dPt: np.ndarray, jac: bool,
                                q: np.ndarray, dq: np.ndarray, v: np.ndarray, f: np.ndarray,
                                dfq: np.ndarray, dfv: np.ndarray, G: np.ndarray,
                                dG: np.ndarray, dGdw: np.ndarray, R: np.ndarray,
                                J: np.ndarray, dR: np.ndarray) -> int:
    """:func:`rotorsfd.harmonic.aft_kernels.condensed_residual` of an inertial kernel
    (the same arguments and returns; the acceleration work arrays allocated here)."""
    bad, ddq, dfa = sampled_forces_inertial(kernel, params, xs, w, E, Ed, q, dq, v, f,
                                            dfq, dfv)
    if bad:
        return bad
    if not project_inertial(P, E, Ed, w, f, dfq, dfv, dfa, dq, ddq, jac, G, dG, dGdw):
        return -1
    nu = G.size
    condensed_assembly(xs, G, dG.reshape(nu, nu), dGdw, delta, delta_real, Ht, Pt, dHt,
                       dPt, dw, jac, R, J, dR)
    return 0


@njit(cache=True)
def force_coefficients_inertial(kernel: Any, params: np.ndarray, xs: np.ndarray, w: float,
                                E: np.ndarray, Ed: np.ndarray, P: np.ndarray, q: np.ndarray,
                                dq: np.ndarray, v: np.ndarray, f: np.ndarray,
                                dfq: np.ndarray, dfv: np.ndarray, G: np.ndarray) -> int:
    """``G = P F(E xs, w Ed xs, w^2 Edd xs)`` alone; returns like
    :func:`condensed_residual_inertial`."""
    bad, ddq, dfa = sampled_forces_inertial(kernel, params, xs, w, E, Ed, q, dq, v, f,
                                            dfq, dfv)
    if bad:
        return bad
    if not project_inertial(P, E, Ed, w, f, dfq, dfv, dfa, dq, ddq, False, G,
                            np.empty((0, 0, 0, 0)), G):
        return -1
    return 0


# ---- what the condensed HB calls: the plain or the inertial loop, by the law's kernel ----
def hb_kernel(problem: Any) -> KernelRef | InertialKernelRef | None:
    """The first-class kernel of a periodic problem's force law: its inertial kernel when
    the law has one (``problem.nl_inertial_kernel``), else its kernel (None without)."""
    inertial = getattr(problem, "nl_inertial_kernel", None)
    if inertial is not None:
        return as_inertial_kernel_ref(inertial)
    return as_kernel_cfunc(problem.nl_kernel) if problem.nl_kernel is not None else None


def condensed_residual(kernel: Any, *args: Any) -> int:
    """:func:`rotorsfd.harmonic.aft_kernels.condensed_residual`, or its inertial form
    for an :class:`InertialKernelRef` (the same arguments)."""
    if isinstance(kernel, InertialKernelRef):
        return condensed_residual_inertial(kernel, *args)
    return plain_condensed_residual(kernel, *args)


def force_coefficients(kernel: Any, *args: Any) -> int:
    """:func:`rotorsfd.harmonic.aft_kernels.force_coefficients`, or its inertial form."""
    if isinstance(kernel, InertialKernelRef):
        return force_coefficients_inertial(kernel, *args)
    return plain_force_coefficients(kernel, *args)
