"""Compiled AFT of the nonlinear force and assembly of the condensed residual (numba).

The same equations as :func:`rotorsfd.harmonic.residual.nonlinear_coefficients` and
:meth:`rotorsfd.harmonic.condensation.CondensedHB.residual` (see their docstrings), in
loops without temporaries:

- samples ``q_n = E[n] xs``, ``q'_n = Ed[n] xs``, ``v_n = w q'_n``; the force and its
  Jacobian at every sample from a compiled kernel (``docs/INTERFACES.md``:
  ``kernel(q, v, params, F, dFdq, dFdv) -> int``) or given;
- ``G = P f``, ``dG[a,i,b,j] = sum_n P[a,n] (dfq[n,i,j] E[n,b] + w dfv[n,i,j] Ed[n,b])``,
  ``dG/dw = P (dfv . q')``;
- ``R_k = Xs_k - Pt_k - Ht_k Gt_k``, ``Gt_k = G_k + Delta_k Xs_k``,
  ``dR/dxs = I - Ht (dG + Delta)`` (real layout), ``dR/dlam = -(dPt + dHt Gt + w' Ht dG/dw)``.

Real layout (:mod:`rotorsfd.harmonic.fourier`): row 0 is harmonic 0, rows 2k-1 and 2k the
real and imaginary parts of harmonic k. The kernel is passed as a first-class function
(:func:`as_kernel_cfunc`), so one compiled loop serves every force law and is cached.
"""

from __future__ import annotations

from typing import Any

import numpy as np
from numba import njit
from numba.core.ccallback import CFunc
from numba.core.types.function_type import WrapperAddressProtocol

from rotorsfd.harmonic.aft_jacobian import force_jacobian_coefficients
from rotorsfd.kernels import KERNEL_SIGNATURE, KERNEL_TYPE, as_cfunc


class KernelRef(WrapperAddressProtocol):
    """A compiled kernel as a first-class function argument of the loops below, with its
    numba type attached: passing a bare ``cfunc`` makes every call re-derive the type
    (about 10 us per call); this costs about 3 us. A subclass for another kernel
    signature sets ``_numba_type_``, ``kernel_signature`` and ``compile`` (e.g.
    :class:`rotorsfd.harmonic.aft_inertia.InertialKernelRef`)."""

    _numba_type_ = KERNEL_TYPE
    kernel_signature = KERNEL_SIGNATURE
    compile = staticmethod(as_cfunc)

    def __init__(self, compiled: CFunc) -> None:
        self.compiled = compiled
        self._address = compiled.address

    def __wrapper_address__(self) -> int:
        return self._address

    def signature(self) -> Any:
        return self.kernel_signature

    @classmethod
    def of(cls, kernel: Any) -> Any:
        """The memoised reference of this class to ``kernel`` (compiled on first use)."""
        refs = _REFS.setdefault(cls, {})
        cached = refs.get(kernel)
        if cached is None:
            cached = refs[kernel] = cls(cls.compile(kernel))
        return cached


_REFS: dict[type, dict[Any, KernelRef]] = {}


def as_kernel_cfunc(kernel: Any) -> KernelRef:
    """First-class compiled version of a force kernel (an ``@njit`` dispatcher, a plain
    function with the kernel signature, or a ``cfunc``); memoised per kernel."""
    return KernelRef.of(kernel)


@njit(cache=True)
def sample_states(xs: np.ndarray, w: float, E: np.ndarray, Ed: np.ndarray,
                  q: np.ndarray, dq: np.ndarray, v: np.ndarray) -> None:
    """``q = E xs``, ``dq = Ed xs`` (d/dtau), ``v = w dq``; each (N, m)."""
    N, nh = E.shape
    m = xs.shape[1]
    for n in range(N):
        for i in range(m):
            a = 0.0
            b = 0.0
            for h in range(nh):
                a += E[n, h] * xs[h, i]
                b += Ed[n, h] * xs[h, i]
            q[n, i] = a
            dq[n, i] = b
            v[n, i] = w * b


@njit(cache=True)
def force_samples(kernel: Any, params: np.ndarray, q: np.ndarray, v: np.ndarray,
                  f: np.ndarray, dfq: np.ndarray, dfv: np.ndarray) -> int:
    """The kernel at every sample; returns 0, or n + 1 for the first sample it rejects."""
    for n in range(q.shape[0]):
        if kernel(q[n], v[n], params, f[n], dfq[n], dfv[n]) != 0:
            return n + 1
    return 0


@njit(cache=True)
def project_forces(P: np.ndarray, f: np.ndarray, G: np.ndarray) -> bool:
    """``G = P f`` (nh, m) from the force samples f (N, m); False if G is not finite."""
    nh, N = P.shape
    m = f.shape[1]
    G[:] = 0.0
    for n in range(N):
        for a in range(nh):
            pa = P[a, n]
            for i in range(m):
                G[a, i] += pa * f[n, i]
    for a in range(nh):
        for i in range(m):
            if not np.isfinite(G[a, i]):
                return False
    return True


@njit(cache=True)
def project(P: np.ndarray, E: np.ndarray, Ed: np.ndarray, w: float, f: np.ndarray,
            dfq: np.ndarray, dfv: np.ndarray, dq: np.ndarray, jac: bool, G: np.ndarray,
            dG: np.ndarray, dGdw: np.ndarray) -> bool:
    """G (nh, m), and with jac dG (nh, m, nh, m) and dG/dw (nh, m), from the samples
    (module docstring; dG from the samples' spectrum,
    :func:`~rotorsfd.harmonic.aft_jacobian.force_jacobian_coefficients`, for the P, E, Ed
    of ``aft_matrices``). Returns False if G is not finite."""
    if not project_forces(P, f, G):
        return False
    if not jac:
        return True
    nh, N = P.shape
    m = f.shape[1]
    dGdw[:] = 0.0
    for n in range(N):
        for i in range(m):
            acc = 0.0
            for j in range(m):
                acc += dfv[n, i, j] * dq[n, j]
            for a in range(nh):
                dGdw[a, i] += P[a, n] * acc
    force_jacobian_coefficients(dfq, dfv, w, nh, dG)
    return True


@njit(cache=True)
def condensed_assembly(xs: np.ndarray, G: np.ndarray, dG: np.ndarray, dGdw: np.ndarray,
                       delta: np.ndarray, delta_real: np.ndarray, Ht: np.ndarray,
                       Pt: np.ndarray, dHt: np.ndarray, dPt: np.ndarray, dw: float,
                       jac: bool, R: np.ndarray, J: np.ndarray, dR: np.ndarray) -> None:
    """Condensed residual R (nh, m) and, with jac, J (nh m, nh m) and dR (nh, m)
    (module docstring); dG as (nh m, nh m); delta (H+1, m, m) complex, delta_real its
    real-layout matrix."""
    nh, m = xs.shape
    H = (nh - 1) // 2
    nu = nh * m
    Gt = np.empty(m, dtype=np.complex128)
    for k in range(H + 1):
        re = 0 if k == 0 else 2 * k - 1
        for i in range(m):
            xg = complex(G[re, i], 0.0 if k == 0 else G[re + 1, i])
            for j in range(m):
                xj = complex(xs[re, j], 0.0 if k == 0 else xs[re + 1, j])
                xg += delta[k, i, j] * xj
            Gt[i] = xg
        for i in range(m):
            r = -Pt[k, i]
            for j in range(m):
                r -= Ht[k, i, j] * Gt[j]
            R[re, i] = xs[re, i] + r.real
            if k > 0:
                R[re + 1, i] = xs[re + 1, i] + r.imag
        if not jac:
            continue
        for i in range(m):
            d = dPt[k, i]
            for j in range(m):
                d += dHt[k, i, j] * Gt[j]
                d += dw * Ht[k, i, j] * complex(dGdw[re, j], 0.0 if k == 0 else dGdw[re + 1, j])
            dR[re, i] = -d.real
            if k > 0:
                dR[re + 1, i] = -d.imag
        # rows of harmonic k: J = I - [Re H, -Im H; Im H, Re H] (dG + Delta)
        for i in range(m):
            r1 = re * m + i
            r2 = r1 + m
            for c in range(nu):
                a1 = 0.0
                a2 = 0.0
                for l in range(m):
                    h = Ht[k, i, l]
                    g1 = dG[re * m + l, c] + delta_real[re * m + l, c]
                    if k == 0:
                        a1 += h.real * g1
                    else:
                        g2 = dG[(re + 1) * m + l, c] + delta_real[(re + 1) * m + l, c]
                        a1 += h.real * g1 - h.imag * g2
                        a2 += h.imag * g1 + h.real * g2
                J[r1, c] = -a1
                if k > 0:
                    J[r2, c] = -a2
    if jac:
        for c in range(nu):
            J[c, c] += 1.0


@njit(cache=True)
def condensed_residual(kernel: Any, params: np.ndarray, xs: np.ndarray, w: float,
                       dw: float, E: np.ndarray, Ed: np.ndarray, P: np.ndarray,
                       delta: np.ndarray, delta_real: np.ndarray, Ht: np.ndarray,
                       Pt: np.ndarray, dHt: np.ndarray, dPt: np.ndarray, jac: bool,
                       q: np.ndarray, dq: np.ndarray, v: np.ndarray, f: np.ndarray,
                       dfq: np.ndarray, dfv: np.ndarray, G: np.ndarray, dG: np.ndarray,
                       dGdw: np.ndarray, R: np.ndarray, J: np.ndarray, dR: np.ndarray) -> int:
    """Samples, kernel, projection and assembly in one call (the arrays after ``jac`` are
    outputs and work space). Returns 0; n + 1 if the kernel rejected sample n (contact:
    q[n], v[n] hold the state); -1 if G is not finite."""
    sample_states(xs, w, E, Ed, q, dq, v)
    bad = force_samples(kernel, params, q, v, f, dfq, dfv)
    if bad:
        return bad
    if not project(P, E, Ed, w, f, dfq, dfv, dq, jac, G, dG, dGdw):
        return -1
    nu = G.size
    condensed_assembly(xs, G, dG.reshape(nu, nu), dGdw, delta, delta_real, Ht, Pt, dHt,
                       dPt, dw, jac, R, J, dR)
    return 0


@njit(cache=True)
def force_coefficients(kernel: Any, params: np.ndarray, xs: np.ndarray, w: float,
                       E: np.ndarray, Ed: np.ndarray, P: np.ndarray, q: np.ndarray,
                       dq: np.ndarray, v: np.ndarray, f: np.ndarray, dfq: np.ndarray,
                       dfv: np.ndarray, G: np.ndarray) -> int:
    """``G = P F(E xs, w Ed xs)`` alone (e.g. with 2N samples for the aliasing test).
    Returns like :func:`condensed_residual`."""
    sample_states(xs, w, E, Ed, q, dq, v)
    bad = force_samples(kernel, params, q, v, f, dfq, dfv)
    if bad:
        return bad
    if not project_forces(P, f, G):     # project() without the Jacobian
        return -1
    return 0
