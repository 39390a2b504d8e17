"""The torus problem and its coupled linear operator, condensed exactly onto the nonlinear DOFs.

The linear part has coefficients periodic in ``theta2 = w_b t`` (the moving-base terms of
a harmonic base law):

    M q'' + D(theta2) q' + K(theta2) q = f(theta) + S^T F_nl(q_n, q_n'),
    D(theta2) = sum_{|j| <= b} D_j e^{i j theta2},   K(theta2) = sum_{|j| <= b} K_j e^{i j theta2}

(``D_{-j} = conj(D_j)``; b = 2 for the built-in laws, whose coefficients hold w_b(t),
w_b(t)^2 and dw_b/dt). Balancing ``exp(i (k1 theta1 + k2 theta2))`` gives, for harmonic
``(k1, k2)`` with ``omega_k = k1 Omega + k2 w_b``,

    sum_{|j| <= b} Z_{k, j} X_{(k1, k2 - j)} = F_k + S^T G_k,
    Z_{k, j} = K_j + i omega_{(k1, k2-j)} D_j - delta_{j0} omega_k^2 M.

The operator couples k2 to k2 +- 1, +- 2 but never two values of k1 (the base terms do
not depend on theta1): it is block diagonal over k1, one complex block of
``n (2 h(k1) + 1)`` unknowns per k1 (the k1 = 0 block on the two-sided ``c_{0,k2}``,
:func:`~rotorsfd.quasiperiodic.torus_fourier.block_vectors`). Harmonics with k2 beyond the
truncation are dropped from the coupling (the truncation).

**Condensation.** As in :mod:`rotorsfd.harmonic.condensation`, a fixed fictitious
spring/damper ``Delta_k = K_r + i omega_k^* C_r`` on the nonlinear DOFs (omega^* the
frequencies when it was set) is added to both sides, and with ``Zt = Z + S^T Delta S`` per
block (one complex LU of the whole k1 block: exact, since the harmonics of one block
couple)

    X = u + C (G + Delta Xs),   u = Zt^{-1} F,   C = Zt^{-1} S^T,
    R(Xs, lam) = Xs - Pt - Ht (G(Xs) + Delta Xs) = 0,   Ht = S C,  Pt = S u,

so the receptance ``Ht`` couples the k2 harmonics of one k1 at the nonlinear DOFs: the
condensed unknowns are those of the nonlinear DOFs only, as in the periodic case, at the
price of a solve of size ``n (2h + 1)`` per block instead of n per harmonic (banded when
the rotor's matrices are: :mod:`~rotorsfd.quasiperiodic.torus_columns` writes each block
straight into band storage, DOF-major; :func:`column_operator` builds the dense block,
the reference of the tests). Exact
derivatives: ``dHt = -S Zt^{-1} dZ C``, ``dPt = S Zt^{-1} (dF - dZ u)``.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.harmonic.fourier import to_complex
from rotorsfd.harmonic.residual import real_blocks
from rotorsfd.quasiperiodic.torus_bands import TorusBands, two_sided
from rotorsfd.quasiperiodic.torus_columns import (
    BandedColumn,
    column_pattern,
    dof_major,
    half_bandwidth,
    harmonic_major,
    two_sided_band,
)
from rotorsfd.quasiperiodic.torus_fourier import (
    TorusLattice,
    block_real_indices,
    block_real_maps,
    block_vectors,
    from_blocks,
)

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass
class TorusProblem:
    """A second-order system with theta2-periodic linear terms and a local nonlinearity.

    ``coefficients(lam) -> (D, K)``, each (b+1, n, n) complex: D_j, K_j for j = 0..b
    (module docstring); ``dcoefficients(lam)`` their lam-derivatives. ``forcing(lam,
    lattice) -> (nk, n)`` one-sided coefficients F_k of f on the half lattice,
    ``dforcing`` their derivative. ``frequencies(lam) -> (Omega, w_b)``,
    ``dfrequencies(lam)``. ``elements``: the nonlinear force (an
    :class:`~rotorsfd.elements.ElementSet`: ``force``, ``force_and_jacobian`` over sample
    axes, ``limit``) on ``nl_dofs``; ``scaling`` (n,) the per-DOF length scales.
    ``bands``: the same linear part in sparse storage
    (:class:`~rotorsfd.quasiperiodic.torus_bands.TorusBands`): the condenser reads its
    band entries only, no dense n x n array (``M`` is then None above
    :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs).
    """

    n_dof: int
    nl_dofs: NDArray[np.int64]
    M: FloatArray
    coefficients: Callable[[float], tuple[ComplexArray, ComplexArray]]
    dcoefficients: Callable[[float], tuple[ComplexArray, ComplexArray]]
    forcing: Callable[[float, TorusLattice], ComplexArray]
    dforcing: Callable[[float, TorusLattice], ComplexArray]
    frequencies: Callable[[float], tuple[float, float]]
    dfrequencies: Callable[[float], tuple[float, float]]
    elements: Any = None
    scaling: FloatArray | float = 1.0
    name: str = "torus problem"
    info: dict = field(default_factory=dict)
    bands: TorusBands | None = None

    def __post_init__(self) -> None:
        self.nl_dofs = np.atleast_1d(np.asarray(self.nl_dofs, dtype=np.int64))

    @property
    def m(self) -> int:
        return int(self.nl_dofs.size)

    @property
    def dof_scale(self) -> FloatArray:
        return np.broadcast_to(np.asarray(self.scaling, dtype=float), (self.n_dof,)).copy()

    def limit(self, q_nl: FloatArray) -> float:
        """The elements' validity measure of samples (0 without elements)."""
        if self.elements is None or not self.m:
            return 0.0
        return float(self.elements.limit(q_nl))


def dense_mass(problem: TorusProblem) -> FloatArray:
    """The dense M of ``problem`` (from its bands when it keeps them: the dense
    references and the Hill matrix only)."""
    return problem.M if problem.M is not None else problem.bands.M.toarray()


def column_operator(problem: TorusProblem, lattice: TorusLattice, k1: int, lam: float,
                    deriv: bool = False) -> tuple[ComplexArray, ComplexArray | None]:
    """The block Z of column k1 (p n, p n), p = 2h+1, rows and columns ordered (k2 from
    -h, DOF), and its lam-derivative (module docstring)."""
    n, h = problem.n_dof, lattice.h(k1)
    p = 2 * h + 1
    D, K = problem.coefficients(lam)
    b = D.shape[0] - 1
    om, wb = problem.frequencies(lam)
    w = k1 * om + np.arange(-h, h + 1) * wb
    Z = np.zeros((p, n, p, n), dtype=complex)
    if deriv:
        dD, dK = problem.dcoefficients(lam)
        dom, dwb = problem.dfrequencies(lam)
        dw = k1 * dom + np.arange(-h, h + 1) * dwb
        dZ = np.zeros_like(Z)
    for j in range(-min(b, p - 1), min(b, p - 1) + 1):   # Z[r, :, r - j, :]
        rr = np.arange(max(0, j), min(p, p + j))
        cc = rr - j
        Dj = D[j] if j >= 0 else np.conj(D[-j])
        Kj = K[j] if j >= 0 else np.conj(K[-j])
        Z[rr, :, cc, :] = Kj[None] + 1j * w[cc, None, None] * Dj[None]
        if deriv:
            dDj = dD[j] if j >= 0 else np.conj(dD[-j])
            dKj = dK[j] if j >= 0 else np.conj(dK[-j])
            dZ[rr, :, cc, :] = dKj[None] + 1j * (dw[cc, None, None] * Dj[None]
                                                 + w[cc, None, None] * dDj[None])
    diag = np.arange(p)
    M = dense_mass(problem)
    Z[diag, :, diag, :] -= (w**2)[:, None, None] * M[None]
    if deriv:
        dZ[diag, :, diag, :] -= (2 * w * dw)[:, None, None] * M[None]
    shape = (p * n, p * n)
    return Z.reshape(shape), (dZ.reshape(shape) if deriv else None)


def complex_to_real(lattice: TorusLattice, k1: int, A: ComplexArray, width: int
                    ) -> tuple[NDArray[np.int64], FloatArray]:
    """A complex column operator A (p w, p w) as a real matrix on the real layout:
    ``(global indices g, Re((U x I) A (T x I)))`` with g into the flattened (n_real, w)
    layout (:func:`~rotorsfd.quasiperiodic.torus_fourier.block_real_maps`)."""
    UI, TI, g = real_maps(lattice, k1, width)
    return g, (UI @ A @ TI).real


@lru_cache(maxsize=256)
def real_maps(lattice: TorusLattice, k1: int, width: int
              ) -> tuple[ComplexArray, ComplexArray, NDArray[np.int64]]:
    """``(U x I, T x I, g)`` of :func:`complex_to_real` (cached per lattice column)."""
    T, U = block_real_maps(lattice, k1)
    eye = np.eye(width)
    idx = block_real_indices(lattice, k1)
    g = (idx[:, None] * width + np.arange(width)[None, :]).ravel()
    return np.kron(U, eye), np.kron(T, eye), g


@dataclass
class TorusCondensed:
    """Condensed operators at one lam, in the real layout of the nonlinear DOFs:
    ``Ht`` (n_real m, n_real m), ``Pt`` (n_real, m), their lam-derivatives (None when not
    asked), and per k1 ``u`` (p n,) and ``C`` (p n, p m) for the recovery."""

    lam: float
    Ht: FloatArray
    Pt: FloatArray
    u: list[ComplexArray]
    C: list[ComplexArray]
    dHt: FloatArray | None = None
    dPt: FloatArray | None = None
    #: per k1: the factorised column, its DOF-major solution [C, u], and the band entries
    #: of dD_j, dK_j (for :meth:`TorusCondenser.response_derivative`)
    columns: list[Any] | None = None
    solutions: list[ComplexArray] | None = None
    dbands: tuple[ComplexArray, ComplexArray] | None = None


class TorusCondenser:
    """Exact condensation of the torus equations onto the nonlinear DOFs (module doc)."""

    def __init__(self, problem: TorusProblem, lattice: TorusLattice) -> None:
        self.problem, self.lattice = problem, lattice
        m = problem.m
        self.Kr = np.zeros((m, m))
        self.Cr = np.zeros((m, m))
        self.freq_shift = (0.0, 0.0)
        self._cache: TorusCondensed | None = None

    def set_shift(self, Kr: FloatArray, Cr: FloatArray, lam: float) -> None:
        """Delta_k = Kr + i omega_k(lam) Cr, held fixed (also when lam changes)."""
        self.Kr, self.Cr = np.asarray(Kr, float), np.asarray(Cr, float)
        om, wb = self.problem.frequencies(lam)
        self.freq_shift = (float(om), float(wb))
        self._cache = None

    def delta(self, k1: int) -> ComplexArray:
        """(p, m, m) shift of column k1, k2 = -h..h."""
        om_s, wb_s = self.freq_shift
        h = self.lattice.h(k1)
        w = k1 * om_s + np.arange(-h, h + 1) * wb_s
        return self.Kr[None] + 1j * w[:, None, None] * self.Cr[None]

    def delta_real(self) -> FloatArray:
        """Delta on the real layout (n_real m, n_real m), per half-lattice harmonic."""
        w = self.lattice.frequencies(*self.freq_shift)
        stack = self.Kr[None] + 1j * w[:, None, None] * self.Cr[None]
        return real_blocks(stack)

    def condense(self, lam: float, deriv: bool = True) -> TorusCondensed:
        """Receptance, particular response and (deriv) their lam-derivatives at lam; the
        column blocks written in band storage (:mod:`~rotorsfd.quasiperiodic.
        torus_columns`), one LU each."""
        c = self._cache
        if c is not None and c.lam == lam and (c.dHt is not None or not deriv):
            return c
        p_, lat = self.problem, self.lattice
        n, m, s = p_.n_dof, p_.m, p_.nl_dofs
        nr = lat.n_real
        F = block_vectors(lat, p_.forcing(lam, lat))
        om, wb = p_.frequencies(lam)
        if deriv:
            dF = block_vectors(lat, p_.dforcing(lam, lat))
            dom, dwb = p_.dfrequencies(lam)
        b, beta, (Dv, Kv, Mv), dbands = self.band_coefficients(lam)
        dDv, dKv = dbands if deriv else (None, None)
        Ht = np.zeros((nr * m, nr * m))
        Pt = np.zeros((nr, m))
        dHt = np.zeros_like(Ht) if deriv else None
        dPt = np.zeros_like(Pt) if deriv else None
        us, Cs, cols, sols = [], [], [], []
        for k1 in range(lat.H1 + 1):
            h = lat.h(k1)
            p = 2 * h + 1
            pt = column_pattern(n, p, b, beta)
            w = k1 * om + np.arange(-h, h + 1) * wb
            dw = k1 * dom + np.arange(-h, h + 1) * dwb if deriv else None
            col = BandedColumn(pt, Dv, Kv, Mv, w, s, self.delta(k1) if m else None)
            rows = (s[None, :] * p + np.arange(p)[:, None]).ravel()   # S, DOF-major
            rhs = np.zeros((p * n, p * m + 1), dtype=complex)
            rhs[rows, np.arange(p * m)] = 1.0
            rhs[:, -1] = dof_major(F[k1].ravel(), p, n)
            sol, sol2 = col.condense(rhs, dDv, dKv, dw, dof_major(dF[k1].ravel(), p, n)
                                     if deriv else None)
            us.append(harmonic_major(sol[:, -1], p, n))
            Cs.append(harmonic_major(sol[:, :-1], p, n))
            cols.append(col)
            sols.append(sol)
            idx = block_real_indices(lat, k1)
            _, U = block_real_maps(lat, k1)
            Pt[idx] = (U @ sol[rows, -1].reshape(p, m)).real
            if m:
                g, R = complex_to_real(lat, k1, sol[rows, :-1], m)
                Ht[np.ix_(g, g)] = R
            if not deriv:
                continue
            sol2 = sol2[rows]             # Zt^-1 [-dZ C, dF - dZ u]
            dPt[idx] = (U @ sol2[:, -1].reshape(p, m)).real
            if m:
                g, R = complex_to_real(lat, k1, sol2[:, :-1], m)
                dHt[np.ix_(g, g)] = R
        out = TorusCondensed(lam, Ht, Pt, us, Cs, dHt, dPt, cols, sols, dbands)
        self._cache = out
        return out

    def band_coefficients(self, lam: float) -> tuple[int, int, tuple[ComplexArray, ...],
                                                      tuple[ComplexArray, ComplexArray]]:
        """``(b, beta, (Dv, Kv, Mv), (dDv, dKv))``: the two-sided band entries (2b + 1, ne)
        of D_j, K_j (and M (ne,)) at lam on ``|I - J| <= beta`` (beta the half bandwidth
        of the matrices and the shift's couplings), from ``problem.bands`` when set (no
        n x n array), else read from the dense stacks."""
        p_ = self.problem
        s = p_.nl_dofs
        shift = 0
        if p_.m:                                # the shift's couplings stay in the band
            a_, b_ = np.nonzero(np.abs(self.Kr) + np.abs(self.Cr))
            shift = int(np.abs(s[a_] - s[b_]).max(initial=0))
        bands = p_.bands
        if bands is not None:
            beta = max(bands.beta, shift)
            D, K = bands.band(lam, beta)
            dD, dK = bands.band(lam, beta, deriv=True)
            Mv = bands.entries(beta)[2]
            return (D.shape[0] - 1, beta, (two_sided(D), two_sided(K), Mv),
                    (two_sided(dD), two_sided(dK)))
        D, K = p_.coefficients(lam)
        dD, dK = p_.dcoefficients(lam)
        beta = max(half_bandwidth(p_.M[None], D, K, dD, dK), shift)   # dZ in the same band
        I, J = column_pattern(p_.n_dof, 1, D.shape[0] - 1, beta).band_entries
        return (D.shape[0] - 1, beta,
                (two_sided_band(D, I, J), two_sided_band(K, I, J), p_.M[I, J]),
                (two_sided_band(dD, I, J), two_sided_band(dK, I, J)))

    def response_derivative(self, cond: TorusCondensed, g: FloatArray) -> FloatArray:
        """``d(Pt + Ht g)/dlam`` at fixed g (n_real, m), real layout: per k1 column
        ``S Zt^-1 (dF - dZ X)`` with ``X = u + C g`` the column's response, one solve
        (``dPt + dHt g`` without forming dHt: ``dHt = -S Zt^-1 dZ C``)."""
        p_, lat = self.problem, self.lattice
        n, m, s = p_.n_dof, p_.m, p_.nl_dofs
        lam = cond.lam
        dF = block_vectors(lat, p_.dforcing(lam, lat))
        dom, dwb = p_.dfrequencies(lam)
        dDv, dKv = cond.dbands
        out = np.zeros((lat.n_real, m))
        gb = block_vectors(lat, to_complex(np.asarray(g, dtype=float).reshape(-1, m))) \
            if m else None
        for k1 in range(lat.H1 + 1):
            h = lat.h(k1)
            p = 2 * h + 1
            sol = cond.solutions[k1]
            X = sol[:, -1] + (sol[:, :-1] @ gb[k1].ravel() if m else 0.0)
            dw = k1 * dom + np.arange(-h, h + 1) * dwb
            y = cond.columns[k1].direction(X, dDv, dKv, dw, dof_major(dF[k1].ravel(), p, n))
            rows = (s[None, :] * p + np.arange(p)[:, None]).ravel()
            _, U = block_real_maps(lat, k1)
            out[block_real_indices(lat, k1)] = (U @ y[rows].reshape(p, m)).real
        return out

    def recover(self, cond: TorusCondensed, xs: FloatArray, G: FloatArray) -> ComplexArray:
        """All-DOF one-sided coefficients (nk, n): ``X = u + C (G + Delta Xs)`` per k1."""
        lat, n, m = self.lattice, self.problem.n_dof, self.problem.m
        cols = []
        if m:
            rhs = (G.reshape(-1) + self.delta_real() @ xs.reshape(-1)).reshape(-1, m)
            rb = block_vectors(lat, to_complex(rhs))
        for k1 in range(lat.H1 + 1):
            p = 2 * lat.h(k1) + 1
            X = cond.u[k1].copy()
            if m:
                X = X + cond.C[k1] @ rb[k1].ravel()
            cols.append(X.reshape(p, n))
        return from_blocks(lat, cols)
