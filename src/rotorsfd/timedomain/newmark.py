"""Compiled Newmark / generalized-alpha stepping with condensed Newton on the nonlinear DOFs.

System: ``M q'' + D(t) q' + K(t) q = g(t, q, q')`` with
``g = f(t) + F_nl(q[nl], q'[nl]) - sum d_i(t) D_i q' - sum k_i(t) K_i q``
(time-varying parts of the matrices moved to the right-hand side, ``forcing.py``).

Generalized-alpha (Chung & Hulbert 1993), force-averaged::

    (1-am) M a1 + am M a0 + (1-af)(D v1 + K q1) + af (D v0 + K q0) = (1-af) g1 + af g0
    q1 = q0 + h v0 + h^2 ((1/2-b) a0 + b a1),   v1 = v0 + h ((1-c) a0 + c a1)

which is linear in the increment ``d = q1 - q0`` apart from ``g1``::

    K_eff d = [-K Cv Ca] [q0; v0; a0] + (1-af) g1 + af g0
    K_eff = (1-am) M/(b h^2) + (1-af) (c/(b h) D + K)

HHT-alpha is ``am = 0``. Newmark average acceleration (``b = 1/4, c = 1/2``) is the
trapezoidal rule; written on the state ``(q, v)`` only (two matrix-vector products a step)::

    (4/h^2 M + 2/h D + K) d = g0 + g1 + 4/h M v0 - 2 K q0,   v1 = 2 d/h - v0

Both read ``d = A x0 + wn1 Kinv g1 + wn Kinv g0`` and ``v1 = vhat + cv d`` (the increment
form keeps the velocity free of the cancellation in ``cv (q1 - q0)``). ``A``,
``Kinv f_j`` and ``Kinv D_i``, ``Kinv K_i`` are formed once per run (one LU). With
``B = Kinv[:, nl]``, ``S = Kinv[nl, nl]`` the nonlinear DOFs solve the exact condensed
m-dimensional equation ``y = dl[nl] + wn1 S F(q0[nl] + y, vhat[nl] + cv y)`` by Newton,
then ``d = dl + wn1 B F``. A force of the acceleration too (a film's fluid inertia,
an inertial kernel) is evaluated at the scheme's ``a1 = ahat + y/(b h^2)`` and its
``dF/da/(b h^2)`` joins the Newton matrix (an added mass on the nonlinear DOFs).
Time-varying matrices add ``Kinv g_tv(q1, v1)`` to ``dl``, found by fixed-point iteration
(each pass: one product with each ``Kinv D_i``, ``Kinv K_i``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
import scipy.linalg
from numba import njit

NEWMARK, GENERALIZED_ALPHA = 0, 1

#: Status codes of the compiled loop.
OK, CONTACT, NEWTON_FAILED, TV_FAILED, NOT_FINITE = 0, 1, 2, 3, 4

# info array layout (int64) of the compiled loop
I_STATUS, I_STEP, I_NREC, I_NPC, I_NEWTON_TOTAL, I_NEWTON_MAX, I_TV_MAX, I_CONTACTS = range(8)
N_INFO = 8

_FASTMATH = {"reassoc", "contract"}  # vectorised reductions; keeps NaN/inf semantics


@dataclass(frozen=True)
class Scheme:
    """Time-integration scheme: ``kind`` (NEWMARK, GENERALIZED_ALPHA) and its
    parameters ``alpha_m, alpha_f, beta, gamma``."""

    kind: int
    alpha_m: float = 0.0
    alpha_f: float = 0.0
    beta: float = 0.25
    gamma: float = 0.5

    @classmethod
    def from_method(cls, method: str, alpha: float = 0.05, rho_inf: float = 0.9) -> Scheme:
        """``"newmark"`` (average acceleration), ``"hht"`` (``alpha`` in ``[0, 1/3]``:
        ``af = alpha, am = 0, c = 1/2 + alpha, b = (1 + alpha)^2/4``) or
        ``"generalized-alpha"`` (spectral radius at infinity ``rho_inf`` in ``[0, 1]``:
        ``am = (2 rho - 1)/(rho + 1), af = rho/(rho + 1), c = 1/2 - am + af,
        b = (1 - am + af)^2/4``)."""
        if method == "newmark":
            return cls(NEWMARK)
        if method == "hht":
            if not 0.0 <= alpha <= 1.0 / 3.0:
                raise ValueError(f"hht alpha must be in [0, 1/3], got {alpha}")
            return cls(GENERALIZED_ALPHA, 0.0, alpha, 0.25 * (1 + alpha) ** 2, 0.5 + alpha)
        if method in ("generalized-alpha", "genalpha"):
            if not 0.0 <= rho_inf <= 1.0:
                raise ValueError(f"rho_inf must be in [0, 1], got {rho_inf}")
            am = (2.0 * rho_inf - 1.0) / (rho_inf + 1.0)
            af = rho_inf / (rho_inf + 1.0)
            return cls(GENERALIZED_ALPHA, am, af, 0.25 * (1.0 - am + af) ** 2, 0.5 - am + af)
        raise ValueError(f"method must be 'newmark', 'hht' or 'generalized-alpha', "
                         f"got {method!r}")


@dataclass(frozen=True)
class Operators:
    """Per-run constant arrays of the compiled loop (see the module docstring)."""

    scheme: Scheme
    dt: float
    A: np.ndarray          # (n, 2n) or (n, 3n)
    B: np.ndarray          # (n, m) Kinv[:, nl]
    S: np.ndarray          # (m, m) Kinv[nl, nl]
    nl: np.ndarray         # (m,) int64
    coef: np.ndarray       # [h, wn1, wn, cv, c0, gamma h, beta, gamma]
    lu: tuple              # LU factors of K_eff (scipy)

    @property
    def n_dof(self) -> int:
        return self.A.shape[0]

    def solve(self, rhs: np.ndarray) -> np.ndarray:
        """``K_eff^-1 rhs`` (columns)."""
        return scipy.linalg.lu_solve(self.lu, rhs)


def build_operators(M: np.ndarray, D: np.ndarray, K: np.ndarray, nl_dofs: np.ndarray,
                    dt: float, scheme: Scheme) -> Operators:
    """Factorise ``K_eff`` once and form ``A``, ``B``, ``S`` (module docstring)."""
    n = M.shape[0]
    h = float(dt)
    nl = np.array(nl_dofs, dtype=np.int64).reshape(-1)
    if scheme.kind == NEWMARK:
        k_eff = 4.0 / h**2 * M + 2.0 / h * D + K
        blocks = [-2.0 * K, 4.0 / h * M]
        wn1, wn, cv = 1.0, 1.0, 2.0 / h
        c0 = 4.0 / h**2
    else:
        am, af, b, c = scheme.alpha_m, scheme.alpha_f, scheme.beta, scheme.gamma
        c0 = 1.0 / (b * h * h)
        c1 = c / (b * h)
        k_eff = (1.0 - am) * c0 * M + (1.0 - af) * (c1 * D + K)
        blocks = [
            -K,
            (1.0 - am) * c0 * h * M + ((1.0 - af) * c1 * h - 1.0) * D,
            ((1.0 - am) * c0 * h * h * (0.5 - b) - am) * M
            + (1.0 - af) * (c1 * h * h * (0.5 - b) - h * (1.0 - c)) * D,
        ]
        wn1, wn, cv = 1.0 - af, af, c1
    lu = scipy.linalg.lu_factor(k_eff, check_finite=True)
    A = scipy.linalg.lu_solve(lu, np.hstack(blocks))
    eye_nl = np.zeros((n, nl.size))
    eye_nl[nl, np.arange(nl.size)] = 1.0
    B = scipy.linalg.lu_solve(lu, eye_nl)
    coef = np.array([h, wn1, wn, cv, c0, scheme.gamma * h, scheme.beta, scheme.gamma])
    return Operators(scheme, h, np.ascontiguousarray(A), np.ascontiguousarray(B),
                     np.ascontiguousarray(B[nl, :]), nl, coef, lu)


@njit(cache=True)
def eval_kernel(kernel, params, y, vy, F, dq, dv) -> int:
    """Call a first-class kernel once (for initial forces)."""
    return kernel(y, vy, params, F, dq, dv)


@njit(cache=True)
def eval_inertial_kernel(kernel_a, params, y, vy, ay, F, dq, dv, da) -> int:
    """Call a first-class inertial kernel once (for initial forces)."""
    return kernel_a(y, vy, ay, params, F, dq, dv, da)


@njit(cache=True)
def _solve_small(J: np.ndarray, r: np.ndarray, x: np.ndarray) -> bool:
    """``x = J^-1 r`` by Gauss elimination with partial pivoting (J, r overwritten)."""
    m = r.shape[0]
    for k in range(m):
        p = k
        big = abs(J[k, k])
        for i in range(k + 1, m):
            if abs(J[i, k]) > big:
                big = abs(J[i, k])
                p = i
        if big == 0.0 or not np.isfinite(big):
            return False
        if p != k:
            for j in range(m):
                J[k, j], J[p, j] = J[p, j], J[k, j]
            r[k], r[p] = r[p], r[k]
        for i in range(k + 1, m):
            f = J[i, k] / J[k, k]
            for j in range(k, m):
                J[i, j] -= f * J[k, j]
            r[i] -= f * r[k]
    for k in range(m - 1, -1, -1):
        s = r[k]
        for j in range(k + 1, m):
            s -= J[k, j] * x[j]
        x[k] = s / J[k, k]
    return True


@njit(cache=True, fastmath=_FASTMATH)
def _newton_nl(kernel, params, q0, dl, vhat, cv, wn1, S, nl, y, yprev, qy, F, dq, dv,
               J, r, dy, vy, rtol, atol, max_newton, kernel_a, inertial, ahat, c0, ay, da):
    """Solve ``y = dl[nl] + wn1 S F(q0[nl] + y, vhat[nl] + cv y)`` for the increment ``y``
    of the nonlinear DOFs by Newton from the given ``y``. With ``inertial`` the force is
    ``F(q, v, a)`` of the inertial kernel ``kernel_a`` at the scheme's acceleration
    ``a = ahat + c0 y`` (``c0 = 1/(beta h^2)``), and the Newton matrix gains the added
    mass ``c0 dF/da``: ``J = I - wn1 S (dF/dq + cv dF/dv + c0 dF/da)``.

    Converged when ``|residual|_inf <= rtol s + atol`` (``s = max(|y|, |dl[nl]|)``), or
    when a Newton update is ``<= sqrt(rtol) s + atol``: by quadratic convergence the
    residual after it is ``O(rtol)``, so ``y`` takes the update and ``F`` its linear
    change ``(dFdq + cv dFdv) dy`` without another kernel call. Returns
    ``(status, iterations, touched_contact)``. A trial point in contact is pulled back
    halfway towards the last valid point (``yprev``).
    """
    m = nl.shape[0]
    touched = False
    for it in range(max_newton):
        for a in range(m):
            qy[a] = q0[nl[a]] + y[a]
            vy[a] = vhat[nl[a]] + cv * y[a]
            if inertial:
                ay[a] = ahat[a] + c0 * y[a]
        if inertial:
            st = kernel_a(qy, vy, ay, params, F, dq, dv, da)
        else:
            st = kernel(qy, vy, params, F, dq, dv)
        n_back = 0
        while st != 0 and n_back < 40:
            touched = True
            for a in range(m):
                y[a] = yprev[a] + 0.5 * (y[a] - yprev[a])
                qy[a] = q0[nl[a]] + y[a]
                vy[a] = vhat[nl[a]] + cv * y[a]
                if inertial:
                    ay[a] = ahat[a] + c0 * y[a]
            if inertial:
                st = kernel_a(qy, vy, ay, params, F, dq, dv, da)
            else:
                st = kernel(qy, vy, params, F, dq, dv)
            n_back += 1
        if st != 0:
            return 1, it + 1, touched
        rn = 0.0
        scale = 0.0
        for a in range(m):
            s = y[a] - dl[nl[a]]
            for b in range(m):
                s -= wn1 * S[a, b] * F[b]
            r[a] = -s
            rn = max(rn, abs(s))
            scale = max(scale, abs(y[a]), abs(dl[nl[a]]))
        if not np.isfinite(rn):
            return 4, it + 1, touched
        if rn <= rtol * scale + atol:
            return 0, it + 1, touched
        for a in range(m):
            for b in range(m):
                s = 0.0
                for c in range(m):
                    s += S[a, c] * (dq[c, b] + cv * dv[c, b])
                    if inertial:
                        s += S[a, c] * c0 * da[c, b]
                J[a, b] = -wn1 * s
            J[a, a] += 1.0
        if not _solve_small(J, r, dy):
            return 2, it + 1, touched
        step = 0.0
        for a in range(m):
            step = max(step, abs(dy[a]))
            yprev[a] = y[a]
            y[a] += dy[a]
        if step <= math.sqrt(rtol) * scale + atol:
            for a in range(m):
                s = 0.0
                for b in range(m):
                    s += (dq[a, b] + cv * dv[a, b]) * dy[b]
                    if inertial:
                        s += c0 * da[a, b] * dy[b]
                F[a] += s
            return 0, it + 1, touched
    return (1 if touched else 2), max_newton, touched


@njit(cache=True, fastmath=_FASTMATH)
def run_steps(kernel, params, kind, coef, A, B, S, nl,
              omega, t0, KF0, hmult, KFc, KFs, scoef, KFj, tvcoef, tvkind, PX,
              X, Fn, Gn, Tn, step0, n_steps,
              rec_dofs, rec_every, rec_start, rec_t, rec_q, rec_v,
              pc_every, pc_start, pc_t, pc_q, pc_v,
              rtol, atol, max_newton, tv_rtol, max_tv, info, fail_state,
              kernel_a, inertial, Anl):
    """Advance ``X = [q; v(; a)]`` by ``n_steps`` from global step ``step0``.

    With ``inertial`` the force is the inertial kernel's ``F(q, v, a)`` (``kernel_a``,
    :mod:`rotorsfd.kernels`) at the scheme's acceleration of the nonlinear DOFs,
    ``a1 = ahat + c0 y``: generalized-alpha ``ahat = -c0 (h v0 + h^2 (1/2 - b) a0)``,
    Newmark ``ahat = -(4/h) v0 - a0`` with ``a0`` the nonlinear DOFs' acceleration carried
    in ``Anl`` (m), updated in place.

    ``Fn`` (m), ``Gn = Kinv g_n`` (n), ``Tn = Kinv g_tv,n`` (n) carry the force terms of
    the current step and are updated in place, so chunked calls continue exactly.
    Samples ``q, v`` of ``rec_dofs`` at steps ``k >= rec_start`` with
    ``k % rec_every == 0`` and Poincare samples at ``k % pc_every == 0`` (``k >=
    pc_start``), appending at ``info[I_NREC]``, ``info[I_NPC]``. Returns the status.
    """
    n = A.shape[0]
    sn = A.shape[1]
    m = nl.shape[0]
    P = tvkind.shape[0]
    H = hmult.shape[0]
    nJ = KFj.shape[0]
    h = coef[0]
    wn1 = coef[1]
    wn = coef[2]
    cv = coef[3]
    c0 = coef[4]
    gh = coef[5]
    beta = coef[6]
    gamma = coef[7]
    nr = rec_dofs.shape[0]

    df = np.empty(n)    # increment predictor (linear part)
    dl = np.empty(n)    # ... plus the time-varying terms
    dn = np.empty(n)    # increment q1 - q0
    vn = np.empty(n)
    qn = np.empty(n)
    vhat = np.empty(n)
    dtil = np.empty(n)
    vtil = np.empty(n)
    Gf = np.empty(n)
    T = np.zeros(n)
    Tnew = np.empty(n)
    y = np.empty(m)
    yprev = np.empty(m)
    qy = np.empty(m)
    F = np.empty(m)
    dq = np.empty((m, m))
    dv = np.empty((m, m))
    J = np.empty((m, m))
    r = np.empty(m)
    dy = np.empty(m)
    vy = np.empty(m)
    ay = np.empty(m)
    ahat = np.zeros(m)
    da = np.zeros((m, m))

    status = 0
    for i in range(n_steps):
        k1 = step0 + i + 1
        t1 = t0 + k1 * h
        # -- linear predictor: df = A x + wn Kinv g_n + wn1 Kinv f(t1)
        for j in range(n):
            Gf[j] = KF0[j]
        for hh in range(H):
            ph = hmult[hh] * omega * t1
            cs = np.cos(ph)
            sn_ = np.sin(ph)
            for j in range(n):
                Gf[j] += cs * KFc[hh, j] + sn_ * KFs[hh, j]
        for jj in range(nJ):
            cj = scoef[k1, jj]
            for j in range(n):
                Gf[j] += cj * KFj[jj, j]
        for rr in range(n):
            s = 0.0
            for c in range(sn):
                s += A[rr, c] * X[c]
            df[rr] = s + wn * Gn[rr] + wn1 * Gf[rr]
        # -- velocity relation v1 = vhat + cv d
        if kind == 0:
            for j in range(n):
                vhat[j] = -X[n + j]
        else:
            for j in range(n):
                dtil[j] = h * X[n + j] + h * h * (0.5 - beta) * X[2 * n + j]
                vtil[j] = X[n + j] + h * (1.0 - gamma) * X[2 * n + j]
                vhat[j] = vtil[j] - cv * dtil[j]
        if inertial:
            for a in range(m):
                if kind == 0:
                    ahat[a] = -2.0 * cv * X[n + nl[a]] - Anl[a]
                else:
                    ahat[a] = -c0 * dtil[nl[a]]
        # -- Newton on the nonlinear DOFs, inside the fixed point of the varying matrices
        for j in range(n):
            T[j] = Tn[j] if P > 0 else 0.0
        for a in range(m):
            s = 0.0
            for b in range(m):
                s += S[a, b] * Fn[b]
            y[a] = df[nl[a]] + wn1 * (s + T[nl[a]])
            yprev[a] = 0.0
        converged = P == 0
        it_tv = 0
        while True:
            for j in range(n):
                dl[j] = df[j] + wn1 * T[j]
            if m > 0:
                st, its, touched = _newton_nl(kernel, params, X, dl, vhat, cv, wn1, S, nl,
                                              y, yprev, qy, F, dq, dv, J, r, dy, vy, rtol,
                                              atol, max_newton, kernel_a, inertial, ahat,
                                              c0, ay, da)
                info[I_NEWTON_TOTAL] += its
                if its > info[I_NEWTON_MAX]:
                    info[I_NEWTON_MAX] = its
                if touched:
                    info[I_CONTACTS] += 1
                if st != 0:
                    status = st
                    break
            for j in range(n):
                s = dl[j]
                for a in range(m):
                    s += wn1 * B[j, a] * F[a]
                dn[j] = s
            if converged:
                break
            # time-varying matrices: T = Kinv g_tv(q1, v1)
            it_tv += 1
            if it_tv > max_tv:
                status = 3
                break
            for j in range(n):
                vn[j] = vhat[j] + cv * dn[j]
                qn[j] = X[j] + dn[j]
                Tnew[j] = 0.0
            for p in range(P):
                cp = tvcoef[k1, p]
                if cp == 0.0:
                    continue
                for rr in range(n):
                    s = 0.0
                    if tvkind[p] == 0:
                        for c in range(n):
                            s += PX[p, rr, c] * vn[c]
                    else:
                        for c in range(n):
                            s += PX[p, rr, c] * qn[c]
                    Tnew[rr] -= cp * s
            diff = 0.0
            scale = 0.0
            for j in range(n):
                diff = max(diff, abs(Tnew[j] - T[j]))
                scale = max(scale, abs(dn[j]))
                T[j] = Tnew[j]
            if not np.isfinite(diff):
                status = 4
                break
            if wn1 * diff <= tv_rtol * scale:
                converged = True  # one last pass with the converged T
        if it_tv > info[I_TV_MAX]:
            info[I_TV_MAX] = it_tv
        if status != 0:
            for a in range(m):
                fail_state[a] = X[nl[a]] + y[a]
                fail_state[m + a] = vhat[nl[a]] + cv * y[a]
            info[I_STEP] = k1 - 1
            break
        # -- new state and force terms
        if inertial:
            for a in range(m):
                Anl[a] = ahat[a] + c0 * dn[nl[a]]
        chk = 0.0
        if kind == 0:
            for j in range(n):
                v1 = vhat[j] + cv * dn[j]
                X[j] += dn[j]
                X[n + j] = v1
                chk += dn[j] + v1
        else:
            for j in range(n):
                a1 = c0 * (dn[j] - dtil[j])
                v1 = vtil[j] + gh * a1
                X[j] += dn[j]
                X[n + j] = v1
                X[2 * n + j] = a1
                chk += dn[j] + v1
        if not np.isfinite(chk):
            status = 4
            info[I_STEP] = k1 - 1
            break
        for j in range(n):
            s = Gf[j] + T[j]
            for a in range(m):
                s += B[j, a] * F[a]
            Gn[j] = s
            Tn[j] = T[j]
        for a in range(m):
            Fn[a] = F[a]
        info[I_STEP] = k1
        # -- sampling
        if k1 >= rec_start and k1 % rec_every == 0 and info[I_NREC] < rec_t.shape[0]:
            idx = info[I_NREC]
            rec_t[idx] = t1
            for j in range(nr):
                rec_q[idx, j] = X[rec_dofs[j]]
                rec_v[idx, j] = X[n + rec_dofs[j]]
            info[I_NREC] += 1
        if pc_every > 0 and k1 >= pc_start and k1 % pc_every == 0 \
                and info[I_NPC] < pc_t.shape[0]:
            idx = info[I_NPC]
            pc_t[idx] = t1
            for j in range(nr):
                pc_q[idx, j] = X[rec_dofs[j]]
                pc_v[idx, j] = X[n + rec_dofs[j]]
            info[I_NPC] += 1
    info[I_STATUS] = status
    return status
