"""Compiled per-harmonic condensation of a banded dynamic stiffness (numba).

For k = 0..H the shifted dynamic stiffness ``Zt_k = K - (kw)^2 M + i kw D + S^T Delta_k S``
(Delta_k diagonal, on the nonlinear DOFs s) is factorised once by a complex banded LU with
partial pivoting (the algorithm of LAPACK ``zgbtf2``: lower and upper bandwidths kl, ku,
fill-in up to kl + ku above the diagonal, pivot = largest ``|re| + |im|``), and the same
factors give

- ``C_k = Zt_k^-1 S^T`` and ``u_k = Zt_k^-1 F_k`` (m + 1 right-hand sides), and
- the exact lam-derivatives of the receptance and of the particular response from
  ``d(Zt^-1) = -Zt^-1 dZ Zt^-1``: the rows s of ``Zt_k^-1 [-dZ_k C_k, dF_k - dZ_k u_k]``
  are ``[dHt_k, dPt_k]``, with ``dZ_k = dK - (kw)^2 dM - 2 k^2 w w' M + i k (w' D + w dD)``.

The matrices come in band storage (:func:`condense_bands`, ``Ab[j, ku + i - j] = A[i, j]``,
the layout of :mod:`rotorsfd.model.sparse`: no n x n array is read) or dense
(:func:`condense_banded` copies their band first). All harmonics in one call, no Python
between them (the LU and the solves run at the speed of LAPACK
``zgbtrf``/``zgbtrs`` on these sizes, without their per-call overhead); the arithmetic is
LAPACK's, so the results agree with it to rounding. Storage of the factors (the transpose
of LAPACK's): ``ab[j, kl + ku + i - j] = A[i, j]``, shape (n, 2 kl + ku + 1);
column j of A is the contiguous row ``ab[j]``, its first kl entries hold the fill-in.
(Running the H+1 factorisations side by side, harmonics as the innermost SIMD axis, was
measured slower on the paper rotor: the loops are too short to vectorise.)

Above ``REFINE_MIN_DOF`` DOFs each ``Zt_k^-1 [S^T, F_k]`` (k >= 1) gets one step of
iterative refinement whose residual has ``K x`` in doubled precision (:func:`_refine`):
on a fine mesh the rounding of ``K - (kw)^2 M`` alone moves the solution by ``cond eps``
near a resonance (1e-5 at 1280 elements, above the Newton tolerance, and jumping with lam).
"""

from __future__ import annotations

import numpy as np
from numba import njit, types
from numba.extending import intrinsic

#: return codes of :func:`condense_banded` (k + 1 > 0: Zt_k is singular)
OK, OUTSIDE_BAND, NOT_FINITE = 0, -1, -2

#: Models above this many DOFs get one step of iterative refinement per harmonic
#: (:func:`_refine`). At 0.999 of the first critical speed of the stepped rotor of
#: ``benchmarks/bench_scale.py`` the unrefined receptances are off by 7.5e-9 (relative) at
#: 324 DOFs, 3.9e-7 at 1284, 3.1e-7 at 5124, and the refined ones by 1e-13; the step costs
#: 40-60 % of a condensation, so the small models (the paper rotor's 84 DOFs) skip it.
REFINE_MIN_DOF = 400


def refinement_steps(n: int) -> int | None:
    """Steps of iterative refinement of :func:`condense_bands` for an n-DOF model; None
    for none (numba then leaves the refinement out of the compiled condensation: a small
    model does not pay its compilation, ``benchmarks/README.md`` "Compiling the kernels")."""
    return 1 if n > REFINE_MIN_DOF else None

@njit(cache=True)
def band_lu(ab: np.ndarray, kl: int, ku: int, ipiv: np.ndarray) -> int:
    """In-place LU with partial pivoting of a band matrix (module docstring for the
    storage; ``ab[j, :kl]`` zero on entry). Returns 0, or j + 1 if the pivot of column j
    is exactly zero (singular)."""
    n = ab.shape[0]
    kv = kl + ku
    ju = 0
    for j in range(n):
        km = min(kl, n - 1 - j)
        jp = 0
        big = abs(ab[j, kv].real) + abs(ab[j, kv].imag)
        for t in range(1, km + 1):
            a = ab[j, kv + t]
            v = abs(a.real) + abs(a.imag)
            if v > big:
                big = v
                jp = t
        ipiv[j] = j + jp
        if big == 0.0:
            return j + 1
        ju = max(ju, min(j + ku + jp, n - 1))
        if jp != 0:
            for c in range(j, ju + 1):
                o = kv + j - c
                tmp = ab[c, o]
                ab[c, o] = ab[c, o + jp]
                ab[c, o + jp] = tmp
        r = 1.0 / ab[j, kv]
        for t in range(1, km + 1):
            ab[j, kv + t] *= r
        for c in range(j + 1, ju + 1):
            o = kv + j - c
            a = ab[c, o]
            if a != 0.0:
                for t in range(1, km + 1):
                    ab[c, o + t] -= ab[j, kv + t] * a
    return 0

@njit(cache=True)
def band_solve(ab: np.ndarray, kl: int, ku: int, ipiv: np.ndarray, b: np.ndarray) -> None:
    """Solve ``A x = b`` in place for the columns of b (n, nrhs) with the factors of
    :func:`band_lu` (LAPACK ``zgbtrs``, no transpose)."""
    n = ab.shape[0]
    kv = kl + ku
    nr = b.shape[1]
    for j in range(n - 1):
        p = ipiv[j]
        if p != j:
            for r in range(nr):
                tmp = b[j, r]
                b[j, r] = b[p, r]
                b[p, r] = tmp
        for t in range(1, min(kl, n - 1 - j) + 1):
            lv = ab[j, kv + t]
            if lv != 0.0:
                for r in range(nr):
                    b[j + t, r] -= lv * b[j, r]
    for j in range(n - 1, -1, -1):
        d = 1.0 / ab[j, kv]
        for r in range(nr):
            b[j, r] *= d
        for i in range(max(0, j - kv), j):
            uv = ab[j, kv + i - j]
            if uv != 0.0:
                for r in range(nr):
                    b[i, r] -= uv * b[j, r]

@njit(cache=True)
def _outside_band(A: np.ndarray, kl: int, ku: int) -> bool:
    n = A.shape[0]
    for i in range(n):
        for j in range(0, max(0, i - kl)):
            if A[i, j] != 0.0:
                return True
        for j in range(min(n, i + ku + 1), n):
            if A[i, j] != 0.0:
                return True
    return False

@njit(cache=True)
def _real_harmonic0(delta: np.ndarray, F: np.ndarray, dF: np.ndarray, deriv: bool) -> bool:
    """Whether harmonic 0 is real (Delta_0, F_0 and, with deriv, dF_0 real)."""
    for a in range(delta.shape[1]):
        if delta[0, a].imag != 0.0:
            return False
    for i in range(F.shape[1]):
        if F[0, i].imag != 0.0 or (deriv and dF[0, i].imag != 0.0):
            return False
    return True


@njit(cache=True)
def _static_harmonic(Mb: np.ndarray, Kb: np.ndarray, dKb: np.ndarray, kl: int, ku: int,
                     s: np.ndarray, delta: np.ndarray, F: np.ndarray, dF: np.ndarray,
                     deriv: bool, sol: np.ndarray, dsol: np.ndarray) -> int:
    """Harmonic 0 of :func:`condense_bands` in real arithmetic (``Zt_0 = K + S^T Delta_0
    S``, ``dZ_0 = dK``; a quarter of the complex work), when it is real."""
    n = Kb.shape[0]
    m = s.shape[0]
    nb = kl + ku + 1
    ab = np.zeros((n, 2 * kl + ku + 1))
    for j in range(n):
        for o in range(nb):
            ab[j, kl + o] = Kb[j, o]
    for a in range(m):
        ab[s[a], kl + ku] += delta[0, a].real
    ipiv = np.empty(n, dtype=np.int64)
    if band_lu(ab, kl, ku, ipiv) != 0:
        return 1
    x = np.zeros((n, m + 1))
    for i in range(n):
        x[i, m] = F[0, i].real
    for a in range(m):
        x[s[a], a] = 1.0
    band_solve(ab, kl, ku, ipiv, x)
    for i in range(n):
        for c in range(m + 1):
            sol[0, i, c] = x[i, c]
    if not deriv:
        return 0
    y = np.zeros((n, m + 1))
    for i in range(n):
        y[i, m] = dF[0, i].real
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            dz = dKb[j, ku + i - j]
            if dz != 0.0:
                for c in range(m + 1):
                    y[i, c] -= dz * x[j, c]
    band_solve(ab, kl, ku, ipiv, y)
    for a in range(m):
        for c in range(m + 1):
            dsol[0, a, c] = y[s[a], c]
    return 0


@njit(cache=True)
def dense_to_band(A: np.ndarray, kl: int, ku: int) -> np.ndarray:
    """Band storage ``Ab[j, ku + i - j] = A[i, j]`` (n, kl + ku + 1) of a dense A (the
    layout of :mod:`rotorsfd.model.sparse`)."""
    n = A.shape[0]
    out = np.zeros((n, kl + ku + 1))
    for j in range(n):
        for i in range(max(0, j - ku), min(n, j + kl + 1)):
            out[j, ku + i - j] = A[i, j]
    return out


@intrinsic
def _fma(typingctx, a, b, c):
    """``a * b + c`` rounded once (LLVM ``llvm.fma.f64``: the FMA instruction, or libm's
    exact fma where the CPU has none)."""
    sig = types.float64(types.float64, types.float64, types.float64)

    def codegen(context, builder, signature, args):
        return builder.fma(*args)
    return sig, codegen


@njit(cache=True)
def _exact_dot_row(Kb: np.ndarray, kl: int, ku: int, i: int, x: np.ndarray, c: int
                   ) -> tuple[float, float]:
    """``sum_j K_ij x_jc`` (row i of band storage K, real column c of x) as an unevaluated
    sum hi + lo, accurate as if computed in twice the working precision (Ogita, Rump and
    Oishi's Dot2, SIAM J. Sci. Comput. 26, 2005: TwoProduct by FMA, Knuth's TwoSum)."""
    n = Kb.shape[0]
    s = 0.0
    comp = 0.0
    for j in range(max(0, i - kl), min(n, i + ku + 1)):
        a = Kb[j, ku + i - j]
        if a == 0.0:
            continue
        b = x[j, c]
        p = a * b
        e = _fma(a, b, -p)
        t = s + p
        bp = t - s
        comp += ((s - (t - bp)) + (p - bp)) + e
        s = t
    return s, comp


@njit(cache=True)
def band_residual(Mb: np.ndarray, Db: np.ndarray, Kb: np.ndarray, kl: int, ku: int,
                  kw: float, kw2: float, s: np.ndarray, delta_k: np.ndarray,
                  F_k: np.ndarray, x: np.ndarray, r: np.ndarray) -> None:
    """``r = [S^T, F_k] - Zt_k x`` (n, m + 1) with the stiffness part ``K x`` in doubled
    precision (Dot2 of :func:`_exact_dot_row`) and the mass, damping and shift terms in
    working precision: the residual of :func:`_refine`.

    The 2 (m + 1) Dot2 sums of a row (real and imaginary part of every column) run side by
    side in one pass over the row's band: each sum sees the same operations in the same
    order as :func:`_exact_dot_row` (the same bits), but the independent chains overlap
    in the CPU instead of waiting on each other's latency."""
    n = Kb.shape[0]
    m = s.shape[0]
    nc = m + 1
    nr = 2 * nc
    xr = np.empty((n, nr))          # columns: Re x_c, Im x_c
    for j in range(n):
        for c in range(nc):
            xr[j, 2 * c] = x[j, c].real
            xr[j, 2 * c + 1] = x[j, c].imag
    hi = np.empty(nr)
    lo = np.empty(nr)
    for i in range(n):
        for q in range(nr):
            hi[q] = 0.0
            lo[q] = 0.0
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            a = Kb[j, ku + i - j]
            if a == 0.0:
                continue
            for q in range(nr):
                b = xr[j, q]
                p = a * b
                e = _fma(a, b, -p)
                sq = hi[q]
                t = sq + p
                bp = t - sq
                lo[q] += ((sq - (t - bp)) + (p - bp)) + e
                hi[q] = t
        for c in range(nc):
            rhs = F_k[i] if c == m else 0.0j
            r[i, c] = complex((rhs.real - hi[2 * c]) - lo[2 * c],
                              (rhs.imag - hi[2 * c + 1]) - lo[2 * c + 1])
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            o = ku + i - j
            e = complex(-kw2 * Mb[j, o], kw * Db[j, o])
            if e != 0.0:
                for c in range(nc):
                    r[i, c] -= e * x[j, c]
    for a in range(m):
        r[s[a], a] += 1.0
        for c in range(nc):
            r[s[a], c] -= delta_k[a] * x[s[a], c]


@njit(cache=True)
def _refine(Mb: np.ndarray, Db: np.ndarray, Kb: np.ndarray, kl: int, ku: int, kw: float,
            kw2: float, s: np.ndarray, delta_k: np.ndarray, F_k: np.ndarray, ab: np.ndarray,
            ipiv: np.ndarray, x: np.ndarray, r: np.ndarray) -> None:
    """One step of iterative refinement of ``x = Zt_k^-1 [S^T, F_k]`` (n, m + 1) in place:
    ``x += LU^-1 ([S^T, F_k] - Zt_k x)``, the residual's ``K x`` in doubled precision
    (:func:`band_residual`).

    Why: on a fine mesh the stiffness entries exceed the stiffness the response sees by
    ``~ (L / l_e)^3``, so rounding ``K - (kw)^2 M + i kw D`` to the working precision
    perturbs Zt_k by ``eps |K|``, and near a resonance the solution moves by ``cond eps``
    (about 1e-5 relative at 1280 elements: more than the Newton tolerance, and it jumps as
    lam crosses rounding boundaries, so Newton stalls). With ``K x`` exact to ``eps |K x|``
    the refined x solves the unrounded system; one step leaves ``(cond eps)^2``
    (Higham, Accuracy and Stability of Numerical Algorithms, 2nd ed., section 12.1).
    ``r`` (n, m + 1) complex is workspace."""
    band_residual(Mb, Db, Kb, kl, ku, kw, kw2, s, delta_k, F_k, x, r)
    band_solve(ab, kl, ku, ipiv, r)
    n, nc = x.shape
    for i in range(n):
        for c in range(nc):
            x[i, c] += r[i, c]


@njit(cache=True)
def harmonic_band_lu(Mb: np.ndarray, Db: np.ndarray, Kb: np.ndarray, kl: int, ku: int,
                     kw: float, s: np.ndarray, delta_k: np.ndarray, ab: np.ndarray,
                     ipiv: np.ndarray) -> int:
    """``Zb_k = K - (kw)^2 M + i kw D + S^T diag(delta_k) S`` into the LU storage ab
    (n, 2 kl + ku + 1) and factored in place; returns :func:`band_lu`'s info."""
    n = Kb.shape[0]
    nb = kl + ku + 1
    kw2 = kw * kw
    for j in range(n):
        for t in range(kl):
            ab[j, t] = 0.0
        for o in range(nb):
            ab[j, kl + o] = complex(Kb[j, o] - kw2 * Mb[j, o], kw * Db[j, o])
    for a in range(s.shape[0]):
        ab[s[a], kl + ku] += delta_k[a]
    return band_lu(ab, kl, ku, ipiv)


@njit(cache=True)
def unit_rhs(s: np.ndarray, F_k: np.ndarray, out: np.ndarray) -> None:
    """The right-hand sides ``[S^T, F_k]`` (n, m + 1) into out."""
    n, m1 = out.shape
    for i in range(n):
        for c in range(m1):
            out[i, c] = 0.0
        out[i, m1 - 1] = F_k[i]
    for a in range(s.shape[0]):
        out[s[a], a] = 1.0


@njit(cache=True)
def derivative_rhs(Mb: np.ndarray, Db: np.ndarray, dMb: np.ndarray, dDb: np.ndarray,
                   dKb: np.ndarray, kl: int, ku: int, k: int, w: float, dw: float,
                   dF_k: np.ndarray, sol_k: np.ndarray, rhs: np.ndarray) -> None:
    """``rhs = [0, dF_k] - dZ_k sol_k`` (n, m + 1) with the banded
    ``dZ_k = dK - (kw)^2 dM - 2 k^2 w w' M + i k (w' D + w dD)``."""
    n, m1 = rhs.shape
    kw2 = (k * w) * (k * w)
    c2 = 2.0 * k * k * w * dw
    for i in range(n):
        for c in range(m1 - 1):
            rhs[i, c] = 0.0
        rhs[i, m1 - 1] = dF_k[i]
    for i in range(n):
        for j in range(max(0, i - kl), min(n, i + ku + 1)):
            o = ku + i - j
            dz = complex(dKb[j, o] - kw2 * dMb[j, o] - c2 * Mb[j, o],
                         k * (dw * Db[j, o] + w * dDb[j, o]))
            if dz != 0.0:
                for c in range(m1):
                    rhs[i, c] -= dz * sol_k[j, c]


@njit(cache=True)
def condense_banded(M: np.ndarray, D: np.ndarray, K: np.ndarray, dM: np.ndarray,
                    dD: np.ndarray, dK: np.ndarray, w: float, dw: float, kl: int, ku: int,
                    s: np.ndarray, delta: np.ndarray, F: np.ndarray, dF: np.ndarray,
                    deriv: bool, check: np.ndarray, sol: np.ndarray, dsol: np.ndarray,
                    Ht: np.ndarray, Pt: np.ndarray, dHt: np.ndarray, dPt: np.ndarray) -> int:
    """:func:`condense_bands` of dense matrices M, D, K, dM, dD, dK (n, n) C-contiguous,
    copied into band storage; ``check`` (6,) bool: which of the six to scan for nonzeros
    outside the band first. Returns OUTSIDE_BAND (-1) if a checked matrix has one
    (nothing computed: widen the band), else what :func:`condense_bands` returns."""
    mats = (M, D, K, dM, dD, dK)
    for i in range(6):
        if check[i] and _outside_band(mats[i], kl, ku):
            return OUTSIDE_BAND
    return condense_bands(dense_to_band(M, kl, ku), dense_to_band(D, kl, ku),
                          dense_to_band(K, kl, ku), dense_to_band(dM, kl, ku),
                          dense_to_band(dD, kl, ku), dense_to_band(dK, kl, ku), w, dw, kl,
                          ku, s, delta, F, dF, deriv, sol, dsol, Ht, Pt, dHt, dPt)


@njit(cache=True)
def condense_bands(Mb: np.ndarray, Db: np.ndarray, Kb: np.ndarray, dMb: np.ndarray,
                   dDb: np.ndarray, dKb: np.ndarray, w: float, dw: float, kl: int, ku: int,
                   s: np.ndarray, delta: np.ndarray, F: np.ndarray, dF: np.ndarray,
                   deriv: bool, sol: np.ndarray, dsol: np.ndarray, Ht: np.ndarray,
                   Pt: np.ndarray, dHt: np.ndarray, dPt: np.ndarray,
                   refine: int | None = None, k_first: int = 0) -> int:
    """Condensation of all harmonics (module docstring) from band storage.

    Inputs: Mb, Db, Kb, dMb, dDb, dKb (n, kl + ku + 1) the band storage
    ``Ab[j, ku + i - j] = A[i, j]`` of M, D, K and their lam-derivatives (no n x n array);
    w, w' = dw/dlam; s (m,) nonlinear DOFs; delta (H+1, m) the diagonal of Delta_k;
    F, dF (H+1, n).
    Outputs: sol (H+1, n, m+1) = ``Zt_k^-1 [S^T, F_k]``; with ``deriv``, dsol (H+1, m, m+1)
    = rows s of ``Zt_k^-1 [-dZ_k C_k, dF_k - dZ_k u_k]``; the same split into the
    receptance Ht (H+1, m, m), particular response Pt (H+1, m) and, with ``deriv``, their
    derivatives dHt, dPt. ``refine``: steps of iterative refinement of sol for k >= 1
    with the residual's stiffness part in doubled precision (:func:`_refine`); None (as
    0) compiles without it.
    ``k_first``: harmonics ``k < k_first`` are taken as already in sol (and dsol), e.g.
    copied from a condensation at fewer harmonics with the same lam and shift, and only
    ``k >= k_first`` are factorised (the same numbers as computing all).
    Returns OK (0); k + 1 if Zt_k is exactly singular; NOT_FINITE (-2) if an output is not
    finite.
    """
    n = Kb.shape[0]
    m = s.shape[0]
    nh = F.shape[0]
    ab = np.zeros((n, 2 * kl + ku + 1), dtype=np.complex128)
    ipiv = np.empty(n, dtype=np.int64)
    rhs = np.empty((n, m + 1), dtype=np.complex128)
    k0 = k_first
    if k0 == 0 and _real_harmonic0(delta, F, dF, deriv):
        status = _static_harmonic(Mb, Kb, dKb, kl, ku, s, delta, F, dF, deriv, sol, dsol)
        if status != 0:
            return status
        k0 = 1
    for k in range(k0, nh):
        kw = k * w
        kw2 = kw * kw
        if harmonic_band_lu(Mb, Db, Kb, kl, ku, kw, s, delta[k], ab, ipiv) != 0:
            return k + 1
        out = sol[k]
        unit_rhs(s, F[k], out)
        band_solve(ab, kl, ku, ipiv, out)
        if refine is not None:
            for _ in range(refine):
                _refine(Mb, Db, Kb, kl, ku, kw, kw2, s, delta[k], F[k], ab, ipiv, out, rhs)
        if not deriv:
            continue
        # right-hand sides [-dZ_k C_k, dF_k - dZ_k u_k] = [0, dF_k] - dZ_k sol_k
        derivative_rhs(Mb, Db, dMb, dDb, dKb, kl, ku, k, w, dw, dF[k], out, rhs)
        band_solve(ab, kl, ku, ipiv, rhs)
        for a in range(m):
            for c in range(m + 1):
                dsol[k, a, c] = rhs[s[a], c]
    return _split(s, deriv, sol, dsol, Ht, Pt, dHt, dPt)


@njit(cache=True)
def _split(s: np.ndarray, deriv: bool, sol: np.ndarray, dsol: np.ndarray, Ht: np.ndarray,
           Pt: np.ndarray, dHt: np.ndarray, dPt: np.ndarray) -> int:
    """Ht, Pt (and dHt, dPt) from the rows s of sol (and dsol); NOT_FINITE or OK."""
    nh, n, m1 = sol.shape
    m = m1 - 1
    for k in range(nh):
        for i in range(n):
            for c in range(m1):
                if not np.isfinite(sol[k, i, c]):
                    return NOT_FINITE
        for a in range(m):
            for c in range(m):
                Ht[k, a, c] = sol[k, s[a], c]
                if deriv:
                    dHt[k, a, c] = dsol[k, a, c]
            Pt[k, a] = sol[k, s[a], m]
            if deriv:
                dPt[k, a] = dsol[k, a, m]
                for c in range(m1):
                    if not np.isfinite(dsol[k, a, c]):
                        return NOT_FINITE
    return OK


#: the building blocks :mod:`rotorsfd.harmonic.banded_lowrank` shares
split_outputs, static_harmonic, real_harmonic0 = _split, _static_harmonic, _real_harmonic0
