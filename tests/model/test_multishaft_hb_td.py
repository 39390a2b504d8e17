"""The shipped dual-spool rotor with an intershaft SFD (issue 20 item 1): HB of the
two-shaft system against time integration (an independent method) at one speed."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.analyses.simulate import hb_state, run_simulation
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.io.config import config_from_dict, read_toml
from rotorsfd.model.build import build_system

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "dual_spool.toml"


@pytest.mark.slow
def test_hb_equals_time_integration_with_an_intershaft_sfd() -> None:
    raw = copy.deepcopy(read_toml(EXAMPLE))
    del raw["rotor"]["intershaft"]
    raw["elements"]["isfd"] = dict(kind="intershaft_sfd", node=9, outer_node=18,
                                   viscosity="0.01 Pa*s", radius="45 mm", length="12 mm",
                                   clearance="50 um", centring_stiffness="2e5 N/m")
    raw["unbalance"][0]["magnitude"] = "150 g*mm"
    system = build_system(config_from_dict(raw))
    speed = 540.0                     # below the second forward critical (557 rad/s)
    sol = solve_periodic(system.periodic_problem(), speed, 8, tol=1e-10)
    C = system.length_scale
    t = np.linspace(0.0, 2 * np.pi, 64, endpoint=False)
    orbit = np.real(np.exp(1j * np.outer(t, np.arange(sol.X.shape[0]))) @ sol.X)
    assert 0.1 < system.elements["isfd"].limit(orbit[:, [32, 33, 68, 69]]) < 1  # film active
    r = run_simulation(system, speed, periods=300, poincare_periods=5, steps_per_period=400,
                       initial_displacement=0.0, progress=False, lyapunov_periods=0)
    q_hb, _ = hb_state(sol.X, speed)
    q_td = r.q_final
    yz = np.sort(np.concatenate([np.arange(0, system.n_dof, 4), np.arange(1, system.n_dof, 4)]))
    err = np.abs(q_td[yz] - q_hb[yz]).max() / C
    assert np.abs(q_hb[yz]).max() / C > 0.05         # a real orbit
    assert err < 5e-4, err
