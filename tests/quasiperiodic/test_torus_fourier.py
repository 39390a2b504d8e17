"""Lattice, packing and the 2D AFT of the torus."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.harmonic.fourier import to_complex
from rotorsfd.quasiperiodic.torus_fourier import (
    TorusAFT,
    TorusLattice,
    block_real_indices,
    block_real_maps,
    block_vectors,
    choose_grid,
    derivative,
    from_blocks,
    grid_aliasing,
    synthesize,
)

LATTICES = [TorusLattice(3, 2), TorusLattice(4, 4, "diamond"), TorusLattice(0, 3),
            TorusLattice(2, 0)]


def test_half_lattice_counts():
    """Box: (2H1+1)(2H2+1) lattice points, (that + 1)/2 in the half; diamond 2H(H+1)+1."""
    box, diamond = TorusLattice(3, 2), TorusLattice(4, 4, "diamond")
    assert box.nk == (7 * 5 + 1) // 2 and box.n_real == 7 * 5
    assert diamond.n_real == 2 * 4 * 5 + 1
    assert np.all(np.abs(diamond.k).sum(axis=1) <= 4)
    assert box.index(0, 0) == 0 and box.index(2, -2) == box.k.tolist().index([2, -2])
    with pytest.raises(KeyError):
        box.index(0, -1)     # the conjugate half is not stored


@pytest.mark.parametrize("lattice", LATTICES)
def test_fft_sampling_and_projection_are_the_matrices(lattice):
    """ifft2 sampling = E x, fft2 projection inverts it on the smallest alias-free grid,
    and the velocity samples are Ev x = E (i omega x)."""
    n1, n2 = lattice.min_grid()
    aft = TorusAFT(lattice, n1, n2)
    x = np.random.default_rng(2).normal(size=(lattice.n_real, 3))
    np.testing.assert_allclose(aft.sample(x), aft.E @ x, atol=1e-13)
    np.testing.assert_allclose(aft.project(aft.E @ x), x, atol=1e-13)
    w = lattice.frequencies(1.3, 0.7)
    np.testing.assert_allclose(aft.sample(derivative(x, w)), aft.velocity_matrix(w) @ x,
                               atol=1e-12)
    with pytest.raises(ValueError):
        TorusAFT(lattice, n1 - 1, n2) if n1 > 1 else TorusAFT(lattice, n1, n2 - 1)


@pytest.mark.parametrize("lattice", LATTICES)
@pytest.mark.parametrize("grow", [(1, 1), (2, 4)])
def test_product_matrix_is_the_matrix_product(lattice, grow):
    """P diag(g) E (the exact AFT Jacobian's building block) from the FFT of g alone
    (entries at k_a -+ k_b) = the explicit product with the sampling and projection
    matrices, on the smallest grid (aliases included) and a finer one, for g (N, 2, 3)."""
    n1, n2 = lattice.min_grid()
    aft = TorusAFT(lattice, n1 * grow[0], n2 * grow[1])
    g = np.random.default_rng(3).normal(size=(aft.N, 2, 3))
    ref = aft.project(g[..., None] * aft.E[:, None, None, :])     # (n_real, 2, 3, n_real)
    np.testing.assert_allclose(aft.product_matrix(g), ref, atol=1e-13)


def test_convention_in_time():
    """Q = Re(sum X_k e^{i(k1 Omega + k2 w_b) t}): X_(1,-1) = 2 - i gives
    2 cos((Omega - w_b) t) + sin((Omega - w_b) t), with its derivative by finite
    differences of the synthesis."""
    lat = TorusLattice(1, 1)
    X = np.zeros((lat.nk, 1), dtype=complex)
    X[lat.index(1, -1)] = 2 - 1j
    X[0] = 0.5
    om, wb = 3.0, np.sqrt(2.0)
    t = np.linspace(0, 5, 11)
    q = synthesize(lat, X, om, wb, t)[:, 0]
    np.testing.assert_allclose(q, 0.5 + 2 * np.cos((om - wb) * t) + np.sin((om - wb) * t),
                               atol=1e-14)


@pytest.mark.parametrize("lattice", LATTICES)
def test_blocks_round_trip(lattice):
    """Per-k1 columns (the two-sided k1 = 0 column) and their real maps T, U."""
    x = np.random.default_rng(3).normal(size=(lattice.n_real, 2))
    X = to_complex(x)
    cols = block_vectors(lattice, X)
    np.testing.assert_allclose(from_blocks(lattice, cols), X, atol=1e-15)
    for k1, col in enumerate(cols):
        T, U = block_real_maps(lattice, k1)
        idx = block_real_indices(lattice, k1)
        np.testing.assert_allclose(T @ x[idx], col, atol=1e-15)
        np.testing.assert_allclose((U @ col).real, x[idx], atol=1e-15)
    c0 = cols[0]
    np.testing.assert_allclose(c0[::-1], np.conj(c0), atol=1e-15)   # c_{-k} = conj c_k


def test_cubic_force_is_alias_free_on_the_default_grid():
    """A cubic is exact when N > 4H per direction: the grid rule keeps the default grid,
    and a too coarse grid shows the aliasing."""
    lat = TorusLattice(3, 2)
    x = 0.3 * np.random.default_rng(4).normal(size=(lat.n_real, 1))
    w = lat.frequencies(1.0, 0.37)

    def cubic(q, v):
        return q**3 + 0.1 * v

    assert grid_aliasing(cubic, lat, x, w, 13, 9, axis=0) < 1e-13
    assert grid_aliasing(cubic, lat, x, w, 13, 9, axis=1) < 1e-13
    assert grid_aliasing(cubic, lat, x, w, 8, 6, axis=0) > 1e-3
    assert choose_grid(cubic, lat, x, w) == (32, 32)


def test_grid_rule_doubles_for_a_rational_force():
    """A force with a pole near the orbit needs more samples in the direction with the
    larger content: the rule doubles until doubling changes < tol."""
    lat = TorusLattice(2, 1)
    x = np.zeros((lat.n_real, 1))
    x[2 * lat.index(1, 0) - 1] = 0.9       # cos(theta1) reaching 0.9
    x[2 * lat.index(0, 1) - 1] = 0.05
    w = lat.frequencies(1.0, 0.37)

    def force(q, v):
        return 1.0 / (1.0 - q**2) ** 1.5

    N1, N2 = choose_grid(force, lat, x, w, tol=1e-8)
    assert N1 > 32 and N2 <= 64
    assert grid_aliasing(force, lat, x, w, N1, N2, axis=0) < 1e-8
    assert grid_aliasing(force, lat, x, w, N1 // 2, N2, axis=0) > 1e-8
