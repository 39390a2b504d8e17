"""Exact condensation: condensed and full HB give the same solution."""

import numpy as np
import pytest

from rotorsfd.harmonic import continue_periodic, solve_periodic
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.examples import beam_rotor, generic_chain
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.harmonic.residual import FullHB


@pytest.mark.parametrize("lam", [0.3, 0.7, 1.1])
def test_condensed_equals_full_chain(lam):
    p = generic_chain(n=8, nl=(2, 5))
    a = solve_periodic(p, lam, 4, tol=1e-12)
    b = solve_periodic(p, lam, 4, tol=1e-12, condensed=False)
    assert a.n_samples == b.n_samples
    assert np.abs(a.X - b.X).max() <= 1e-9 * np.abs(b.X).max()


def test_recovered_dofs_satisfy_full_residual():
    """All DOFs recovered from the condensed solution solve the full HB equations."""
    p = beam_rotor()
    s = solve_periodic(p, 850.0, 3, tol=1e-12)
    full = FullHB(p, 3, s.n_samples)
    R, _, _ = full.residual(to_real(s.X), 850.0, jac=False)
    K = p.matrices(850.0)[2]
    force_scale = np.abs(K).max() * np.abs(s.X).max()
    assert np.abs(R).max() <= 1e-12 * force_scale
    f = solve_periodic(p, 850.0, 3, tol=1e-12, condensed=False)
    assert np.abs(s.X - f.X).max() <= 1e-7 * np.abs(f.X).max()


def test_schur_jacobian_is_full_jacobian_reduced():
    """Stored condensed Jacobian = Schur complement of the full HB Jacobian on nl_dofs."""
    p = generic_chain(n=6, nl=(1, 4))
    H, lam = 3, 0.9
    s = solve_periodic(p, lam, H, tol=1e-12)
    full = FullHB(p, H, s.n_samples)
    _, J, dR = full.residual(to_real(s.X), lam)
    n, nh = p.n_dof, 2 * H + 1
    idx = (np.arange(nh)[:, None] * n + p.nl_dofs[None, :]).ravel()
    rest = np.setdiff1d(np.arange(nh * n), idx)
    Je = np.column_stack([J, dR])
    Jss = Je[np.ix_(idx, np.append(idx, nh * n))]
    Jsl = Je[np.ix_(idx, rest)]
    Jll = Je[np.ix_(rest, rest)]
    Jle = Je[np.ix_(rest, np.append(idx, nh * n))]
    schur = Jss - Jsl @ np.linalg.solve(Jll, Jle)
    np.testing.assert_allclose(s.jacobian, schur, atol=1e-9 * np.abs(schur).max())


def test_condensed_branch_equals_full_branch():
    p = generic_chain(n=6, nl=(2, 3))
    kw = dict(tol=1e-10, ds=0.05, ds_max=0.5)
    a = continue_periodic(p, 0.2, 1.2, 3, **kw)
    b = continue_periodic(p, 0.2, 1.2, 3, condensed=False, **kw)
    assert a.success and b.success
    # compare the full solution at the condensed branch's parameter values
    for i in range(0, a.n_points, max(a.n_points // 5, 1)):
        f = solve_periodic(p, a.lam[i], 3, a.X[i], tol=1e-12, condensed=False)
        assert np.abs(a.X[i] - f.X).max() <= 1e-8 * np.abs(f.X).max()
    assert abs(b.lam[-1] - 1.2) < 1e-12


def test_shift_keeps_undamped_resonance_regular():
    """Undamped linear part at resonance: Z_1 singular, shifted Zt_1 is not."""
    p = beam_rotor()
    hb = CondensedHB(p, 1, 16)
    x = np.zeros((3, 2))
    hb.set_shift(x, 800.0)
    assert np.all(np.diag(hb.delta[1]).imag > 0)
