"""The stability chart and the modal analyses take their matrices from the model's one
record (issue 16 item 1): the chart's multipliers and the linear system's matrices
against an assembly written here from the rotor's own matrices and base basis (the
assembly the two had before they took the record), to 1e-12, on the paper examples."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla

from rotorsfd.analyses.modal import linear_system
from rotorsfd.analyses.stability_chart import run_stability_chart
from rotorsfd.analyses.stability_chart_rates import (
    ChartParams,
    coefficient_target,
    rate_specs_from_config,
)
from rotorsfd.io.config import config_from_dict, load_config, with_values
from rotorsfd.model.base_terms import base_basis, base_coefficients
from rotorsfd.model.build import build_base_motion, build_rotor, build_system
from rotorsfd.stability.chart import LTPSystem, stability_chart

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
FIG6 = EXAMPLES / "paper" / "fig06_stability_chart.toml"
FREQ = "base.pitching.frequency"
A0 = "base.pitching.angle_amplitude"
PROBE_T = np.sqrt(2.0) * np.arange(1, 8)[:, None] / 3.7


def _reference_ltp(rotor, params: ChartParams, p1, p2) -> LTPSystem:
    """The LTP system from the rotor's M, C, G, K and its 12 base matrices with the chart
    coefficients: a base term whose coefficient is zero at every probe is dropped, one
    constant there is folded into the constant matrices."""
    B = base_basis(rotor).matrices
    D0 = np.array(rotor.C, float)
    K0 = np.array(rotor.K, float)
    d_terms, k_terms = [], []
    targets = (params.p1, params.p2)
    if any(t is not None and t[0] < 0 for t in targets):
        first = params.p1 is not None and params.p1[0] < 0
        d_terms.append((np.asarray(rotor.G, float),
                        (lambda t, a, b: a + 0.0 * t) if first else
                        (lambda t, a, b: b + 0.0 * t)))
    else:
        D0 += params.speed * np.asarray(rotor.G, float)
    probes = [params.coefficients(PROBE_T, float(a), np.asarray(p2)[None, :])
              for a in np.atleast_1d(p1)]
    for which, (const, terms) in enumerate(((D0, d_terms), (K0, k_terms))):
        values = np.concatenate([p[which].reshape(12, -1) for p in probes], axis=1)
        for i in range(12):
            v = values[i]
            if np.all(v == 0.0):
                continue
            if np.all(v == v[0]):
                const += v[0] * B[i]
            else:
                terms.append((B[i], lambda t, a, b, which=which, i=i:
                              params.coefficients(np.asarray(t, float), a, b)[which][i]))
    return LTPSystem(np.asarray(rotor.M, float), [(D0, None), *d_terms],
                     [(K0, None), *k_terms], params.period)


def _reference_chart(config, x, y, speed, n_intervals: int, n_modes: int):
    """The chart of two coefficient axes on the reference LTP system, reduced on the
    lowest ``n_modes`` undamped modes of its constant stiffness."""
    params = ChartParams(rate_specs_from_config(config), speed, coefficient_target(x[0]),
                         coefficient_target(y[0]))
    ltp = _reference_ltp(build_rotor(config), params, np.asarray(x[1], float),
                         np.asarray(y[1], float))
    K0 = sum(K for K, c in ltp.K_terms if c is None)
    V = sla.eigh(0.5 * (K0 + K0.T), 0.5 * (ltp.M + ltp.M.T),
                 subset_by_index=(0, n_modes - 1))[1]
    return stability_chart(ltp, x[1], y[1], n_intervals=n_intervals, basis=V)


def _chart_config(**base) -> object:
    raw = {"materials": {"steel": {"density": 7800.0, "young_modulus": 2e11,
                                   "poisson_ratio": 0.3}},
           "rotor": {"shaft": [{"length": 0.4, "n_elements": 4, "outer_radius": 0.01,
                                "material": "steel"}],
                     "disks": [{"node": 2, "material": "steel", "inner_radius": 0.01,
                                "outer_radius": 0.15, "thickness": 0.03}],
                     "supports": [{"node": 1, "stiffness": 1e9},
                                  {"node": 5, "stiffness": 1e9}],
                     "damping": {"kind": "modal", "ratio": 0.01}},
           "base": base or {"pitching": {"law": "harmonic", "frequency": 300.0,
                                         "angle_amplitude": 0.1}},
           "analysis": {"stability_chart": {"speed": 250.0}}}
    return config_from_dict(raw)


CASES = {
    # the paper's Figure 6 rotor: angle amplitude x base frequency
    "fig6": (lambda: load_config(FIG6), (A0, [0.3, 0.5]), (FREQ, np.linspace(240, 310, 15)),
             None),
    # speed as an axis (Omega G and the Omega w_bx stiffness as chart terms)
    "speed axis": (lambda: load_config(FIG6), ("speed", [150.0, 250.0]),
                   (FREQ, np.linspace(240, 310, 15)), None),
    # rolling with a constant yawing rate: Coriolis damping terms, folded constants
    "rolling": (lambda: _chart_config(
        rolling={"law": "harmonic", "frequency": 280.0, "angle_amplitude": 0.2},
        yawing={"law": "constant", "value": 3.0}),
        ("base.rolling.angle_amplitude", [0.2, 0.4]),
        ("base.rolling.frequency", np.linspace(220, 320, 6)), 250.0),
}


@pytest.mark.parametrize("case", sorted(CASES))
def test_chart_multipliers_equal_the_rotor_assembly(case):
    make, x, y, speed = CASES[case]
    config = make()
    speed = config.analysis.stability_chart.speed if speed is None else speed
    res = run_stability_chart(config, x=x, y=y, speed=speed, n_intervals=100, n_modes=6)
    ref = _reference_chart(config, x, y, speed, 100, 6)
    np.testing.assert_allclose(res.chart.max_abs, ref.max_abs, rtol=0, atol=1e-12)
    # the critical multiplier where it is one (unstable: a real one or a conjugate pair;
    # on the unit circle of an undamped rotor several share the largest modulus)
    bad = ~ref.stable
    for part in (np.real, lambda z: np.abs(np.imag(z))):
        np.testing.assert_allclose(part(res.chart.critical[bad]), part(ref.critical[bad]),
                                   rtol=0, atol=1e-12)
    # the stability boundary: the same points unstable, and some of each
    assert np.array_equal(res.stable, ref.stable)
    if case != "rolling":
        assert 0 < (~ref.stable).sum() < ref.stable.size


def _linear_reference(config, speed: float) -> tuple[np.ndarray, ...]:
    """(M, C + Omega G + C_base, K + K_base) of the rotor at the base state of t = 0."""
    rotor = build_rotor(config)
    motion = build_base_motion(config)
    if motion is None:
        return rotor.M, rotor.C + speed * rotor.G, rotor.K
    C_b, K_b, _ = base_basis(rotor).combine(base_coefficients(motion.state(0.0), speed))
    return rotor.M, rotor.C + speed * rotor.G + C_b, rotor.K + K_b


LINEAR = sorted({*EXAMPLES.glob("paper/fig*.toml"), EXAMPLES / "paper_rolling.toml",
                 EXAMPLES / "paper_yawing.toml", EXAMPLES / "dual_spool.toml"}
                - {FIG6})


@pytest.mark.parametrize("path", LINEAR, ids=lambda p: p.stem)
def test_linear_system_matrices_equal_the_rotor_assembly(path):
    config = load_config(path)
    system = linear_system(config)
    record = build_system(config).second_order(600.0)
    for speed in (0.0, 600.0, 1700.0):
        ref = _linear_reference(config, speed)
        got = system.matrices(speed)
        for a, b in zip(got, ref, strict=True):
            scale = max(np.abs(b).max(), 1e-300)
            assert np.abs(np.asarray(a) - b).max() <= 1e-12 * scale
        sparse = getattr(system, "sparse_matrices", lambda s: ())(speed)
        for a, b in zip(sparse, ref, strict=False):
            assert np.abs(a.toarray() - b).max() <= 1e-12 * max(np.abs(b).max(), 1e-300)
    # the record at 600 rad/s has the same (M, D, K)
    for a, b in zip((record.M, record.D, record.K), _linear_reference(config, 600.0),
                    strict=True):
        assert np.abs(a - b).max() <= 1e-12 * max(np.abs(b).max(), 1e-300)


def test_linear_system_of_a_harmonic_translation_keeps_the_constant_rates():
    """A harmonic base translation with a constant pitching rate: the translation loads
    the rotor only, the matrices are those of the constant rate."""
    steady = load_config(EXAMPLES / "paper_pitching.toml")
    shaken = with_values(steady, {"base.y.law": "harmonic", "base.y.amplitude": 0.5,
                                  "base.y.frequency": 100.0})
    for speed in (0.0, 900.0):
        got = linear_system(shaken).matrices(speed)
        for a, b in zip(got, _linear_reference(steady, speed), strict=True):
            assert np.abs(np.asarray(a) - b).max() <= 1e-12 * max(np.abs(b).max(), 1e-300)


def test_the_chart_is_the_floquet_problem_of_the_record():
    """At a grid point, the chart's LTP system has the D(t), K(t) of the linear part's
    record at that point's base motion, ``linear_part(system).second_order(Omega)``."""
    from rotorsfd.analyses.stability_chart_ltp import rotor_ltp_system
    from rotorsfd.model.time_terms import linear_part

    config = _chart_config(rolling={"law": "harmonic", "frequency": 280.0,
                                    "angle_amplitude": 0.2},
                           yawing={"law": "constant", "value": 3.0})
    a0, w_b, speed = 0.3, 260.0, 250.0     # a point off the probes; the speed an axis
    point = with_values(config, {"base.rolling.angle_amplitude": a0,
                                 "base.rolling.frequency": w_b})
    params = ChartParams(rate_specs_from_config(point), None,
                         coefficient_target("base.rolling.angle_amplitude"),
                         coefficient_target("speed"))
    ltp = rotor_ltp_system(build_system(point), params, np.array([0.2, 0.4]),
                           np.array([150.0, 250.0]))
    record = linear_part(build_system(point)).second_order(speed)
    assert record.time_varying is not None and record.n_nl == 0
    for t in (0.0, 0.0031, 0.017):
        _, D, K = record.matrices_at(t)
        tt = np.array([[t]])
        D_ltp = sum(X * (1.0 if c is None else float(np.asarray(c(tt, a0, speed)).ravel()[0]))
                    for X, c in ltp.D_terms)
        K_ltp = sum(X * (1.0 if c is None else float(np.asarray(c(tt, a0, speed)).ravel()[0]))
                    for X, c in ltp.K_terms)
        assert np.abs(D_ltp - D).max() <= 1e-12 * np.abs(D).max()
        assert np.abs(K_ltp - K).max() <= 1e-12 * np.abs(K).max()
    np.testing.assert_allclose(ltp.period(a0, speed), 2 * np.pi / w_b, rtol=1e-15)


def test_linear_part_is_the_record_without_the_elements():
    """The linear part's record at a speed: the system's record without its nonlinear
    elements (and without its loads): the same M, D, K and time-varying terms."""
    from rotorsfd.model.time_terms import linear_part

    config = load_config(EXAMPLES / "paper_harmonic_pitching.toml")
    system = build_system(config)
    full = system.second_order(800.0).linear()
    lin = linear_part(system).second_order(800.0)
    assert full.n_nl == 0 and full.kernel is None and len(system.elements) > 0
    for t in (0.0, 0.002, 0.01):
        for a, b in zip(full.matrices_at(t), lin.matrices_at(t), strict=True):
            assert np.abs(a - b).max() <= 1e-12 * np.abs(b).max()
    np.testing.assert_array_equal(lin.gyroscopic, system.rotor.G)


def test_config_path_equals_the_system_path_with_its_settings():
    """run_stability_chart(config) = run_stability_chart(build(config), section, context,
    source=...) (structural axis included), and a system with the section alone gives the
    coefficient chart of the config (the rates as a BaseMotion keeps them)."""
    from rotorsfd.analyses.stability_chart import ConfigSource, chart_context

    config = with_values(load_config(FIG6), {
        "analysis.stability_chart.intervals": 100,
        "analysis.stability_chart.x": {"parameter": A0, "values": ["0.3 rad", "0.5 rad"]},
        "analysis.stability_chart.y": {"parameter": FREQ, "start": "240 rad/s",
                                       "stop": "310 rad/s", "n": 15}})
    by_config = run_stability_chart(config, n_modes=4)
    system = build_system(config)
    section = config.analysis.stability_chart
    by_system = run_stability_chart(system, section, chart_context(config), n_modes=4,
                                    source=ConfigSource(config))
    np.testing.assert_array_equal(by_config.chart.max_abs, by_system.chart.max_abs)
    assert by_config.config_toml == by_system.config_toml and by_config.title == \
        by_system.title
    # the system alone: its BaseMotion holds the rate amplitude A0 w_b, the angle-amplitude
    # axis sets it again, so the chart is the config's
    alone = run_stability_chart(system, section, n_modes=4)
    np.testing.assert_array_equal(alone.chart.max_abs, by_config.chart.max_abs)
    assert (~alone.stable).sum() >= 1 and alone.x.units == "rad"
    np.testing.assert_array_equal(alone.y.values, by_config.y.values)
    # a structural axis: each config value rebuilt by the source
    k = "rotor.supports[1].stiffness"
    both = run_stability_chart(config, x=(FREQ, by_config.y.values), y=(k, [5e6, 1e9]),
                               n_modes=4)
    via = run_stability_chart(system, section, x=(FREQ, by_config.y.values),
                              y=(k, [5e6, 1e9]), n_modes=4, source=ConfigSource(config))
    np.testing.assert_array_equal(both.chart.max_abs, via.chart.max_abs)
    assert both.y.units == "N/m"
