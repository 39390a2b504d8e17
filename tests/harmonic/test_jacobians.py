"""Exact Jacobians of the HB residual (full and condensed) against central differences."""

import numpy as np
import pytest

from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.examples import beam_rotor, generic_chain, jeffcott_damper
from rotorsfd.harmonic.residual import FullHB


def _d4(fun, x, h):
    """Fourth-order central difference of fun at x along step h."""
    return (8 * (fun(x + h) - fun(x - h)) - (fun(x + 2 * h) - fun(x - 2 * h))).ravel() / 12


def _fd(fun, x, h):
    cols = []
    for i in range(x.size):
        e = np.zeros_like(x)
        e[i] = h[i]
        cols.append(_d4(fun, x, e) / h[i])
    return np.array(cols).T


def _check(hb, x, lam, hx, hl, rtol):
    _, J, dR = hb.residual(x, lam)
    Jfd = _fd(lambda y: hb.residual(y, lam, jac=False)[0], x.ravel(), np.full(x.size, hx))
    dRfd = _d4(lambda l: hb.residual(x, l, jac=False)[0], lam, hl) / hl
    scale = np.abs(J).max()
    assert np.abs(J - Jfd).max() <= rtol * scale
    assert np.abs(dR - dRfd).max() <= rtol * max(np.abs(dR).max(), 1e-300)


def _random_state(H, m, amp, seed):
    rng = np.random.default_rng(seed)
    x = amp * rng.normal(size=(2 * H + 1, m)) / np.arange(1, 2 * H + 2)[:, None]
    return x


@pytest.mark.parametrize("condensed", [False, True])
def test_generic_chain(condensed):
    p = generic_chain()
    H, N = 3, 32
    hb = (CondensedHB if condensed else FullHB)(p, H, N)
    m = p.m if condensed else p.n_dof
    x = _random_state(H, m, 0.4, 2)
    if condensed:
        hb.set_shift(x, 0.8)                      # non-zero shift Delta
        assert np.abs(hb.delta).max() > 0
    _check(hb, x, 0.8, 1e-6, 1e-6, 1e-7)


@pytest.mark.parametrize("condensed", [False, True])
def test_rational_damper_rotor(condensed):
    p = jeffcott_damper(static=(0.0, -30.0))
    H, N = 4, 64
    hb = (CondensedHB if condensed else FullHB)(p, H, N)
    m = 2
    x = _random_state(H, m, 0.1 * 2e-4, 3)
    if condensed:
        hb.set_shift(x, 320.0)
    _check(hb, x, 320.0, 1e-10, 1e-2, 1e-6)


def test_beam_rotor_condensed_lam_derivative():
    """Gyroscopic D(lam) = C + lam G, banded LU path."""
    p = beam_rotor()
    hb = CondensedHB(p, 3, 32)
    x = _random_state(3, 2, 0.2 * 1.27e-4, 4)
    hb.set_shift(x, 800.0)
    _check(hb, x, 800.0, 1e-11, 1e-2, 1e-6)
