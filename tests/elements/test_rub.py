"""The rub element: law, kernel, Jacobians, config, and its periodic response on a Jeffcott
rotor against the full annular rub closed form and against time integration."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import rub_jeffcott as J
from pydantic import ValidationError

from rotorsfd import cli
from rotorsfd.elements import KINDS
from rotorsfd.elements.rub import RubConfig, RubElement, smooth_ramp
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.timedomain import integrate

DELTA = J.CLEARANCE


def states(n: int = 400, seed: int = 1) -> tuple[np.ndarray, np.ndarray]:
    """Samples around the clearance circle of a stator offset by (0.2, -0.1) delta: out of
    contact, in the smoothing band and deep in contact."""
    rng = np.random.default_rng(seed)
    r = DELTA * rng.uniform(0.5, 1.3, n)
    r[: n // 4] = DELTA + rng.uniform(-0.5, 0.5, n // 4) * 0.2 * DELTA   # in the band
    th = rng.uniform(0, 2 * np.pi, n)
    q = np.stack([r * np.cos(th), r * np.sin(th)], axis=-1) + np.array([0.2, -0.1]) * DELTA
    return q, rng.normal(size=(n, 2)) * 0.1


def band_rub() -> RubElement:
    return J.rub(friction=0.3, smoothing=0.2 * DELTA, offset=(0.2 * DELTA, -0.1 * DELTA))


# ---- the law ---------------------------------------------------------------------------
def test_smooth_ramp_is_c2_and_exact_outside_the_band():
    eps = 0.1
    p = np.linspace(-0.2, 0.2, 4001)
    s, ds = smooth_ramp(p, eps)
    outside = np.abs(p) >= eps / 2
    assert np.array_equal(s[outside], np.maximum(p, 0.0)[outside])
    # s' is the derivative of s, s'' (differences of s') is continuous: no jump at the edges
    h = p[1] - p[0]
    assert np.max(np.abs(np.gradient(s, h) - ds)[1:-1]) < 1e-6
    d2 = np.diff(ds) / h
    assert np.max(np.abs(np.diff(d2))) < 10 * h / eps**2
    # the smoothing error s - max(p, 0) is even in p: its first moment vanishes (O(eps^2))
    err = s - np.maximum(p, 0.0)
    assert np.max(np.abs(err - err[::-1])) < 1e-15


def test_kernel_matches_numpy():
    e = band_rub()
    q, v = states()
    F, Jq, Jv = e.force_and_jacobian(q, v)
    assert np.count_nonzero(np.any(F != 0, axis=1)) > 100    # many samples in contact
    assert np.count_nonzero(np.all(F == 0, axis=1)) > 50     # and many out of it
    f, a, b = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
    params = e.kernel_params
    for i in range(len(q)):
        assert e.kernel(q[i].copy(), v[i].copy(), params, f, a, b) == 0
        np.testing.assert_allclose(f, F[i], rtol=1e-12, atol=1e-12 * np.abs(F).max())
        np.testing.assert_allclose(a, Jq[i], rtol=1e-12, atol=1e-12 * np.abs(Jq).max())
        np.testing.assert_array_equal(b, Jv[i])


def test_jacobian_against_finite_differences():
    e = band_rub()
    q, v = states(200, seed=2)
    _, Jq, Jv = e.force_and_jacobian(q, v)
    h = 1e-4 * e.smoothing
    for k in range(2):
        dq = np.zeros(2)
        dq[k] = h
        fd = (e.force(q + dq, v) - e.force(q - dq, v)) / (2 * h)
        np.testing.assert_allclose(Jq[:, :, k], fd, rtol=0, atol=1e-6 * np.abs(Jq).max())
        fdv = (e.force(q, v + dq) - e.force(q, v - dq)) / (2 * h)
        np.testing.assert_array_equal(fdv, 0.0)
    assert np.all(Jv == 0.0)


def test_force_direction_normal_and_friction():
    """``F = -F_n (e_r + mu e_t)``: radial part -F_n, tangential part -mu F_n (against
    forward spin), F_n = k_c (r - delta) beyond the band."""
    e = J.rub(friction=0.25, contact_stiffness=3e7, smoothing=0.01 * DELTA)
    th = np.linspace(0, 2 * np.pi, 7)
    r = 1.2 * DELTA
    er = np.stack([np.cos(th), np.sin(th)], axis=-1)
    et = np.stack([-np.sin(th), np.cos(th)], axis=-1)
    F = e.force(r * er, np.zeros_like(er))
    fn = 3e7 * (r - DELTA)
    np.testing.assert_allclose(np.sum(F * er, axis=-1), -fn, rtol=1e-13)
    np.testing.assert_allclose(np.sum(F * et, axis=-1), -0.25 * fn, rtol=1e-13)
    assert np.all(e.force(0.9 * DELTA * er, np.zeros_like(er)) == 0.0)
    assert np.all(e.force(np.zeros((1, 2)), np.zeros((1, 2))) == 0.0)   # at the centre


def test_diagnostics_of_a_circular_orbit():
    e = J.rub(smoothing=0.01 * DELTA)
    th = np.linspace(0, 2 * np.pi, 64, endpoint=False)
    ring = np.stack([np.cos(th), np.sin(th)], axis=-1)
    d = e.diagnostics(1.05 * DELTA * ring, ring)
    assert d["force_max"] == pytest.approx(1e7 * 0.05 * DELTA, rel=1e-12)
    assert d["penetration_max"] == pytest.approx(0.05 * DELTA, rel=1e-12)
    assert d["contact_fraction"] == 1.0
    # a circle of radius a = 0.6 delta about the origin, the stator at o = (0.5 delta, 0):
    # |q - o|^2 = a^2 + o^2 - 2 a o cos(theta) > delta^2 on a fraction 1 - arccos(c0) / pi
    # of the period, c0 = (a^2 + o^2 - delta^2) / (2 a o)
    shifted = J.rub(smoothing=0.01 * DELTA, offset=(0.5 * DELTA, 0.0))
    th = np.linspace(0, 2 * np.pi, 4096, endpoint=False)
    a, o = 0.6 * DELTA, 0.5 * DELTA
    orbit = a * np.stack([np.cos(th), np.sin(th)], axis=-1)
    d = shifted.diagnostics(orbit, orbit)
    c0 = (a**2 + o**2 - DELTA**2) / (2 * a * o)
    assert d["contact_fraction"] == pytest.approx(1 - np.arccos(c0) / np.pi, abs=1e-3)
    assert d["penetration_max"] == pytest.approx(a + o - DELTA, rel=1e-9)
    assert e.limit(ring) == 0.0 and e.limit_label is None


# ---- config --------------------------------------------------------------------------
def test_config_model_builds_the_element():
    assert KINDS["rub"] is RubConfig
    cfg = RubConfig(node=3, clearance="0.1 mm", contact_stiffness="2e7 N/m", friction=0.2,
                    smoothing="2 um", offset_y="10 um")
    e = cfg.build("seal")
    assert isinstance(e, RubElement) and e.name == "seal" and e.nodes == (3,)
    assert e.dofs.tolist() == [8, 9]
    np.testing.assert_allclose(e.kernel_params, [1e-4, 2e7, 0.2, 2e-6, 1e-5, 0.0])
    assert cfg.linear_supports() == [] and cfg.nodes == (3,)
    assert RubConfig(node=1, clearance=1e-4, contact_stiffness=1e7).build("r").smoothing \
        == pytest.approx(1e-6)


@pytest.mark.parametrize("fields, word", [
    ({"clearance": -1e-4}, "must be > 0"),
    ({"smoothing": "0.2 mm"}, "smaller than the clearance"),
    ({"friction": -0.1}, "must be 0 <= value <= 2"),
    ({"clearance": "0.1 kg"}, "length"),
    ({"spin": 1}, "extra"),
])
def test_config_errors(fields, word):
    base = dict(node=1, clearance="0.1 mm", contact_stiffness=1e7)
    with pytest.raises(ValidationError, match=word):
        RubConfig(**(base | fields))


PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"
SEAL = """
[elements.seal]
kind = "rub"
node = 8
clearance = "0.2 mm"
contact_stiffness = "5e7 N/m"
friction = 0.1
"""


@pytest.mark.parametrize("change, words", [
    ({}, None),
    ({'kind = "rub"': 'kind = "rubb"'}, ["elements.seal", "'rubb'", "'sfd'", "'rub'"]),
    ({'friction = 0.1': 'smoothing = "0.3 mm"'}, ["smoothing", "smaller than the clearance"]),
])
def test_config_check_with_a_rub_table(tmp_path, capsys, change, words):
    """``rotorsfd config check`` on the paper rotor with a rub at the disk: ok, or exit 2
    with one line naming the table and what is allowed."""
    text = SEAL
    for old, new in change.items():
        text = text.replace(old, new)
    path = tmp_path / "rub.toml"
    path.write_text(f'extends = "{PAPER.as_posix()}"\n' + text)
    status = cli.main(["config", "check", str(path)])
    out = capsys.readouterr()
    if words is None:
        assert status == 0, out.err
        assert "elements.seal: smoothing eps = 2e-06 m (eps/delta = 0.01, the default)" \
            in out.out
        return
    assert status == 2
    lines = out.err.strip().splitlines()
    assert len(lines) == 1 and "Traceback" not in out.err
    assert all(w in lines[0] for w in words), lines[0]


# ---- periodic response on a Jeffcott rotor ----------------------------------------------
def annular_rub_radius(omega: float, friction: float, kc: float) -> np.ndarray:
    """Radii r > delta of the synchronous full annular rub (``docs/elements.md``).

    With z = y + i z = R exp(i Omega t), the force is -k_c (r - delta)(1 + i mu) z / r, so
    ``(k - m Omega^2 + i c Omega) R + k_c (1 + i mu)(r - delta) R / r = U Omega^2``;
    its modulus, with ``a = k - m Omega^2 + k_c``, ``b = c Omega + mu k_c``:
    ``(a r - k_c delta)^2 + (b r - mu k_c delta)^2 = (U Omega^2)^2``, a quadratic in r.
    """
    m, k, c, U = J.MASS, J.STIFFNESS, J.DAMPING, J.UNBALANCE
    a, b, f = k - m * omega**2 + kc, c * omega + friction * kc, U * omega**2
    roots = np.roots([a * a + b * b, -2 * kc * DELTA * (a + friction * b),
                      kc**2 * DELTA**2 * (1 + friction**2) - f * f])
    return np.sort(roots.real[(np.abs(roots.imag) == 0) & (roots.real > DELTA)])


def annular_rub_amplitude(omega: float, r: float, friction: float, kc: float) -> complex:
    """``R = U Omega^2 / (k - m Omega^2 + i c Omega + k_c (1 + i mu)(r - delta) / r)``."""
    m, k, c, U = J.MASS, J.STIFFNESS, J.DAMPING, J.UNBALANCE
    g = kc * (r - DELTA) / r
    return U * omega**2 / (k - m * omega**2 + 1j * c * omega + g * (1 + 1j * friction))


def test_full_annular_rub_against_closed_form():
    mu, kc = 0.1, 1e7
    e = J.rub(friction=mu, contact_stiffness=kc, smoothing=0.01 * DELTA)
    problem = J.problem(e)
    branch = continue_periodic(problem, 300.0, 420.0, 3, tol=1e-10, ds=0.05, ds_max=0.2,
                               harmonics_tol=None)
    assert branch.success, branch.message
    checked = 0
    for lam, X in zip(branch.lam, branch.X, strict=True):
        R = X[1, 0]
        r = abs(R)
        if r < DELTA + 0.5 * e.smoothing:
            continue
        roots = annular_rub_radius(lam, mu, kc)
        assert np.min(np.abs(roots - r)) < 1e-6 * r
        assert abs(R - annular_rub_amplitude(lam, r, mu, kc)) < 1e-6 * r
        assert abs(X[1, 1] + 1j * R) < 1e-9 * r             # circular forward orbit
        assert np.abs(X[[0, 2, 3]]).max() < 1e-9 * r        # no other harmonic
        checked += 1
    assert checked >= 5
    assert branch.lam.max() >= 419.0


# the partial rub of an offset stator: one contact per revolution over about a third of it
PARTIAL = dict(omega=300.0, damping=600.0, offset=(0.5 * DELTA, 0.0), friction=0.1)


def partial_rub(smoothing: float) -> RubElement:
    return J.rub(friction=PARTIAL["friction"], smoothing=smoothing, offset=PARTIAL["offset"])


def hb_orbit(e: RubElement, H: int) -> np.ndarray:
    """HB coefficients (H+1, 2) at PARTIAL's speed, continued from below the first contact."""
    problem = J.problem(e, damping=PARTIAL["damping"])
    omega = PARTIAL["omega"]
    branch = continue_periodic(problem, 150.0, omega, H, tol=1e-8, ds=0.05, ds_max=0.2,
                               harmonics_tol=None)
    assert branch.success, branch.message
    start = branch.X[np.argmin(np.abs(branch.lam - omega))]
    return solve_periodic(problem, omega, H, start, tol=1e-10).X


def td_orbit(e: RubElement, steps_per_period: int = 2000, n_periods: int = 80):
    """The last period of a time integration of the same rotor and law, from rest."""
    M, D, K = J.matrices(damping=PARTIAL["damping"])
    res = integrate(M, D, K, [0, 1], e.kernel, e.kernel_params, J.forcing(PARTIAL["omega"]),
                    steps_per_period=steps_per_period, n_periods=n_periods,
                    record_start=(n_periods - 1) * steps_per_period)
    assert res.success, res.message
    drift = np.abs(res.poincare_q[-1] - res.poincare_q[-2]).max()
    assert drift < 1e-6 * DELTA                                 # settled on a periodic orbit
    return res


def test_partial_rub_hb_against_time_integration():
    e = partial_rub(0.1 * DELTA)
    X = hb_orbit(e, 16)
    res = td_orbit(e)
    k = np.arange(X.shape[0])
    q_hb = np.real(np.exp(1j * PARTIAL["omega"] * np.outer(res.t, k)) @ X)
    assert np.abs(q_hb - res.q).max() < 1e-3 * DELTA
    d = e.diagnostics(q_hb, q_hb)
    assert 0.1 < d["contact_fraction"] < 0.9 and d["penetration_max"] > e.smoothing


def test_smoothing_sensitivity_is_second_order():
    """The largest orbit radius of the partial rub converges as eps^2 (the smoothing error
    of the centred ramp is even in p): successive halvings shrink the change ~4 times."""
    radii = []
    for ratio in (0.1, 0.05, 0.025):   # measured ratio 4.28 (4.83 from 0.2 down)
        res = td_orbit(partial_rub(ratio * DELTA))
        radii.append(np.hypot(*res.q.T).max())
    d1, d2 = radii[0] - radii[1], radii[1] - radii[2]
    assert 3.0 < d1 / d2 < 5.5
    assert abs(d2) < 1e-3 * DELTA
