"""Two-frequency Fourier machinery on the 2-torus: the truncation lattice, the real packing
and the AFT on an N1 x N2 grid by a 2D FFT.

A quasi-periodic response with base frequencies Omega (spin) and w_b (base motion) is
written on the torus angles ``theta1 = Omega t``, ``theta2 = w_b t``:

    q(t) = Q(Omega t, w_b t),   Q(theta) = Re( sum_{k in half} X_k exp(i (k1 theta1 + k2 theta2)) )

with ``X_0`` real and ``c_{-k} = conj(c_k)`` folded into the one-sided ``X_k = 2 c_k``: the
*half lattice* is ``{(0, k2): 0 <= k2 <= h(0)} u {(k1, k2): 1 <= k1 <= H1, |k2| <= h(k1)}``
with ``h(k1) = H2`` (the *box* ``|k1| <= H1, |k2| <= H2``) or ``h(k1) = H - k1`` (the
*diamond* ``|k1| + |k2| <= H``, H1 = H2 = H). Harmonic ``k`` turns at
``omega_k = k1 Omega + k2 w_b``.

Real layout (as :mod:`rotorsfd.harmonic.fourier` in one dimension): the harmonics in the
order above, index j = 0..nk-1, and per DOF ``x = [Re X_0, Re X_1, Im X_1, ...]`` of length
``2 nk - 1`` (:func:`~rotorsfd.harmonic.fourier.to_real` / ``to_complex`` convert).

Samples on ``theta = (2 pi a / N1, 2 pi b / N2)``, flattened a-major (n = a N2 + b):

- ``Q = E x``: E[:, 2j-1] = cos(phi_j), E[:, 2j] = -sin(phi_j), ``phi_j = k_j . theta``;
- ``dQ/dt = Ev x``: Ev[:, 2j-1] = -omega_j sin(phi_j), Ev[:, 2j] = -omega_j cos(phi_j);
- ``x_F = P f``: F_0 = mean(f), F_j = (2/N) sum_n f_n exp(-i phi_j(n)).

The sampling and the projection run as 2D FFTs (``numpy.fft``); E and Ev are formed only
for the exact Jacobians. ``P E = I`` exactly when N1 > 2 H1 and N2 > 2 max h: then the
full lattice +-k maps to distinct grid points.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import cached_property, lru_cache

import numpy as np
from numpy.typing import NDArray

from rotorsfd.harmonic.fourier import default_min_samples, to_complex, to_real

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
SHAPES = ("box", "diamond")


@dataclass(frozen=True)
class TorusLattice:
    """The truncation set: a box ``|k1| <= H1, |k2| <= H2`` or a diamond
    ``|k1| + |k2| <= H1`` (then H2 = H1), as its half lattice (module docstring)."""

    H1: int
    H2: int
    shape: str = "box"

    def __post_init__(self) -> None:
        if self.shape not in SHAPES:
            raise ValueError(f"shape must be one of {SHAPES}, got {self.shape!r}")
        if self.H1 < 0 or self.H2 < 0:
            raise ValueError(f"need H1, H2 >= 0, got {self.H1}, {self.H2}")
        if self.shape == "diamond" and self.H1 != self.H2:
            raise ValueError(f"a diamond has H1 = H2 = H, got {self.H1}, {self.H2}")

    def h(self, k1: int) -> int:
        """Largest |k2| kept with this k1."""
        return self.H2 if self.shape == "box" else self.H1 - abs(k1)

    @cached_property
    def k(self) -> NDArray[np.int64]:
        """(nk, 2) harmonics of the half lattice, in the order of the real layout."""
        rows = [(0, k2) for k2 in range(self.h(0) + 1)]
        for k1 in range(1, self.H1 + 1):
            rows += [(k1, k2) for k2 in range(-self.h(k1), self.h(k1) + 1)]
        return np.array(rows, dtype=np.int64).reshape(-1, 2)

    @property
    def nk(self) -> int:
        """Number of complex harmonics of the half lattice."""
        return int(self.k.shape[0])

    @property
    def n_real(self) -> int:
        """Real unknowns per DOF, 2 nk - 1."""
        return 2 * self.nk - 1

    def index(self, k1: int, k2: int) -> int:
        """Position of harmonic (k1, k2) of the half lattice; KeyError if not kept."""
        hit = np.nonzero((self.k[:, 0] == k1) & (self.k[:, 1] == k2))[0]
        if not hit.size:
            raise KeyError((k1, k2))
        return int(hit[0])

    def frequencies(self, omega: float, wb: float) -> FloatArray:
        """``omega_k = k1 Omega + k2 w_b`` of every harmonic (nk,)."""
        return self.k[:, 0] * float(omega) + self.k[:, 1] * float(wb)

    # ---- per-k1 blocks (the linear part couples k2 only) ------------------------------
    def block(self, k1: int) -> NDArray[np.int64]:
        """Harmonic positions of column k1 in the order k2 = -h..h; for k1 = 0 the
        negative k2 are the conjugates (-1 - position, see :func:`block_vectors`)."""
        return _block(self, k1)

    def _block(self, k1: int) -> NDArray[np.int64]:
        h = self.h(k1)
        if k1 == 0:
            return np.array([-1 - self.index(0, -j) if j < 0 else self.index(0, j)
                             for j in range(-h, h + 1)], dtype=np.int64)
        return np.array([self.index(k1, j) for j in range(-h, h + 1)], dtype=np.int64)

    def min_grid(self) -> tuple[int, int]:
        """Smallest alias-free grid for the retained harmonics (P E = I): 2H1+1, 2h+1."""
        return 2 * self.H1 + 1, 2 * self.h(0) + 1


@lru_cache(maxsize=256)
def _block(lattice: TorusLattice, k1: int) -> NDArray[np.int64]:
    return lattice._block(k1)


def block_vectors(lattice: TorusLattice, X: ComplexArray) -> list[ComplexArray]:
    """One-sided coefficients X (nk, ...) as per-k1 columns over k2 = -h..h: for k1 >= 1
    the X_k themselves, for k1 = 0 the two-sided c_{0,k2} (c_0 = X_0, c_{+-j} = X_j / 2,
    conj(X_j) / 2), on which the linear operator acts with the same matrices."""
    out = []
    for k1 in range(lattice.H1 + 1):
        pos = lattice.block(k1)
        if k1:
            out.append(X[pos])
            continue
        col = np.empty((pos.size, *X.shape[1:]), dtype=complex)
        for r, p in enumerate(pos):
            if p < 0:
                col[r] = np.conj(X[-1 - p]) / 2
            else:
                col[r] = X[p] if lattice.k[p, 1] == 0 else X[p] / 2
        out.append(col)
    return out


def from_blocks(lattice: TorusLattice, cols: list[ComplexArray]) -> ComplexArray:
    """Inverse of :func:`block_vectors` (the k1 = 0 column read on k2 >= 0; its
    imaginary part at k2 = 0 dropped)."""
    X = np.empty((lattice.nk, *cols[0].shape[1:]), dtype=complex)
    for k1, col in enumerate(cols):
        for r, p in enumerate(lattice.block(k1)):
            if p < 0:
                continue
            if k1 == 0:
                X[p] = col[r].real if lattice.k[p, 1] == 0 else 2 * col[r]
            else:
                X[p] = col[r]
    return X


@lru_cache(maxsize=256)
def block_real_maps(lattice: TorusLattice, k1: int) -> tuple[ComplexArray, ComplexArray]:
    """``(T, U)``: the column k1 (complex, over k2 = -h..h) of a real-layout vector x is
    ``T x``, and ``x = Re(U col)`` on that column's real indices
    (:func:`block_real_indices`); per DOF, so both act on the harmonic axis."""
    pos = lattice.block(k1)
    idx = block_real_indices(lattice, k1)
    T = np.zeros((pos.size, idx.size), dtype=complex)
    U = np.zeros((idx.size, pos.size), dtype=complex)
    where = {int(i): c for c, i in enumerate(idx)}
    for r, p in enumerate(pos):
        j = -1 - p if p < 0 else p
        if j == 0:
            T[r, where[0]] = 1.0
            U[where[0], r] = 1.0
            continue
        half = 0.5 if k1 == 0 else 1.0
        sign = -1.0 if p < 0 else 1.0
        T[r, where[2 * j - 1]] = half
        T[r, where[2 * j]] = sign * 1j * half
        if k1 == 0:      # x_re = c_j + c_-j, x_im = -i (c_j - c_-j)
            U[where[2 * j - 1], r] += 1.0
            U[where[2 * j], r] += -sign * 1j
        else:            # x_re = Re X, x_im = Im X = Re(-i X)
            U[where[2 * j - 1], r] = 1.0
            U[where[2 * j], r] = -1j
    return T, U


@lru_cache(maxsize=256)
def block_real_indices(lattice: TorusLattice, k1: int) -> NDArray[np.int64]:
    """Real-layout indices (per DOF) of column k1, ascending."""
    pos = lattice.block(k1)
    out: list[int] = []
    for p in pos:
        if p < 0:
            continue
        out += [0] if p == 0 else [2 * int(p) - 1, 2 * int(p)]
    return np.array(sorted(out), dtype=np.int64)


# ---------------------------------------------------------------------------------------
# AFT on the N1 x N2 grid
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class TorusAFT:
    """Sampling and projection on an N1 x N2 grid of the torus (module docstring)."""

    lattice: TorusLattice
    N1: int
    N2: int
    _slots: tuple = field(init=False, repr=False, compare=False)

    def __post_init__(self) -> None:
        n1, n2 = self.lattice.min_grid()
        if self.N1 < n1 or self.N2 < n2:
            raise ValueError(f"the grid {self.N1} x {self.N2} aliases the retained "
                             f"harmonics: need at least {n1} x {n2}")
        k = self.lattice.k
        object.__setattr__(self, "_slots", (k[:, 0] % self.N1, k[:, 1] % self.N2))

    @property
    def N(self) -> int:
        return self.N1 * self.N2

    @cached_property
    def phases(self) -> FloatArray:
        """(N, nk) phases phi_j at the grid points."""
        a, b = np.meshgrid(np.arange(self.N1), np.arange(self.N2), indexing="ij")
        t1 = 2 * np.pi * a.ravel() / self.N1
        t2 = 2 * np.pi * b.ravel() / self.N2
        return np.outer(t1, self.lattice.k[:, 0]) + np.outer(t2, self.lattice.k[:, 1])

    @cached_property
    def E(self) -> FloatArray:
        """(N, n_real) sampling matrix."""
        phi = self.phases
        E = np.empty((self.N, self.lattice.n_real))
        E[:, 0] = 1.0
        E[:, 1::2] = np.cos(phi[:, 1:])
        E[:, 2::2] = -np.sin(phi[:, 1:])
        return E

    def velocity_matrix(self, omegas: FloatArray) -> FloatArray:
        """(N, n_real) ``Ev``: dQ/dt samples for harmonic frequencies ``omegas`` (nk,)."""
        phi = self.phases
        w = np.asarray(omegas, dtype=float)[None, 1:]
        Ev = np.zeros((self.N, self.lattice.n_real))
        Ev[:, 1::2] = -w * np.sin(phi[:, 1:])
        Ev[:, 2::2] = -w * np.cos(phi[:, 1:])
        return Ev

    def sample(self, x: FloatArray) -> FloatArray:
        """``E x`` by an inverse 2D FFT: x (n_real, ...) -> (N, ...)."""
        X = to_complex(x)
        A = np.zeros((self.N1, self.N2, *X.shape[1:]), dtype=complex)
        A[self._slots] = X
        return (self.N * np.fft.ifft2(A, axes=(0, 1))).real.reshape(self.N, *X.shape[1:])

    @cached_property
    def _pairs(self) -> tuple[tuple[NDArray[np.int64], ...], tuple[NDArray[np.int64], ...]]:
        """Grid bins of ``k_a - k_b`` and ``k_a + k_b`` for every pair of harmonics."""
        k = self.lattice.k
        d, s = k[:, None, :] - k[None, :, :], k[:, None, :] + k[None, :, :]
        n = (self.N1, self.N2)
        return (tuple(d[..., i] % n[i] for i in (0, 1)),
                tuple(s[..., i] % n[i] for i in (0, 1)))

    def product_matrix(self, g: FloatArray) -> FloatArray:
        """``P diag(g) E`` (n_real, ..., n_real) for samples g (N, ...): the projection of
        the product of g with every sampled harmonic, from the 2D FFT of g alone.

        With ``g^(k) = (1/N) sum_n g_n exp(-i k . theta_n)`` (on the grid, bins mod N),
        ``A_ab = g^(k_a - k_b)``, ``B_ab = g^(k_a + k_b)``: column ``cos phi_b`` projects
        to ``X_a = A_ab + B_ab`` and column ``-sin phi_b`` to ``X_a = i (A_ab - B_ab)``
        (halved for a = 0, whose coefficient is the mean): equal to the product of the
        sampled matrices, aliases included."""
        g = np.asarray(g, dtype=float)
        rest = g.shape[1:]
        gh = np.fft.fft2(g.reshape(self.N1, self.N2, *rest), axes=(0, 1)) / self.N
        d, s = self._pairs
        A, B = gh[d], gh[s]                    # (nk, nk, ...)
        cos, sin = A + B, 1j * (A - B)
        cos[0] *= 0.5
        sin[0] *= 0.5
        nr = self.lattice.n_real
        out = np.empty((nr, nr, *rest))
        out[0, 0] = cos[0, 0].real
        out[0, 1::2] = cos[0, 1:].real
        out[0, 2::2] = sin[0, 1:].real
        out[1::2, 0] = cos[1:, 0].real
        out[2::2, 0] = cos[1:, 0].imag
        out[1::2, 1::2] = cos[1:, 1:].real
        out[2::2, 1::2] = cos[1:, 1:].imag
        out[1::2, 2::2] = sin[1:, 1:].real
        out[2::2, 2::2] = sin[1:, 1:].imag
        return np.moveaxis(out, 1, -1)

    def project(self, f: FloatArray) -> FloatArray:
        """``P f`` by a 2D FFT: samples (N, ...) -> real layout (n_real, ...)."""
        f = np.asarray(f, dtype=float)
        c = np.fft.fft2(f.reshape(self.N1, self.N2, *f.shape[1:]), axes=(0, 1)) / self.N
        X = 2.0 * c[self._slots]
        X[0] = c[0, 0].real
        return to_real(X)


def derivative(x: FloatArray, omegas: FloatArray) -> FloatArray:
    """Real layout of ``i omega_k X_k`` (the time derivative on the torus)."""
    out = np.zeros_like(np.asarray(x, dtype=float))
    w = np.asarray(omegas, dtype=float)[1:].reshape(-1, *([1] * (x.ndim - 1)))
    out[1::2] = -w * x[2::2]
    out[2::2] = w * x[1::2]
    return out


def grid_aliasing(force: Callable[[FloatArray, FloatArray], FloatArray],
                  lattice: TorusLattice, xs: FloatArray, omegas: FloatArray,
                  N1: int, N2: int, axis: int) -> float:
    """Relative max-norm change of the retained force coefficients when N1 (axis 0) or N2
    (axis 1) doubles, at the nonlinear-DOF coefficients ``xs`` (n_real, m)."""
    out = []
    v = derivative(xs, omegas)
    for d in (1, 2):
        aft = TorusAFT(lattice, N1 * (d if axis == 0 else 1), N2 * (d if axis == 1 else 1))
        out.append(aft.project(force(aft.sample(xs), aft.sample(v))))
    scale = max(float(np.max(np.abs(out[1]))), np.finfo(float).tiny)
    return float(np.max(np.abs(out[1] - out[0]))) / scale


def choose_grid(force: Callable[[FloatArray, FloatArray], FloatArray],
                lattice: TorusLattice, xs: FloatArray, omegas: FloatArray,
                tol: float = 1e-8, n_max: int = 512) -> tuple[int, int]:
    """The grid rule, today's one-dimensional rule per torus direction: start from
    ``default_min_samples(H1) x default_min_samples(h(0))`` (alias-free for a polynomial
    force up to degree 7) and double N1 or N2 while doubling it changes the retained
    force coefficients by more than ``tol`` (relative; :func:`grid_aliasing`), up to
    ``n_max`` per direction."""
    N1, N2 = default_min_samples(lattice.H1), default_min_samples(lattice.h(0))
    for _ in range(16):
        grow = [grid_aliasing(force, lattice, xs, omegas, N1, N2, a) > tol
                if n < n_max else False for a, n in enumerate((N1, N2))]
        if not any(grow):
            break
        N1, N2 = N1 * (2 if grow[0] else 1), N2 * (2 if grow[1] else 1)
    return N1, N2


def synthesize(lattice: TorusLattice, X: ComplexArray, omega: float, wb: float,
               t: FloatArray, phase: tuple[float, float] = (0.0, 0.0)) -> FloatArray:
    """The response in time, ``q(t) = Re(sum_k X_k exp(i (omega_k t + k . phase)))``:
    X (nk, n) -> (nt, n); ``phase`` the torus angles at t = 0."""
    w = lattice.frequencies(omega, wb)
    ph = lattice.k @ np.asarray(phase, dtype=float)
    return (np.exp(1j * (np.outer(np.asarray(t, dtype=float), w) + ph[None])) @ X).real
