"""A posteriori truncation error of HB solutions and the adaptive number of harmonics.

Independent checks: the estimate against the actual change of the solution when it is
solved again with more harmonics (a second computation, not the estimate's one Newton
step); a circular whirl (whose exact solution is one harmonic) has a zero estimate; the
folds of an adaptive branch against those of a branch with many more harmonics.
"""

import numpy as np
import pytest

from rotorsfd.continuation.folds import locate_branch_fold
from rotorsfd.harmonic import continue_periodic, solve_periodic
from rotorsfd.harmonic.examples import duffing, jeffcott_damper
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.harmonic.truncation import pad_harmonics, truncation_error

# a hardening Duffing oscillator driven hard enough that 3X, 5X matter near resonance
STRONG = {"c": 0.05, "k": 1.0, "k3": 1.0, "F": 0.3}   # folds 2.3996 / 1.3292


def _fold_speeds(branch):
    return np.sort([locate_branch_fold(branch, int(i)).lam for i in branch.folds()])


@pytest.mark.parametrize("H", [1, 3])
@pytest.mark.parametrize("lam", [0.8, 1.1])
def test_estimate_is_the_change_to_more_harmonics(H, lam):
    p = duffing(**STRONG)
    one = solve_periodic(p, lam, 1, tol=1e-12)          # single-valued below the folds
    lo = solve_periodic(p, lam, H, one.X, tol=1e-12)
    H_check = 3 * H
    est = truncation_error(p, lo.X, lam, H_check=H_check)
    hi = solve_periodic(p, lam, H_check, lo.X, tol=1e-12)
    change = np.linalg.norm(to_real(hi.X) - pad_harmonics(to_real(lo.X), H_check))
    assert change > 1e-4                 # the case is not trivially converged
    assert est.error == pytest.approx(change, rel=0.1)
    # the dropped harmonics are where the change is: odd ones for the cubic force
    assert est.per_harmonic[H + 1:].max() > 10 * est.per_harmonic[H + 1::2][1:].max(
        initial=0.0) or H + 2 > H_check


def test_circular_whirl_has_no_truncation_error():
    # isotropic Jeffcott rotor with a radial damper: the exact orbit is a circle (1X only)
    p = jeffcott_damper()
    b = continue_periodic(p, 0.5 * 316.0, 1.5 * 316.0, 3)
    te = b.info["truncation_error"]
    assert b.success and te.size == b.n_points
    assert np.all(te < 1e-10), te.max()


def test_fixed_low_H_warns_and_adaptive_H_converges_the_folds():
    p = duffing(**STRONG)
    ref = continue_periodic(p, 0.5, 4.0, 15, harmonics_tol=None)
    fixed = continue_periodic(p, 0.5, 4.0, 1)
    auto = continue_periodic(p, 0.5, 4.0, 1, adaptive_harmonics=True, harmonics_tol=1e-4)
    f_ref, f_fixed, f_auto = (_fold_speeds(b) for b in (ref, fixed, auto))
    assert len(f_ref) == len(f_fixed) == len(f_auto) == 2
    # H = 1 moves the folds (the describing-function error), and says so
    assert np.max(np.abs(f_fixed - f_ref) / f_ref) > 1e-3
    assert "warning: HB truncation error above" in fixed.message
    # the adaptive branch keeps its estimate below the tolerance, and its folds agree with
    # the H = 15 ones far better than the estimate's tolerance would need
    assert auto.success and "warning" not in auto.message
    assert auto.info["truncation_error"].max() <= 1e-4
    Hs = auto.info["harmonics"]
    assert Hs.min() == 1 and Hs.max() >= 3            # raised near resonance, low elsewhere
    np.testing.assert_allclose(f_auto, f_ref, rtol=2e-5)
    assert auto.X.shape[1] == Hs.max() + 1            # padded to the largest H
