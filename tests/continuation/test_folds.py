"""Fold curves of the Duffing oscillator x'' + c x' + k x + k3 x^3 = F cos(w t) in (w, F):
the fold-augmented system against one-parameter branches."""

import numpy as np
import pytest

from rotorsfd.continuation.folds import FoldSystem, continue_folds, locate_branch_fold
from rotorsfd.harmonic import continue_periodic
from rotorsfd.harmonic.examples import duffing
from rotorsfd.harmonic.fold_curve import TwoParameterHB, TwoParameterProblem
from rotorsfd.harmonic.problem import PeriodicProblem

C, K, K3 = 0.05, 1.0, 0.1
H, N = 3, 32
F0 = 0.1
W_RANGE = (0.8, 1.4)


def duffing_in_force(w: float) -> PeriodicProblem:
    """The Duffing problem with the forcing amplitude F as parameter, at fixed w."""
    M, D, Kk, Z = np.eye(1), np.array([[C]]), np.array([[K]]), np.zeros((1, 1))

    def forcing(F, h):
        f = np.zeros((h + 1, 1), dtype=complex)
        f[1, 0] = F
        return f

    def dforcing(F, h):
        f = np.zeros((h + 1, 1), dtype=complex)
        f[1, 0] = 1.0
        return f

    return PeriodicProblem(
        n_dof=1, nl_dofs=np.array([0]), matrices=lambda F: (M, D, Kk),
        dmatrices=lambda F: (Z, Z, Z), forcing=forcing, dforcing=dforcing,
        frequency=lambda F: w, dfrequency=lambda F: 0.0, nl_force=lambda q, v: -K3 * q**3,
        nl_jacobian=lambda q, v: ((-3 * K3 * q**2)[..., None], np.zeros((*q.shape, 1))))


FAMILY = TwoParameterProblem(lambda F: duffing(C, K, K3, F), duffing_in_force, ("w", "F"))


def branch_at(F: float, ds_max: float = 0.02):
    return continue_periodic(duffing(C, K, K3, F), *W_RANGE, H, n_samples=N, ds_max=ds_max)


def branch_folds(F: float) -> list[float]:
    b = branch_at(F)
    return sorted(locate_branch_fold(b, int(i)).lam for i in b.folds())


@pytest.fixture(scope="module")
def start():
    b = branch_at(F0)
    folds = [locate_branch_fold(b, int(i)) for i in b.folds()]
    assert len(folds) == 2
    hb = TwoParameterHB(FAMILY, H, N, (W_RANGE[1] - W_RANGE[0], F0), folds[0].xs,
                        (folds[0].lam, F0))
    return hb, folds


@pytest.fixture(scope="module")
def curve(start):
    hb, folds = start
    p = folds[0]
    return continue_folds(hb, hb.to_z(p.xs, p.lam, F0), (1.0, 0.2))


def test_located_branch_fold_is_a_turning_point(start):
    _, folds = start
    for p in folds:
        assert abs(p.dlam_ds) < 1e-8


def test_fold_system_jacobian_matches_finite_differences(start):
    hb, folds = start
    p = folds[1]
    z = hb.to_z(p.xs, p.lam, F0) + 1e-3
    fold = FoldSystem(hb, z)
    F, J = fold.evaluate(z)
    assert F.shape == (fold.n,) and J.shape == (fold.n, fold.n + 1)
    h = 1e-6
    num = np.column_stack([(fold.evaluate(z + h * e)[0] - fold.evaluate(z - h * e)[0])
                           / (2 * h) for e in np.eye(z.size)])
    assert np.max(np.abs(num - J)) <= 1e-6 * np.max(np.abs(J))


def test_fold_curve_turns_at_a_cusp_and_returns_to_the_other_fold(start, curve):
    hb, folds = start
    assert curve.success, curve.message
    assert len(curve.cusps) == 1
    assert set(curve.segment) == {0, 1}
    _, w_end, F_end = hb.from_z(curve.z[-1])
    assert F_end == pytest.approx(F0, rel=1e-12)
    assert w_end == pytest.approx(folds[1].lam, rel=1e-8)   # the other fold of the pair
    cusp = curve.cusps[0]
    assert abs(curve.tangents[cusp.index][-1]) < 1e-8      # dF/ds = 0 there


@pytest.mark.parametrize("F", [0.06, 0.08, 0.1])
def test_fold_curve_passes_through_one_parameter_folds(start, curve, F):
    hb, _ = start
    on_curve = sorted(hb.from_z(z)[1] for z in curve.solve_at(F / F0))
    expected = branch_folds(F)
    assert len(on_curve) == len(expected) == 2
    np.testing.assert_allclose(on_curve, expected, rtol=1e-4)


def test_cusp_matches_the_smallest_force_with_a_fold_pair(start, curve):
    """Bisection on F (to 1e-4 relative) for the smallest F whose one-parameter branch
    (w in 0.95..1.15, ds_max 0.01) has a fold pair; the cusp of the fold curve agrees
    to 2e-4 relative (a pair closer than a step is missed, which biases the bisection
    upwards by a few 1e-5)."""
    hb, _ = start
    F_cusp = hb.from_z(curve.cusps[0].z)[2]

    def has_pair(F: float) -> bool:
        b = continue_periodic(duffing(C, K, K3, F), 0.95, 1.15, H, n_samples=N, ds_max=0.01)
        return b.folds().size >= 2

    lo, hi = 0.04, 0.06
    assert not has_pair(lo) and has_pair(hi)
    while hi - lo > 1e-4 * hi:
        mid = 0.5 * (lo + hi)
        lo, hi = (lo, mid) if has_pair(mid) else (mid, hi)
    assert F_cusp == pytest.approx(0.5 * (lo + hi), rel=2e-4)
