"""HB with the real squeeze film damper (rotorsfd.sfd, pi film): Jeffcott rotor against
time integration, Jacobians against finite differences, N_f adapted along the branch."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorsfd.harmonic import continue_periodic, solve_periodic
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.examples import beam_rotor, jeffcott_damper
from rotorsfd.harmonic.residual import FullHB
from rotorsfd.sfd import SFD

MASS, STIFF, UNB, STATIC = 10.0, 1e6, 3e-4, (0.0, -60.0)
SFD_JEFF = SFD(viscosity=0.03, radius=0.03, length=0.012, clearance=2e-4, cavitation="pi")
H = 8


def _problem():
    return jeffcott_damper(MASS, STIFF, 0.0, UNB, static=STATIC, sfd=SFD_JEFF)


@pytest.fixture(scope="module")
def branch():
    return continue_periodic(_problem(), 100.0, 600.0, H)


def _steady_state(lam, X):
    p = _problem()
    st = np.array(STATIC)

    def rhs(t, y):
        q, v = y[:2], y[2:]
        f = UNB * lam**2 * np.array([np.cos(lam * t), np.sin(lam * t)]) + st \
            + p.nl_force(q, v) - STIFF * q
        return np.concatenate([v, f / MASS])

    k = np.arange(H + 1)
    y0 = np.concatenate([X.sum(0).real * 1.002, (1j * lam * k @ X).real])
    T = 2 * np.pi / lam
    n_per = int(np.ceil(1.0 / T))
    sol = solve_ivp(rhs, (0, n_per * T), y0, method="DOP853", rtol=1e-9, atol=1e-14,
                    dense_output=True)
    t = (n_per - 1) * T + np.arange(256) * T / 256
    q = sol.sol(t)[:2]
    return np.abs(2 / 256 * (q * np.exp(-1j * lam * t)).sum(1)), q.mean(1)


def test_branch_and_sample_count(branch):
    assert branch.success, branch.message
    assert branch.amplitude(0).max() > 0.5 * SFD_JEFF.clearance
    assert branch.aliasing.max() <= 1e-6
    assert branch.info["n_samples"][-1] >= branch.info["n_samples"][0]


def test_against_time_integration(branch):
    """HB amplitudes at 10 speeds equal the steady state of solve_ivp to 1e-3."""
    for lam in np.linspace(150.0, 580.0, 10):
        i = np.argmin(np.abs(branch.lam - lam))
        s = solve_periodic(_problem(), lam, H, branch.X[i], tol=1e-9,
                           n_samples=int(branch.info["n_samples"][i]))
        a1, mean = _steady_state(lam, s.X)
        np.testing.assert_allclose(a1, np.abs(s.X[1]), rtol=1e-3)
        np.testing.assert_allclose(mean, s.X[0].real, rtol=1e-3,
                                   atol=1e-3 * SFD_JEFF.clearance)


@pytest.mark.parametrize("condensed", [False, True])
def test_jacobians_with_sfd(condensed):
    p = beam_rotor(sfd=SFD.from_ratios(0.0051, 1.27e-4, 0.00485, 0.325))
    Hh, N, lam = 3, 64, 850.0
    hb = (CondensedHB if condensed else FullHB)(p, Hh, N)
    s = solve_periodic(p, lam, Hh, tol=1e-10)
    x = np.concatenate([s.X[:1].real, np.stack([s.X[1:].real, s.X[1:].imag], 1)
                        .reshape(2 * Hh, -1)])
    x = x[:, p.nl_dofs] if condensed else x
    x = x * 1.05                                   # off the solution, eps < 1
    _, J, dR = hb.residual(x, lam)
    h = 1e-4 * 1.27e-4
    cols = []
    for i in range(x.size):
        e = np.zeros(x.size)
        e[i] = h
        rp = hb.residual((x.ravel() + e).reshape(x.shape), lam, jac=False)[0]
        rm = hb.residual((x.ravel() - e).reshape(x.shape), lam, jac=False)[0]
        cols.append((rp - rm).ravel() / (2 * h))
    Jfd = np.array(cols).T
    assert np.abs(J - Jfd).max() <= 1e-6 * np.abs(J).max()
    hl = 1e-3
    dRfd = (hb.residual(x, lam + hl, jac=False)[0] - hb.residual(x, lam - hl, jac=False)[0]
            ).ravel() / (2 * hl)
    assert np.abs(dR - dRfd).max() <= 1e-5 * np.abs(dR).max()
