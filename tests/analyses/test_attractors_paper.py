"""Attractor census on the paper's C/R = 0.728 % case (examples/paper/fig23_time_domain.toml)
at Omega~ = 1.075, the file's converged step T/800: without being told where, the census
finds the main branch (journal Poincare point (0.2952, -0.8169) C, the file's header) and
the isola (-0.2262, -0.9022) C (README "Coexisting motions"), both stable by Floquet on
their HB corrections; and the command writes its files without NaN."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.cli import main

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "examples/paper/fig23_time_domain.toml"
MAIN, ISOLA = (0.2952, -0.8169), (-0.2262, -0.9022)


@pytest.mark.slow
def test_census_finds_main_branch_and_isola(tmp_path):
    out = tmp_path / "census"
    status = main(["attractors", str(CONFIG), "--speed-ratio", "1.075", "--starts", "24",
                   "--harmonics", "16", "--workers", "2", "-o", str(out), "--quiet"])
    assert status == 0
    rows = list(csv.DictReader(open(out / "attractors.csv")))
    periodic = [r for r in rows if r["motion"] == "period-1"]
    points = [tuple(float(x) for x in r["poincare_points"].split()) for r in periodic]
    for target in (MAIN, ISOLA):
        d = [max(abs(p[0] - target[0]), abs(p[1] - target[1])) for p in points]
        assert min(d) < 5e-3, (target, points)
        r = periodic[int(np.argmin(d))]
        assert r["hb_stable"] == "True" and float(r["hb_max_multiplier"]) < 1.0
        assert float(r["step_check"]) < 5e-3          # T/800 against T/1600, in C
        assert 0.0 < float(r["basin_fraction"]) < 1.0
        assert float(r["eps_max_sfd"]) > 0.98         # close to contact, both
    fractions = [float(r["basin_fraction"]) for r in rows]
    assert sum(fractions) == pytest.approx(1.0)
    summary = json.loads((out / "summary.json").read_text())
    assert summary["censuses"][0]["n_starts"] == 24
    assert "NaN" not in (out / "summary.json").read_text()
    assert (out / "basins.png").stat().st_size > 10_000


def test_bad_option_is_one_line_exit_2(tmp_path, capsys):
    status = main(["attractors", str(CONFIG), "--speed-ratio", "1.075", "--sampling",
                   "random", "-o", str(tmp_path / "x")])
    assert status == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and "--sampling" in err[0] and "lhs or grid" in err[0]


def test_prepared_step_against_integrate_periods():
    """The census's stepping (prepared once, the reduced state carried over check chunks
    of 10 periods) against one integrate_periods run of the same 30 periods from the same
    start (chunks of one period, restarted from the projected physical state): the same
    scheme and step, so the Poincare points, the recorded last periods and the final state
    agree to rounding (1e-9 C), far below settle_tol (1e-4 C)."""
    from rotorsfd.analyses.attractors import (
        CensusOptions,
        start_states,
        stepper_of,
        unit_samples,
    )
    from rotorsfd.analyses.attractors_config import census_model
    from rotorsfd.analyses.context import build, config_context
    from rotorsfd.analyses.td_integration import integrate_periods
    from rotorsfd.io.config import load_config

    config = load_config(CONFIG)
    system = build(config, CONFIG.parent)
    ref = config_context(config, system, "simulate", search_path=CONFIG.parent
                         ).reference(system)
    model = census_model(system, 1.075 * ref, reduction="auto", reference_speed=ref)
    assert model.inputs.reduction is not None      # the reduced step is what is checked
    o = CensusOptions(n_starts=4, steps_per_period=800).validate().resolved()
    _, q0, v0 = start_states(model, unit_samples(4, 2 * model.nl_dofs.size), o)
    st = stepper_of(model, o)
    state = st.start(q0[1], v0[1])
    chunks = [st.advance(state, 10, 8) for _ in range(3)]
    P = np.concatenate([c.pq for c in chunks]) / model.scale
    traj = integrate_periods(model.inputs, q0[1], v0[1], steps_per_period=800, periods=30,
                             record_dofs=model.nl_dofs, record_periods=8,
                             poincare_periods=30, chunk_periods=1)
    P_ref = traj.poincare_q[traj.poincare_t > 0.5 * model.inputs.period] / model.scale
    assert P.shape == P_ref.shape == (30, 2)
    assert np.max(np.abs(P - P_ref)) < 1e-9
    # the transient still moves by far more than that: the comparison could fail
    assert np.max(np.abs(P[-1] - P[0])) > 1e-3
    assert chunks[-1].t == pytest.approx(traj.t, abs=1e-12)
    assert np.max(np.abs(chunks[-1].q - traj.q) / model.scale) < 1e-9
    q, v, t = st.final(state)
    assert t == pytest.approx(traj.t_final, rel=1e-14)
    nl = model.nl_dofs
    assert np.max(np.abs(q[nl] - traj.q_final[nl]) / model.scale) < 1e-9
    assert np.max(np.abs(v[nl] - traj.v_final[nl]) / (model.scale * model.speed)) < 1e-9
