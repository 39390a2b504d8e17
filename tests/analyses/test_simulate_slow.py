"""Heavier checks on the paper rotor (84 DOFs, 2000 periods x 200 steps)."""

from __future__ import annotations

from pathlib import Path

import pytest

from rotorsfd import api
from rotorsfd.analyses.simulate import run_simulation

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "paper_rotor.toml"
FIG23 = ["elements.sfd.clearance_ratio=0.728 %", "unbalance[0].magnitude=252 g*mm",
         "base.pitching.law=constant", "base.pitching.value=10 rad/s"]


@pytest.mark.slow
def test_paper_rotor_2000_periods() -> None:
    """The example at Omega~ = 1: 400000 steps in under 5 s, period-1, no contact."""
    res = run_simulation(api.load_config(EXAMPLE), speed_ratio=1.0, progress=False)
    assert res.settings["elapsed_integration_s"] < 5.0
    assert res.motion.motion == "period-1" and res.max_eccentricity < 0.9


@pytest.mark.slow
def test_figure_23_case_is_resolved_in_time() -> None:
    """C/R 0.728 %, U = 252 g mm, pitching 10 rad/s, Omega~ = 1.075 (eps ~ 0.99): the
    same period-1 orbit at 200 and 400 steps per period (peak eps within 1e-3)."""
    config = api.load_config(EXAMPLE, FIG23)
    a = run_simulation(config, speed_ratio=1.075, periods=1000, progress=False)
    b = run_simulation(config, speed_ratio=1.075, periods=1000, steps_per_period=400,
                       progress=False)
    assert a.motion.motion == b.motion.motion == "period-1"
    assert abs(a.max_eccentricity - b.max_eccentricity) < 1e-3
