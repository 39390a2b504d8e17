"""Pinned-pinned uniform Timoshenko beam (non-rotating) against the analytic frequencies.

For simple supports the modes are exactly v = V sin(k x), psi = Psi cos(k x), k = n pi / L.
Substituting in  kGA (v'' - psi') = rho A v_tt  and  EI psi'' + kGA (v' - psi) = rho I psi_tt
gives the frequency equation (rotary inertia and shear, Timoshenko 1921):

    (kGA k^2 - rho A w^2) (EI k^2 + kGA - rho I w^2) - (kGA k)^2 = 0,

a quadratic in w^2 whose lower root is the bending frequency of mode n.
"""

from __future__ import annotations

import numpy as np
import pytest
from linear_helpers import STEEL, pinned_pinned

from rotorsfd.linear import eigen
from rotorsfd.model import Rotor, uniform_shaft

L, RI, RO = 1.0, 0.03, 0.05   # stubby tube, L / D = 10: shear and rotary inertia matter


def analytic_timoshenko(n: int, kappa: float) -> float:
    a = np.pi * (RO**2 - RI**2)
    i = np.pi * (RO**4 - RI**4) / 4.0
    rho, e, g = STEEL.density, STEEL.young_modulus, STEEL.shear_modulus
    k = n * np.pi / L
    kga, ei = kappa * g * a, e * i
    # (kga k^2 - rho A W)(ei k^2 + kga - rho I W) - (kga k)^2 = 0,  W = w^2
    c2 = rho * a * rho * i
    c1 = -(kga * k**2 * rho * i + rho * a * (ei * k**2 + kga))
    c0 = kga * k**2 * (ei * k**2 + kga) - (kga * k) ** 2
    w2 = np.roots([c2, c1, c0]).real.min()
    return float(np.sqrt(w2))


def analytic_euler_bernoulli(n: int) -> float:
    a = np.pi * (RO**2 - RI**2)
    i = np.pi * (RO**4 - RI**4) / 4.0
    return float((n * np.pi / L) ** 2 * np.sqrt(STEEL.young_modulus * i / (STEEL.density * a)))


def fe_frequencies(n_el: int, n_modes: int = 3) -> tuple[np.ndarray, float]:
    shaft = uniform_shaft(L, n_el, RI, RO, STEEL)
    res = eigen(pinned_pinned(Rotor(shaft)), 0.0, 2 * n_modes)
    return res.frequencies[::2], shaft[0].kappa   # each bending mode twice (y and z planes)


def test_first_three_modes_within_half_percent():
    freq, kappa = fe_frequencies(40)
    exact = np.array([analytic_timoshenko(n, kappa) for n in (1, 2, 3)])
    rel = np.abs(freq / exact - 1.0)
    assert np.all(rel < 0.005), rel
    assert np.all(rel < 1e-3), rel     # in fact 1e-5, 1.2e-4, 5e-4 at 40 elements
    # the check is meaningful: Euler-Bernoulli differs by more than 3 % on mode 3
    assert abs(analytic_euler_bernoulli(3) / exact[2] - 1.0) > 0.03


def test_both_planes_degenerate():
    shaft = uniform_shaft(L, 20, RI, RO, STEEL)
    f = eigen(pinned_pinned(Rotor(shaft)), 0.0, 6).frequencies
    np.testing.assert_allclose(f[0::2], f[1::2], rtol=1e-9)


@pytest.mark.parametrize("mode", [1, 2, 3])
def test_mesh_convergence(mode):
    errors = []
    for n_el in (3, 6, 12, 24):
        freq, kappa = fe_frequencies(n_el)
        errors.append(abs(freq[mode - 1] / analytic_timoshenko(mode, kappa) - 1.0))
    errors = np.array(errors)
    assert np.all(np.diff(errors) < 0.0), errors
    # The element's shear strain v' - psi is constant per element (static shape functions),
    # so the shear energy, hence the frequency, converges like h^2: halving h gains ~4x.
    # (With kappa -> inf the same element converges like h^4, see the next test.)
    assert errors[-2] / errors[-1] > 3.5, errors


def test_rayleigh_limit_converges_h4():
    """Without shear (kappa huge) the cubic consistent-mass element converges like h^4."""
    errors = []
    for n_el in (6, 12, 24):
        shaft = uniform_shaft(L, n_el, RI, RO, STEEL, shear_coefficient=1e8)
        freq = eigen(pinned_pinned(Rotor(shaft)), 0.0, 6).frequencies[::2]
        errors.append(abs(freq[2] / analytic_timoshenko(3, 1e8) - 1.0))
    assert errors[0] / errors[1] > 12.0 and errors[1] / errors[2] > 12.0, errors
