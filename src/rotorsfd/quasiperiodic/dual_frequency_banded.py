"""The per-harmonic condensation of a time-invariant torus problem (b = 0, the dual-spool
rotor: :mod:`~rotorsfd.quasiperiodic.dual_frequency`) from band storage (issue 17 item 2).

Each harmonic (k1, k2) is its own block, ``Zt_k = K + i omega_k D - omega_k^2 M + S^T
Delta_k S`` with ``omega_k = k1 Omega + k2 w_2``: one complex banded LU of n DOFs per
harmonic and the nonlinear DOFs' m + 1 columns (:func:`rotorsfd.harmonic.banded.
condense_bands`, harmonic 1 at ``w = omega_k``, ``dw = domega_k/dlam``: its pivoting and
refinement step), the linear part read from the problem's CSR terms
(:class:`~rotorsfd.quasiperiodic.torus_bands.TorusBands`) in band storage, no n x n array.

    C_k = Zt_k^-1 S^T,  u_k = Zt_k^-1 F_k,
    dHt_k = -S Zt_k^-1 dZ_k C_k,  dPt_k = S Zt_k^-1 (dF_k - dZ_k u_k),

the same :class:`~rotorsfd.quasiperiodic.torus_linear.TorusCondensed` as the dense
per-harmonic condenser (the tests compare the two). The shift Delta_k must be diagonal
(the torus residual's is: the positive parts of the diagonals). Without the kernel's
refinement step: on the 520-DOF dual-spool rotor (an intershaft bearing: half bandwidth
260) it moved the harmonic (2, 0) near a mode by 9e-10 of its block from the classically
refined dense solve, the unrefined banded LU agrees with it and with the dense LU to
5e-11 (tests/multishaft/test_dual_spool_banded.py).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from rotorsfd.harmonic import banded
from rotorsfd.model.sparse import to_band
from rotorsfd.quasiperiodic.torus_fourier import (
    TorusLattice,
    block_real_indices,
    block_real_maps,
    block_vectors,
)
from rotorsfd.quasiperiodic.torus_linear import (
    TorusCondensed,
    TorusCondenser,
    TorusProblem,
    complex_to_real,
)

FloatArray = NDArray[np.float64]


class BandedHarmonicCondenser(TorusCondenser):
    """Per-harmonic condensation from band storage (module docstring)."""

    def __init__(self, problem: TorusProblem, lattice: TorusLattice) -> None:
        if problem.bands is None:
            raise ValueError("BandedHarmonicCondenser needs the problem's bands")
        super().__init__(problem, lattice)
        bands = problem.bands
        self.kl = self.ku = bands.beta
        self.Mb = to_band(bands.M, self.kl, self.ku)
        self.term_bands = np.array([to_band(t, self.kl, self.ku) for t in bands.terms])
        self.last: TorusCondensed | None = None

    def set_shift(self, Kr, Cr, lam: float) -> None:
        Kr, Cr = np.asarray(Kr, float), np.asarray(Cr, float)
        if np.any(Kr - np.diag(np.diag(Kr))) or np.any(Cr - np.diag(np.diag(Cr))):
            raise ValueError("the banded per-harmonic condensation takes a diagonal shift")
        super().set_shift(Kr, Cr, lam)
        self.last = None

    def linear_bands(self, lam: float) -> tuple[np.ndarray, ...]:
        """Band storage of (D, K, dD, dK) at lam: the weights (1, T) (real, b = 0) times
        the terms' bands."""
        bands = self.problem.bands
        out = []
        for w in (*bands.weights(lam), *bands.dweights(lam)):
            w = np.asarray(w)
            if w.shape[0] != 1 or np.any(np.imag(w)):
                raise ValueError("BandedHarmonicCondenser needs a real time-invariant "
                                 "linear part (b = 0)")
            out.append(np.tensordot(np.real(w[0]), self.term_bands, axes=(0, 0)))
        return tuple(out)

    def condense(self, lam: float, deriv: bool = True) -> TorusCondensed:
        c = self.last
        if c is not None and c.lam == lam and (c.dHt is not None or not deriv):
            return c
        p_, lat = self.problem, self.lattice
        n, m, s = p_.n_dof, p_.m, np.ascontiguousarray(p_.nl_dofs, dtype=np.int64)
        Db, Kb, dDb, dKb = self.linear_bands(lam)
        zero = np.zeros_like(self.Mb)
        om, wb = p_.frequencies(lam)
        dom, dwb = p_.dfrequencies(lam)
        F = block_vectors(lat, p_.forcing(lam, lat))
        dF = block_vectors(lat, p_.dforcing(lam, lat)) if deriv else F
        nr = lat.n_real
        Ht, Pt = np.zeros((nr * m, nr * m)), np.zeros((nr, m))
        dHt = np.zeros_like(Ht) if deriv else None
        dPt = np.zeros_like(Pt) if deriv else None
        refine = 0     # module docstring: the refinement step moves near-modal harmonics
        sol = np.zeros((2, n, m + 1), dtype=complex)
        dsol = np.zeros((2, m, m + 1), dtype=complex)
        h_, ph_ = np.empty((2, 2, m, m), dtype=complex), np.empty((2, 2, m), dtype=complex)
        F2, dF2 = np.zeros((2, n), dtype=complex), np.zeros((2, n), dtype=complex)
        delta = np.zeros((2, m), dtype=complex)
        us, Cs = [], []
        for k1 in range(lat.H1 + 1):
            h = lat.h(k1)
            p = 2 * h + 1
            dl = self.delta(k1)
            C = np.zeros((p * n, p * m), dtype=complex)
            u = np.zeros(p * n, dtype=complex)
            dC = np.zeros((p * m, p * m), dtype=complex)
            du = np.zeros(p * m, dtype=complex)
            for r, k2 in enumerate(range(-h, h + 1)):
                w, dw = k1 * om + k2 * wb, k1 * dom + k2 * dwb
                delta[1] = np.diagonal(dl[r]) if m else delta[1]
                F2[1], dF2[1] = F[k1][r], dF[k1][r]
                status = banded.condense_bands(
                    self.Mb, Db, Kb, zero, dDb, dKb, float(w), float(dw), self.kl, self.ku,
                    s, delta, F2, dF2, deriv, sol, dsol, h_[0], ph_[0], h_[1], ph_[1],
                    refine, 1)
                if status != banded.OK:
                    raise np.linalg.LinAlgError(
                        f"singular torus harmonic ({k1}, {k2}) at lam = {lam:.6g}")
                rn, rm = slice(r * n, (r + 1) * n), slice(r * m, (r + 1) * m)
                C[rn, rm], u[rn] = sol[1][:, :m], sol[1][:, m]
                if deriv:
                    dC[rm, rm], du[rm] = dsol[1][:, :m], dsol[1][:, m]
            rows = (np.arange(p)[:, None] * n + s[None, :]).ravel()
            idx = block_real_indices(lat, k1)
            _, U = block_real_maps(lat, k1)
            Pt[idx] = (U @ u[rows].reshape(p, m)).real
            if m:
                g, R = complex_to_real(lat, k1, C[rows], m)
                Ht[np.ix_(g, g)] = R
            if deriv:
                dPt[idx] = (U @ du.reshape(p, m)).real
                if m:
                    g, R = complex_to_real(lat, k1, dC, m)
                    dHt[np.ix_(g, g)] = R
            us.append(u)
            Cs.append(C)
        out = TorusCondensed(lam, Ht, Pt, us, Cs, dHt, dPt)
        self.last = out
        return out

    def response_derivative(self, cond: TorusCondensed, g: FloatArray) -> FloatArray:
        """``d(Pt + Ht g)/dlam = dPt + dHt g`` at fixed g (n_real, m) (the condensation
        with its derivatives at cond.lam, m x m per harmonic)."""
        full = self.condense(cond.lam, deriv=True)
        g = np.asarray(g, dtype=float)
        return full.dPt + (full.dHt @ g.reshape(-1)).reshape(g.shape)

