"""The two entry paths of modal, static, the attractor census and the response without
settings are one (issue 16 item 3): ``run_x(config)`` is ``run_x(build(config),
config.analysis.<section>, context=config_context(...))``, and a system given alone gets an
empty configuration's defaults. On the shipped examples; the first critical speeds are
also checked against the values the paper rotor's supports were fitted to (811.3 and
2784.6 rad/s, Zhang et al. 2025), the static offset against its equation."""

from __future__ import annotations

import tomllib
from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.attractors import CensusOptions
from rotorsfd.analyses.attractors_config import run_census
from rotorsfd.analyses.context import RunContext, build, config_context
from rotorsfd.analyses.modal import run_modal
from rotorsfd.analyses.response import run_response
from rotorsfd.analyses.static import run_static
from rotorsfd.errors import ConfigError
from rotorsfd.io.config import config_from_dict
from rotorsfd.io.schema import ModalAnalysis

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
PAPER = EXAMPLES / "paper_rotor.toml"
FIRST_CRITICAL = ["reference.speed=first_critical"]


def _same_modal(a, b) -> None:
    assert a.reference_speed == pytest.approx(b.reference_speed, rel=1e-12)
    assert [(c.mode, c.whirl) for c in a.critical_speeds] == \
        [(c.mode, c.whirl) for c in b.critical_speeds]
    np.testing.assert_allclose([c.speed_rad_s for c in a.critical_speeds],
                               [c.speed_rad_s for c in b.critical_speeds], rtol=1e-12)
    np.testing.assert_array_equal(a.campbell.speeds, b.campbell.speeds)
    np.testing.assert_allclose(a.campbell.frequencies, b.campbell.frequencies, rtol=1e-12,
                               atol=1e-12 * np.abs(a.campbell.frequencies).max())


def test_modal_config_path_is_the_system_path():
    cfg = api.load_config(PAPER, [*FIRST_CRITICAL, "analysis.modal.speed_range.n=5"])
    a = run_modal(cfg)
    system = build(cfg)
    b = run_modal(system, cfg.analysis.modal,
                  context=config_context(cfg, system, "modal", resolve_reference=False))
    _same_modal(a, b)
    assert a.title == b.title == cfg.title
    # the paper's critical speeds, which the supports were fitted to (to 1e-13)
    np.testing.assert_allclose([c.speed_rad_s for c in a.critical_speeds],
                               [811.3, 2784.6], rtol=1e-9)
    assert a.reference_speed == a.critical_speeds[0].speed_rad_s == api.reference_speed(cfg)
    # a system alone: an empty configuration's defaults (first_critical below 2e4 rad/s)
    c = run_modal(system, cfg.analysis.modal)
    _same_modal(a, c)
    assert c.title == ""
    # a number in [reference] is the context's reference speed on both paths
    fixed = api.with_values(cfg, {"reference.speed": 800.0})
    d = run_modal(fixed)
    e = run_modal(system, fixed.analysis.modal, context=RunContext(reference_speed=800.0))
    assert d.reference_speed == e.reference_speed == 800.0
    np.testing.assert_array_equal(d.campbell.speeds, e.campbell.speeds)


def test_modal_of_two_spools_config_path_is_the_system_path():
    cfg = api.load_config(EXAMPLES / "dual_spool.toml",
                          ["analysis.modal.speeds=[0, 300, 600]", "analysis.modal.spool=hp"])
    a = run_modal(cfg)
    system = build(cfg)
    b = run_modal(system, cfg.analysis.modal,
                  context=config_context(cfg, system, "modal", resolve_reference=False))
    _same_modal(a, b)
    assert (a.spool, a.ratio, a.lines) == (b.spool, b.ratio, b.lines) == \
        ("hp", 1.8, {"lp": 1 / 1.8, "hp": 1.0})
    assert a.title == b.title == cfg.title


def test_static_config_path_is_the_system_path_and_solves_its_equation():
    cfg = api.load_config(EXAMPLES / "paper_pitching.toml",
                          [*FIRST_CRITICAL, "analysis.modal.speed_range.n=4"])
    a = run_static(cfg)
    system = build(cfg)
    b = run_static(system, cfg.analysis.modal, context=config_context(cfg, system, "modal"))
    np.testing.assert_array_equal(a.speeds, b.speeds)
    np.testing.assert_allclose(a.q, b.q, rtol=1e-12, atol=1e-12 * np.abs(a.q).max())
    assert a.reference_speed == b.reference_speed and a.title == b.title == cfg.title
    # a system alone: the reference speed is the first forward critical speed (as the
    # config's first_critical), not 1 rad/s; its speeds [analysis.modal]'s defaults
    c = run_static(system, speeds=a.speeds)
    assert c.reference_speed == pytest.approx(a.reference_speed, rel=1e-12)
    np.testing.assert_allclose(c.q, a.q, rtol=1e-12, atol=1e-12 * np.abs(a.q).max())
    d = run_static(system)
    np.testing.assert_allclose(d.speeds, np.linspace(0.0, 4.0, 81) * a.reference_speed,
                               rtol=1e-12)
    # (K + K_base) q = F_base at every speed
    assert np.abs(a.q).max() > 0.0
    for w, q in zip(a.speeds, a.q, strict=True):
        _, _, K = system.matrices(float(w))
        f = system.static_force(float(w))
        assert np.linalg.norm(K @ q - f) <= 1e-9 * np.linalg.norm(f)


def test_census_config_path_is_the_system_path():
    cfg = api.load_config(PAPER, [*FIRST_CRITICAL, "analysis.response.harmonics=3"])
    opts = CensusOptions(n_starts=2, steps_per_period=48, check_periods=10, max_periods=20,
                         classify_periods=16, around="rest")
    (a,) = run_census(cfg, speed_ratios=[1.2], options=opts)
    system = build(cfg)
    (b,) = run_census(system, speed_ratios=[1.2], options=opts,
                      settings=cfg.analysis.simulate,
                      context=config_context(cfg, system, "simulate"))
    assert a.speed == b.speed == pytest.approx(1.2 * a.reference_speed, rel=1e-15)
    assert a.reference_speed == b.reference_speed
    np.testing.assert_array_equal(a.coords, b.coords)
    for p, q in zip(a.outcomes, b.outcomes, strict=True):
        assert (p.motion, p.period, p.periods_run) == (q.motion, q.period, q.periods_run)
        np.testing.assert_allclose(p.points, q.points, rtol=1e-12, atol=1e-12)
    assert a.options == b.options and a.options.harmonics == 3
    # a system alone: an empty configuration's reference speed and H (8: 'auto')
    (c,) = run_census(system, speed_ratios=[1.2], options=opts)
    assert c.reference_speed == pytest.approx(a.reference_speed, rel=1e-12)
    assert c.options.harmonics == 8


def test_response_of_a_system_alone_is_that_of_an_empty_section():
    """``run_response(system)`` runs ``ResponseAnalysis()``: the branch of a config whose
    ``[analysis.response]`` is empty (speeds 0.5 to 1.6 x Omega_ref, H 'auto' from 3),
    point for point, not continue_periodic's own defaults."""
    raw = tomllib.loads(PAPER.read_text())
    del raw["analysis"]["response"]
    raw["analysis"]["stability"] = {"enabled": False}
    cfg = config_from_dict(raw, FIRST_CRITICAL)
    a = run_response(cfg, progress=False)
    b = run_response(build(cfg), stability_options=False, progress=False)   # default: on
    assert a.branch.n_points == b.branch.n_points > 10
    np.testing.assert_array_equal(a.branch.lam, b.branch.lam)
    np.testing.assert_array_equal(a.branch.X, b.branch.X)
    assert a.branch.lam[0] == pytest.approx(0.5 * a.reference_speed, rel=1e-12)
    assert a.branch.info["adaptive_harmonics"] and b.branch.info["adaptive_harmonics"]
    assert (a.nodes, a.directions, a.reference_speed) == \
        (b.nodes, b.directions, b.reference_speed)
    assert a.stable is None and b.stable is None


def test_modal_of_a_time_varying_rate_names_the_law():
    cfg = api.load_config(EXAMPLES / "paper_harmonic_pitching.toml")
    with pytest.raises(ConfigError, match=r"base\.pitching\.law: got 'harmonic'"):
        run_modal(cfg, ModalAnalysis(speeds=[0.0]))


def _same_torus(a, b) -> None:
    assert a.branch.n_points == b.branch.n_points >= 2
    np.testing.assert_allclose(a.branch.lam, b.branch.lam, rtol=1e-12)
    np.testing.assert_allclose(a.branch.X, b.branch.X, rtol=1e-12,
                               atol=1e-12 * np.abs(a.branch.X).max())
    assert (a.reference_speed, a.nodes, a.directions, a.title) == \
        (b.reference_speed, b.nodes, b.directions, b.title)
    assert a.info == b.info


@pytest.mark.parametrize("over", [
    ["analysis.response.speed_range.stop_ratio=0.805"],
    ['analysis.response.parameter="base.pitching.frequency"',
     "analysis.response.speed_ratio=0.8",
     'analysis.response.parameter_range=["60 rad/s", "61 rad/s"]']],
    ids=["speed", "base frequency"])
def test_torus_config_path_is_the_system_path(over):
    from rotorsfd.analyses.torus_parameters import torus_parameter
    from rotorsfd.analyses.torus_response import run_torus_response

    cfg = api.load_config(EXAMPLES / "paper_harmonic_pitching.toml",
                          ["analysis.stability.enabled=false",
                           "analysis.response.step_initial=0.05",
                           "analysis.response.step_max=0.1", *over])
    a = run_torus_response(cfg, progress=False)
    system = build(cfg)
    r = cfg.analysis.response
    par = torus_parameter(cfg, r.parameter)
    span = {} if par.name == "speed" else {"start": 60.0, "stop": 61.0}
    b = run_torus_response(system, r, context=config_context(cfg, system, "response"),
                           parameter=par, progress=False, **span)
    _same_torus(a, b)
    assert a.parameter == b.parameter == r.parameter and a.speed == b.speed


def test_dual_spool_config_path_is_the_system_path():
    from rotorsfd.analyses.dual_spool_response import run_dual_spool_response

    cfg = api.load_config(EXAMPLES / "dual_spool_unbalance.toml",
                          ["analysis.response.speed_range.start=150 rad/s",
                           "analysis.response.speed_range.stop=152 rad/s",
                           "analysis.response.step_initial=0.3",
                           "analysis.response.step_max=0.5",
                           "analysis.stability.enabled=false"])
    a = run_dual_spool_response(cfg, progress=False)
    system = build(cfg)
    b = run_dual_spool_response(system, cfg.analysis.response,
                                context=config_context(cfg, system, "response"),
                                progress=False)
    _same_torus(a, b)
    assert a.ratio == b.ratio == 1.8 and not a.lyapunov and not b.lyapunov
    # a system alone: an empty configuration's [analysis.stability] (on)
    assert RunContext().stability.enabled
