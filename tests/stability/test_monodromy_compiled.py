"""The compiled monodromy loops (``rotorsfd.stability.monodromy_kernels``) against the numpy
reference loops (``compiled=False``): the same multipliers to 1e-10 on the paper rotor's
Craig-Bampton model (and its full 84-DOF model), on Mathieu-type systems and on a
gyroscopic 3-DOF system; plus independent checks of the compiled path (Cayley closed
form, Liouville, DOP853 reference, Floquet theory of the Mathieu equation)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from stability_helpers import ltp3, match_error, reference_monodromy

from rotorsfd.stability.monodromy import (
    floquet_multipliers,
    monodromy_generalized_alpha,
    monodromy_newmark,
)

ROOT = Path(__file__).resolve().parents[2]
SCHEMES = {"newmark": monodromy_newmark, "generalized-alpha": monodromy_generalized_alpha}


def _pair(f, *args, **kw):
    return f(*args, compiled=True, **kw), f(*args, compiled=False, **kw)


def _assert_same(a, b, tol=1e-10):
    """Same multipliers (matched) and the same monodromy, relative to its size."""
    assert match_error(a.multipliers, b.multipliers) < tol
    scale = np.abs(b.monodromy).max()
    assert np.abs(a.monodromy - b.monodromy).max() < tol * scale
    assert a.log_det_exact == pytest.approx(b.log_det_exact, rel=1e-12, abs=1e-12)


@pytest.fixture(scope="module")
def paper():
    """The paper rotor's HB orbit at 850 rad/s (H = 3), its SFD Jacobian samples at
    N = 400, 800 and 1600 intervals, the full matrices and the Craig-Bampton model of the
    branch analysis (modes with omega h <= 1/4 at N = 400)."""
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem
    from rotorsfd.stability.orbit import orbit_samples
    from rotorsfd.stability.reduction import craig_bampton

    model = build_model(load_config(ROOT / "examples" / "paper_rotor.toml"))
    system = RotorSystem(model.rotor, model.elements, model.unbalances,
                         model.base_motion)
    problem = system.periodic_problem()
    speed = 850.0
    sol = solve_periodic(problem, speed, H=3)
    M, D, K = system.matrices(speed)
    nl = np.asarray(system.nl_dofs)
    T = 2 * np.pi / speed
    jac = {}
    for N in (400, 800, 1600):
        q, v = orbit_samples(sol.X[:, nl], speed, N)
        jac[N] = problem.nl_jacobian(q, v)
    red = craig_bampton(M, D, K, nl, omega_max=0.25 * 400 / T)
    return {"M": M, "D": D, "K": K, "nl": nl, "T": T, "jac": jac, "red": red}


@pytest.mark.parametrize("scheme", list(SCHEMES))
@pytest.mark.parametrize("N", [400, 800])
def test_paper_rotor_reduced_compiled_equals_numpy(paper, scheme, N):
    """On the reduced model of the branch analysis (2 SFD DOFs + its kept modes) at M and
    2M intervals (the step control's pair): the same multipliers to 1e-10."""
    red, (Jq, Jv) = paper["red"], paper["jac"][N]
    assert 6 <= red.n_dof <= 30
    a, b = _pair(SCHEMES[scheme], red.M, red.D, red.K, paper["T"], nl_dofs=red.nl_dofs,
                 dFdq=Jq, dFdv=Jv, n_intervals=N)
    _assert_same(a, b)
    assert 0.5 < a.max_abs < 1.0  # the SFD-damped orbit at 850 rad/s is stable


def test_paper_rotor_full_model_compiled_equals_numpy(paper):
    """The paper's literal method (full 84-DOF model, N = 400) through
    ``floquet_multipliers(reduction=None)``: compiled and numpy agree to 1e-10."""
    Jq, Jv = paper["jac"][400]
    kw = {"nl_dofs": paper["nl"], "dFdq": Jq, "dFdv": Jv, "n_intervals": 400,
          "reduction": None}
    for scheme in SCHEMES:
        a = floquet_multipliers(paper["M"], paper["D"], paper["K"], paper["T"],
                                scheme=scheme, **kw)
        b = floquet_multipliers(paper["M"], paper["D"], paper["K"], paper["T"],
                                scheme=scheme, compiled=False, **kw)
        assert a.monodromy.shape == (168, 168)
        _assert_same(a, b)


def test_paper_rotor_reduced_converges_second_order(paper):
    """Compiled Newmark on the fixed reduced model at N = 400, 800, 1600: the leading
    (SFD-coupled) multiplier converges at second order, successive differences in the
    ratio 4 (+-10 %), and the N = 400 error is below 1e-3 (Richardson estimate)."""
    red = paper["red"]
    mu = [monodromy_newmark(red.M, red.D, red.K, paper["T"], nl_dofs=red.nl_dofs,
                            dFdq=paper["jac"][N][0], dFdv=paper["jac"][N][1],
                            n_intervals=N).critical for N in (400, 800, 1600)]
    ratio = abs(mu[0] - mu[1]) / abs(mu[1] - mu[2])
    assert ratio == pytest.approx(4.0, rel=0.1)
    assert abs(mu[0] - (4 * mu[2] - mu[1]) / 3) < 1e-3


def _mathieu(delta: float, eps: float, c: float = 0.0):
    """``x'' + c x' + (delta + eps cos t) x = 0`` (period 2 pi) as a 1-DOF model with
    the parametric term as the 'nonlinear' Jacobian ``dF/dq = -eps cos t``."""
    def kq(t):
        return np.array([[-eps * np.cos(t)]])

    return np.eye(1), c * np.eye(1), delta * np.eye(1), 2 * np.pi, kq


@pytest.mark.parametrize("scheme", list(SCHEMES))
@pytest.mark.parametrize("delta, eps", [(0.25, 0.1), (1.0, 0.3), (0.6, 0.2)])
def test_mathieu_compiled_equals_numpy_and_theory(scheme, delta, eps):
    """Mathieu: compiled = numpy to 1e-10; against theory, the undamped equation has
    det Phi = 1 (Liouville) and its multipliers are either a real pair mu, 1/mu (inside
    a tongue: delta = 1/4 +- eps/2 at first order, so (0.25, 0.1) is unstable) or a pair
    on the unit circle (outside: (0.6, 0.2))."""
    M, D, K, T, kq = _mathieu(delta, eps)
    a, b = _pair(SCHEMES[scheme], M, D, K, T, nl_dofs=[0], dFdq=kq, n_intervals=800)
    _assert_same(a, b)
    ref = np.linalg.eigvals(reference_monodromy(M, D, K, T, [0], kq))
    assert match_error(a.multipliers, ref) < 2e-4  # second order at h = 2 pi / 800
    if scheme == "newmark":  # symplectic on undamped systems: det Phi = 1 exactly
        assert abs(np.prod(a.multipliers) - 1.0) < 1e-10
    if (delta, eps) == (0.25, 0.1):
        assert a.max_abs > 1.02 and abs(a.critical.imag) < 1e-8
    if (delta, eps) == (0.6, 0.2):
        assert a.max_abs < 1.0 + 1e-6


def test_mathieu_in_a_larger_model_nl_dof_not_first():
    """A damped Mathieu oscillator coupled to two linear DOFs, the parametric DOF placed
    last (nl = [2]) and, relabelled, first (nl = [0]): the same multipliers (to
    round-off) and compiled = numpy."""
    M = np.diag([1.0, 1.5, 0.8])
    K = np.array([[3.0, -1.0, -0.5], [-1.0, 2.5, 0.0], [-0.5, 0.0, 1.2]])
    D = 0.02 * K
    T = 2 * np.pi

    def kq(t):
        return np.array([[-0.4 * np.cos(t)]])

    def kv(t):
        return np.array([[0.03 * np.sin(t)]])

    perm = [2, 1, 0]
    for f in SCHEMES.values():
        a, b = _pair(f, M, D, K, T, nl_dofs=[0], dFdq=kq, dFdv=kv, n_intervals=400)
        _assert_same(a, b)
        Mp, Dp, Kp = (x[np.ix_(perm, perm)] for x in (M, D, K))
        c = f(Mp, Dp, Kp, T, nl_dofs=[2], dFdq=kq, dFdv=kv, n_intervals=400)
        assert match_error(a.multipliers, c.multipliers) < 1e-11


@pytest.mark.parametrize("scheme", list(SCHEMES))
def test_ltp3_two_nonlinear_dofs(scheme):
    """The gyroscopic 3-DOF system with a rank-2 Jacobian in q and q': compiled = numpy
    to 1e-10, 2e-4 close to the DOP853 monodromy and to Liouville at N = 400."""
    s = ltp3()
    a, b = _pair(SCHEMES[scheme], s["M"], s["D"], s["K"], s["T"], nl_dofs=s["nl"],
                 dFdq=s["dFdq"], dFdv=s["dFdv"], n_intervals=400)
    _assert_same(a, b)
    ref = reference_monodromy(s["M"], s["D"], s["K"], s["T"], s["nl"], s["dFdq"], s["dFdv"])
    assert match_error(a.multipliers, np.linalg.eigvals(ref)) < 2e-4
    assert a.liouville_error < 3e-5  # det Phi: O(h^2) off exp(-int tr M^-1 D dt)


def test_lti_without_nonlinear_dofs_is_cayley():
    """m = 0: compiled Newmark is the Cayley map per step, (1 + lam h/2)/(1 - lam h/2)^N
    for every eigenvalue lam of the first-order matrix (closed form, 1e-11)."""
    s = ltp3()
    M, D, K, T = s["M"], s["D"], s["K"], s["T"]
    A = np.block([[np.zeros((3, 3)), np.eye(3)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    lam = np.linalg.eigvals(A)
    N = 200
    h = T / N
    r = monodromy_newmark(M, D, K, T, n_intervals=N)
    assert match_error(r.multipliers, ((1 + lam * h / 2) / (1 - lam * h / 2)) ** N) < 1e-11
    _assert_same(r, monodromy_newmark(M, D, K, T, n_intervals=N, compiled=False))
    g = monodromy_generalized_alpha(M, D, K, T, n_intervals=N)
    _assert_same(g, monodromy_generalized_alpha(M, D, K, T, n_intervals=N, compiled=False))


def test_fortran_ordered_and_integer_inputs():
    """Fortran-ordered matrices, a list of nl DOFs and Jacobian samples in F order give
    the C-ordered result bit for bit, and no second compiled specialisation."""
    from rotorsfd.stability.monodromy_kernels import generalized_alpha_loop, newmark_loop

    s = ltp3()
    t = np.arange(201) * s["T"] / 200
    Jq = np.array([s["dFdq"](x) for x in t])
    for f in SCHEMES.values():
        a = f(s["M"], s["D"], s["K"], s["T"], nl_dofs=np.array(s["nl"]), dFdq=Jq,
              n_intervals=200)
        b = f(*(np.asfortranarray(x) for x in (s["M"], s["D"], s["K"])), s["T"],
              nl_dofs=list(s["nl"]), dFdq=np.asfortranarray(Jq), n_intervals=200)
        assert np.array_equal(a.monodromy, b.monodromy)
    assert len(newmark_loop.signatures) == 1
    assert len(generalized_alpha_loop.signatures) == 1


def test_compiled_rejects_non_finite_like_numpy():
    """NaN in the Jacobian samples: both paths raise the same ConvergenceError."""
    from rotorsfd.errors import ConvergenceError

    s = ltp3()
    Jq = np.zeros((101, 2, 2))
    Jq[50, 0, 0] = np.nan
    for f in SCHEMES.values():
        for compiled in (True, False):
            with pytest.raises(ConvergenceError):
                f(s["M"], s["D"], s["K"], s["T"], nl_dofs=s["nl"], dFdq=Jq,
                  n_intervals=100, compiled=compiled)
