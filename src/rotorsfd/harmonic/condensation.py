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
``dPt_k = S Zt^-1 (dF_k - dZ_k u_k)``, ``dR/dlam = -dPt - dHt (G + Delta Xs) - Ht dG/dlam``
(``dG/dlam``: through the frequency, plus the AFT of the force's own lam-derivative when
it has one, :attr:`~rotorsfd.harmonic.problem.NonlinearLaw.dforce`).

``R = Ht R_schur`` with the Schur-complement (dynamic-stiffness) residual
``R_schur = (Ht^-1 - Delta) Xs - Ht^-1 Pt - G``, independent of Delta; it is the full
residual at nl_dofs once the linear DOFs are eliminated. Both share their zeros and Newton
iterates; the receptance form is used for solving (units of length, finite at any
resonance of the linear part), the Schur form is reported for stability analyses.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.harmonic import banded
from rotorsfd.harmonic.aft_inertia import condensed_residual, force_coefficients, hb_kernel
from rotorsfd.harmonic.aft_kernels import condensed_assembly, project
from rotorsfd.harmonic.banded_lowrank import condense_bands_lowrank
from rotorsfd.harmonic.dense_condensation import dense_solves
from rotorsfd.harmonic.fourier import aft_matrices, aliasing_error, to_complex, to_real
from rotorsfd.harmonic.pencil_condensation import condense_pencils
from rotorsfd.harmonic.problem import NonlinearLaw, PeriodicProblem
from rotorsfd.harmonic.residual import nonlinear_coefficients, nonlinear_samples, real_blocks

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass
class Condensed:
    """Condensed operators at one lam: receptance Ht (H+1, m, m), particular response Pt
    (H+1, m), their lam-derivatives, and u (H+1, n), C (H+1, n, m) for recovery (given, or
    formed on first use by ``recovery() -> (u, C)``: the Newton iterations need Ht, Pt
    only)."""

    lam: float
    Ht: ComplexArray
    Pt: ComplexArray
    u_: ComplexArray | None
    C_: ComplexArray | None
    dHt: ComplexArray | None = None
    dPt: ComplexArray | None = None
    recovery: Callable[[], tuple[ComplexArray, ComplexArray]] | None = None

    @property
    def u(self) -> ComplexArray:
        """Particular response of every DOF (H+1, n)."""
        if self.u_ is None:
            self.u_, self.C_ = self.recovery()
        return self.u_

    @property
    def C(self) -> ComplexArray:
        """Receptance columns of every DOF (H+1, n, m)."""
        if self.C_ is None:
            self.u_, self.C_ = self.recovery()
        return self.C_


def _c_float(A: FloatArray) -> FloatArray:
    """A itself if C-contiguous float64 (the usual case), else a converted copy."""
    if type(A) is np.ndarray and A.dtype == np.float64 and A.flags.c_contiguous:
        return A
    return np.ascontiguousarray(A, dtype=np.float64)


def _positive_diagonal(A: FloatArray) -> FloatArray:
    """Diagonal matrix of the positive part of diag(A); where that is zero, the largest
    magnitude in the row (a purely cross-coupled stiffness, such as a journal bearing's
    at the bearing centre, still regularises the shift)."""
    d = np.maximum(np.diag(A), 0.0)
    return np.diag(np.where(d > 0.0, d, np.max(np.abs(A), axis=1)))


def _bandwidth(*mats: FloatArray) -> tuple[int, int]:
    """Lower and upper bandwidths (kl, ku) of the union of the nonzero patterns."""
    kl = ku = 0
    for A in mats:
        r, c = np.nonzero(A)
        if r.size:
            kl, ku = max(kl, int((r - c).max())), max(ku, int((c - r).max()))
    return kl, ku


def banded_band(matrices: object) -> tuple[int, int] | None:
    """(kl, ku) when the problem's ``matrices`` also give band storage (attributes
    ``n``, ``band``, ``banded(lam)``, ``dbanded(lam)``, e.g.
    :class:`rotorsfd.model.sparse.BandedLinearPart`) narrow enough for the banded kernel
    to pay off (``3 (kl + ku + 1) < n``); None otherwise (the dense matrices are used)."""
    band, n = getattr(matrices, "band", None), getattr(matrices, "n", None)
    if band is None or n is None or not hasattr(matrices, "dbanded"):
        return None
    kl, ku = band
    return (int(kl), int(ku)) if 3 * (kl + ku + 1) < n else None


def apply_blocks(A: ComplexArray, Y: FloatArray) -> FloatArray:
    """Real layout of ``A_k Y_k`` for per-harmonic complex matrices A (H+1, p, p) and
    real-layout columns Y (2H+1, p, c): the product by ``real_blocks(A)`` without forming
    it."""
    return to_real(A @ to_complex(Y))


def _kernel_status(law: NonlinearLaw, status: int, q: FloatArray, v: FloatArray
                   ) -> None:
    """Raise for a nonzero status of a compiled AFT: sample status - 1 rejected by the
    kernel (the force law's own error, e.g. JournalContactError), or a non-finite force."""
    if status > 0:
        law.force(q[status - 1], v[status - 1])
        raise FloatingPointError(f"nonlinear kernel rejected the state q={q[status - 1]}, "
                                 f"v={v[status - 1]}")
    if status < 0:
        raise FloatingPointError("non-finite nonlinear force in AFT")


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
        self._delta_seen: tuple | None = None  # (delta object, its diagonal or None)
        self._shift_parts: tuple | None = None  # (K_r, C_r, w_r) of the last set_shift
        self._cache: Condensed | None = None
        self._band: tuple[int, int] | None = None  # (kl, ku); (-1, -1): dense
        self._scanned: tuple = (None,) * 6   # matrices known to lie inside the band
        self._last: tuple | None = None      # (lam, xs, G) of the last AFT
        self._kernel = hb_kernel(problem)   # the inertial kernel when the law has one
        self._work: tuple | None = None      # AFT work arrays

    # -- shift --------------------------------------------------------------------------
    def set_shift(self, xs: FloatArray, lam: float) -> None:
        """Delta_k = K_r + i k w C_r from the nonlinearity's Jacobian averaged over the
        period at xs (positive parts of the diagonals of -<dF/dq> and -<dF/dv>; diagonal, so
        a banded Z_k stays banded); held fixed until the next call."""
        p = self.problem
        w = p.frequency(lam)
        q = self.aft.E @ xs
        v = w * (self.aft.Ed @ xs)
        dfq, dfv = p.law(lam).jacobian(q, v)
        Kr = _positive_diagonal(-np.mean(dfq, axis=0))
        Cr = _positive_diagonal(-np.mean(dfv, axis=0))
        if not (np.all(np.isfinite(Kr)) and np.all(np.isfinite(Cr))):
            return
        self._shift_parts = (Kr, Cr, w)
        self._apply_shift()

    def _apply_shift(self) -> None:
        """delta (H+1, m, m) = K_r + i k w_r C_r from the stored (K_r, C_r, w_r)."""
        Kr, Cr, w = self._shift_parts
        k = np.arange(self.H + 1)[:, None, None]
        self.delta = Kr[None] + 1j * k * w * Cr[None]
        self._delta_real = real_blocks(self.delta)
        self._cache = None
        self._last = None

    def adopt_shift(self, other: CondensedHB) -> bool:
        """Take the shift (K_r, C_r, w_r) of ``other`` (the same problem at fewer or
        equally many harmonics), extended to this H by ``Delta_k = K_r + i k w_r C_r``: its
        harmonics ``k <= other.H`` are then the same numbers as other's, so
        :meth:`condense` with ``reuse=other`` copies them instead of factorising them
        again. False (nothing changed) if other has no such shift."""
        parts = other._shift_parts
        if parts is None or other.problem is not self.problem or other.H > self.H:
            return False
        if self._shift_parts is not parts:
            self._shift_parts = parts
            self._apply_shift()
        return True

    def adopt_condensation(self, other: CondensedHB) -> bool:
        """Take other's shift and cached condensation (the same problem and H; the AFT
        samples may differ: the condensation does not depend on them). False (nothing
        changed) otherwise."""
        if other.problem is not self.problem or other.H != self.H \
                or other._shift_parts is None:
            return False
        self._shift_parts = other._shift_parts
        self._apply_shift()
        self._cache = other._cache
        return True

    def _reusable(self, other: CondensedHB | None, lam: float, deriv: bool
                  ) -> Condensed | None:
        """other's condensation at lam if its harmonics can stand for this one's
        ``k <= other.H`` (same problem, same shift values, the derivatives if needed)."""
        if other is None or other.problem is not self.problem or other.H > self.H:
            return None
        c = other._cache
        if c is None or c.lam != lam or (deriv and c.dHt is None):
            return None
        if not np.array_equal(other.delta, self.delta[: other.H + 1]):
            return None
        return c

    def with_problem(self, problem: PeriodicProblem) -> CondensedHB:
        """A condenser of another problem on the same nonlinear DOFs (the same system at
        other parameter values, or its view in another parameter) with the same H, N and
        this one's shift Delta, held fixed (shared, not copied)."""
        if problem.m != self.problem.m:
            raise ValueError(f"the shift is for {self.problem.m} nonlinear DOFs, the "
                             f"problem has {problem.m}")
        hb = CondensedHB(problem, self.H, self.aft.N)
        hb.delta, hb._delta_real = self.delta, self._delta_real
        return hb

    def _delta_diagonal(self) -> ComplexArray | None:
        """Diagonal (H+1, m) of the shift, or None if it is not diagonal."""
        seen = self._delta_seen
        if seen is None or seen[0] is not self.delta:
            d = np.ascontiguousarray(np.diagonal(self.delta, axis1=1, axis2=2))
            diagonal = np.count_nonzero(self.delta) == np.count_nonzero(d)
            self._delta_seen = seen = (self.delta, d if diagonal else None)
        return seen[1]

    # -- condensation -------------------------------------------------------------------
    def condense(self, lam: float, deriv: bool = True, reuse: CondensedHB | None = None
                 ) -> Condensed:
        """Receptances and particular responses at lam (one complex LU per harmonic;
        :mod:`rotorsfd.harmonic.banded` for banded matrices, LAPACK for dense ones).
        ``reuse``: a condenser of the same problem at fewer harmonics whose cached
        condensation at lam has this one's shift (:meth:`adopt_shift`): on the banded
        path its harmonics are copied, only the higher ones factorised."""
        c = self._cache
        if c is not None and c.lam == lam and (c.dHt is not None or not deriv):
            return c
        p, H, s, m = self.problem, self.H, self.problem.nl_dofs, self.problem.m
        w = p.frequency(lam)
        n = p.n_dof
        F = np.ascontiguousarray(p.forcing(lam, H), dtype=complex)
        dF = np.ascontiguousarray(p.dforcing(lam, H), dtype=complex) if deriv else F
        dw = p.dfrequency(lam) if deriv else 0.0
        sol = np.empty((H + 1, n, m + 1), dtype=complex)
        dsol = np.empty((H + 1, m, m + 1), dtype=complex)
        Ht, dHt = np.empty((2, H + 1, m, m), dtype=complex)
        Pt, dPt = np.empty((2, H + 1, m), dtype=complex)
        diag = self._delta_diagonal()
        band = banded_band(p.matrices)
        if band is not None and diag is not None:
            # band storage from the problem itself (e.g. model.sparse.BandedLinearPart):
            # the band known, no n x n matrix formed or scanned
            kl, ku = band
            mb = p.matrices.banded(lam)
            dmb = p.matrices.dbanded(lam) if deriv else mb
            lowrank = getattr(p.matrices, "lowrank", None)   # U diag(c) U^T beside D
            k_first = self._copy_harmonics(self._reusable(reuse, lam, deriv), sol, dsol)
            if lowrank is None:
                status = banded.condense_bands(*mb, *dmb, w, dw, kl, ku, s, diag, F, dF,
                                               deriv, sol, dsol, Ht, Pt, dHt, dPt,
                                               banded.refinement_steps(n), k_first)
            else:
                status = condense_bands_lowrank(*mb, *dmb, *lowrank, w, dw, kl, ku, s, diag,
                                                F, dF, deriv, sol, dsol, Ht, Pt, dHt, dPt,
                                                banded.refinement_steps(n), k_first)
        else:
            # a branch on a wide linear part: one eigendecomposition per harmonic instead
            # of an LU per point (pencil_condensation), once it has seen enough points
            parts = condense_pencils(p, lam, H, self.delta, w, dw, F, dF, deriv)
            if parts is not None:
                pHt, pPt, pdHt, pdPt, recovery = parts
                self._cache = Condensed(lam, pHt, pPt, None, None, pdHt, pdPt, recovery)
                return self._cache
            status = self._dense_condense(lam, deriv, w, dw, F, dF, diag, sol, dsol, Ht,
                                          Pt, dHt, dPt, self._reusable(reuse, lam, deriv))
        if status > 0:
            raise FloatingPointError(f"singular dynamic stiffness Z_{status - 1} "
                                     f"(w={w:.6g}, lam={lam:.6g})")
        if status == banded.NOT_FINITE:
            raise FloatingPointError(f"singular dynamic stiffness at lam={lam:.6g}")
        out = Condensed(lam, Ht, Pt, sol[:, :, m], sol[:, :, :m],
                        dHt if deriv else None, dPt if deriv else None)
        self._cache = out
        return out

    @staticmethod
    def _copy_harmonics(known: Condensed | None, sol: ComplexArray, dsol: ComplexArray
                        ) -> int:
        """Harmonics 0..h of a known condensation into sol (and dsol); returns h + 1 (0
        without one): the first harmonic left to the kernel."""
        if known is None:
            return 0
        h1, m = known.Ht.shape[0], known.Ht.shape[1]
        sol[:h1, :, :m] = known.C
        sol[:h1, :, m] = known.u
        if known.dHt is not None:
            dsol[:h1, :, :m] = known.dHt
            dsol[:h1, :, m] = known.dPt
        return h1

    def _dense_condense(self, lam, deriv, w, dw, F, dF, diag, sol, dsol, Ht, Pt, dHt, dPt,
                        known: Condensed | None = None) -> int:
        """:meth:`condense` from the problem's dense matrices: the compiled banded kernel
        on their band (found by scanning them), or dense LAPACK when it is too wide (then
        the harmonics of ``known``, a reusable condensation at fewer harmonics, copied
        instead of factorised again, as on the banded path)."""
        p, s = self.problem, self.problem.nl_dofs
        M, D, K = p.matrices(lam)
        dM, dD, dK = p.dmatrices(lam) if deriv else (M, D, K)
        mats = tuple(_c_float(A) for A in (M, D, K, dM, dD, dK))
        # scan for nonzeros outside the band only the matrices not scanned before (the
        # problem returns the same array objects for constant matrices, e.g. M and K)
        sc = self._scanned
        check = np.array([mats[0] is not sc[0], mats[1] is not sc[1], mats[2] is not sc[2],
                          mats[3] is not sc[3], mats[4] is not sc[4], mats[5] is not sc[5]])
        status = banded.OUTSIDE_BAND
        while status == banded.OUTSIDE_BAND:
            kl, ku = self._bandwidths(mats)
            if kl < 0 or diag is None:
                k_first = self._copy_harmonics(known, sol, dsol)
                dense_solves(p, self.H, self.delta, *mats, w, dw, F, dF, deriv, sol,
                             dsol, k_first)
                return banded._split(s, deriv, sol, dsol, Ht, Pt, dHt, dPt)
            status = banded.condense_banded(*mats, w, dw, kl, ku, s, diag, F, dF, deriv,
                                            check, sol, dsol, Ht, Pt, dHt, dPt)
            if status == banded.OUTSIDE_BAND:
                kl2, ku2 = _bandwidth(*mats)
                self._band = (max(kl, kl2), max(ku, ku2))
            else:
                self._scanned = mats
        return status

    def _bandwidths(self, mats: list[FloatArray]) -> tuple[int, int]:
        """(kl, ku) of the band used, found at the first call (the union of the patterns
        of the matrices and their derivatives) and widened when the kernel meets a nonzero
        outside it; (-1, -1) when the band is too wide to pay off (dense LAPACK)."""
        if self._band is None:
            self._band = _bandwidth(*mats)
        kl, ku = self._band
        if kl >= 0 and 3 * (kl + ku + 1) >= self.problem.n_dof:
            self._band = (kl, ku) = (-1, -1)
        return kl, ku

    # -- residual -----------------------------------------------------------------------
    def _work_arrays(self) -> tuple:
        if self._work is None:
            N, nh, m = self.aft.N, 2 * self.H + 1, self.problem.m
            self._work = (np.empty((N, m)), np.empty((N, m)), np.empty((N, m)),
                          np.empty((N, m)), np.empty((N, m, m)), np.empty((N, m, m)),
                          np.empty((nh, m, nh, m)), np.empty((nh, m)),
                          np.zeros((self.H + 1, m, m), dtype=complex),
                          np.zeros((self.H + 1, m), dtype=complex))
        return self._work

    def residual(self, xs: FloatArray, lam: float, jac: bool = True, dlam: bool = True
                 ) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
        """Receptance-form residual R (2H+1, m); with jac also dR/dxs (nu, nu), dR/dlam
        (the AFT and the assembly in compiled loops, :mod:`rotorsfd.harmonic.aft_kernels`).
        ``dlam=False`` skips the lam-derivatives (dR/dlam is then None)."""
        p, H, nu = self.problem, self.H, self.n_unknowns
        xs = np.ascontiguousarray(xs, dtype=float).reshape(2 * H + 1, p.m)
        w = p.frequency(lam)
        with_dlam = jac and dlam
        dw = p.dfrequency(lam) if with_dlam else 0.0
        cd = self.condense(lam, deriv=with_dlam)
        q, dq, v, f, dfq, dfv, dG, dGdw, zH, zP = self._work_arrays()
        dHt, dPt = (cd.dHt, cd.dPt) if with_dlam else (zH, zP)
        G = np.empty_like(xs)
        R = np.empty_like(xs)
        J = np.empty((nu, nu)) if jac else np.empty((0, 0))
        dR = np.empty_like(xs)
        a = self.aft
        delta = np.ascontiguousarray(self.delta, dtype=complex)
        law = p.law(lam)
        if self._kernel is not None:
            status = condensed_residual(self._kernel, law.kernel_params, xs, w, dw, a.E,
                                        a.Ed, a.P, delta, self._delta_real, cd.Ht, cd.Pt,
                                        dHt, dPt, jac, q, dq, v, f, dfq, dfv, G, dG, dGdw,
                                        R, J, dR)
            _kernel_status(law, status, q, v)
        else:
            nl = nonlinear_samples(p, a, xs, w, jac, lam=lam)
            q, v = a.E @ xs, w * nl[3]
            if not project(a.P, a.E, a.Ed, w, nl[0], nl[1], nl[2], nl[3], jac, G, dG, dGdw):
                raise FloatingPointError("non-finite nonlinear force in AFT")
            condensed_assembly(xs, G, dG.reshape(nu, nu), dGdw, delta, self._delta_real,
                               cd.Ht, cd.Pt, dHt, dPt, dw, jac, R, J, dR)
        self._last = (lam, xs.copy(), G)
        if not jac:
            return R, None, None
        if with_dlam and law.dforce is not None:   # the force's own dependence on lam
            dR += self.displacement_of(a.P @ law.dforce(q, v), lam)
        return R, J, dR.reshape(nu) if with_dlam else None

    def force_coefficients(self, xs: FloatArray, lam: float, N: int) -> FloatArray:
        """Nonlinear-force coefficients G (2H+1, m) at (xs, lam) with N samples: those of
        the last residual evaluation when it was there with this N, else one AFT (the
        compiled kernel when the problem has one)."""
        p, H = self.problem, self.H
        xs = np.ascontiguousarray(xs, dtype=float).reshape(2 * H + 1, p.m)
        if N == self.aft.N:
            G = self.last_G(xs, lam)
            if G is not None:
                return G
        w = p.frequency(lam)
        a = aft_matrices(H, N)
        law = p.law(lam)
        if self._kernel is None:
            return nonlinear_coefficients(p, a, xs, w, jac=False, lam=lam).G
        q, dq, v, f = (np.empty((N, p.m)) for _ in range(4))
        dfq, dfv = np.empty((N, p.m, p.m)), np.empty((N, p.m, p.m))
        G = np.empty_like(xs)
        status = force_coefficients(self._kernel, law.kernel_params, xs, w, a.E, a.Ed,
                                    a.P, q, dq, v, f, dfq, dfv, G)
        _kernel_status(law, status, q, v)
        return G

    def aliasing(self, xs: FloatArray, lam: float) -> float:
        """:func:`rotorsfd.harmonic.fourier.aliasing_error` at (xs, lam), the 2N-sample
        force by the compiled kernel when the problem has one."""
        p, H = self.problem, self.H
        xs = np.ascontiguousarray(xs, dtype=float).reshape(2 * H + 1, p.m)
        G_N = self.last_G(xs, lam)
        if self._kernel is None or G_N is None:
            return aliasing_error(p.law(lam).force, xs, p.frequency(lam), self.aft.N, G_N)
        G2 = self.force_coefficients(xs, lam, 2 * self.aft.N)
        scale = max(float(np.max(np.abs(G2))), np.finfo(float).tiny)
        return float(np.max(np.abs(G2 - G_N))) / scale

    def sampling_error(self, xs: FloatArray, lam: float, N: int,
                       G_hi: FloatArray | None = None) -> tuple[float, FloatArray]:
        """Error of N AFT samples at (xs, lam) in the units of the Newton test of the
        scaled receptance-form residual: the 2-norm of ``Ht_k (G_k(2N) - G_k(N)) / c`` (the
        force error of the retained harmonics as the displacement it causes, over the
        length scale c of each nonlinear DOF); ``G_hi`` = G(2N) if known. Returns it and
        G(N). The one N_f criterion of condensed HB: ``continue_periodic``'s adaptive rule
        and the fold curve (:func:`~rotorsfd.harmonic.fourier.smallest_n_samples`)."""
        G_lo = self.force_coefficients(xs, lam, N)
        if G_hi is None:
            G_hi = self.force_coefficients(xs, lam, 2 * N)
        return self.residual_change(G_hi - G_lo, lam), G_lo

    def residual_change(self, dG: FloatArray, lam: float) -> float:
        """2-norm of the change of the scaled residual (:meth:`displacement_of` over the
        length scale c of each nonlinear DOF) caused by a change dG of the force
        coefficients."""
        c = self.problem.dof_scale[self.problem.nl_dofs]
        return float(np.linalg.norm(self.displacement_of(dG, lam) / c[None, :]))

    def displacement_of(self, dG: FloatArray, lam: float) -> FloatArray:
        """Change of the receptance-form residual (units of length, real layout (2H+1, m))
        caused by a change dG of the nonlinear-force coefficients: ``-Ht_k dG_k``."""
        Ht = self.condense(lam, deriv=False).Ht
        return -to_real(np.einsum("kij,kj->ki", Ht, to_complex(dG)))

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
            G = nonlinear_coefficients(p, self.aft, xs, p.frequency(lam), jac=False,
                                       lam=lam).G
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
