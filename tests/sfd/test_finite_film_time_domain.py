"""The finite film in a rotor: HB against time integration (the compiled kernel in both the
HB loop and the time stepping), the paper rotor with the finite-length film."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.analyses.simulate import displaced_state
from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_model
from rotorsfd.model.system import RotorSystem

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"
W1, C = 811.3, 1.27e-4


@pytest.mark.slow
@pytest.mark.parametrize("overrides", [[], ["elements.sfd.film_table=false"],
                                       ["elements.sfd.end_flow=1.0"],
                                       ["elements.sfd.cavitation=guembel"]])
def test_hb_against_time_integration_with_the_finite_film(overrides: list[str]) -> None:
    """Omega~ = 0.95 (a stable period-1 orbit below the folds): HB (H = 8) against Newmark from
    near rest (200 steps per period, the last of 300 periods) on the SFD's DOFs, 1e-3 C
    (measured 4.5e-4 C at eps = 0.38 with open ends; also the Guembel film's field
    table)."""
    config = load_config(PAPER, ["unbalance[0].magnitude=144.02 g*mm",
                                 "elements.sfd.film_length=finite", *overrides])
    m = build_model(config)
    system = RotorSystem(m.rotor, m.elements, m.unbalances, m.base_motion)
    speed = 0.95 * W1
    sol = solve_periodic(system.periodic_problem(), speed, 8, tol=1e-10)
    inputs = time_domain_inputs(system, speed)
    dofs = inputs.nl_dofs[:2]
    q0 = displaced_state(inputs.M.shape[0], 1e-6)
    tr = integrate_periods(inputs, q0, np.zeros_like(q0), steps_per_period=200,
                           periods=300, record_dofs=dofs, record_periods=1,
                           poincare_periods=1)
    k = np.arange(sol.X.shape[0])
    hb = (np.exp(1j * speed * np.outer(tr.t, k)) @ sol.X[:, dofs]).real
    eps = np.hypot(*hb.T).max() / C
    assert 0.1 < eps < 0.9
    assert np.abs(hb - tr.q).max() < 1e-3 * C
