"""2-DOF Jeffcott rotor with a rational radial damper against time integration; H
convergence; failures are reported, never silent."""

import itertools

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic import continue_periodic, solve_periodic
from rotorsfd.harmonic.examples import jeffcott_damper

MASS, STIFF, DAMP, UNB, C0, CLR, STATIC = 10.0, 1e6, 20.0, 2e-4, 400.0, 2e-4, (0.0, -60.0)
H = 10


def _problem():
    return jeffcott_damper(MASS, STIFF, DAMP, UNB, C0, CLR, STATIC)


@pytest.fixture(scope="module")
def branch():
    return continue_periodic(_problem(), 100.0, 600.0, H)


def _time_integration(lam, X):
    """Steady state of m q'' + c q' + k q = U lam^2 (cos, sin) + static + F_nl."""
    p = _problem()
    st = np.array(STATIC)

    def rhs(t, y):
        q, v = y[:2], y[2:]
        f = UNB * lam**2 * np.array([np.cos(lam * t), np.sin(lam * t)]) + st \
            + p.nl_force(q, v) - DAMP * v - STIFF * q
        return np.concatenate([v, f / MASS])

    k = np.arange(H + 1)
    y0 = np.concatenate([(X.sum(0)).real * 1.01, (1j * lam * k @ X).real])
    T = 2 * np.pi / lam
    n_per = int(np.ceil(0.6 / T))
    sol = solve_ivp(rhs, (0, n_per * T), y0, method="DOP853", rtol=1e-10, atol=1e-14,
                    dense_output=True)
    t = (n_per - 1) * T + np.arange(256) * T / 256
    q = sol.sol(t)[:2]
    X1 = 2 / 256 * (q * np.exp(-1j * lam * t)).sum(1)
    return np.abs(X1), q.mean(1)


def test_branch_reaches_the_end(branch):
    assert branch.success, branch.message
    assert branch.amplitude(0).max() > 0.35 * CLR
    assert branch.aliasing.max() < 1e-6


def test_against_time_integration(branch):
    lams = np.linspace(120.0, 580.0, 10)
    for lam in lams:
        i = np.argmin(np.abs(branch.lam - lam))
        s = solve_periodic(_problem(), lam, H, branch.X[i], tol=1e-9)
        a1, mean = _time_integration(lam, s.X)
        np.testing.assert_allclose(a1, np.abs(s.X[1]), rtol=1e-3)
        np.testing.assert_allclose(mean, s.X[0].real, rtol=1e-3, atol=1e-3 * CLR)


def test_harmonic_convergence():
    """The first harmonic changes less and less as H grows."""
    p = _problem()
    ref = solve_periodic(p, 330.0, 16, tol=1e-12).X[1]
    errs = [np.abs(solve_periodic(p, 330.0, h, tol=1e-12).X[1] - ref).max()
            for h in (1, 2, 4, 8)]
    assert all(e1 > e2 for e1, e2 in itertools.pairwise(errs))
    assert errs[-1] < 1e-6 * np.abs(ref).max()


def test_failure_is_reported_with_where_and_why():
    p = _problem()
    with pytest.raises(ConvergenceError, match=r"lam=330"):
        solve_periodic(p, 330.0, 3, max_iter=1, tol=1e-14)
    b = continue_periodic(p, 100.0, 600.0, 3, limit_max=0.35)
    assert not b.success
    assert "lam=" in b.message and "limit" in b.message
    assert b.n_points > 0
    t = 2 * np.pi * np.arange(b.n_samples) / b.n_samples      # the AFT samples
    for X in b.X:
        q = (np.exp(1j * np.outer(t, np.arange(4))) @ X).real
        assert np.sqrt((q**2).sum(1)).max() < 0.35 * CLR


def test_event_hook_sees_every_point_and_can_stop():
    seen = []

    def hook(point):
        seen.append((point.index, point.lam, point.X.shape, point.jacobian.shape, point.s,
                     point.dlam_ds))
        return point.lam > 300.0

    b = continue_periodic(_problem(), 100.0, 600.0, 3, callback=hook)
    assert b.success and "callback" in b.message
    assert [s[0] for s in seen] == list(range(b.n_points))
    assert seen[0][2] == (4, 2) and seen[0][3] == (14, 15)
    assert 300.0 < b.lam[-1] < 400.0
    np.testing.assert_allclose([x[4] for x in seen], b.s)
    np.testing.assert_allclose([x[5] for x in seen], b.dlam_ds)
    assert np.all(b.dlam_ds > 0)
