"""The two entry paths of an analysis are one (issue 16 item 3): ``run_x(config)`` is
``run_x(build(config), config.analysis.x, context=config_context(...))``, and a system
given alone gets an empty configuration's defaults (H, the critical-speed bound)."""

from __future__ import annotations

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.bifurcation_diagram import run_bifurcation_diagram
from rotorsfd.analyses.context import RunContext, build, config_context
from rotorsfd.analyses.simulate import run_simulation
from rotorsfd.io.schema import Config

SIM = ["analysis.simulate.steps_per_period=64", "analysis.simulate.periods=30",
       "analysis.simulate.poincare_periods=10", "analysis.simulate.step_check_periods=0",
       "analysis.response.harmonics=5"]


@pytest.fixture(scope="module")
def config(tmp_path_factory) -> Config:
    path = small_rotor_toml(tmp_path_factory.mktemp("entry") / "small.toml",
                            reference="first_critical")
    return api.load_config(path, SIM)


def test_simulate_config_path_is_the_system_path(config):
    a = run_simulation(config, speed_ratio=1.1, from_hb=True, lyapunov_periods=0,
                       progress=False)
    system = build(config)
    ctx = config_context(config, system, "simulate")
    b = run_simulation(system, speed_ratio=1.1, settings=config.analysis.simulate,
                       context=ctx, from_hb=True, lyapunov_periods=0, progress=False)
    assert a.settings["initial_state"] == b.settings["initial_state"] \
        == "HB periodic solution (H=5)"
    assert a.reference_speed == b.reference_speed == ctx.reference_speed
    np.testing.assert_array_equal(a.q, b.q)
    assert a.nodes == b.nodes and a.title == b.title and a.config_toml == b.config_toml


def test_a_system_alone_gets_an_empty_configurations_defaults(config):
    """The reference speed of a system given alone: the first forward critical speed
    below ``ModalAnalysis().critical_speed_max`` (the config's ``first_critical``); H of an
    HB start ``ResponseAnalysis().start_harmonics``."""
    system = build(config)
    ctx = RunContext()
    assert ctx.harmonics == 3
    assert ctx.reference(system) == pytest.approx(
        config_context(config, system, "simulate").reference_speed, rel=1e-12)
    r = run_simulation(system, speed_ratio=1.1, settings=config.analysis.simulate,
                       from_hb=True, lyapunov_periods=0, progress=False)
    assert r.settings["initial_state"] == "HB periodic solution (H=3)"
    assert r.speed == pytest.approx(1.1 * ctx.reference(system), rel=1e-12)


def test_bifurcation_diagram_config_path_is_the_system_path(config):
    over = {"n": 2, "settle_periods": 5, "record_periods": 5, "direction": "up",
            "progress": False}
    a = run_bifurcation_diagram(config, **over)
    system = build(config)
    b = run_bifurcation_diagram(system, config.analysis.bifurcation_diagram,
                                simulate=config.analysis.simulate,
                                context=config_context(config, system, "simulate"), **over)
    assert a.settings == b.settings
    for p, q in zip(a.points, b.points, strict=True):
        assert p.speed == q.speed and p.start == q.start == ("hb" if p is a.points[0]
                                                             else "previous")
        np.testing.assert_array_equal(p.poincare_q, q.poincare_q)


def test_response_config_path_is_the_system_path_with_its_section(config):
    """``run_response(config)`` = ``run_response(build(config), settings=section,
    context=config_context(...))``: the same speed range (Omega~ on the same reference),
    continuation options, H, nodes and branch, point for point."""
    from rotorsfd.analyses.response import run_response
    from rotorsfd.io.config import with_values

    cfg = with_values(config, {"analysis.response.speed_range.stop_ratio": 0.8,
                               "analysis.stability.enabled": False})
    a = run_response(cfg, progress=False)
    system = build(cfg)
    b = run_response(system, settings=cfg.analysis.response,
                     context=config_context(cfg, system, "response"), progress=False)
    assert a.branch.n_points == b.branch.n_points > 5
    np.testing.assert_array_equal(a.branch.lam, b.branch.lam)
    np.testing.assert_array_equal(a.branch.X, b.branch.X)
    assert (a.nodes, a.directions, a.reference_speed, a.title) == \
        (b.nodes, b.directions, b.reference_speed, b.title)
