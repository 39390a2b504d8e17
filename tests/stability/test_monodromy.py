"""Newmark and Magnus monodromy: LTI exactness, convergence to a solve_ivp reference,
Liouville identity, input formats."""

from __future__ import annotations

import numpy as np
import pytest
from stability_helpers import ltp3, match_error, reference_monodromy

from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.stability.monodromy import (
    floquet_multipliers,
    monodromy_generalized_alpha,
    monodromy_magnus4,
    monodromy_newmark,
)


def _lti():
    M = np.diag([1.0, 2.0, 1.5])
    K = np.array([[3.0, -1.0, 0.0], [-1.0, 4.0, -1.0], [0.0, -1.0, 2.0]])
    D = 0.05 * K + 0.3 * np.array([[0, 1.0, 0], [-1.0, 0, 0], [0, 0, 0]])
    A = np.block([[np.zeros((3, 3)), np.eye(3)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    return M, D, K, A


def test_lti_magnus_exact():
    """Constant coefficients: Magnus-4 is expm(A h) per step, hence exact:
    multipliers = exp(lambda T) to 1e-8 (here ~1e-15)."""
    M, D, K, A = _lti()
    T = 2.0
    exact = np.exp(np.linalg.eigvals(A) * T)
    r = monodromy_magnus4(M, D, K, T, n_intervals=5)
    assert match_error(r.multipliers, exact) < 1e-8
    assert r.liouville_error < 1e-12


def test_lti_newmark_second_order():
    """Newmark (trapezoidal) on an LTI system: error O(h^2), ~1e-5 at N=400, and the
    Cayley map exp(lambda h) ~ (1 + lambda h/2)/(1 - lambda h/2) exactly per step."""
    M, D, K, A = _lti()
    T = 2.0
    exact = np.exp(np.linalg.eigvals(A) * T)
    e = [match_error(monodromy_newmark(M, D, K, T, n_intervals=N).multipliers, exact)
         for N in (400, 800)]
    assert e[0] < 5e-5
    assert 3.8 < e[0] / e[1] < 4.2
    h = T / 400
    lam = np.linalg.eigvals(A)
    cayley = ((1 + lam * h / 2) / (1 - lam * h / 2)) ** 400
    r = monodromy_newmark(M, D, K, T, n_intervals=400)
    assert match_error(r.multipliers, cayley) < 1e-11


def test_ltp_newmark_magnus_vs_solve_ivp():
    s = ltp3()
    ref = reference_monodromy(s["M"], s["D"], s["K"], s["T"], s["nl"], s["dFdq"],
                              s["dFdv"])
    mu_ref = np.linalg.eigvals(ref)
    kw = dict(nl_dofs=s["nl"], dFdq=s["dFdq"], dFdv=s["dFdv"])
    nm = monodromy_newmark(s["M"], s["D"], s["K"], s["T"], n_intervals=400, **kw)
    mg = monodromy_magnus4(s["M"], s["D"], s["K"], s["T"], n_intervals=100, **kw)
    assert np.abs(nm.monodromy - ref).max() < 1e-4
    assert match_error(nm.multipliers, mu_ref) < 1e-4
    assert np.abs(mg.monodromy - ref).max() < 1e-7
    assert match_error(mg.multipliers, mu_ref) < 1e-7
    # second order: halving h divides the monodromy error by ~4
    nm2 = monodromy_newmark(s["M"], s["D"], s["K"], s["T"], n_intervals=800, **kw)
    ratio = np.abs(nm.monodromy - ref).max() / np.abs(nm2.monodromy - ref).max()
    assert 3.5 < ratio < 4.5


def test_liouville_check():
    """det Phi = exp(-int tr(M^-1 D(t)) dt): reported error small for resolved systems
    and decreasing as O(h^2) with Newmark."""
    s = ltp3()
    kw = dict(nl_dofs=s["nl"], dFdq=s["dFdq"], dFdv=s["dFdv"])
    ref = reference_monodromy(s["M"], s["D"], s["K"], s["T"], s["nl"], s["dFdq"],
                              s["dFdv"])
    r400 = monodromy_newmark(s["M"], s["D"], s["K"], s["T"], n_intervals=400, **kw)
    r1600 = monodromy_newmark(s["M"], s["D"], s["K"], s["T"], n_intervals=1600, **kw)
    assert abs(np.log(np.linalg.det(ref)) - r1600.log_det_exact) < 1e-6
    assert r400.liouville_error < 3e-5
    assert r1600.liouville_error < r400.liouville_error / 10


def test_liouville_flags_unresolved_stiff_modes():
    """A stiff lightly damped mode (omega h >> 1) is mapped near |mu| = 1 by Newmark:
    the Liouville error shows it."""
    M = np.eye(2)
    K = np.diag([1.0, 1e8])
    D = np.diag([0.1, 0.1 * 2e4 * 0.01])  # 1 % damping on the stiff mode
    r = monodromy_newmark(M, D, K, 2 * np.pi, n_intervals=400)
    assert r.max_abs > 0.9  # true value exp(-0.01 * 1e4 * 2 pi) ~ 0
    assert r.liouville_error > 100


def test_jacobian_input_formats():
    s = ltp3()
    N = 200
    t = np.linspace(0, s["T"], N + 1)
    q = np.array([s["dFdq"](x) for x in t])
    v = np.array([s["dFdv"](x) for x in t])
    a = monodromy_newmark(s["M"], s["D"], s["K"], s["T"], nl_dofs=s["nl"],
                          dFdq=s["dFdq"], dFdv=s["dFdv"], n_intervals=N)
    b = monodromy_newmark(s["M"], s["D"], s["K"], s["T"], nl_dofs=s["nl"], dFdq=q,
                          dFdv=v, n_intervals=N)
    c = monodromy_newmark(s["M"], s["D"], s["K"], s["T"], nl_dofs=s["nl"], dFdq=q[:-1],
                          dFdv=v[:-1], n_intervals=N)
    assert np.allclose(a.monodromy, b.monodromy, atol=1e-13)
    assert np.allclose(a.monodromy, c.monodromy, atol=1e-13)
    with pytest.raises(ConfigError):
        monodromy_newmark(s["M"], s["D"], s["K"], s["T"], nl_dofs=s["nl"], dFdq=q[:10],
                          n_intervals=N)


def test_woodbury_equals_dense_full_time_variation():
    """The low-rank update with nl_dofs = all DOFs equals the plain dense recursion."""
    s = ltp3()
    n, N, T = 3, 50, s["T"]
    h = T / N
    nl = np.arange(3)

    def kq(t):
        return np.array([[0.3 * np.cos(t), 0.1, 0.0], [0.0, -0.2 * np.sin(t), 0.1],
                         [0.05, 0.0, 0.4 * np.cos(2 * t)]])

    def kv(t):
        return 0.05 * np.sin(t) * np.eye(3)

    r = monodromy_newmark(s["M"], s["D"], s["K"], T, nl_dofs=nl, dFdq=kq, dFdv=kv,
                          n_intervals=N)
    X, V = np.hstack([np.eye(n), np.zeros((n, n))]), np.hstack([np.zeros((n, n)), np.eye(n)])
    M = s["M"]
    for j in range(N):
        D0, K0 = s["D"] - kv(j * h), s["K"] - kq(j * h)
        D1, K1 = s["D"] - kv((j + 1) * h), s["K"] - kq((j + 1) * h)
        S = 4 / h**2 * M + 2 / h * D1 + K1
        Xn = np.linalg.solve(S, (4 / h**2 * M + 2 / h * D1 - K0) @ X
                             + (4 / h * M + D1 - D0) @ V)
        V = 2 / h * (Xn - X) - V
        X = Xn
    assert np.allclose(r.monodromy, np.vstack([X, V]), atol=1e-12)


def test_floquet_multipliers_paper_literal_equals_newmark():
    s = ltp3()
    kw = dict(nl_dofs=s["nl"], dFdq=s["dFdq"], dFdv=s["dFdv"])
    a = floquet_multipliers(s["M"], s["D"], s["K"], s["T"], reduction=None, **kw)
    b = monodromy_newmark(s["M"], s["D"], s["K"], s["T"], n_intervals=400, **kw)
    assert a.method == "newmark" and a.info["n_intervals"] == 400
    assert np.allclose(a.multipliers, b.multipliers)


@pytest.mark.parametrize("rho_inf", [0.9, 0.6])
def test_generalized_alpha_second_order(rho_inf):
    s = ltp3()
    kw = dict(nl_dofs=s["nl"], dFdq=s["dFdq"], dFdv=s["dFdv"], rho_inf=rho_inf)
    ref = reference_monodromy(s["M"], s["D"], s["K"], s["T"], s["nl"], s["dFdq"],
                              s["dFdv"])
    e = [np.abs(monodromy_generalized_alpha(s["M"], s["D"], s["K"], s["T"], n_intervals=N,
                                            **kw).monodromy - ref).max() for N in (400, 800)]
    assert e[0] < 2e-4
    assert 3.8 < e[0] / e[1] < 4.2


def test_generalized_alpha_damps_unresolved_mode():
    """The stiff undamped mode (omega h = 157) that Newmark keeps at |mu| = 1 is damped
    away; the resolved mode's multiplier is unchanged to O(h^2)."""
    M, K, D = np.eye(2), np.diag([1.0, 1e8]), np.diag([0.1, 0.0])
    ga = monodromy_generalized_alpha(M, D, K, 2 * np.pi, n_intervals=400)
    nm = monodromy_newmark(M, D, K, 2 * np.pi, n_intervals=400)
    exact = np.exp(2 * np.pi * (-0.05 + 1j * np.sqrt(1 - 0.05**2)))
    assert abs(nm.max_abs - 1.0) < 1e-12
    assert ga.max_abs == pytest.approx(abs(exact), abs=1e-3)
    assert np.sort(np.abs(ga.multipliers))[0] < 1e-20
    with pytest.raises(ConfigError):
        monodromy_generalized_alpha(M, D, K, 1.0, rho_inf=1.0)


def test_bad_inputs_raise():
    s = ltp3()
    q = np.full((401, 2, 2), np.nan)
    with pytest.raises(ConvergenceError):
        monodromy_newmark(s["M"], s["D"], s["K"], s["T"], nl_dofs=s["nl"], dFdq=q)
    with pytest.raises(ConfigError):
        monodromy_newmark(s["M"], s["D"], s["K"], -1.0)
    with pytest.raises(ConfigError):
        monodromy_newmark(s["M"], s["D"], np.eye(2), 1.0)


def test_newmark_false_instability_of_unresolved_mode():
    """The trap: an undamped mode with omega h >> 1 and a modulated stiffness
    x'' + w^2 (1 + 0.1 cos t) x = 0. Newmark's per-step rotation is ~pi - 4/(w h), a slow
    beat that meets the modulation (first-order tongue) at w = 4 N^2 / (pi T); there the
    average-acceleration monodromy reports |mu| = 1.08 while the exact system (adiabatic,
    Magnus-4 with w h = 0.5) is neutral and generalized-alpha damps the mode."""
    T, N = 2 * np.pi, 40
    w = 4 * N**2 / (np.pi * T)

    def f(t):
        return np.array([[-0.1 * w * w * np.cos(t)]])

    args = (np.eye(1), np.zeros((1, 1)), np.array([[w * w]]), T)
    nm = monodromy_newmark(*args, nl_dofs=[0], dFdq=f, n_intervals=N)
    ex = monodromy_magnus4(*args, nl_dofs=[0], dFdq=f, n_intervals=4000)
    ga = monodromy_generalized_alpha(*args, nl_dofs=[0], dFdq=f, n_intervals=N)
    assert nm.max_abs > 1.05 and not nm.stable
    assert abs(ex.max_abs - 1.0) < 1e-9
    assert ga.max_abs < 1e-3
