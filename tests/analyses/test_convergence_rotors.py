"""Converged results on rotors (issues 14 and 27): the anisotropic two-element rotor whose
H = 3 branch has a fold pair that the converged one has not, the Floquet step control
against a fine-step reference, and the narrow fold pair of the paper rotor under pitching.

Independent checks: multipliers against the same monodromy at M = 12800 (second order:
its error is ~1e-3 of the M = 400 one); the fold pair's existence against a branch with
many more harmonics (H = 20); at a fold of a converged orbit one multiplier is +1 and
the middle branch is unstable.
"""

from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.harmonic import continue_periodic
from rotorsfd.stability.branch_stability import FloquetEvaluator, StabilityOptions

DATA = Path(__file__).resolve().parents[1] / "data"
ROOT = Path(__file__).resolve().parents[2]
ANISO = DATA / "issue14_anisotropic.toml"


def _system(path, sets=()):
    cfg = api.load_config(path, list(sets))
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem

    m = build_model(cfg)
    return RotorSystem(m.rotor, m.elements, m.unbalances, m.base_motion)


def test_step_control_meets_the_multiplier_tolerance_where_m400_does_not():
    p = _system(ANISO).periodic_problem("speed")
    w1 = 907.73                                      # first critical speed [rad/s]
    branch = continue_periodic(p, 0.5 * w1, 0.95 * w1, 3, adaptive_harmonics=True)
    ref = FloquetEvaluator(p, StabilityOptions(n_intervals=12800))
    fixed = FloquetEvaluator(p, StabilityOptions())
    pts = range(branch.n_points - 12, branch.n_points)    # near the resonance
    err = [abs(fixed(branch.lam[i], branch.X[i]).max_abs
               - ref(branch.lam[i], branch.X[i]).max_abs) for i in pts]
    i = list(pts)[int(np.argmax(err))]
    assert max(err) > 2e-4                           # M = 400 is not enough there
    ctrl = FloquetEvaluator(p, StabilityOptions(interval_tol=1e-4))(branch.lam[i],
                                                                    branch.X[i])
    err_ctrl = abs(ctrl.max_abs - ref(branch.lam[i], branch.X[i]).max_abs)
    assert err_ctrl < 2e-4 and ctrl.info["n_intervals"] > 400
    # the estimate does not understate the true error, and is of its size (here 5x:
    # the M/2 difference over 3 assumes the asymptotic second-order regime)
    est = ctrl.info["multiplier_error"]
    assert 0.5 * err_ctrl <= est <= 10 * err_ctrl + 1e-5


@pytest.mark.slow
def test_anisotropic_rotor_has_no_fold_by_default_and_h3_says_its_pair_is_unconfirmed():
    cfg = api.load_config(ANISO)
    auto = api.run_response(cfg, progress=False)
    assert auto.success and not auto.bifurcations
    assert auto.branch.info["truncation_error"].max() <= 1e-3
    high = api.run_response(api.with_values(cfg, {"analysis.response.harmonics": 20,
                                                  "analysis.stability.enabled": False}),
                            progress=False)
    assert high.success and high.branch.folds().size == 0     # the converged truth
    h3 = api.run_response(api.with_values(cfg, {"analysis.response.harmonics": 3}),
                          progress=False)
    rows = h3.bifurcations
    assert [r["type"] for r in rows] == ["saddle-node", "saddle-node"]
    assert [r["status"] for r in rows] == ["unconfirmed", "unconfirmed"]
    assert all(r["check_shift"] == "" for r in rows)           # vanished at H = 5
    assert "warning: HB truncation error above" in h3.message
    assert "UNCONFIRMED" in h3.summary()


@pytest.mark.slow
def test_narrow_fold_pair_under_pitching_has_its_unstable_middle_segment():
    # issue 27: at H = 3 the pair 1.060053 / 1.059867 had no unstable point between
    cfg = api.load_config(ROOT / "examples" / "paper" / "fig19_unstable_range.toml",
                          ["unbalance[0].magnitude=144.02 g*mm",
                           "base.pitching.value=4.3 rad/s",
                           "analysis.response.harmonics=auto"])
    r = api.run_response(cfg, progress=False)
    rows = [x for x in r.bifurcations if x["type"] == "saddle-node"]
    assert len(rows) == 2 and all(x["status"] == "confirmed" for x in rows)
    for x in rows:
        assert abs(x["located_multiplier_re"] - 1.0) < 1e-3
    lo, hi = sorted(x["parameter"] for x in rows)
    s_lo, s_hi = sorted(r.branch.s[[x["nearest_point"] for x in rows]])
    between = (r.branch.s > s_lo) & (r.branch.s < s_hi)
    assert between.any() and not r.stable[between].all()
    inserted = r.branch.info["inserted"]
    assert np.count_nonzero(inserted == 1) == 2
    np.testing.assert_allclose(np.sort(r.branch.lam[inserted == 1]), [lo, hi])
