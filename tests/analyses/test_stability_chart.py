"""Stability chart of the linear rotor under harmonic base pitching (issue 6 item 5):
the LTI limit A0 = 0, the first Mathieu tongue of a Jeffcott-like rotor, speed and
structural axes against separate runs."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from rotorsfd.analyses.stability_chart import run_stability_chart
from rotorsfd.io.config import config_from_dict, with_values
from rotorsfd.model.base_terms import base_basis
from rotorsfd.model.build import build_rotor

FREQ = "base.pitching.frequency"
A0 = "base.pitching.angle_amplitude"


def _config(*, n_el: int = 4, disk: dict | None = None, damping: dict | None = None,
            length: float = 0.4, radius: float = 0.01, support: float = 1e9) -> dict:
    disk = disk or {"node": 2, "material": "steel", "inner_radius": 0.01,
                    "outer_radius": 0.15, "thickness": 0.03}
    return {
        "materials": {"steel": {"density": 7800.0, "young_modulus": 2e11,
                                "poisson_ratio": 0.3}},
        "rotor": {"shaft": [{"length": length, "n_elements": n_el, "outer_radius": radius,
                             "material": "steel"}],
                  "disks": [disk],
                  "supports": [{"node": 1, "stiffness": support},
                               {"node": n_el + 1, "stiffness": support}],
                  "damping": damping or {"kind": "none"}},
        "base": {"pitching": {"law": "harmonic", "frequency": 300.0,
                              "angle_amplitude": 0.1}},
        "analysis": {"stability_chart": {"speed": 250.0}},
    }


def _reduced(rotor, n: int):
    """Lowest n undamped modes of (K, M) and the projected M, D(Omega = 250), K."""
    V = sla.eigh(rotor.K, rotor.M, subset_by_index=(0, n - 1))[1]
    return V, V.T @ rotor.M @ V, V.T @ rotor.K @ V


def test_a0_zero_gives_the_lti_multipliers_exp_lambda_t():
    """A0 = 0: the base terms vanish and the multipliers are exp(lambda T), lambda the
    eigenvalues of the (reduced) damped rotor at Omega, T = 2 pi / w_b; stable."""
    config = config_from_dict(_config(damping={"kind": "modal", "ratio": 0.01}))
    rotor = build_rotor(config)
    w_b = np.array([180.0, 300.0])
    res = run_stability_chart(config, x=(A0, [0.0]), y=(FREQ, w_b), n_intervals=12000,
                              n_modes=4)
    V, M, K = _reduced(rotor, 4)
    D = V.T @ (rotor.C + 250.0 * rotor.G) @ V
    A = np.block([[np.zeros((4, 4)), np.eye(4)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    lam = np.linalg.eigvals(A)
    assert res.chart.info["n_reduced"] == 4
    for j, w in enumerate(w_b):
        mu = np.exp(lam * 2 * np.pi / w)
        assert res.chart.max_abs[0, j] == pytest.approx(np.abs(mu).max(), abs=1e-6)
        assert np.abs(mu - res.chart.critical[0, j]).min() < 1e-6
    assert res.stable.all() and res.chart.max_abs.max() < 0.99


def _z_plane_ratio(rotor) -> tuple[float, float]:
    """First natural frequency and r = phi^T T22 phi / phi^T M phi of its z-plane mode."""
    lam, V = sla.eigh(rotor.K, rotor.M, subset_by_index=(0, 1))
    Y = V[0::4, :]                                   # y components of the pair
    c = np.linalg.svd(Y)[2][-1]                      # the combination without y motion
    phi = V @ c
    T22 = base_basis(rotor).matrix("T22")
    return float(np.sqrt(lam.mean())), float(phi @ T22 @ phi / (phi @ rotor.M @ phi))


def test_first_tongue_of_a_jeffcott_rotor_where_mathieu_puts_it():
    """A point-mass disk at midspan of a light shaft, pitching w_by = A0 w_b sin(w_b t),
    Omega ~ 0. The z-mode obeys z'' + (w^2 - r w_by^2) z = 0, i.e. with tau = w_b t the
    Mathieu equation z'' + (a - 2 q cos 2 tau) z = 0, a = w^2 / w_b^2 - r A0^2 / 2,
    q = -r A0^2 / 4; its first tongue a = 1 +/- |q| - q^2 / 8 gives
    w_b = w / sqrt(1 + r A0^2 / 2 +/- |q| - q^2 / 8) (A0 = 0.4: 0.945 w .. 0.981 w).
    Edges within 1.5 grid steps + 1e-4 w, centre within 1e-3 w."""
    disk = {"node": 3, "mass": 10.0, "polar_inertia": 0.0, "diametral_inertia": 0.0}
    config = config_from_dict(_config(disk=disk, length=0.5, radius=0.005, support=1e10))
    w, r = _z_plane_ratio(build_rotor(config))
    a0 = 0.4
    q = r * a0**2 / 4
    edges = w / np.sqrt(1 + r * a0**2 / 2 + np.array([q, -q]) - q**2 / 8)
    w_b = np.linspace(0.93, 1.0, 141) * w
    res = run_stability_chart(config, x=(A0, [a0]), y=(FREQ, w_b), speed=1.0)
    bad = np.flatnonzero(~res.stable[0])
    assert bad.size > 10 and np.all(np.diff(bad) == 1)   # one interval
    step = w_b[1] - w_b[0]
    assert abs(w_b[bad[0]] - edges[0]) < 1.5 * step + 1e-4 * w
    assert abs(w_b[bad[-1]] - edges[1]) < 1.5 * step + 1e-4 * w
    centre = 0.5 * (w_b[bad[0]] + w_b[bad[-1]])
    assert abs(centre - edges.mean()) < 1e-3 * w
    # undamped: stable points stay on the unit circle
    assert np.abs(res.chart.max_abs[res.stable] - 1.0).max() < 1e-9


def test_speed_axis_equals_runs_at_fixed_speed():
    """The speed enters D (Omega G) and the base coefficients linearly: a speed axis gives
    the numbers of separate fixed-speed runs."""
    config = with_values(config_from_dict(_config()), {A0: 0.4})
    w_b = np.linspace(220.0, 320.0, 60)
    speeds = [150.0, 250.0]
    both = run_stability_chart(config, x=("speed", speeds), y=(FREQ, w_b),
                               n_intervals=100, n_modes=4)
    for i, s in enumerate(speeds):
        one = run_stability_chart(config, x=(A0, [0.4]), y=(FREQ, w_b), speed=s,
                                  n_intervals=100, n_modes=4)
        np.testing.assert_allclose(both.chart.max_abs[i], one.chart.max_abs[0], atol=1e-10)
        assert (~one.stable).sum() >= 3


def test_structural_axis_rebuilds_the_rotor():
    """A support stiffness as an axis: each column equals a run of the modified config."""
    config = with_values(config_from_dict(_config()), {A0: 0.4})
    w_b = np.linspace(220.0, 320.0, 60)
    k = [5e6, 1e9]
    path = "rotor.supports[1].stiffness"
    res = run_stability_chart(config, x=(FREQ, w_b), y=(path, k), n_intervals=100,
                              n_modes=4, workers=2)
    assert res.y.units == "N/m" and res.x.units == "rad/s"
    for j, kj in enumerate(k):
        one = run_stability_chart(with_values(config, {path: kj}), x=(FREQ, w_b),
                                  y=(A0, [0.4]), n_intervals=100, n_modes=4)
        np.testing.assert_allclose(res.chart.max_abs[:, j], one.chart.max_abs[:, 0],
                                   atol=1e-10)
    # the softer right bearing moves the frequencies: different charts
    assert not np.array_equal(res.stable[:, 0], res.stable[:, 1])


def test_rotor_system_input_equals_the_config_run():
    """From a RotorSystem (harmonic law with a rate amplitude) with an angle-amplitude
    axis: the same chart as from the config."""
    from rotorsfd.model.base_motion import BaseMotion, Harmonic
    from rotorsfd.model.system import RotorSystem

    config = config_from_dict(_config())
    w_b = np.linspace(220.0, 320.0, 40)
    kw = {"x": (A0, [0.2, 0.4]), "y": (FREQ, w_b), "n_intervals": 100}
    system = RotorSystem(build_rotor(config), base=BaseMotion(wy=Harmonic(30.0, 300.0)))
    a = run_stability_chart(system, speed=250.0, **kw)
    b = run_stability_chart(config, **kw)
    np.testing.assert_array_equal(a.chart.max_abs, b.chart.max_abs)
    assert (~a.stable).sum() > 3 and a.x.units == "rad" and a.y.units == "rad/s"
    with pytest.raises(ValueError, match="only 'speed'"):
        run_stability_chart(system, x=("rotor.supports[0].stiffness", [1e9]),
                            y=(FREQ, w_b), speed=250.0)


def test_yawing_chart_equals_pitching_chart_and_rolling_runs():
    """An isotropic rotor turned by 90 degrees about x: harmonic yawing gives the pitching
    chart. Rolling (Coriolis C terms, Omega w_bx stiffness) gives a finite chart with its
    own zones."""
    w_b = np.linspace(220.0, 320.0, 100)
    kw = {"x": (A0, [0.4]), "y": (FREQ, w_b), "n_intervals": 100, "n_modes": 4}
    pitch = run_stability_chart(config_from_dict(_config()), **kw)
    raw = _config()
    raw["base"] = {"yawing": raw["base"].pop("pitching")}
    kw_yaw = {**kw, "x": ("base.yawing.angle_amplitude", [0.4]),
              "y": ("base.yawing.frequency", w_b)}
    yaw = run_stability_chart(config_from_dict(raw), **kw_yaw)
    np.testing.assert_allclose(yaw.chart.max_abs, pitch.chart.max_abs, atol=1e-9)
    assert (~pitch.stable).sum() >= 3
    raw["base"] = {"rolling": raw["base"].pop("yawing")}
    kw_roll = {**kw, "x": ("base.rolling.angle_amplitude", [0.4]),
               "y": ("base.rolling.frequency", w_b)}
    roll = run_stability_chart(config_from_dict(raw), **kw_roll)
    assert np.all(np.isfinite(roll.chart.max_abs))
    assert not np.array_equal(roll.stable, pitch.stable)
