"""The AFT Jacobian from the spectrum of the Jacobian samples (aft_jacobian) against the
direct product P (dF/dq E + w dF/dv Ed) with the AFT matrices; the HB Jacobians built on
it are checked against finite differences in test_jacobians.py."""

import numpy as np
import pytest

from rotorsfd.harmonic.aft_jacobian import force_jacobian_coefficients
from rotorsfd.harmonic.aft_kernels import project
from rotorsfd.harmonic.fourier import aft_matrices


def _direct(a, dfq, dfv, w):
    N, m = dfq.shape[:2]
    nh = a.E.shape[1]
    T = dfq[..., None] * a.E[:, None, None, :] + w * dfv[..., None] * a.Ed[:, None, None, :]
    return (a.P @ T.reshape(N, -1)).reshape(nh, m, m, nh).transpose(0, 1, 3, 2)


# N just above 2H (aliased products), odd N, powers of two, one and three DOFs
@pytest.mark.parametrize("H, N, m", [(0, 4, 1), (1, 3, 2), (3, 7, 2), (3, 32, 2),
                                     (8, 17, 3), (15, 128, 2), (23, 256, 2)])
def test_spectrum_jacobian_equals_direct_product(H, N, m):
    rng = np.random.default_rng(H + N)
    a = aft_matrices(H, N)
    dfq, dfv = rng.standard_normal((2, N, m, m))
    w = 1.7
    ref = _direct(a, dfq, dfv, w)
    dG = np.empty_like(ref)
    force_jacobian_coefficients(dfq, dfv, w, 2 * H + 1, dG)
    assert np.abs(dG - ref).max() <= 1e-13 * np.abs(ref).max()


def test_compiled_projection_jacobian_equals_direct_product():
    """``aft_kernels.project`` (the compiled HB path): G = P f, dG as the direct product,
    dG/dw = P (dfv . q')."""
    H, N, m = 5, 64, 2
    rng = np.random.default_rng(3)
    a = aft_matrices(H, N)
    f, dq = rng.standard_normal((2, N, m))
    dfq, dfv = rng.standard_normal((2, N, m, m))
    w = 0.8
    nh = 2 * H + 1
    G, dGdw = np.empty((nh, m)), np.empty((nh, m))
    dG = np.empty((nh, m, nh, m))
    assert project(a.P, a.E, a.Ed, w, f, dfq, dfv, dq, True, G, dG, dGdw)
    ref = _direct(a, dfq, dfv, w)
    assert np.abs(G - a.P @ f).max() <= 1e-14 * np.abs(a.P @ f).max()
    assert np.abs(dG - ref).max() <= 1e-13 * np.abs(ref).max()
    gw = a.P @ np.einsum("nij,nj->ni", dfv, dq)
    assert np.abs(dGdw - gw).max() <= 1e-14 * np.abs(gw).max()
