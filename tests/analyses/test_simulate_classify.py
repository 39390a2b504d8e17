"""Issue 24 item 2: ``simulate`` called a period-1 motion quasi-periodic (the README's own
rotor at Omega~ 1.06: Poincare points spread by 1e-6 C at the journal and 1.2e-4 C at
node 12; velocities carry a lightly damped high mode's free vibration) and printed a
positive Lyapunov exponent without its uncertainty. The section is now the displacements
in one scale, and the exponent excludes the neutral high modes: negative, equal to
ln |mu|max of the HB orbit's Floquet multipliers (0.8145 here) within its uncertainty."""

from __future__ import annotations

import math
import re
from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.simulate import classify, run_simulation, system_from_config
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.stability.branch_stability import FloquetEvaluator

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def readme_rotor(tmp_path_factory):
    """``my_rotor.toml`` of the README's tutorial (section 4), as a user copies it."""
    text = (ROOT / "README.md").read_text()
    m = re.search(r'```toml\n(title = "My rotor.*?)```', text, re.S)
    path = tmp_path_factory.mktemp("readme") / "my_rotor.toml"
    path.write_text(m.group(1))
    return api.load_config(path)


@pytest.mark.parametrize("steps", [pytest.param("auto", marks=pytest.mark.slow), 200])
def test_readme_rotor_at_1_06_is_period_1(readme_rotor, steps) -> None:
    config = readme_rotor
    r = run_simulation(config, speed_ratio=1.06, steps_per_period=steps, progress=False)
    assert r.motion_name == "period-1", r.summary()
    ev = r.motion.evidence
    assert ev["n_distinct_poincare"] == 1 and ev["poincare_spread"] < 1e-3
    ly, full = r.lyapunov, r.lyapunov_full
    err = ly.half_spread * r.period
    assert ly.per_period + err < 0.0
    system = system_from_config(config)
    problem = system.periodic_problem()
    sol = solve_periodic(problem, r.speed, 5)  # the H the README rotor had before "auto"
    floquet = FloquetEvaluator(problem)(r.speed, sol.X)
    assert floquet.stable
    assert abs(ly.per_period - math.log(floquet.max_abs)) < err + 0.03
    # the whole-state exponent, reported apart, is about zero (a neutral direction)
    assert abs(full.per_period) < 0.02
    text = r.summary()
    assert "+/-" in text and "neutral high modes excluded" in text
    d = r.summary_dict()
    assert d["lyapunov"]["high_modes_excluded"] is True
    assert d["lyapunov"]["uncertainty_per_period"] == pytest.approx(err, rel=1e-9)
    assert d["lyapunov_whole_state"]["per_period"] == pytest.approx(full.per_period)


def test_small_jittering_node_does_not_decide() -> None:
    """A period-1 orbit at two nodes, the second with a small orbit (1e-3 of the first)
    and a free vibration of 2e-6 of the first's size at 50 Omega on top: per-coordinate
    scales made it 'not periodic'; in one displacement scale it is period-1, and the
    velocity spread is reported apart."""
    spp, n_per, w = 200, 100, 1.0
    t = np.arange(n_per * spp + 1) * (2 * np.pi / w) / spp
    q = np.column_stack([np.cos(t), np.sin(t), 1e-3 * np.cos(t), 1e-3 * np.sin(t)])
    q[:, 2] += 2e-6 * np.cos(50.3 * t)
    v = np.gradient(q, t, axis=0)
    idx = np.arange(spp, q.shape[0], spp)
    mc = classify(q[idx], v[idx], q, v, t[1] - t[0], w)
    assert mc.motion == "period-1"
    assert mc.evidence["poincare_spread"] < 1e-5
    assert mc.evidence["poincare_velocity_spread"] > 1e-4
