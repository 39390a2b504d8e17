"""Exact condensation of the HB equations onto the nonlinear DOFs (receptance form).

Per harmonic, ``Z_k X_k = F_k + S^T G_k``. Adding a constant fictitious spring/damper
``Delta_k = K_r + i k w_r C_r`` (m x m, on nl_dofs only) to both sides keeps the equations
exact and keeps ``Zt_k = Z_k + S^T Delta_k S`` regular even when the linear part alone is
undamped at a resonance. With one complex LU of ``Zt_k`` per harmonic and lam value:

    X_k = u_k + C_k (G_k + Delta_k Xs_k),   u_k = Zt_k^{-1} F_k,   C_k = Zt_k^{-1} S^T,

and on the nonlinear DOFs (``Ht_k = S C_k`` the receptance, ``Pt_k = S u_k``)

    R_k(Xs, lam) = Xs_k - Pt_k - Ht_k (G_k(Xs) + Delta_k Xs_k) = 0        (m(2H+1) reals).

Exact derivatives: ``dR/dXs = I - Ht (dG/dXs + Delta)`` (real layout) and, with
``d(Zt^-1) = -Zt^-1 dZ Zt^-1``, ``dHt_k = -S Zt^-1 dZ_k C_k``,
``dPt_k = S Zt^-1 (dF_k - dZ_k u_k)``, ``dR/dlam = -dPt - dHt (G + Delta Xs) - Ht dG/dlam``.

``R = Ht R_schur`` with the Schur-complement (dynamic-stiffness) residual
``R_schur = (Ht^-1 - Delta) Xs - Ht^-1 Pt - G``, independent of Delta; it is the full
residual at nl_dofs once the linear DOFs are eliminated. Both share their zeros and Newton
iterates; the receptance form is used for solving (units of length, finite at any
resonance of the linear part), the Schur form is reported for stability analyses.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import lapack

from rotorsfd.harmonic.fourier import aft_matrices, to_complex, to_real
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.residual import nonlinear_coefficients, real_blocks

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass
class Condensed:
    """Condensed operators at one lam: receptance Ht (H+1, m, m), particular response Pt
    (H+1, m), their lam-derivatives, and u (H+1, n), C (H+1, n, m) for recovery."""

    lam: float
    Ht: ComplexArray
    Pt: ComplexArray
    u: ComplexArray
    C: ComplexArray
    dHt: ComplexArray | None = None
    dPt: ComplexArray | None = None


def _positive_diagonal(A: FloatArray) -> FloatArray:
    """Diagonal matrix of the positive part of diag(A)."""
    return np.diag(np.maximum(np.diag(A), 0.0))


def _bandwidth(*mats: FloatArray) -> tuple[int, int]:
    """Lower and upper bandwidths (kl, ku) of the union of the nonzero patterns."""
    kl = ku = 0
    for A in mats:
        r, c = np.nonzero(A)
        if r.size:
            kl, ku = max(kl, int((r - c).max())), max(ku, int((c - r).max()))
    return kl, ku


def apply_blocks(A: ComplexArray, Y: FloatArray) -> FloatArray:
    """Real layout of ``A_k Y_k`` for per-harmonic complex matrices A (H+1, p, p) and
    real-layout columns Y (2H+1, p, c): the product by ``real_blocks(A)`` without forming
    it."""
    return to_real(A @ to_complex(Y))


class CondensedHB:
    """HB-AFT residual condensed exactly onto nl_dofs (module docstring)."""

    def __init__(self, problem: PeriodicProblem, H: int, N: int) -> None:
        self.problem = problem
        self.H = H
        self.aft = aft_matrices(H, N)
        self.n_unknowns = (2 * H + 1) * problem.m
        m = problem.m
        self.delta = np.zeros((H + 1, m, m), dtype=complex)
        self._delta_real = np.zeros((self.n_unknowns, self.n_unknowns))
        self._cache: Condensed | None = None
        self._band: tuple | None = None      # (kl, ku, gather/scatter indices, guard)
        self._last: tuple | None = None      # (lam, xs, G) of the last AFT

    # -- shift --------------------------------------------------------------------------
    def set_shift(self, xs: FloatArray, lam: float) -> None:
        """Delta_k = K_r + i k w C_r from the nonlinearity's Jacobian averaged over the
        period at xs (positive parts of the diagonals of -<dF/dq> and -<dF/dv>; diagonal, so
        a banded Z_k stays banded); held fixed until the next call."""
        p = self.problem
        w = p.frequency(lam)
        q = self.aft.E @ xs
        v = w * (self.aft.Ed @ xs)
        dfq, dfv = p.nl_jacobian(q, v)
        Kr = _positive_diagonal(-np.mean(dfq, axis=0))
        Cr = _positive_diagonal(-np.mean(dfv, axis=0))
        if not (np.all(np.isfinite(Kr)) and np.all(np.isfinite(Cr))):
            return
        k = np.arange(self.H + 1)[:, None, None]
        self.delta = Kr[None] + 1j * k * w * Cr[None]
        self._delta_real = real_blocks(self.delta)
        self._cache = None
        self._last = None

    # -- condensation -------------------------------------------------------------------
    def condense(self, lam: float, deriv: bool = True) -> Condensed:
        """Receptances and particular responses at lam (one complex LU per harmonic)."""
        c = self._cache
        if c is not None and c.lam == lam and (c.dHt is not None or not deriv):
            return c
        p, H, s, m = self.problem, self.H, self.problem.nl_dofs, self.problem.m
        M, D, K = p.matrices(lam)
        w = p.frequency(lam)
        n = p.n_dof
        F = p.forcing(lam, H)
        rhs = np.zeros((n, m + 1), dtype=complex, order="F")
        rhs[s, np.arange(m)] = 1.0
        sel = np.asfortranarray(rhs[:, :m])
        sol = np.empty((H + 1, n, m + 1), dtype=complex)
        rows = np.empty((H + 1, m, n), dtype=complex)
        band = self._band_structure(lam, M, D, K)
        if band is not None:
            self._banded_solves(M, D, K, w, band, rhs, sel, F, sol, rows if deriv else None)
        else:
            self._dense_solves(M, D, K, w, rhs, sel, F, sol, rows if deriv else None)
        C, u = sol[:, :, :m], sol[:, :, m]
        if not np.all(np.isfinite(sol)):
            raise FloatingPointError(f"singular dynamic stiffness at lam={lam:.6g}")
        out = Condensed(lam, C[:, s, :], u[:, s], u, C)
        if deriv:
            # T_k = S Zt_k^-1 dZ_k, dZ_k = dK - (kw)^2 dM - 2k^2 w w' M + ik(w' D + w dD)
            dM, dD, dK = p.dmatrices(lam)
            dw = p.dfrequency(lam)
            R2 = np.concatenate([rows.real, rows.imag]).reshape(-1, n)

            def prod(A: FloatArray) -> ComplexArray:
                P = (R2 @ A).reshape(2, H + 1, m, n)
                return P[0] + 1j * P[1]

            k = np.arange(H + 1)[:, None, None]
            T = 1j * k * prod(dw * D + w * dD)
            if dK.any():
                T += prod(dK)
            if dM.any():
                T -= (k * w) ** 2 * prod(dM)
            if dw != 0.0:
                T -= 2 * k**2 * w * dw * prod(M)
            out.dHt = -T @ C
            out.dPt = np.einsum("kmn,kn->km", rows, p.dforcing(lam, H)) \
                - np.einsum("kmn,kn->km", T, u)
        self._cache = out
        return out

    def _dense_solves(self, M, D, K, w, rhs, sel, F, sol, rows) -> None:
        """Dense complex LU of Zt_k per harmonic; fills sol = Zt^-1 [S^T, F_k], rows."""
        s, m, n = self.problem.nl_dofs, self.problem.m, self.problem.n_dof
        Zk = np.empty((n, n), dtype=complex)
        for k in range(self.H + 1):
            # Zk is C-ordered, so Zk.T is Fortran-contiguous: LAPACK factors Z_k^T in place
            Zk.real = K - (k * w) ** 2 * M
            Zk.imag = (k * w) * D
            Zk[s, s] += np.diag(self.delta[k])
            lu, piv, info = lapack.zgetrf(Zk.T, overwrite_a=True)
            if info != 0:
                raise FloatingPointError(f"singular dynamic stiffness Z_{k} (w={w:.6g})")
            rhs[:, m] = F[k]
            sol[k] = lapack.zgetrs(lu, piv, rhs, trans=1)[0]       # Z_k x = rhs
            if rows is not None:
                rows[k] = lapack.zgetrs(lu, piv, sel)[0].T        # rows s of Z_k^-1

    def _band_structure(self, lam: float, M: FloatArray, D: FloatArray, K: FloatArray
                        ) -> tuple | None:
        """Band of the matrices (the union of their patterns and those of dmatrices, found
        once), or None when it is too wide to pay off. Every call checks that M, D, K have
        nothing outside the band (cheap gather), and widens it if they do."""
        n = self.problem.n_dof
        if self._band is not None:
            out = self._band[-1]
            if not any(np.take(A, out).any() for A in (M, D, K)):
                return self._band if self._band[0] >= 0 else None
        kl, ku = _bandwidth(M, D, K, *self.problem.dmatrices(lam))
        if self._band is not None and self._band[0] >= 0:
            kl, ku = max(kl, self._band[0]), max(ku, self._band[1])
        i, j = np.indices((n, n))
        inside = (i - j <= kl) & (j - i <= ku)
        out = np.flatnonzero(~inside)
        if 3 * (kl + ku + 1) >= n:
            self._band = (-1, -1, out)
            return None
        ii, jj = i[inside], j[inside]
        # LAPACK band storage ab[kl + ku + i - j, j]; stored as abT[j, kl + ku + i - j]
        self._band = (kl, ku, ii * n + jj, jj, kl + ku + ii - jj, out)
        return self._band

    def _banded_solves(self, M, D, K, w, band, rhs, sel, F, sol, rows) -> None:
        """Banded complex LU (LAPACK gbtrf) of Zt_k per harmonic; same outputs."""
        s, m, n = self.problem.nl_dofs, self.problem.m, self.problem.n_dof
        kl, ku, flat, jj, rr, _ = band
        kw = w * np.arange(self.H + 1)[:, None]
        vals = np.take(K, flat) - kw**2 * np.take(M, flat) + 1j * kw * np.take(D, flat)
        abT = np.zeros((self.H + 1, n, 2 * kl + ku + 1), dtype=complex)
        abT[:, jj, rr] = vals
        abT[:, s, kl + ku] += np.diagonal(self.delta, axis1=1, axis2=2)
        for k in range(self.H + 1):
            lu, piv, info = lapack.zgbtrf(abT[k].T, kl, ku, overwrite_ab=True)
            if info != 0:
                raise FloatingPointError(f"singular dynamic stiffness Z_{k} (w={w:.6g})")
            rhs[:, m] = F[k]
            sol[k] = lapack.zgbtrs(lu, kl, ku, rhs, piv)[0]
            if rows is not None:
                rows[k] = lapack.zgbtrs(lu, kl, ku, sel, piv, trans=1)[0].T

    # -- residual -----------------------------------------------------------------------
    def residual(self, xs: FloatArray, lam: float, jac: bool = True
                 ) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
        """Receptance-form residual R (2H+1, m); with jac also dR/dxs (nu, nu), dR/dlam."""
        p, H = self.problem, self.H
        xs = xs.reshape(2 * H + 1, p.m)
        w = p.frequency(lam)
        cd = self.condense(lam, deriv=jac)
        nl = nonlinear_coefficients(p, self.aft, xs, w, jac)
        self._last = (lam, xs.copy(), nl.G)
        Xs = to_complex(xs)
        Gt = to_complex(nl.G) + np.einsum("kij,kj->ki", self.delta, Xs)
        R = xs - to_real(cd.Pt + np.einsum("kij,kj->ki", cd.Ht, Gt))
        if not jac:
            return R, None, None
        nu = self.n_unknowns
        dGt = (nl.dG.reshape(nu, nu) + self._delta_real).reshape(2 * H + 1, p.m, nu)
        J = np.eye(nu) - apply_blocks(cd.Ht, dGt).reshape(nu, nu)
        dGdl = p.dfrequency(lam) * to_complex(nl.dGdw)
        dR = -to_real(cd.dPt + np.einsum("kij,kj->ki", cd.dHt, Gt)
                      + np.einsum("kij,kj->ki", cd.Ht, dGdl))
        return R, J, dR.reshape(nu)

    def schur_jacobian(self, J: FloatArray, dR: FloatArray, lam: float) -> FloatArray:
        """Jacobian [dR_schur/dxs, dR_schur/dlam] (nu, nu+1) from the receptance-form one
        at a solution (where R = 0): ``R_schur = Ht^-1 R``."""
        cd = self.condense(lam, deriv=False)
        S = real_blocks(np.linalg.inv(cd.Ht))
        return S @ np.column_stack([J, dR])

    def recover(self, xs: FloatArray, lam: float) -> ComplexArray:
        """All DOFs: ``X_k = u_k + C_k (G_k + Delta_k Xs_k)`` (H+1, n) complex; the
        nonlinear DOFs keep the solved values Xs."""
        p, H = self.problem, self.H
        xs = xs.reshape(2 * H + 1, p.m)
        cd = self.condense(lam, deriv=False)
        G = self.last_G(xs, lam)
        if G is None:
            G = nonlinear_coefficients(p, self.aft, xs, p.frequency(lam), jac=False).G
        Gt = to_complex(G) + np.einsum("kij,kj->ki", self.delta, to_complex(xs))
        X = cd.u + np.einsum("knm,km->kn", cd.C, Gt)
        X[:, p.nl_dofs] = to_complex(xs)    # = the recovered values up to the residual
        X[0] = X[0].real
        return X

    def last_G(self, xs: FloatArray, lam: float) -> FloatArray | None:
        """Nonlinear-force coefficients of the last residual evaluation if it was at
        (xs, lam), else None."""
        if self._last is not None and self._last[0] == lam \
                and np.array_equal(self._last[1], xs.reshape(self._last[1].shape)):
            return self._last[2]
        return None

    def nl_part(self, xs: FloatArray) -> FloatArray:
        """The unknowns are the nonlinear-DOF coefficients themselves (2H+1, m)."""
        return xs.reshape(2 * self.H + 1, self.problem.m)
