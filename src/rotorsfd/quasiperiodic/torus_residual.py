"""Condensed two-frequency HB-AFT residual of a torus and its exact Jacobians.

Unknowns: the real layout ``xs`` (n_real, m) of the nonlinear DOFs on the half lattice
(:mod:`~rotorsfd.quasiperiodic.torus_fourier`). With the condensed operators of
:class:`~rotorsfd.quasiperiodic.torus_linear.TorusCondenser`,

    R(xs, lam) = xs - Pt - Ht (G(xs) + Delta xs),
    G = P F_nl(E xs, Ev xs)                                     (AFT, 2D FFT)

and exactly (Ev = E D_omega, linear in the frequencies omega_k = k1 Omega + k2 w_b):

    dG/dxs [a,i,b,j] = sum_n P[a,n] (dF/dq[n,i,j] E[n,b] + dF/dv[n,i,j] Ev[n,b]),
    dR/dxs = I - Ht (dG/dxs + Delta),
    dR/dlam = -dPt - dHt (G + Delta xs) - Ht dG/dlam,
            (dPt + dHt g = S Zt^-1 (dF - dZ X), X the all-DOF response: one solve per
            column, :meth:`~rotorsfd.quasiperiodic.torus_linear.TorusCondenser.
            response_derivative`)
    dG/dlam = P (dF/dv . Ev' xs),   Ev' = Ev at the frequencies d omega_k / dlam.

Each ``P diag(g) E`` comes from the 2D FFT of the samples g alone (its entries are g's
coefficients at k_a -+ k_b:
:meth:`~rotorsfd.quasiperiodic.torus_fourier.TorusAFT.product_matrix`), and
``P diag(g) Ev = (P diag(g) E) D_omega``: the N x n_real sampling matrices are never formed.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.quasiperiodic.torus_fourier import TorusAFT, TorusLattice, derivative
from rotorsfd.quasiperiodic.torus_linear import TorusCondenser, TorusProblem

FloatArray = NDArray[np.float64]


@dataclass
class TorusForce:
    """AFT result at the nonlinear DOFs: G (n_real, m), dG/dxs (n_real m, n_real m),
    dG/dlam (n_real, m) (None when not asked) and the displacement samples (N, m)."""

    G: FloatArray
    dG: FloatArray | None
    dGdlam: FloatArray | None
    q: FloatArray


def torus_force(problem: TorusProblem, aft: TorusAFT, xs: FloatArray, lam: float,
                jac: bool = True) -> TorusForce:
    """G and its exact derivatives (module docstring) from ``elements.force_and_jacobian``
    at the N1 x N2 samples."""
    lat = aft.lattice
    w = lat.frequencies(*problem.frequencies(lam))
    el = problem.elements
    nr, m = xs.shape
    if el is None or not m:              # a linear system: no force, no derivative
        nu = xs.size
        return TorusForce(np.zeros_like(xs), np.zeros((nu, nu)), np.zeros_like(xs),
                          aft.sample(xs))
    parts = [xs, derivative(xs, w)]
    if jac:                              # the velocity's lam-derivative, for dG/dlam
        parts.append(derivative(xs, lat.frequencies(*problem.dfrequencies(lam))))
    samples = aft.sample(np.concatenate(parts, axis=1))      # one inverse 2D FFT
    q, v = samples[:, :m], samples[:, m:2 * m]
    if not jac:
        f = np.asarray(el.force(q, v), dtype=float)
        if not np.all(np.isfinite(f)):
            raise FloatingPointError("non-finite nonlinear force in the torus AFT")
        return TorusForce(aft.project(f), None, None, q)
    f, dfq, dfv = el.force_and_jacobian(q, v)
    if not np.all(np.isfinite(f)):
        raise FloatingPointError("non-finite nonlinear force in the torus AFT")
    dv = samples[:, 2 * m:]
    both = aft.project(np.concatenate([f, np.einsum("nij,nj->ni", dfv, dv)], axis=1))
    G, dGdlam = both[:, :m], both[:, m:]
    T = aft.product_matrix(np.stack([dfq, dfv], axis=1))    # P dF/dq E, P dF/dv E
    T, Tv = T[:, 0], T[:, 1]                                 # (a, i, j, b); Ev = E D_omega
    wk = w[1:]
    T[..., 1::2] += wk * Tv[..., 2::2]
    T[..., 2::2] -= wk * Tv[..., 1::2]
    dG = T.transpose(0, 1, 3, 2).reshape(nr * m, nr * m)
    return TorusForce(G, dG, dGdlam, q)


class TorusHB:
    """The condensed torus residual ``R(xs, lam)`` on a lattice and an N1 x N2 grid."""

    def __init__(self, problem: TorusProblem, lattice: TorusLattice, N1: int, N2: int
                 ) -> None:
        self.problem, self.lattice = problem, lattice
        self.aft = TorusAFT(lattice, N1, N2)
        # a problem may bring its own condenser class (a time-invariant linear part:
        # quasiperiodic.dual_frequency.HarmonicCondenser, one LU per harmonic)
        self.condenser = problem.info.get("condenser", TorusCondenser)(problem, lattice)
        self.n_unknowns = lattice.n_real * problem.m

    def set_shift(self, xs: FloatArray, lam: float) -> None:
        """Delta from the nonlinearity's Jacobian averaged over the torus at xs (positive
        parts of the diagonals of -<dF/dq>, -<dF/dv>), as the periodic condensation."""
        p = self.problem
        if not p.m:
            return
        w = self.lattice.frequencies(*p.frequencies(lam))
        q = self.aft.sample(xs)
        v = self.aft.sample(derivative(xs, w))
        _, dfq, dfv = p.elements.force_and_jacobian(q, v)
        Kr = np.diag(np.maximum(np.diag(-np.mean(dfq, axis=0)), 0.0))
        Cr = np.diag(np.maximum(np.diag(-np.mean(dfv, axis=0)), 0.0))
        if np.all(np.isfinite(Kr)) and np.all(np.isfinite(Cr)):
            self.condenser.set_shift(Kr, Cr, lam)

    def residual(self, xs: FloatArray, lam: float, jac: bool = True
                 ) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
        """R (n_real, m) and, if jac, dR/dxs (nu, nu) and dR/dlam (nu,)."""
        nr, m = self.lattice.n_real, self.problem.m
        xs = np.asarray(xs, dtype=float).reshape(nr, m)
        cond = self.condenser.condense(lam, deriv=False)
        nl = torus_force(self.problem, self.aft, xs, lam, jac)
        Dl = self.condenser.delta_real()
        g = nl.G.reshape(-1) + Dl @ xs.reshape(-1)
        R = xs.reshape(-1) - cond.Pt.reshape(-1) - cond.Ht @ g
        if not jac:
            return R.reshape(nr, m), None, None
        J = np.eye(nr * m) - cond.Ht @ (nl.dG + Dl)
        dPg = self.condenser.response_derivative(cond, g.reshape(nr, m))  # dPt + dHt g
        dR = -dPg.reshape(-1) - cond.Ht @ nl.dGdlam.reshape(-1)
        return R.reshape(nr, m), J, dR

    def coefficients(self, xs: FloatArray, lam: float) -> np.ndarray:
        """All-DOF one-sided coefficients (nk, n) of the torus at a solution xs."""
        cond = self.condenser.condense(lam, deriv=False)
        xs = np.asarray(xs, dtype=float).reshape(self.lattice.n_real, self.problem.m)
        G = torus_force(self.problem, self.aft, xs, lam, jac=False).G if self.problem.m \
            else np.zeros_like(xs)
        return self.condenser.recover(cond, xs, G)
