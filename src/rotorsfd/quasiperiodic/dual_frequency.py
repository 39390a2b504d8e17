"""The two-frequency response of a dual-spool rotor: the unbalance of each spool at its own
speed, Omega_LP = Omega and Omega_HP = r Omega (issue 20 item 3).

    M q'' + (C + Omega sum_s r_s G_s) q' + K q = F_0 + F_LP(t) + F_HP(t) + F_nl

(:mod:`rotorsfd.model.multishaft`). The unbalances on the shafts at ratio 1 turn at Omega,
those on the shaft at ratio r at r Omega (:mod:`rotorsfd.model.multishaft_loads`), so the
response lies on the 2-torus ``theta1 = Omega t``, ``theta2 = r Omega t``:

    q(t) = Re sum_k X_k exp(i (k1 Omega + k2 r Omega) t)

(:mod:`~rotorsfd.quasiperiodic.torus_fourier`). Unlike under a harmonic base law, the
linear part is time-invariant: the coefficient series of
:class:`~rotorsfd.quasiperiodic.torus_linear.TorusProblem` has b = 0,

    D_0 = C + Omega G,   K_0 = K,   dD_0/dOmega = G,

so every harmonic (k1, k2) of the linear operator is its own block,
``Z_k = K + i omega_k D_0 - omega_k^2 M`` with ``omega_k = (k1 + k2 r) Omega``, and the
condensation is per harmonic (the torus condenser's block of one k1 is block diagonal in
k2; its banded LU does that work). Above :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs
the linear part is kept as the rotor's CSR matrices (:func:`spool_bands`) and each
harmonic condensed from band storage
(:class:`~rotorsfd.quasiperiodic.dual_frequency_banded.BandedHarmonicCondenser`). The
loads, one-sided on the half lattice
(``F = Fc cos + Fs sin = Re((Fc - i Fs) e^{i theta})``):

    F_(0,0) = F_0 (gravity, constant base translations),
    F_(1,0) = Omega^2 (Fc_1 - i Fs_1)            (LP unbalances, their pattern at speed 1)
    F_(0,1) = (r Omega)^2 (Fc_1 - i Fs_1)        (HP unbalances)

exact in Omega with ``dF/dOmega = 2 F / Omega`` (and the affine F_0). The nonlinear force
is the elements' (an SFD on either spool, an intershaft SFD on the relative motion),
sampled on the torus by the 2D AFT. The time-domain counterpart runs each shaft's
unbalance at its own speed (:func:`~rotorsfd.analyses.td_integration.time_domain_inputs`),
which the Lyapunov stability of a torus integrates
(:func:`~rotorsfd.quasiperiodic.torus_stability.torus_lyapunov`).

At a rational ratio r = p / q the motion is periodic at ``w0 = Omega / q`` with the LP load
on harmonic q and the HP load on harmonic p (:func:`common_period_problem`, the periodic
HB that checks the torus).
"""

from __future__ import annotations

import dataclasses
from fractions import Fraction

import numpy as np
import scipy.sparse as sp
from scipy.linalg import lu_factor, lu_solve

from rotorsfd.errors import ConfigError
from rotorsfd.harmonic.fourier import to_complex
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.model.multishaft import check_base_motion
from rotorsfd.model.multishaft_loads import second_ratio, split_unbalances
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import unbalance_harmonics
from rotorsfd.quasiperiodic.dual_frequency_banded import BandedHarmonicCondenser
from rotorsfd.quasiperiodic.torus_bands import TorusBands, dense_coefficients
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
    dense_mass,
)

__all__ = ["HarmonicCondenser", "common_period_problem", "dual_spool_problem", "one_sided",
           "spool_ratio"]


def one_sided(unbalances, rotor, speed: float) -> np.ndarray:
    """``Fc - i Fs`` (n,) of ``unbalances`` turning at ``speed`` (fixed base)."""
    Fc, Fs = unbalance_harmonics(unbalances, rotor, speed)
    return Fc - 1j * Fs


def spool_ratio(system: RotorSystem) -> float:
    """r = Omega_HP / Omega_LP of ``system``: the ratio of the unbalances not on the first
    spool, else the one other ratio of the rotor's shafts. ConfigError for a single-speed
    rotor (the response is then periodic) or several other ratios."""
    r = second_ratio(system.rotor, system.unbalances)
    if r is not None:
        return r
    ratios = sorted({float(v) for v in getattr(system.rotor, "speed_ratios", [1.0])} - {1.0})
    if len(ratios) != 1:
        raise ConfigError("rotor.shafts.speed_ratio", ratios or [1.0],
                          "a two-frequency (dual-spool) response needs exactly one shaft "
                          "speed ratio other than 1")
    return ratios[0]


def _check(system: RotorSystem) -> None:
    if not system.base.is_constant:
        raise ConfigError("base", "harmonic", "the dual-spool response needs a base motion "
                          "constant in time (a harmonic base law would add a third "
                          "frequency); use `rotorsfd simulate`")
    check_base_motion(system.rotor, system.base)


def dual_spool_problem(system: RotorSystem, ratio: float | None = None) -> TorusProblem:
    """The torus problem of a dual-spool ``system`` continued in lam = Omega_LP [rad/s]
    with theta2 = ``ratio`` Omega t (default :func:`spool_ratio`; module docstring)."""
    _check(system)
    r = spool_ratio(system) if ratio is None else float(ratio)
    if not (np.isfinite(r) and r > 0.0 and r != 1.0):
        raise ConfigError("speed_ratio", r, "must be a finite number > 0 other than 1")
    rot = system.rotor
    n = system.n_dof
    own, other = split_unbalances(rot, system.unbalances)
    hp = other.get(r, ())
    if set(other) - {r}:
        raise ConfigError("unbalance.node", [u.node for us in other.values() for u in us],
                          f"unbalances at speed ratios {sorted(other)}: the torus has the "
                          f"ratio {r:g} only")
    lp1, hp1 = one_sided(own, rot, 1.0), one_sided(hp, rot, r)
    f0, f1 = system.static_force(0.0), system.static_force(1.0)
    bands, M = None, None
    if n > DENSE_MAX_DOF and hasattr(rot, "G_csr"):   # CSR terms, no n x n array
        bands = spool_bands(system)
        coefficients, dcoefficients = dense_coefficients(bands)
        condenser = BandedHarmonicCondenser
    else:
        M = np.asarray(rot.M, dtype=float)
        G = np.asarray(rot.G, dtype=float)
        _, D0, K0 = system.matrices(0.0)
        D0, K0 = np.asarray(D0, dtype=float), np.asarray(K0, dtype=float)
        condenser = HarmonicCondenser

        def coefficients(lam: float):
            return (D0 + float(lam) * G)[None].astype(complex), K0[None].astype(complex)

        def dcoefficients(lam: float):
            return G[None].astype(complex), np.zeros((1, n, n), dtype=complex)

    def place(lattice: TorusLattice, static: np.ndarray, lp: np.ndarray, hpv: np.ndarray
              ) -> np.ndarray:
        F = np.zeros((lattice.nk, n), dtype=complex)
        F[lattice.index(0, 0)] = static
        if lattice.H1 >= 1 and lattice.h(1) >= 0:
            F[lattice.index(1, 0)] = lp
        if lattice.h(0) >= 1:
            F[lattice.index(0, 1)] = hpv
        return F

    def forcing(lam: float, lattice: TorusLattice) -> np.ndarray:
        om = float(lam)
        return place(lattice, f0 + om * (f1 - f0), om**2 * lp1, om**2 * hp1)

    def dforcing(lam: float, lattice: TorusLattice) -> np.ndarray:
        om = float(lam)
        return place(lattice, f1 - f0, 2 * om * lp1, 2 * om * hp1)

    return TorusProblem(
        n_dof=n, nl_dofs=system.nl_dofs, M=M, bands=bands, coefficients=coefficients,
        dcoefficients=dcoefficients, forcing=forcing, dforcing=dforcing,
        frequencies=lambda lam: (float(lam), r * float(lam)),
        dfrequencies=lambda lam: (1.0, r),
        elements=system.elements if len(system.elements) else None,
        scaling=system.dof_scale(), name="dual-spool torus in speed",
        info={"speed_ratio": r, "parameter": "speed", "base_band": 0,
              "condenser": condenser,
              "unbalance_lp": len(own), "unbalance_hp": len(hp)})


def spool_bands(system: RotorSystem) -> TorusBands:
    """The linear part ``D_0 = C + Omega G, K_0 = K`` (module docstring) as CSR terms
    (C, G, K) with the weights ``a = (1, Omega, 0)``, ``c = (0, 0, 1)``
    (:class:`~rotorsfd.quasiperiodic.torus_bands.TorusBands`); ConfigError for a damping
    kept beside the band (modal damping of a few modes)."""
    M, D0, K0 = system.split_matrices(0.0)
    if not sp.issparse(D0):
        raise ConfigError("rotor.damping.kind", "modal", f"the dual-spool torus above "
                          f"{DENSE_MAX_DOF} DOFs keeps the band and does not take modal "
                          "damping (a full matrix) yet")
    G = system.rotor.G_csr
    one = np.array([[1.0, 0.0, 0.0]], dtype=complex)
    return TorusBands(M, (D0, G, K0),
                      lambda lam: (one + float(lam) * np.array([[0.0, 1.0, 0.0]]),
                                   np.array([[0.0, 0.0, 1.0]], dtype=complex)),
                      lambda lam: (np.array([[0.0, 1.0, 0.0]], dtype=complex),
                                   np.zeros((1, 3), dtype=complex)))


class HarmonicCondenser(TorusCondenser):
    """The exact condensation of :class:`~rotorsfd.quasiperiodic.torus_linear.
    TorusCondenser` for a time-invariant linear part (b = 0, module docstring): the block
    of one k1 is block diagonal over k2, so each harmonic gets its own n x n LU of
    ``Z_k + S^T Delta_k S`` instead of one of the whole (2h + 1) n block;
    ``C = Z_k^-1 S^T``, ``u = Z_k^-1 F_k``, ``dZ_k = dK + i (domega_k D + omega_k dD) -
    2 omega_k domega_k M``. The same ``TorusCondensed`` (the tests compare the two)."""

    def __init__(self, problem: TorusProblem, lattice: TorusLattice) -> None:
        super().__init__(problem, lattice)
        self.last: TorusCondensed | None = None

    def set_shift(self, Kr, Cr, lam: float) -> None:
        super().set_shift(Kr, Cr, lam)
        self.last = None

    def condense(self, lam: float, deriv: bool = True) -> TorusCondensed:
        c = self.last
        if c is not None and c.lam == lam and (c.dHt is not None or not deriv):
            return c
        p_, lat = self.problem, self.lattice
        n, m, s = p_.n_dof, p_.m, p_.nl_dofs
        Dc, Kc = p_.coefficients(lam)
        if Dc.shape[0] != 1:
            raise ValueError("HarmonicCondenser needs a time-invariant linear part (b = 0)")
        D, K, M = Dc[0], Kc[0], np.asarray(dense_mass(p_), dtype=complex)
        om, wb = p_.frequencies(lam)
        F = block_vectors(lat, p_.forcing(lam, lat))
        if deriv:
            dDc, dKc = p_.dcoefficients(lam)
            dD, dK = dDc[0], dKc[0]
            dom, dwb = p_.dfrequencies(lam)
            dF = block_vectors(lat, p_.dforcing(lam, lat))
        nr = lat.n_real
        Ht, Pt = np.zeros((nr * m, nr * m)), np.zeros((nr, m))
        dHt = np.zeros_like(Ht) if deriv else None
        dPt = np.zeros_like(Pt) if deriv else None
        us, Cs, lus = [], [], []
        eye = np.zeros((n, m), dtype=complex)
        eye[s, np.arange(m)] = 1.0
        for k1 in range(lat.H1 + 1):
            h = lat.h(k1)
            p = 2 * h + 1
            dl = self.delta(k1)
            C = np.zeros((p * n, p * m), dtype=complex)
            u = np.zeros(p * n, dtype=complex)
            dC = np.zeros((p * m, p * m), dtype=complex)
            du = np.zeros(p * m, dtype=complex)
            col_lus = []
            for r, k2 in enumerate(range(-h, h + 1)):
                w = k1 * om + k2 * wb
                Z = K + 1j * w * D - w**2 * M
                Z[np.ix_(s, s)] += dl[r]
                lu = lu_factor(Z, check_finite=False)
                col_lus.append(lu)
                sol = lu_solve(lu, np.column_stack([eye, F[k1][r]]), check_finite=False)
                rn, rm = slice(r * n, (r + 1) * n), slice(r * m, (r + 1) * m)
                C[rn, rm], u[rn] = sol[:, :m], sol[:, m]
                if deriv:
                    dw = k1 * dom + k2 * dwb
                    dZ = dK + 1j * (dw * D + w * dD) - 2 * w * dw * M
                    sol2 = lu_solve(lu, np.column_stack([dZ @ sol[:, :m],
                                                         dF[k1][r] - dZ @ sol[:, m]]),
                                    check_finite=False)[s]
                    dC[rm, rm], du[rm] = sol2[:, :m], sol2[:, m]
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
                    g, R = complex_to_real(lat, k1, -dC, m)
                    dHt[np.ix_(g, g)] = R
            us.append(u)
            Cs.append(C)
            lus.append(col_lus)
        out = TorusCondensed(lam, Ht, Pt, us, Cs, dHt, dPt, columns=lus)
        self.last = out
        return out

    def response_derivative(self, cond: TorusCondensed, g: np.ndarray) -> np.ndarray:
        """``d(Pt + Ht g)/dlam`` at fixed g (n_real, m): per harmonic ``S Zt_k^-1 (dF_k -
        dZ_k X_k)`` with ``X_k = u_k + C_k g_k`` (one solve with the stored LU)."""
        p_, lat = self.problem, self.lattice
        n, m, s = p_.n_dof, p_.m, p_.nl_dofs
        lam = cond.lam
        Dc = p_.coefficients(lam)[0]
        dDc, dKc = p_.dcoefficients(lam)
        D, dD, dK, M = Dc[0], dDc[0], dKc[0], np.asarray(dense_mass(p_), dtype=complex)
        om, wb = p_.frequencies(lam)
        dom, dwb = p_.dfrequencies(lam)
        dF = block_vectors(lat, p_.dforcing(lam, lat))
        gb = block_vectors(lat, to_complex(np.asarray(g, dtype=float).reshape(-1, m))) \
            if m else None
        out = np.zeros((lat.n_real, m))
        for k1 in range(lat.H1 + 1):
            h = lat.h(k1)
            col = np.zeros((2 * h + 1, m), dtype=complex)
            for r, k2 in enumerate(range(-h, h + 1)):
                w, dw = k1 * om + k2 * wb, k1 * dom + k2 * dwb
                X = cond.u[k1][r * n:(r + 1) * n]
                if m:
                    X = X + cond.C[k1][r * n:(r + 1) * n, r * m:(r + 1) * m] @ gb[k1][r]
                dZ = dK + 1j * (dw * D + w * dD) - 2 * w * dw * M
                col[r] = lu_solve(cond.columns[k1][r], dF[k1][r] - dZ @ X,
                                  check_finite=False)[s]
            _, U = block_real_maps(lat, k1)
            out[block_real_indices(lat, k1)] = (U @ col).real
        return out


def common_period_problem(system: RotorSystem, p: int, q: int) -> PeriodicProblem:
    """The periodic HB problem of a dual-spool ``system`` at r = p / q (a rational ratio,
    p / q in lowest terms, equal to the HP shaft's ratio): fundamental ``w0 = Omega / q``,
    the LP unbalances on harmonic q, the HP ones on harmonic p, lam = Omega."""
    _check(system)
    frac = Fraction(int(p), int(q))
    if (frac.numerator, frac.denominator) != (p, q) or p <= 0:
        raise ConfigError("p/q", (p, q), "need positive integers in lowest terms")
    r = spool_ratio(system)
    if abs(r - p / q) > 1e-12 * r:
        raise ConfigError("p/q", (p, q), f"must equal the HP speed ratio {r:g}")
    rot = system.rotor
    own, other = split_unbalances(rot, system.unbalances)
    hp = other.get(r, ())
    base = RotorSystem(rot, system.elements, own, system.base).periodic_problem("speed")
    lp1, hp1 = one_sided(own, rot, 1.0), one_sided(hp, rot, r)
    f0, f1 = system.static_force(0.0), system.static_force(1.0)

    def forcing(lam: float, H: int) -> np.ndarray:
        F = np.zeros((H + 1, rot.n_dof), dtype=complex)
        F[0] = f0 + lam * (f1 - f0)
        if q <= H:
            F[q] += lam**2 * lp1
        if p <= H:
            F[p] += lam**2 * hp1
        return F

    def dforcing(lam: float, H: int) -> np.ndarray:
        F = np.zeros((H + 1, rot.n_dof), dtype=complex)
        F[0] = f1 - f0
        if q <= H:
            F[q] += 2 * lam * lp1
        if p <= H:
            F[p] += 2 * lam * hp1
        return F

    return dataclasses.replace(base, forcing=forcing, dforcing=dforcing,
                               frequency=lambda lam: lam / q, dfrequency=lambda lam: 1.0 / q)
