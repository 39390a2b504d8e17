"""The torus problem of a rotor on a base moving harmonically at w_b (from a RotorSystem).

    M q'' + (C + Omega G + C_base(t)) q' + (K + K_base(t)) q = F_mu(t) + F_base(t) + F_nl

With base laws ``w(t) = mean + A sin(w_b t + phi)`` (rates) and harmonic translations at
the same w_b, the base state is periodic in ``theta2 = w_b t``, and so are the scalar
coefficients of :func:`~rotorsfd.model.base_terms.base_coefficients` (they hold w, w^2,
products of rates and dw/dt: trigonometric polynomials of degree 2 in theta2). C_base,
K_base and F_base are those coefficients times constant matrices and vectors
(:class:`~rotorsfd.model.base_terms.BaseBasis`), so their Fourier coefficients in theta2 are

    D_j = delta_j0 (C + Omega G) + sum_i c^C_{i,j} B_i,   K_j = delta_j0 K + sum_i c^K_{i,j} B_i,
    F_base,j = sum_i c^F_{i,j} f_i,

with ``c_{i,j}`` the discrete Fourier coefficients of the coefficients sampled at Nb
points of theta2: exact (to round-off) for a trigonometric polynomial of degree < Nb/2,
and the degree b is read from them (checked: no content above b; b = 2 for the built-in
laws). The unbalance force ``F_mu(Omega t, theta2)`` (:func:`~rotorsfd.model.unbalance.
unbalance_force`, with the base-rotation terms) is sampled on a 4 x Nb grid of the torus
and transformed by a 2D FFT: it sits at k1 = +-1, |k2| <= b.

The dependence on the speed is exact: the base coefficients are affine in Omega (their
derivative is ``c(Omega = 1) - c(Omega = 0)``) and the unbalance force is quadratic in
Omega (its three polynomial coefficients from three speeds).

Storage (:func:`keeps_band`): the sums above are kept unformed, as the CSR matrices
``(C, G, K, B_i)`` with their weights in theta2 and Omega
(:func:`banded_linear_part`, :class:`~rotorsfd.quasiperiodic.torus_bands.TorusBands`):
the condenser reads their band entries only, no n x n array (issue 17 item 2); the
dense stacks (:func:`dense_stacks`, ``banded=False``) are the reference.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model.base_terms import base_coefficients
from rotorsfd.model.sparse import DENSE_MAX_DOF, HALF_BAND
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import unbalance_force
from rotorsfd.quasiperiodic.torus_bands import TorusBands, dense_coefficients
from rotorsfd.quasiperiodic.torus_fourier import TorusLattice
from rotorsfd.quasiperiodic.torus_linear import TorusProblem

#: samples of theta2 for the Fourier coefficients of the base terms
N_BASE = 32
#: content of a base coefficient above the degree b, relative to its largest: must be below
BAND_TOL = 1e-12
PARAMETERS = ("speed", "unbalance")


def base_frequency(system: RotorSystem) -> float:
    """The common frequency w_b [rad/s] of the base laws that vary in time (all harmonic).

    ConfigError if no law varies, if one that varies is not harmonic, if two harmonic
    laws have different frequencies, or if gravity turns with a rotating base."""
    names = ("x", "y", "z", "rolling", "pitching", "yawing")
    laws = (*system.base.translation, *system.base.rotation)
    freqs = []
    for name, law in zip(names, laws, strict=True):
        if law.is_constant:
            continue
        if law.kind != "harmonic":
            raise ConfigError(f"base.{name}.law", law.kind, "a quasi-periodic response "
                              "needs harmonic (or constant, off) base laws")
        freqs.append((name, float(law.frequency)))
    if not freqs:
        raise ConfigError("base", "constant", "a quasi-periodic response needs a harmonic "
                          "base law; under a constant base the response is periodic")
    w_b = freqs[0][1]
    for name, f in freqs[1:]:
        if abs(f - w_b) > 1e-12 * w_b:
            raise ConfigError(f"base.{name}.frequency", f, f"all harmonic base laws need "
                              f"one frequency (base.{freqs[0][0]} has {w_b} rad/s)")
    g = system.base.gravity
    turning = any(not law.is_zero for law in system.base.rotation)
    if g is not None and g.enabled and g.frame == "inertial" and turning:
        raise ConfigError("gravity.frame", "inertial", "under a rotating base the torus "
                          "needs gravity off or fixed to the base (frame = 'base')")
    return w_b


def theta2_series(values: np.ndarray, name: str) -> np.ndarray:
    """Two-sided Fourier coefficients ``c_j`` (..., b+1), j = 0..b, of samples (..., Nb)
    at ``theta2 = 2 pi i / Nb``; b the degree found (ConfigError if not < Nb/4)."""
    nb = values.shape[-1]
    c = np.fft.fft(values, axis=-1) / nb
    scale = np.max(np.abs(c), axis=-1, keepdims=True)
    big = np.abs(c) > BAND_TOL * np.maximum(scale, np.finfo(float).tiny)
    k = np.minimum(np.arange(nb), nb - np.arange(nb))      # |j| of each FFT bin
    b = int(k[np.any(big.reshape(-1, nb), axis=0)].max(initial=0))
    if b >= nb // 4:
        raise ConfigError("base", name, f"the base terms are not a trigonometric "
                          f"polynomial of degree < {nb // 4} in w_b t")
    return c[..., : b + 1]


def keeps_band(system: RotorSystem) -> bool:
    """True when the torus of ``system`` keeps the rotor's CSR storage
    (:class:`~rotorsfd.quasiperiodic.torus_bands.TorusBands`): a rotor assembled sparse,
    above :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs always (a modal damping of a
    few modes is then refused), below it when no modal damping widens the band beyond
    :data:`~rotorsfd.model.sparse.HALF_BAND` (measured as fast as the dense stacks at
    68-196 DOFs, 1.1-1.2x faster per branch at 388: ``python -m
    benchmarks.bench_torus_scale --small``)."""
    r = system.rotor
    if not hasattr(r, "G_csr"):
        return False
    if system.n_dof > DENSE_MAX_DOF:
        return True
    return getattr(r, "damping_lowrank", None) is None and \
        max(getattr(r, "band", (system.n_dof, 0))) <= HALF_BAND


def torus_problem(system: RotorSystem, parameter: str = "speed",
                  speed: float | None = None, banded: bool | None = None) -> TorusProblem:
    """The torus problem of ``system`` under its harmonic base law, continued in
    ``parameter``: "speed" (lam = Omega [rad/s]) or "unbalance" (lam = the first
    unbalance's magnitude [kg m], the others scaled with it, at the fixed ``speed``).
    ``banded`` (default :func:`keeps_band`): the linear part as CSR terms and weights
    (:func:`banded_linear_part`, no dense n x n array) instead of the dense stacks."""
    if parameter not in PARAMETERS:
        raise ConfigError("parameter", parameter, "the torus is continued in " +
                          " or ".join(PARAMETERS))
    if parameter != "speed" and not (speed is not None and speed > 0):
        raise ConfigError("speed", speed, f"continuing in {parameter} needs a speed > 0")
    for e in system.elements:
        if e.inertial:
            raise ConfigError(f"elements.{e.name}.fluid_inertia", True, "the quasi-periodic "
                              "(torus) response does not take a force of the acceleration "
                              "yet: set it to false")
    w_b = base_frequency(system)
    basis = system.basis
    n = system.n_dof
    th2 = 2 * np.pi * np.arange(N_BASE) / N_BASE
    state = system.base.state(th2 / w_b)
    co0, co1 = base_coefficients(state, 0.0), base_coefficients(state, 1.0)

    def series(a: np.ndarray, b: np.ndarray, name: str) -> tuple[np.ndarray, np.ndarray]:
        both = theta2_series(np.stack([a, b - a]), name)   # value at 0 and slope in Omega
        return both[0], both[1]

    cC0, cC1 = series(co0.c_C, co1.c_C, "damping")
    cK0, cK1 = series(co0.c_K, co1.c_K, "stiffness")
    cF0, cF1 = series(co0.c_F, co1.c_F, "load")
    bw = max(cC0.shape[-1], cK0.shape[-1], cF0.shape[-1])

    def pad(c: np.ndarray) -> np.ndarray:
        return np.pad(c, [(0, 0), (0, bw - c.shape[-1])])

    def at(lam: float) -> tuple[float, float]:
        """(speed, unbalance scale) at lam."""
        return (float(lam), 1.0) if parameter == "speed" else (float(speed), lam / U_ref)

    series_C, series_K = (pad(cC0), pad(cC1)), (pad(cK0), pad(cK1))
    bands = None
    if keeps_band(system) if banded is None else banded:
        bands = banded_linear_part(system, series_C, series_K,
                                   lambda lam: at(lam)[0], parameter == "speed")
        coefficients, dcoefficients = dense_coefficients(bands)
    else:
        coefficients, dcoefficients = dense_stacks(system, series_C, series_K,
                                                   lambda lam: at(lam)[0],
                                                   parameter == "speed")
    Fb0 = np.einsum("ij,ia->ja", pad(cF0), basis.vectors)   # (bw, n) two-sided c_j
    Fb1 = np.einsum("ij,ia->ja", pad(cF1), basis.vectors)
    ub = unbalance_polynomial(system, w_b)
    U_ref = system.unbalances[0].magnitude if system.unbalances else 0.0
    if parameter == "unbalance" and U_ref == 0.0:
        raise ConfigError("unbalance", None, "continuing in the unbalance needs a nonzero "
                          "first unbalance")

    def place(lattice: TorusLattice, fb: np.ndarray, fu: np.ndarray) -> np.ndarray:
        """One-sided coefficients on the half lattice of a base load (two-sided c_j of
        theta2) and an unbalance load (c_{1,k2}, k2 = -b..b)."""
        F = np.zeros((lattice.nk, n), dtype=complex)
        for j in range(min(bw, lattice.h(0) + 1)):
            F[lattice.index(0, j)] = fb[j].real if j == 0 else 2 * fb[j]
        if lattice.H1 >= 1:
            b = (fu.shape[0] - 1) // 2
            for k2 in range(-min(b, lattice.h(1)), min(b, lattice.h(1)) + 1):
                F[lattice.index(1, k2)] = 2 * fu[b + k2]
        return F

    def forcing(lam: float, lattice: TorusLattice) -> np.ndarray:
        om, scale = at(lam)
        return place(lattice, Fb0 + om * Fb1, scale * (ub[0] + om * ub[1] + om**2 * ub[2]))

    def dforcing(lam: float, lattice: TorusLattice) -> np.ndarray:
        om = at(lam)[0]
        if parameter == "speed":
            return place(lattice, Fb1, ub[1] + 2 * om * ub[2])
        return place(lattice, 0 * Fb0, (ub[0] + om * ub[1] + om**2 * ub[2]) / U_ref)

    def frequencies(lam: float) -> tuple[float, float]:
        return at(lam)[0], w_b

    def dfrequencies(lam: float) -> tuple[float, float]:
        return (1.0 if parameter == "speed" else 0.0), 0.0

    return TorusProblem(
        n_dof=n, nl_dofs=system.nl_dofs,
        M=None if bands is not None and n > DENSE_MAX_DOF else system.rotor.M,
        coefficients=coefficients, bands=bands,
        dcoefficients=dcoefficients, forcing=forcing, dforcing=dforcing,
        frequencies=frequencies, dfrequencies=dfrequencies,
        elements=system.elements if len(system.elements) else None,
        scaling=system.dof_scale(), name=f"rotor torus in {parameter}",
        info={"base_frequency": w_b, "base_band": bw - 1, "parameter": parameter})


Series = tuple[np.ndarray, np.ndarray]


def dense_stacks(system: RotorSystem, series_C: Series, series_K: Series,
                 speed_of: Callable[[float], float], in_speed: bool
                 ) -> tuple[Callable[[float], Any], Callable[[float], Any]]:
    """``coefficients, dcoefficients`` as dense stacks (b + 1, n, n) (module docstring):
    ``D_j = delta_j0 (C + Omega G) + sum_i (cC0 + Omega cC1)_{i,j} B_i``, ``K_j`` alike;
    ``series_*`` = (value at Omega = 0, slope) of the coefficients (12, b + 1) and
    ``speed_of(lam)`` = Omega; ``in_speed``: lam is the speed (else dD = dK = 0)."""
    r, mats = system.rotor, system.basis.matrices
    D0, D1 = (np.einsum("ij,iab->jab", c, mats) for c in series_C)
    K0, K1 = (np.einsum("ij,iab->jab", c, mats) for c in series_K)
    D0[0] += r.C
    D1[0] += r.G
    K0[0] += r.K

    def coefficients(lam: float):
        om = speed_of(lam)
        return D0 + om * D1, K0 + om * K1

    def dcoefficients(lam: float):
        if in_speed:
            return D1, K1
        return np.zeros_like(D1), np.zeros_like(K1)

    return coefficients, dcoefficients


def banded_linear_part(system: RotorSystem, series_C: Series, series_K: Series,
                       speed_of: Callable[[float], float], in_speed: bool) -> TorusBands:
    """The linear part of :func:`dense_stacks` as :class:`~rotorsfd.quasiperiodic.
    torus_bands.TorusBands`: terms ``(C, G, K, B_1..B_12)`` (the rotor's CSR matrices and
    the base patterns), weights ``a_j = (delta_j0, Omega delta_j0, 0, (cC0 + Omega cC1)_j)``
    and ``c_j = (0, 0, delta_j0, (cK0 + Omega cK1)_j)``. ConfigError with a modal damping
    of the rotor (a full matrix: not in the band)."""
    r = system.rotor
    if getattr(r, "damping_lowrank", None) is not None:
        raise ConfigError("rotor.damping.kind", "modal", f"the quasi-periodic (torus) "
                          f"response above {DENSE_MAX_DOF} DOFs keeps the band and does not "
                          "take modal damping (a full matrix) yet: use proportional damping")
    bw = series_C[0].shape[1]
    e0 = np.zeros(bw)
    e0[0] = 1.0
    z = np.zeros(bw)

    def weights(cC: np.ndarray, cK: np.ndarray, d: float, g: float
                ) -> tuple[np.ndarray, np.ndarray]:
        """(a, c) (b + 1, 15): (C, G, K, B_i) weights of D_j and K_j."""
        a = np.column_stack([d * e0, g * e0, z, cC.T])
        c = np.column_stack([z, z, d * e0, cK.T])
        return a.astype(complex), c.astype(complex)

    def value(lam: float):
        om = speed_of(lam)
        return weights(series_C[0] + om * series_C[1], series_K[0] + om * series_K[1],
                       1.0, om)

    def slope(lam: float):
        if in_speed:
            return weights(series_C[1], series_K[1], 0.0, 1.0)
        return weights(0 * series_C[1], 0 * series_K[1], 0.0, 0.0)

    return TorusBands(r.M_csr, (r.C_csr, r.G_csr, r.K_csr, *system.basis.sparse_matrices),
                      value, slope)


def unbalance_polynomial(system: RotorSystem, w_b: float) -> np.ndarray:
    """(3, 2b+1, n): ``c_{1,k2}(Omega) = sum_p Omega^p a_p[k2 + b]`` of the unbalance force
    on the torus (k1 = 1, k2 = -b..b), from its samples on a 4 x Nb grid at three speeds
    (exact: F_mu is quadratic in Omega, unbalance.py; the speeds 1, 2, 3 times the largest
    base rate keep the three powers apart in round-off)."""
    n = system.n_dof
    if not system.unbalances:
        return np.zeros((3, 1, n), dtype=complex)
    n1 = 4
    a, b = np.meshgrid(np.arange(n1), np.arange(N_BASE), indexing="ij")
    th1, th2 = 2 * np.pi * a.ravel() / n1, 2 * np.pi * b.ravel() / N_BASE
    state = system.base.state(th2 / w_b)
    speeds = np.array([1.0, 2.0, 3.0]) * max(1.0, float(np.max(np.abs(state.w))))
    vals = []
    for s in speeds:
        F = unbalance_force(system.unbalances, system.rotor, s, state, th1 / s)
        c = np.fft.fft2(F.reshape(n, n1, N_BASE), axes=(1, 2)) / (n1 * N_BASE)
        vals.append(c[:, 1, :])                          # k1 = 1, all k2 bins
    V = np.linalg.solve(np.vander(speeds, 3, increasing=True), np.array(vals).reshape(3, -1))
    V = V.reshape(3, n, N_BASE)
    k = np.minimum(np.arange(N_BASE), N_BASE - np.arange(N_BASE))
    size = np.abs(V) * speeds[1] ** np.arange(3)[:, None, None]   # each power's share
    used = k[np.any(size > BAND_TOL * max(float(size.max()), np.finfo(float).tiny),
                    axis=(0, 1))]
    bb = int(used.max(initial=0))
    if bb >= N_BASE // 4:
        raise ConfigError("base", "unbalance", "the unbalance force is not a trigonometric "
                          f"polynomial of degree < {N_BASE // 4} in w_b t")
    order = np.arange(-bb, bb + 1) % N_BASE
    return np.transpose(V[:, :, order], (0, 2, 1))
