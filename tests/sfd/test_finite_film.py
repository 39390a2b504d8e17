"""Finite-length squeeze film (rotorsfd.model.film_finite): closed forms in the short and
long limits, the exact centred solution with end seals, and grid convergence."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest
from sfd_helpers import CR, MU, C

from rotorsfd.errors import ConfigError, JournalContactError
from rotorsfd.model.film_finite import FiniteSFD, centred_damping_ratio
from rotorsfd.sfd import SFD

LD = 0.325


def finite(cavitation: str = "pi", ld: float = LD, **kw) -> FiniteSFD:
    """The grid solver at every sample (the eps table: test_finite_film_jacobian.py)."""
    return FiniteSFD.from_ratios(MU, C, CR, ld, cavitation, **{"table": False} | kw)


def state(eps: float, psi: float = 0.7, vy: float = 0.02, vz: float = -0.03):
    return eps * C * math.cos(psi), eps * C * math.sin(psi), vy, vz


def rel(a, b) -> float:
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    return float(np.abs(a - b).max() / np.abs(b).max())


@pytest.mark.parametrize("end_flow", [math.inf, 1.0, 0.0])
def test_centred_film_matches_the_exact_solution(end_flow: float) -> None:
    """eps = 0: Pi = m_k f(zeta), f = A cosh(s zeta) - 1/lam (module doc), so F = -c v with
    c / c_short = centred_damping_ratio; second order in the grid (measured ratio ~4)."""
    errors = []
    for n, m in ((32, 4), (64, 8)):
        film = finite("none", end_flow=end_flow, n_theta=n, n_axial=m)
        Fy, Fz = film.force(0.0, 0.0, 0.01, 0.0)
        errors.append(abs(-Fy / 0.01 / film.linear_damping - 1.0))
        assert abs(Fz) < 1e-12 * abs(Fy)
    assert errors[1] < 1e-3
    assert 3.0 < errors[0] / errors[1] < 5.0


def test_centred_ratio_limits() -> None:
    """Open ends: 1 - (2/5) lam + O(lam^2) (series of 3 (1 - tanh s / s) / lam); sealed:
    3 / lam, the long bearing; a seal in between lies between them."""
    lam = 0.05**2
    assert centred_damping_ratio(0.05) == pytest.approx(1 - 0.4 * lam + 17 / 105 * lam**2,
                                                        rel=1e-8)
    assert centred_damping_ratio(LD, 0.0) == pytest.approx(3 / LD**2, rel=1e-14)
    assert 1.0 > centred_damping_ratio(LD) / centred_damping_ratio(LD, 1.0) > 3 * LD**2 / 3


@pytest.mark.parametrize("model", ["pi", "none", "guembel"])
def test_short_bearing_limit(model: str) -> None:
    """L/D -> 0: the finite film tends to the short film's closed forms like (L/D)^2. The
    difference is the finite length itself: at the centre it is (2/5)(L/D)^2 = 1.0e-3 at
    L/D = 0.05 (centred_damping_ratio); at L/D = 0.01 it is below 1e-3 up to eps = 0.9;
    halving L/D divides it by 4; extrapolating in (L/D)^2 recovers the short film to 1e-3.
    (The Guembel clamp's kink is resolved by the theta grid only, O(dtheta^2): a finer
    grid keeps it below the length effect up to eps = 0.6; at 0.9 a sign change of the
    pressure next to the thinnest film needs n_theta ~ 512 for 1e-3.)"""
    for eps in (0.0, 0.3, 0.6) if model == "guembel" else (0.0, 0.3, 0.6, 0.9):
        st = state(eps)
        short = np.array(SFD.from_ratios(MU, C, CR, 1.0, model).force(*st))
        # the short film scales as L^3 at fixed R: compare F / L^3
        f = {}
        for ld in (0.05, 0.025, 0.01):
            film = finite(model, ld, n_theta=256 if model == "guembel" else 64, n_axial=4)
            f[ld] = np.array(film.force(*st)) / ld**3
        d05, d025, d01 = (rel(f[ld], short) for ld in (0.05, 0.025, 0.01))
        assert d01 < 1e-3
        assert 3.6 < d05 / d025 < 4.4
        assert rel((4 * f[0.025] - f[0.05]) / 3, short) < 1e-3
        if eps == 0.0:
            assert d05 == pytest.approx(0.4 * 0.05**2, rel=0.02)


def test_long_bearing_sealed_land() -> None:
    """Sealed ends (end_flow = 0): the long bearing. Closed forms (Vance, Rotordynamics of
    Turbomachinery, 1988, ch. 5; derived in docs/sfd.md with the zero-mean datum of a sealed
    land): circular centred orbit, pi film, w_t = C eps Omega::

        F_r = -24 mu R^3 L eps^2 Omega / (C^2 (2 + eps^2)(1 - eps^2))
        F_t = -12 pi mu R^3 L eps Omega / (C^2 (2 + eps^2)(1 - eps^2)^(1/2))

    and the 2 pi film for any velocity, F = -(12 pi mu R^3 L / C^3) [w_r / s^3 e_r +
    2 w_t / (s (2 + eps^2)) e_t], s = sqrt(1 - eps^2)."""
    omega = 300.0
    for eps in (0.2, 0.5, 0.8):
        film = finite("pi", end_flow=0.0, n_theta=96, n_axial=2)
        R, L = film.radius, film.length
        fr, ft = film.force(eps * C, 0.0, 0.0, eps * C * omega)
        k = mu_r3l = MU * R**3 * L
        fr_ref = -24 * k * eps**2 * omega / (C**2 * (2 + eps**2) * (1 - eps**2))
        ft_ref = -12 * math.pi * mu_r3l * eps * omega / (C**2 * (2 + eps**2)
                                                        * math.sqrt(1 - eps**2))
        assert rel([fr, ft], [fr_ref, ft_ref]) < 2e-3
        full = finite("none", end_flow=0.0, n_theta=96, n_axial=2)
        wr, wt = 0.013, -0.021
        s = math.sqrt(1 - eps**2)
        ref = -(12 * math.pi * k / C**3) * np.array([wr / s**3, 2 * wt / (s * (2 + eps**2))])
        psi = 0.4
        cp, sp = math.cos(psi), math.sin(psi)
        F = np.array(full.force(eps * C * cp, eps * C * sp, cp * wr - sp * wt,
                                sp * wr + cp * wt))
        assert rel([cp * F[0] + sp * F[1], -sp * F[0] + cp * F[1]], ref) < 2e-3


@pytest.mark.parametrize("model", ["pi", "guembel"])
def test_grid_convergence_is_second_order(model: str) -> None:
    """Halving both steps divides the error by ~4 (measured against the next refinement:
    e_h / e_h/2 with e_h = |F_h - F_h/2|, at L/D = 0.325, eps = 0.6, a seal end_flow = 2)."""
    st = state(0.6)
    forces = [np.array(finite(model, end_flow=2.0, n_theta=n, n_axial=m).force(*st))
              for n, m in ((32, 2), (64, 4), (128, 8))]
    e1, e2 = rel(forces[0], forces[1]), rel(forces[1], forces[2])
    assert e2 < 2e-3
    assert 3.0 < e1 / e2 < 5.5


def test_end_seal_raises_the_force_monotonically() -> None:
    """Less end flow, more pressure: |F| grows from open ends to a sealed land."""
    st = state(0.5)
    mags = [np.hypot(*finite("pi", end_flow=b).force(*st)) for b in (math.inf, 10.0, 1.0,
                                                                      0.1, 0.0)]
    assert all(b > a for a, b in itertools.pairwise(mags))
    assert mags[-1] / mags[0] > 10.0


def test_dissipative_and_guembel_positive_pressure() -> None:
    """F.v < 0 for every model; the Guembel film has no negative pressure and equals the pi
    film on a circular centred forward orbit up to the grid (its positive region is the pi
    arc there)."""
    rng = np.random.default_rng(3)
    for model in ("pi", "none", "guembel"):
        film = finite(model)
        for _ in range(20):
            eps, psi = rng.uniform(0.05, 0.9), rng.uniform(-np.pi, np.pi)
            v = rng.normal(size=2)
            F = film.force(*state(eps, psi, *v))
            if model != "pi":  # the fixed pi arc keeps negative pressures (paper eq. 11)
                assert F[0] * v[0] + F[1] * v[1] < 0.0
    _, x, p_full, p = finite("guembel").pressure(*state(0.5, 0.3, -0.01, 0.02))
    assert p.min() >= 0.0 and p_full.min() < 0.0 and x[-1] == pytest.approx(
        finite().length / 2)
    pi_f, gu = finite("pi", n_theta=96), finite("guembel", n_theta=96)
    circ = (0.5 * C, 0.0, 0.0, 0.5 * C * 300.0)
    assert rel(gu.force(*circ), pi_f.force(*circ)) < 5e-3


def test_errors() -> None:
    with pytest.raises(ConfigError, match="n_theta"):
        finite(n_theta=30)
    with pytest.raises(ConfigError, match="n_axial"):
        finite(n_axial=3)
    with pytest.raises(ConfigError, match="end_flow"):
        finite(end_flow=-1.0)
    with pytest.raises(JournalContactError):
        finite().force(0.9995 * C, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="not finite"):
        finite().force(0.0, 0.0, np.nan, 0.0)
