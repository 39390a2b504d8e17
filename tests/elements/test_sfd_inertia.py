"""The SFD's fluid inertia (issue 18 item 1): the force against its derivation, its exact
Jacobians (q, v, a) against finite differences, the centred coefficients against the
published closed forms, and the solvers (HB, time stepping, Floquet) with a force of the
acceleration against each other.

Closed forms (San Andres 2012, "Squeeze film damper: operation, models and technical
issues", Modern Lubrication Theory notes 13, Texas A&M; San Andres and Vance 1986, ASME
J. Eng. Gas Turbines Power 108, 332): short open-ended SFD, small motion about the
centre, full film ``C = pi mu R L^3 / c^3``, ``M = pi rho R L^3 / (12 c)``; the pi
(half) film half of each. The test values below are written from these formulas, not
from the code.
"""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from scipy.integrate import quad

from rotors import small_rotor_toml
from rotorsfd.elements import ElementSet
from rotorsfd.elements.sfd import SFDConfig
from rotorsfd.errors import ConfigError
from rotorsfd.io.config import load_config

MU, R, L, C, RHO = 0.004, 0.05, 0.02, 2e-4, 850.0
GEOMETRY = dict(node=1, viscosity=f"{MU} Pa*s", clearance=f"{C} m", radius=f"{R} m",
                length=f"{L} m")
FILMS = ("pi", "none", "guembel")


def element(cavitation: str = "pi", inertia: bool = True, **extra):
    kw = dict(density=f"{RHO} kg/m^3", fluid_inertia=True) if inertia else {}
    return SFDConfig(**GEOMETRY, cavitation=cavitation, **kw, **extra).build("sfd")


def states(n: int, seed: int = 3):
    rng = np.random.default_rng(seed)
    for _ in range(n):
        q = rng.uniform(-0.65, 0.65, 2) * C
        yield q, rng.normal(size=2) * C * 700.0, rng.normal(size=2) * C * 5e5


@pytest.mark.parametrize("cavitation", FILMS)
def test_no_inertia_is_todays_force(cavitation):
    """Without fluid_inertia (density absent, or given for the Reynolds number only) the
    force and Jacobians are the viscous film's, to the last bit; dF/da = 0."""
    plain = element(cavitation, inertia=False)
    with_density = SFDConfig(**GEOMETRY, cavitation=cavitation,
                             density=f"{RHO} kg/m^3").build("sfd")
    assert not plain.inertial and not with_density.inertial
    assert plain.inertial_kernel is None
    for q, v, a in states(5):
        ref = plain.film.force_and_jacobian(q[0], q[1], v[0], v[1])
        for got in (plain.force_and_jacobian(q, v), with_density.force_and_jacobian(q, v)):
            for x, y in zip(got, ref, strict=True):
                np.testing.assert_allclose(x, y, rtol=1e-12, atol=0)
        Ja = with_density.force_and_jacobians(q, v, a)[3]
        assert np.all(Ja == 0.0)


@pytest.mark.parametrize("cavitation", FILMS)
def test_inertia_force_against_pressure_quadrature(cavitation):
    """The implemented force (viscous + inertia) against an adaptive double quadrature
    of the averaged-inertia pressure p = (x^2 - L^2/4) [6 mu h'/h^3 + (rho/2)(h''/h -
    (12/5) h'^2/h^2)] over the film arc of each model (derivations/sfd_inertia.py)."""
    e = element(cavitation)
    for q, v, a in states(3, seed=11):
        F = e.force_and_jacobians(q, v, a)[0]
        psi = math.atan2(q[1], q[0])
        beta = math.atan2(v[1], v[0])
        lo, hi = {"pi": (psi, psi + math.pi), "none": (psi, psi + 2 * math.pi),
                  "guembel": (beta - math.pi / 2, beta + math.pi / 2)}[cavitation]

        def f(phi, k, q=q, v=v, a=a):
            n = np.array([math.cos(phi), math.sin(phi)])
            h, hd, hdd = C - q @ n, -v @ n, -a @ n
            bracket = 6 * MU * hd / h**3 + 0.5 * RHO * (hdd / h - 2.4 * hd**2 / h**2)
            return -R * (-L**3 / 6) * bracket * n[k]   # int (x^2 - L^2/4) dx = -L^3/6

        pts = [psi + 2 * math.pi * j for j in (-1, 0, 1)]
        ref = np.array([quad(f, lo, hi, args=(k,), epsrel=1e-12, limit=200,
                             points=[p for p in pts if lo < p < hi] or None)[0]
                        for k in range(2)])
        np.testing.assert_allclose(F, ref, rtol=1e-9, atol=1e-9 * np.max(np.abs(ref)))


@pytest.mark.parametrize(("cavitation", "share"), [("none", 1.0), ("pi", 0.5),
                                                   ("guembel", 0.5)])
def test_centred_coefficients_match_closed_forms(cavitation, share):
    """At the centre (small motion): dF/da = -M I, dF/dv = -C I with San Andres' closed
    forms M = pi rho R L^3/(12 c), C = pi mu R L^3/c^3 (full film; the pi film half)."""
    e = element(cavitation)
    _, _, Jv, Ja = e.force_and_jacobians(np.zeros(2), np.zeros(2), np.zeros(2))
    mass = share * math.pi * RHO * R * L**3 / (12 * C)
    damping = share * math.pi * MU * R * L**3 / C**3
    np.testing.assert_allclose(Ja, -mass * np.eye(2), rtol=1e-12, atol=1e-12 * mass)
    np.testing.assert_allclose(Jv, -damping * np.eye(2), rtol=1e-12, atol=1e-12 * damping)


def test_convective_inertia_reverses_radial_force_at_large_orbits():
    """San Andres and Vance (1986): on a circular centred orbit the temporal inertia
    pushes the journal outward (an added mass against the centripetal acceleration) at
    small eps, and the convective terms reverse the radial inertia force at large eps.
    Full film, inertia part only (the viscous radial force of a full-film CCO is 0)."""
    e = element("none")
    w = 500.0
    radial = []
    for eps in (0.05, 0.3, 0.6, 0.9):
        q = np.array([eps * C, 0.0])
        v = np.array([0.0, eps * C * w])
        a = np.array([-eps * C * w**2, 0.0])
        radial.append(e.force_and_jacobians(q, v, a)[0][0])
    assert radial[0] > 0.0 and radial[-1] < 0.0


@pytest.mark.parametrize("cavitation", FILMS)
def test_jacobians_against_finite_differences(cavitation):
    """dF/dq, dF/dv, dF/da against central differences (the Guembel states include arcs
    split at the thinnest film)."""
    e = element(cavitation)
    for q, v, a in states(6, seed=5):
        x = [q, v, a]
        J = e.force_and_jacobians(*x)[1:]
        for k in range(3):
            h = 1e-6 * np.max(np.abs(x[k]))
            fd = np.empty((2, 2))
            for j in range(2):
                xp = [y.copy() for y in x]
                xm = [y.copy() for y in x]
                xp[k][j] += h
                xm[k][j] -= h
                fd[:, j] = (e.force_and_jacobians(*xp)[0] - e.force_and_jacobians(*xm)[0]) \
                    / (2 * h)
            scale = np.max(np.abs(J[k]))
            np.testing.assert_allclose(J[k], fd, rtol=0, atol=2e-7 * scale)


def test_kernels_agree_with_numpy_form_and_composite():
    """The composite inertial kernel generated for two elements (an SFD with inertia and
    one without, at two nodes), called through the compiled AFT loop, and the numpy sum
    agree; dF/da is zero on the DOFs of the element without inertia."""
    from rotorsfd.harmonic.aft_inertia import as_inertial_kernel_ref, force_samples_inertial

    e1 = element("pi")
    e2 = SFDConfig(**{**GEOMETRY, "node": 3}, cavitation="none").build("other")
    es = ElementSet([e1, e2])
    assert es.inertial and es.m == 4
    ref_kernel = as_inertial_kernel_ref(es.inertial_kernel)
    rng = np.random.default_rng(2)
    for _ in range(4):
        q = rng.uniform(-0.5, 0.5, (1, 4)) * C
        v = rng.normal(size=(1, 4)) * C * 300
        a = rng.normal(size=(1, 4)) * C * 3e5
        F = np.zeros((1, 4))
        Jq, Jv, Ja = (np.zeros((1, 4, 4)) for _ in range(3))
        assert force_samples_inertial(ref_kernel, es.kernel_params, q, v, a, F, Jq, Jv,
                                      Ja) == 0
        ref = es.force_and_jacobians(q[0], v[0], a[0])
        for got, want in zip((F[0], Jq[0], Jv[0], Ja[0]), ref, strict=True):
            np.testing.assert_allclose(got, want, rtol=0, atol=1e-13 * np.max(np.abs(want)))
        assert np.all(ref[3][2:, :] == 0.0) and np.all(ref[3][:, 2:] == 0.0)
    assert not ElementSet([e2]).inertial and ElementSet([e2]).inertial_kernel is None


@pytest.mark.parametrize(("fields", "message"), [
    ({"fluid_inertia": True}, "needs the oil density"),
    ({"fluid_inertia": True, "density": "850 kg/m^3", "film_length": "finite"},
     "film_length = 'short' only"),
])
def test_bad_inertia_input(tmp_path, fields, message):
    extra = "".join(f"{k} = {v!r}\n".replace("True", "true").replace("'", '"')
                    for k, v in fields.items())
    path = small_rotor_toml(tmp_path / "r.toml")
    path.write_text(path.read_text().replace('centring_stiffness = "1e7 N/m"',
                                             'centring_stiffness = "1e7 N/m"\n' + extra))
    with pytest.raises(ConfigError, match=message):
        load_config(path)


# ---- the solvers with a force of the acceleration ------------------------------------------
INERTIA = ["elements.sfd.density=850 kg/m^3", "elements.sfd.fluid_inertia=true",
           "elements.sfd.viscosity=0.002 Pa*s"]
SPEED = 800.0
C_SMALL = 1.27e-4


def small_system(tmp_path: Path, inertia: bool = True):
    from rotorsfd.model.build import build_system

    path = small_rotor_toml(tmp_path / "small.toml", unbalance="100 g*mm")
    overrides = INERTIA if inertia else INERTIA[2:]
    return build_system(load_config(path, overrides=overrides))


@pytest.fixture(scope="module")
def hb_pair(tmp_path_factory):
    """HB solutions of the small rotor at 800 rad/s with and without the fluid inertia
    (squeeze Reynolds number rho w C^2/mu = 5.5)."""
    from rotorsfd.harmonic.periodic import solve_periodic

    out = {}
    for inertia in (True, False):
        system = small_system(tmp_path_factory.mktemp("hb"), inertia)
        problem = system.periodic_problem("speed")
        assert problem.inertial == inertia
        out[inertia] = (system, problem, solve_periodic(problem, SPEED, 5, tol=1e-11))
    return out


def test_hb_condensed_kernel_matches_full_numpy_path(hb_pair):
    """The condensed HB (compiled inertial AFT) and the full-model HB (numpy AFT with
    a = w^2 Edd xs) give the same orbit."""
    from rotorsfd.harmonic.periodic import solve_periodic

    _, problem, sol = hb_pair[True]
    full = solve_periodic(problem, SPEED, 5, condensed=False, tol=1e-11)
    assert np.max(np.abs(full.X - sol.X)) < 1e-7 * C_SMALL


def test_condensed_jacobian_against_finite_differences(hb_pair):
    """dR/dxs of the condensed residual with the inertial AFT against central
    differences (the -(k w)^2 dF/da chain)."""
    from rotorsfd.harmonic.condensation import CondensedHB
    from rotorsfd.harmonic.fourier import to_real

    _, problem, sol = hb_pair[True]
    hb = CondensedHB(problem, 5, 64)
    xs = to_real(sol.X[:, problem.nl_dofs]) * 1.05
    _, J, dR = hb.residual(xs, SPEED)
    h = 1e-6 * C_SMALL
    fd = np.empty_like(J)
    for c in range(xs.size):
        e = np.zeros(xs.size)
        e[c] = h
        fd[:, c] = (hb.residual(xs + e.reshape(xs.shape), SPEED, jac=False)[0]
                    - hb.residual(xs - e.reshape(xs.shape), SPEED, jac=False)[0]
                    ).ravel() / (2 * h)
    np.testing.assert_allclose(J, fd, rtol=0, atol=1e-6 * np.max(np.abs(J)))
    dl = 1e-3
    fd_l = (hb.residual(xs, SPEED + dl, jac=False)[0]
            - hb.residual(xs, SPEED - dl, jac=False)[0]).ravel() / (2 * dl)
    np.testing.assert_allclose(dR, fd_l, rtol=0, atol=1e-6 * np.max(np.abs(dR)))


def _integrate(system, X, method, periods=20, spp=800, q0=None, v0=None, record=True):
    from rotorsfd.timedomain.forcing import Forcing, HarmonicLoad
    from rotorsfd.timedomain.integrate import integrate

    M, D, K = system.matrices(SPEED)
    Fc, Fs = system.unbalance_harmonics(SPEED)
    forcing = Forcing(omega=SPEED, constant=system.static_force(SPEED),
                      harmonics=[HarmonicLoad(1.0, Fc, Fs)])
    el = system.elements_at(SPEED)
    k = np.arange(X.shape[0])
    if q0 is None:
        q0 = np.real(X.sum(0))
        v0 = np.real((1j * k[:, None] * SPEED * X).sum(0))
    return integrate(M, D, K, system.nl_dofs, el.kernel, el.kernel_params, forcing,
                     steps_per_period=spp, n_periods=periods, q0=q0, v0=v0,
                     record_every=1, record_start=(periods - 1) * spp if record else 0,
                     method=method, inertial_kernel=el.inertial_kernel)


@pytest.mark.parametrize("method", ["newmark", "generalized-alpha"])
def test_hb_against_time_integration_with_inertia(hb_pair, method):
    """20 periods of the compiled step (the added mass dF/da/(beta h^2) in its Newton
    matrix) from the HB orbit stay on it within 1e-3 C (measured 2e-5 C), while the orbit
    without inertia is 5e-3 C away: the check sees the inertia."""
    system, problem, sol = hb_pair[True]
    res = _integrate(system, sol.X, method)
    k = np.arange(sol.X.shape[0])
    phase = np.exp(1j * np.outer(res.t * SPEED, k))
    nl = problem.nl_dofs
    err = np.max(np.abs(res.q - np.real(phase @ sol.X[:, nl]))) / C_SMALL
    other = np.max(np.abs(res.q - np.real(phase @ hb_pair[False][2].X[:, nl]))) / C_SMALL
    assert err < 1e-3
    assert other > 3e-3


def test_floquet_with_added_mass_against_finite_difference_monodromy(hb_pair):
    """The Newmark monodromy of the linearised equation with the time-varying added mass
    M - P dF/da(t) P^T (full model, N = 400) against the finite-difference monodromy of
    the nonlinear time stepper (the same scheme, 400 steps a period, central
    differences in each state direction): the four largest agree to 2e-6 (measured
    2.3e-7) while without the added mass they are 2.4e-2 off. (At N = 400 the full model's
    largest ones belong to unresolved stiff modes, omega h >> 1, which the Craig-Bampton
    default leaves out; here they test the scheme's linearisation, the point.)"""
    from rotorsfd.stability.monodromy import floquet_multipliers
    from rotorsfd.stability.orbit import inertial_jacobians

    system, problem, sol = hb_pair[True]
    M, D, K = problem.matrices(SPEED)
    nl = problem.nl_dofs
    T = 2 * np.pi / SPEED
    Jq, Jv, Ja = inertial_jacobians(problem.law(SPEED).force_jacobians, sol.X[:, nl],
                                    SPEED, 400)
    res = floquet_multipliers(M, D, K, T, nl_dofs=nl, dFdq=Jq, dFdv=Jv, dFda=Ja,
                              n_intervals=400, reduction=None)
    plain = floquet_multipliers(M, D, K, T, nl_dofs=nl, dFdq=Jq, dFdv=Jv,
                                n_intervals=400, reduction=None)
    n = M.shape[0]
    k = np.arange(sol.X.shape[0])
    x0 = np.concatenate([np.real(sol.X.sum(0)), np.real((1j * k[:, None] * SPEED
                                                          * sol.X).sum(0))])
    Phi = np.empty((2 * n, 2 * n))
    for j in range(2 * n):
        s = 1e-6 * C_SMALL * (1.0 if j < n else SPEED)
        ends = []
        for sign in (1.0, -1.0):
            x = x0.copy()
            x[j] += sign * s
            r = _integrate(system, sol.X, "newmark", periods=1, spp=400, q0=x[:n],
                           v0=x[n:], record=False)
            ends.append(np.concatenate([r.q_final, r.v_final]))
        Phi[:, j] = (ends[0] - ends[1]) / (2 * s)
    mu_fd = np.sort(np.abs(np.linalg.eigvals(Phi)))[::-1][:4]
    mu = np.sort(np.abs(res.multipliers))[::-1][:4]
    mu0 = np.sort(np.abs(plain.multipliers))[::-1][:4]
    assert np.max(np.abs(mu - mu_fd)) < 2e-6
    assert np.max(np.abs(mu0 - mu_fd)) > 1e-3


def test_floquet_compiled_and_numpy_loops_agree_with_added_mass(hb_pair):
    from rotorsfd.stability.monodromy import floquet_multipliers
    from rotorsfd.stability.orbit import inertial_jacobians

    _, problem, sol = hb_pair[True]
    M, D, K = problem.matrices(SPEED)
    nl = problem.nl_dofs
    Jq, Jv, Ja = inertial_jacobians(problem.law(SPEED).force_jacobians, sol.X[:, nl],
                                    SPEED, 200)
    for scheme in ("newmark", "generalized-alpha"):
        a, b = (floquet_multipliers(M, D, K, 2 * np.pi / SPEED, nl_dofs=nl, dFdq=Jq,
                                    dFdv=Jv, dFda=Ja, n_intervals=200, scheme=scheme,
                                    compiled=c) for c in (True, False))
        np.testing.assert_allclose(a.multipliers, b.multipliers, rtol=0, atol=1e-10)


def test_reduced_step_with_inertia(hb_pair):
    """The Craig-Bampton reduced step (timedomain.reduced, the nonlinear DOFs kept
    physical, so the added mass acts on the same rows) with the inertial kernel stays on
    the HB orbit within 1e-3 C."""
    from rotorsfd.timedomain.forcing import Forcing, HarmonicLoad
    from rotorsfd.timedomain.integrate import integrate
    from rotorsfd.timedomain.reduced import reduce_step

    system, problem, sol = hb_pair[True]
    M, D, K = system.matrices(SPEED)
    Fc, Fs = system.unbalance_harmonics(SPEED)
    forcing = Forcing(omega=SPEED, constant=system.static_force(SPEED),
                      harmonics=[HarmonicLoad(1.0, Fc, Fs)])
    red = reduce_step(M, D, K, system.nl_dofs, forcing, None, omega_max=30 * SPEED)
    assert red.model.M.shape[0] < M.shape[0]
    el = system.elements_at(SPEED)
    k = np.arange(sol.X.shape[0])
    q0 = np.real(sol.X.sum(0))
    v0 = np.real((1j * k[:, None] * SPEED * sol.X).sum(0))
    spp, periods = 800, 20
    res = integrate(red.model.M, red.model.D, red.model.K, red.nl_dofs, el.kernel,
                    el.kernel_params, red.forcing, steps_per_period=spp, n_periods=periods,
                    q0=red.reduce(q0), v0=red.reduce(v0), record_every=1,
                    record_start=(periods - 1) * spp, inertial_kernel=el.inertial_kernel)
    phase = np.exp(1j * np.outer(res.t * SPEED, k))
    hb = np.real(phase @ sol.X[:, problem.nl_dofs])
    assert np.max(np.abs(res.q - hb)) / C_SMALL < 1e-3


def test_zero_added_mass_path_is_the_usual_recursion(hb_pair):
    """The Newmark monodromy that carries the acceleration (taken with dFda) = the usual
    (x, v) recursion when the added mass is zero."""
    from rotorsfd.stability.monodromy import floquet_multipliers
    from rotorsfd.stability.orbit import inertial_jacobians

    _, problem, sol = hb_pair[True]
    M, D, K = problem.matrices(SPEED)
    nl = problem.nl_dofs
    Jq, Jv, Ja = inertial_jacobians(problem.law(SPEED).force_jacobians, sol.X[:, nl],
                                    SPEED, 200)
    T = 2 * np.pi / SPEED
    a = floquet_multipliers(M, D, K, T, nl_dofs=nl, dFdq=Jq, dFdv=Jv,
                            dFda=np.zeros_like(Ja), n_intervals=200, reduction=None)
    b = floquet_multipliers(M, D, K, T, nl_dofs=nl, dFdq=Jq, dFdv=Jv, n_intervals=200,
                            reduction=None)
    np.testing.assert_allclose(np.sort_complex(a.multipliers), np.sort_complex(b.multipliers),
                               rtol=0, atol=1e-10)


def test_hill_with_added_mass_matches_newmark(hb_pair):
    """Hill's method on A(t) = [[0, I], [-M(t)^-1 K(t), -M(t)^-1 D(t)]] with the
    time-varying mass, sampled and transformed (an independent route: no Newmark, no
    Woodbury), = the Newmark-CB multipliers on the same reduced model (N = 400), 1e-5
    (measured 3e-6), while the multipliers without inertia differ by 5e-3."""
    from rotorsfd.stability.branch_options import StabilityOptions
    from rotorsfd.stability.floquet_evaluator import FloquetEvaluator

    def top(problem, X, method):
        ev = FloquetEvaluator(problem, StabilityOptions(method=method, n_intervals=400))
        return np.sort(np.abs(ev(SPEED, X).multipliers))[::-1][:4]

    _, problem, sol = hb_pair[True]
    hill, newmark = top(problem, sol.X, "hill"), top(problem, sol.X, "newmark-cb")
    assert np.max(np.abs(hill - newmark)) < 1e-5
    _, problem0, sol0 = hb_pair[False]
    assert np.max(np.abs(top(problem0, sol0.X, "newmark-cb") - newmark)) > 3e-3


def test_high_eccentricity_quadrature():
    """The Gauss-Legendre panels near contact (the integrand's poles next to the thinnest
    film): the force against adaptive quadrature at eps = 0.95 and 0.99 (pi and 2 pi
    film), 1e-10."""
    for cavitation in ("pi", "none"):
        e = element(cavitation)
        for eps in (0.95, 0.99):
            q = eps * C * np.array([math.cos(0.3), math.sin(0.3)])
            v = np.array([-40.0, 90.0]) * C
            a = np.array([2e4, -3e4]) * C
            F_in = e.force_and_jacobians(q, v, a)[0] - e.film.nl_force(q, v)
            lo = 0.3
            hi = lo + (math.pi if cavitation == "pi" else 2 * math.pi)

            def f(phi, k, q=q, v=v, a=a):
                n = np.array([math.cos(phi), math.sin(phi)])
                h = C - q @ n
                g = (n @ a) / h + 2.4 * (n @ v) ** 2 / h**2
                return -RHO * R * L**3 / 12 * g * n[k]

            ref = np.array([quad(f, lo, hi, args=(k,), epsabs=0, epsrel=1e-13, limit=400,
                                 points=[lo + 1e-9, hi - 1e-9])[0] for k in range(2)])
            np.testing.assert_allclose(F_in, ref, rtol=1e-10,
                                       atol=1e-10 * np.max(np.abs(ref)))


def test_torus_response_rejects_inertia(tmp_path):
    from rotorsfd.quasiperiodic.torus_system import torus_problem

    system = small_system(tmp_path, True)
    with pytest.raises(ConfigError, match="fluid_inertia"):
        torus_problem(system)
