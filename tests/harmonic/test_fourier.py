"""AFT matrices, real layout and the N_f rule (aliasing)."""

import numpy as np
import pytest

from rotorsfd.harmonic.examples import radial_damper
from rotorsfd.harmonic.fourier import (
    aft_matrices,
    aliasing_error,
    choose_n_samples,
    default_min_samples,
    to_complex,
    to_real,
)


@pytest.mark.parametrize(("H", "N"), [(1, 3), (3, 8), (8, 17), (8, 128)])
def test_projection_inverts_sampling(H, N):
    A = aft_matrices(H, N)
    np.testing.assert_allclose(A.P @ A.E, np.eye(2 * H + 1), atol=1e-13)


def test_convention_matches_interfaces():
    """q(t) = Re(sum X_k e^{ikwt}), X_k = a_k - i b_k: q = a0 + a1 cos + b1 sin."""
    H, N = 2, 16
    X = np.array([[0.3], [1.0 - 2.0j], [0.5j]])
    tau = 2 * np.pi * np.arange(N) / N
    q = 0.3 + 1.0 * np.cos(tau) + 2.0 * np.sin(tau) - 0.5 * np.sin(2 * tau)
    A = aft_matrices(H, N)
    np.testing.assert_allclose(A.E @ to_real(X), q[:, None], atol=1e-14)
    dq = -np.sin(tau) + 2 * np.cos(tau) - np.cos(2 * tau)
    np.testing.assert_allclose(A.Ed @ to_real(X), dq[:, None], atol=1e-14)
    np.testing.assert_allclose(to_complex(A.P @ q[:, None]), X, atol=1e-14)


def test_cubic_is_exact_above_4H():
    """A cubic is alias-free on the retained harmonics when N > 4H."""
    rng = np.random.default_rng(1)
    H = 5
    xs = rng.normal(size=(2 * H + 1, 1))

    def cubic(q, v):
        return q**3

    assert aliasing_error(cubic, xs, 1.0, 4 * H + 1) < 1e-13
    assert aliasing_error(cubic, xs, 1.0, 2 * H + 2) > 1e-3   # too few: aliased
    assert choose_n_samples(cubic, xs, 1.0) == default_min_samples(H)


def test_rule_doubles_for_a_rational_force():
    """Rational force near its singularity: N grows until doubling changes < tol."""
    c = 1e-4
    force = radial_damper(400.0, c)[0]
    H = 3
    xs = np.zeros((2 * H + 1, 2))
    xs[0, 1] = -0.48 * c
    xs[1, 0], xs[2, 1] = 0.48 * c, 0.48 * c      # orbit reaching r = 0.96 c
    xs[3, 0] = 0.02 * c
    w = 300.0
    N = choose_n_samples(force, xs, w, tol=1e-8)
    assert N > default_min_samples(H)
    assert aliasing_error(force, xs, w, N) < 1e-8
    assert aliasing_error(force, xs, w, N // 2) >= 1e-8
    errs = [aliasing_error(force, xs, w, n) for n in (8, 16, 32, 64)]
    assert errs[0] > errs[1] > errs[2] > errs[3]
