"""The paper rotor (examples/paper_rotor.toml: fixed base, C/R 0.485 %, H = 3, fitted
supports): saddle-node pairs and bistable ranges for U = 144.02 and 252 g mm against our
recorded values (tight) and the paper's Table 1 (a stated band); U = 360.04 g mm runs
into journal contact without folding, with a weak secondary Hopf on the upper branch."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.stability.branch_stability import FloquetEvaluator, StabilityOptions

ROOT = Path(__file__).resolve().parents[2]
EXAMPLE = ROOT / "examples" / "paper_rotor.toml"
REF = 811.3

#: Recorded fold speeds Omega~ (located to 1e-6 relative; newmark-cb, N = 400, H = 3) and
#: the |mu|max reported at the nearest unstable point of the branch.
RECORDED = {"144.02 g*mm": ((1.0593463, 1.01304), (1.0526554, 1.01453)),
            "252 g*mm": ((1.1428471, 1.03222), (1.0848677, 1.00081))}
#: Paper, Table 1 (present model): Omega~ of the two bifurcation points.
PAPER_144 = (1.0565, 1.0556)


def response(unbalance: str, *extra: str):
    if not EXAMPLE.exists():
        pytest.skip("paper rotor example not available")
    config = api.load_config(EXAMPLE, overrides=(f"unbalance[0].magnitude={unbalance}",
                                                 *extra))
    return api.run_response(config, search_path=EXAMPLE.parent, progress=False)


@pytest.mark.parametrize("unbalance", list(RECORDED))
def test_saddle_node_pair_and_bistable_range(unbalance):
    # the recorded |mu| are the nearest points' at the paper's fixed M = 400
    r = response(unbalance, "analysis.stability.adaptive_intervals=false")
    assert r.success
    rows = r.bifurcations
    assert [b["status"] for b in rows] == ["confirmed", "confirmed"]
    assert [b["type"] for b in rows] == ["saddle-node", "saddle-node"]
    for row, (ratio, mu) in zip(rows, RECORDED[unbalance], strict=True):
        assert row["speed_ratio"] == pytest.approx(ratio, rel=2e-6)
        assert row["max_multiplier"] == pytest.approx(mu, abs=2e-5)
        assert row["max_multiplier"] > 1 and abs(row["located_re"] - 1) < 1e-3
    hi, lo = rows[0]["speed_ratio"], rows[1]["speed_ratio"]
    x = r.speeds / REF
    unstable = x[~r.stable]
    # unstable exactly on the turned-back segment, i.e. inside the bistable range
    assert unstable.size and lo <= unstable.min() and unstable.max() <= hi
    # bistable: stable points inside (lo, hi) on the upper branch (before the unstable
    # segment) and on the lower one (after it)
    idx = np.arange(x.size)
    iu = idx[~r.stable]
    inside = r.stable & (x > lo) & (x < hi)
    assert np.any(inside & (idx < iu.min())) and np.any(inside & (idx > iu.max()))


def test_fold_speeds_near_table_1():
    """Our supports are fitted (the paper gives none): the folds of U = 144.02 g mm lie
    within 0.5 % of the paper's 1.0565 / 1.0556, the range is wider (0.0067 vs 0.0009)."""
    r = response("144.02 g*mm")
    got = [b["speed_ratio"] for b in r.bifurcations]
    for g, p in zip(got, PAPER_144, strict=True):
        assert abs(g - p) < 5e-3 * p


@pytest.mark.slow
def test_u360_contact_and_weak_secondary_hopf():
    """U = 360.04 g mm (paper: folds at 1.2820 and 1.1245): with the fitted supports the
    upper branch reaches journal contact (eps -> 0.999 at Omega~ 1.3129) without folding;
    a complex pair leaves the unit circle at Omega~ 1.2881 (|mu| <= 1.00034, Hill agrees)
    and re-enters at 1.3124."""
    r = response("360.04 g*mm", "analysis.response.max_eccentricity=0.999")
    assert not r.success and len(r.branch.folds()) == 0
    assert r.deflection(1).max() > 0.998
    hopf = [b for b in r.bifurcations if b["type"] == "secondary-hopf"]
    assert [round(b["speed_ratio"], 4) for b in hopf] == [1.2881, 1.3124]
    i = int(np.argmax(np.where(r.speeds / REF < 1.31, r.max_multiplier, 0)))
    assert 1.0002 < r.max_multiplier[i] < 1.0005
    problem = r.system.periodic_problem("speed")
    hill = FloquetEvaluator(problem, StabilityOptions(method="hill"))(
        r.branch.lam[i], r.branch.X[i])
    assert abs(hill.max_abs - r.max_multiplier[i]) < 1e-5 and hill.crossing_type == (
        "secondary-hopf")


def test_pitching_fold_and_floquet_crossing_merged():
    """Pitching w_by = 4 rad/s, U = 144.02 g mm, H = 3: the orbit is not circular and the
    H = 3 truncation puts the multiplier's +1 crossing 2.6e-4 (relative) below the HB
    turning point; it is one saddle-node (the gap is reported), not two."""
    pitching = ROOT / "examples" / "paper_pitching.toml"
    if not pitching.exists():
        pytest.skip("pitching example not available")
    config = api.load_config(pitching, overrides=("unbalance[0].magnitude=144.02 g*mm",
                                                  "base.pitching.value=4 rad/s",
                                                  "analysis.response.harmonics=3"))
    r = api.run_response(config, search_path=pitching.parent, progress=False)
    st = r.info["stability"]
    assert [b.kind for b in st.bifurcations] == ["saddle-node", "saddle-node"]
    assert all(b.via == "tangent" for b in st.bifurcations)
    upper = st.bifurcations[0]
    gap = abs(upper.info["floquet_lam"] - upper.lam) / upper.lam
    assert 1e-4 < gap < 1e-3 and any("truncation" in m for m in st.messages)


def test_u360_with_light_damping_has_the_papers_saddle_node_pair():
    """Issue 6 asks for the U = 360.04 g mm saddle-node pair and bistable range. The paper
    states no damping; undamped, our branch locks into journal contact (test above). With
    a light modal damping of 0.2 % (our choice, see README) the pair is there, within 1 %
    of the paper's Table 1 (1.2820 / 1.1245): measured 1.2867 / 1.1151."""
    r = response("360.04 g*mm", "rotor.damping.kind=modal", "rotor.damping.ratio=0.002",
                 "analysis.response.max_eccentricity=0.995")
    assert r.success
    rows = [b for b in r.bifurcations if b["type"] == "saddle-node"]
    assert len(rows) == 2
    hi, lo = sorted((b["speed_ratio"] for b in rows), reverse=True)
    assert hi == pytest.approx(1.2820, rel=1e-2) and lo == pytest.approx(1.1245, rel=1e-2)
    x = r.speeds / REF
    inside = r.stable & (x > lo) & (x < hi)
    idx = np.arange(x.size)
    iu = idx[~r.stable & (x >= lo) & (x <= hi)]
    assert iu.size  # the turned-back middle branch is unstable
    assert np.any(inside & (idx < iu.min())) and np.any(inside & (idx > iu.max()))
