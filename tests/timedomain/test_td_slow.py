"""Heavier check: the paper-sized run (84 DOFs, 2000 periods x 200 steps, the paper's 1 um
start) converges onto the harmonic-balance orbit of the same rotor."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_model
from rotorsfd.model.system import RotorSystem
from rotorsfd.timedomain import Forcing, HarmonicLoad, integrate

PAPER = Path(__file__).resolve().parents[2] / "examples" / "paper_rotor.toml"


@pytest.mark.slow
def test_paper_rotor_2000_periods_land_on_the_hb_orbit() -> None:
    """Omega~ = 0.8, U = 360.04 g mm: the last 100 periods of the SFD journal equal the
    H = 8 periodic solution to 1e-3 C (independent methods: time stepping vs HB)."""
    model = build_model(load_config(PAPER))
    system = RotorSystem(model.rotor, model.elements, model.unbalances,
                         model.base_motion)
    speed = 0.8 * 811.3
    M, D, K = system.matrices(speed)
    Fc, Fs = system.unbalance_harmonics(speed)
    forcing = Forcing(speed, constant=system.static_force(speed),
                      harmonics=[HarmonicLoad(1, cos=Fc, sin=Fs)])
    r = integrate(M, D, K, system.nl_dofs, system.elements.kernel, system.elements.kernel_params,
                  forcing, steps_per_period=200, n_periods=2000, q0=1e-6,
                  record_start=1900 * 200)
    assert r.success
    X = solve_periodic(system.periodic_problem(), speed, H=8).X[:, system.nl_dofs]
    k = np.arange(X.shape[0])
    q_hb = (np.exp(1j * speed * np.outer(r.t, k)) @ X).real
    C = model.elements[0].film.clearance
    assert np.abs(r.q - q_hb).max() < 1e-3 * C
    # and the orbit is a real one (not the trivial solution): about 0.15 C at the journal
    assert 0.05 * C < np.abs(r.q).max() < 0.5 * C
