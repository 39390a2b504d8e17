"""Duffing oscillator: branch through both folds against long time integration."""

import numpy as np
import pytest
from scipy.integrate import solve_ivp

from rotorsfd.harmonic import continue_periodic, solve_periodic
from rotorsfd.harmonic.examples import duffing

C, K, K3, F = 0.05, 1.0, 0.1, 0.1
H = 7


@pytest.fixture(scope="module")
def branch():
    return continue_periodic(duffing(C, K, K3, F), 0.5, 2.0, H)


def _steady_amplitude(w, q0, v0, periods=200):
    """|X_1| and max|x| over the last period of a long solve_ivp run."""
    def rhs(t, y):
        return [y[1], F * np.cos(w * t) - C * y[1] - K * y[0] - K3 * y[0] ** 3]

    T = 2 * np.pi / w
    sol = solve_ivp(rhs, (0, periods * T), [q0, v0], method="DOP853", rtol=1e-10,
                    atol=1e-12, dense_output=True)
    t = (periods - 1) * T + np.arange(512) * T / 512
    x = sol.sol(t)[0]
    X1 = 2 / 512 * np.sum(x * np.exp(-1j * w * t))
    return abs(X1), np.abs(x).max()


def test_branch_passes_both_folds(branch):
    assert branch.success, branch.message
    folds = branch.folds()
    assert len(folds) == 2
    lam_f = branch.lam[folds]
    assert lam_f[0] > lam_f[1]                      # upper fold first, then lower
    t = branch.tangents
    angles = np.degrees(np.arccos(np.clip(np.sum(t[1:] * t[:-1], axis=1), -1, 1)))
    assert angles.max() <= 20.0 + 1e-9
    assert branch.lam[-1] == pytest.approx(2.0, abs=1e-12)


def _pick(branch, w, part):
    """Point near w on the upper (before fold 1) or lower (after fold 2) stable part."""
    f1, f2 = branch.folds()
    sl = slice(0, f1 + 1) if part == "upper" else slice(f2 + 1, None)
    lam = branch.lam[sl]
    i = np.argmin(np.abs(lam - w))
    return branch.X[sl][i]


@pytest.mark.parametrize(("w", "part"), [(0.8, "upper"), (1.05, "upper"), (1.1, "upper"),
                                          (1.09, "lower"), (1.3, "lower")])
def test_against_time_integration(branch, w, part):
    s = solve_periodic(duffing(C, K, K3, F), w, H, _pick(branch, w, part), tol=1e-10)
    t = np.linspace(0, 2 * np.pi / w, 512, endpoint=False)
    x_hb = (np.exp(1j * w * np.outer(t, np.arange(H + 1))) @ s.X[:, 0]).real
    # start 1e-3 away from the HB state: the attractor must pull it back
    q0 = x_hb[0] * 1.001
    v0 = (1j * w * np.arange(H + 1) @ s.X[:, 0]).real
    a1, amax = _steady_amplitude(w, q0, v0)
    assert a1 == pytest.approx(abs(s.X[1, 0]), rel=1e-4)
    assert amax == pytest.approx(np.abs(x_hb).max(), rel=1e-4)


def test_bistable_frequency_has_two_stable_amplitudes(branch):
    up = abs(_pick(branch, 1.09, "upper")[1, 0])
    lo = abs(_pick(branch, 1.09, "lower")[1, 0])
    assert up > 2 * lo


def test_downward_sweep_passes_the_folds_the_other_way(branch):
    down = continue_periodic(duffing(C, K, K3, F), 2.0, 0.5, H)
    assert down.success, down.message
    assert len(down.folds()) == 2
    np.testing.assert_allclose(np.sort(down.lam[down.folds()]),
                               np.sort(branch.lam[branch.folds()]), rtol=2e-2)
    assert abs(down.X[-1, 1, 0]) == pytest.approx(abs(branch.X[0, 1, 0]), rel=1e-6)


def test_point_at_resolves_between_points_and_locates_the_fold(branch):
    i = int(branch.folds()[0])
    p = branch.point_at(branch.s[i])
    np.testing.assert_allclose(p.X, branch.X[i], atol=1e-5)
    # bisection on dlam/ds between the bracketing points finds the turning point
    a, b = branch.s[i], branch.s[i + 1]
    for _ in range(40):
        mid = 0.5 * (a + b)
        if branch.point_at(mid).dlam_ds > 0:
            a = mid
        else:
            b = mid
    fold = branch.point_at(0.5 * (a + b))
    assert abs(fold.dlam_ds) < 1e-6
    assert fold.lam >= branch.lam[i] and fold.lam >= branch.lam[i + 1]
    # the fold is where the Jacobian dR/dx is singular
    J = fold.jacobian[:, :-1]
    sv = np.linalg.svd(J, compute_uv=False)
    assert sv[-1] < 1e-6 * sv[0]
