"""The SFD element with the finite film (film_length = "finite"): config, kernel, and the
per-orbit diagnostics (peak pressure, cavitated arc, squeeze Reynolds number)."""

from __future__ import annotations

import math

import numpy as np
import pytest
from pydantic import ValidationError
from sfd_helpers import CR, LD, MU, C

from rotorsfd.elements.sfd import SFDConfig, SFDElement
from rotorsfd.model.film_diagnostics import squeeze_reynolds
from rotorsfd.model.film_finite import FiniteSFD

BASE = dict(node=2, viscosity=MU, clearance=C, clearance_ratio=CR, length_to_diameter=LD)


def circular_orbit(eps: float, omega: float, n: int = 32, centre=(0.0, 0.0)):
    t = 2 * np.pi * np.arange(n) / n
    r = eps * C
    q = np.stack([centre[0] + r * np.cos(t), centre[1] + r * np.sin(t)], 1)
    v = np.stack([-r * omega * np.sin(t), r * omega * np.cos(t)], 1)
    return q, v


def test_config_builds_the_finite_film_with_offset():
    cfg = SFDConfig(**BASE, film_length="finite", end_flow=0.5, grid_theta=32,
                    grid_axial=2, offset_y="10 um", cavitation="guembel")
    e = cfg.build("sfd")
    assert isinstance(e.film, FiniteSFD) and e.finite
    assert (e.film.n_theta, e.film.n_axial, e.film.end_flow) == (32, 2, 0.5)
    assert "finite film, end_flow = 0.5, grid 32 x 2" in cfg.derived_text()
    assert "finite-length guembel film" in e.describe()
    rng = np.random.default_rng(5)
    q = 1e-5 + rng.uniform(-0.5, 0.5, (8, 2)) * C
    v = rng.normal(size=(8, 2)) * 0.03
    F, dq, dv = e.force_and_jacobian(q, v)
    F0, dq0, dv0 = e.film.force_and_jacobian(q[:, 0] - 1e-5, q[:, 1], v[:, 0], v[:, 1])
    for a, b in ((F, F0), (dq, dq0), (dv, dv0)):
        np.testing.assert_array_equal(a, b)
    kernel, params = e.kernel, e.kernel_params
    f, jq, jv = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
    for i in range(8):
        assert kernel(q[i].copy(), v[i].copy(), params, f, jq, jv) == 0
        np.testing.assert_allclose(f, F[i], rtol=1e-12)
        np.testing.assert_allclose(jq, dq[i], rtol=1e-11, atol=1e-11 * np.abs(dq[i]).max())
    assert SFDConfig(**BASE, film_length="finite").build("s").film.end_flow == math.inf


@pytest.mark.parametrize("fields, word", [
    ({"end_flow": 1.0}, "finite film"),
    ({"grid_theta": 64}, "finite film"),
    ({"grid_axial": 8}, "finite film"),
    ({"film_length": "finite", "grid_theta": 50}, "multiple of 4"),
    ({"film_length": "finite", "grid_axial": 3}, "even"),
    ({"film_length": "finite", "end_flow": -1}, ">= 0"),
    ({"film_length": "long"}, "short"),
    ({"density": "-3 kg/m^3"}, "> 0"),
])
def test_config_errors(fields, word):
    with pytest.raises(ValidationError, match=word):
        SFDConfig(**(BASE | fields))


def test_short_film_peak_pressure_closed_form():
    """Circular centred orbit, pi film: p = -(3 mu L^2/(2 C^3)) w_t sin(theta)/H^3 at
    mid-land, largest where -2 eps c^2 + c + 3 eps = 0 (c = cos theta); the arc of negative
    uncavitated pressure is pi; and the finite film at small L/D has the same peak."""
    eps, omega = 0.6, 400.0
    q, v = circular_orbit(eps, omega)
    cfg = SFDConfig(**BASE | {"length_to_diameter": 0.05}, film_report=True)
    e = cfg.build("sfd")
    d = e.diagnostics(q, v)
    c = (1 - math.sqrt(1 + 24 * eps**2)) / (4 * eps)
    L = e.film.length
    p_ref = 1.5 * MU * L**2 / C**3 * eps * C * omega * math.sqrt(1 - c * c) / (1 + eps * c)**3
    assert d["p_max"] == pytest.approx(p_ref, rel=1e-4)
    assert d["p_min"] == pytest.approx(-p_ref, rel=1e-4)
    assert d["cavitated_arc"] == pytest.approx(math.pi)
    fin = SFDConfig(**BASE | {"length_to_diameter": 0.05}, film_length="finite",
                    grid_theta=256).build("f").diagnostics(q, v)
    assert fin["p_max"] == pytest.approx(p_ref, rel=1e-2)  # node values, L/D effect
    assert fin["cavitated_arc"] == pytest.approx(math.pi, abs=2 * 2 * math.pi / 256)
    assert set(SFDConfig(**BASE).build("s").diagnostic_info) == {"eps_max"}


def test_finite_film_report_and_seal():
    """A sealed land at the paper's L/D carries a higher peak than open ends, and the
    cavitated arc is close to pi on a circular centred orbit (the pressure antisymmetric
    about the line of centres)."""
    q, v = circular_orbit(0.4, 500.0, 16)
    open_ = SFDConfig(**BASE, film_length="finite").build("a").diagnostics(q, v)
    sealed = SFDConfig(**BASE, film_length="finite", end_flow=0.0).build("b")
    d = sealed.diagnostics(q, v)
    assert set(d) == {"eps_max", "p_max", "p_min", "cavitated_arc"} == set(
        sealed.diagnostic_info)
    assert d["p_max"] > 5 * open_["p_max"] > 0
    assert abs(d["cavitated_arc"] - math.pi) <= 2 * math.pi / 48 + 1e-12


def test_squeeze_reynolds_number():
    """Re_s = rho omega C^2 / mu of a circular orbit about an offset centre, exactly."""
    omega, rho = 700.0, 860.0
    q, v = circular_orbit(0.3, omega, 24, centre=(0.1 * C, -0.05 * C))
    e = SFDConfig(**BASE, density=f"{rho} kg/m^3", offset_y=0.1 * C).build("s")
    d = e.diagnostics(q, v)
    assert set(d) == {"eps_max", "squeeze_reynolds"} == set(e.diagnostic_info)
    assert d["squeeze_reynolds"] == pytest.approx(rho * omega * C**2 / MU, rel=1e-12)
    assert squeeze_reynolds(q[:1], v[:1], rho, MU, C) == 0.0
    assert isinstance(e, SFDElement)
