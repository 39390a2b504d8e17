"""``bifurcation-curves`` (analyses/bifurcation_curves.py) on the rotor on two journal
bearings (examples/journal_bearing_rotor.toml): with 5 g mm the half-speed whirl locks
between two period doublings (1043 and 1077 rad/s); the period-doubling curve in
(speed, unbalance) from the first one passes, by an independent route, through the
period doublings that Floquet (monodromy multipliers through -1) locates on speed
branches computed at other unbalances, reaches the second start point (so it is not
continued twice), and turns at the lowest unbalance of the pair: below it the branch has
no period doubling, above it two."""

from __future__ import annotations

import dataclasses
import json
from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.bifurcation_curves import at_limit
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.io.config import config_from_dict, read_toml
from rotorsfd.model.build import build_system
from rotorsfd.stability.branch_stability import branch_stability

EXAMPLE = Path(__file__).parents[2] / "examples" / "journal_bearing_rotor.toml"
SPEEDS = ("950 rad/s", "1150 rad/s")


def config():
    raw = read_toml(EXAMPLE)
    raw["analysis"]["response"]["speed_range"] = {"start": SPEEDS[0], "stop": SPEEDS[1]}
    return config_from_dict(raw)


@pytest.fixture(scope="module")
def curves():
    return api.run_bifurcation_curves(config(), "unbalance[0].magnitude", "5 g*mm",
                                      "2 g*mm")


def floquet_flips(U: float) -> list[float]:
    """Period doublings [rad/s] of the speed branch at unbalance ``U`` [kg m] (H = 3, as
    the curves' start branch), located by the branch's Floquet stability."""
    system = build_system(config()).with_parameter("unbalance.magnitude", U)
    problem = system.periodic_problem("speed")
    branch = continue_periodic(problem, 950.0, 1150.0, 3)
    st = branch_stability(branch, problem)
    return sorted(b.lam for b in st.bifurcations if b.kind == "period-doubling")


def test_start_points_and_one_curve_through_both(curves):
    assert curves.success, curves.message
    assert curves.start_folds == [] and curves.H2 == 12
    assert curves.start_period_doublings == pytest.approx([1043.25, 1076.74], abs=0.01)
    assert len(curves.pd_curves) == 1      # the second start point is on the first curve
    w = curves.speeds_at("period-doubling", 5e-6)
    # measured 1.1e-5 and 3.4e-6: the flip of HB with 12 harmonics of Omega/2 against
    # the monodromy's on the H = 3 orbit
    assert w == pytest.approx(curves.start_period_doublings, rel=1e-4)


@pytest.mark.parametrize("U", [4e-6, 3e-6])
def test_curve_passes_through_the_flips_of_branches_at_other_unbalances(curves, U):
    w_curve = curves.speeds_at("period-doubling", U)
    w_floquet = floquet_flips(U)
    assert len(w_curve) == 2 and len(w_floquet) == 2
    # measured 1.4e-5 and 5.9e-6 at 4 g mm
    assert w_curve == pytest.approx(w_floquet, rel=1e-4)


def test_curve_turns_at_the_lowest_unbalance_of_the_pair(curves):
    (turn,) = curves.turns
    assert turn.kind == "period-doubling"
    assert 2e-6 < turn.value < 3e-6 and 1043 < turn.speed_rad_s < 1077
    assert floquet_flips(0.97 * turn.value) == []
    # 10 % above it the pair is 7.7 rad/s apart (at 3 % the branch's points, 8 rad/s
    # apart, step over the window: Floquet misses it, not the curve)
    above = floquet_flips(1.1 * turn.value)
    assert len(above) == 2 and above[0] < turn.speed_rad_s < above[1]
    w_curve = curves.speeds_at("period-doubling", 1.1 * turn.value)
    assert w_curve == pytest.approx(above, rel=1e-4)


def test_files(curves, tmp_path):
    import xarray as xr

    paths = curves.write(tmp_path)
    assert set(paths) == {"curves.csv", "curves.nc", "summary.json", "curves.png"}
    header, *rows = (tmp_path / "curves.csv").read_text().splitlines()
    assert header.split(",")[:2] == ["kind", "curve"]
    assert {r.split(",")[0] for r in rows} == {"period-doubling"}
    with xr.open_dataset(tmp_path / "curves.nc") as ds:
        assert ds.sizes["point"] == len(rows)
        assert np.all(np.isfinite(ds["speed_rad_s"].values))
        assert set(ds["kind"].values.tolist()) == {"period-doubling"}
    summary = json.loads((tmp_path / "summary.json").read_text())
    assert summary["period_doubling_harmonics_of_half_speed"] == 12
    assert [t["kind"] for t in summary["turning_points"]] == ["period-doubling"]
    (c2,) = summary["codim2_points"]
    assert c2["type"] == "1:2 resonance" and c2["curve"] == "period-doubling"
    assert "secondary Hopf meets period doubling" in c2["meaning"]


def test_command_says_when_the_start_branch_has_no_bifurcation(tmp_path, capsys):
    from rotorsfd.cli import main

    status = main(["bifurcation-curves", str(EXAMPLE), "--set",
                   "analysis.response.speed_range.stop=900 rad/s", "--set",
                   "analysis.response.speed_range.start=800 rad/s", "--parameter",
                   "unbalance[0].magnitude", "--from", "5 g*mm", "--to", "2 g*mm",
                   "-o", str(tmp_path / "x")])
    err = capsys.readouterr().err
    assert status == 2 and err.count("\n") == 1
    assert "no saddle-node, period doubling or secondary Hopf" in err


def test_command_bad_parameter_value_before_any_work(tmp_path, capsys):
    from rotorsfd.cli import main

    status = main(["bifurcation-curves", str(EXAMPLE), "--parameter",
                   "unbalance[0].magnitude", "--from", "5 rad/s", "--to", "2 g*mm",
                   "-o", str(tmp_path / "x")])
    assert status == 2 and "--from" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()


def test_fold_curves_of_the_pitching_rotor_through_the_folds_of_another_branch():
    """The paper rotor, U = 144.02 g mm, pitching 0 .. 6 rad/s (H = 3): only saddle-nodes
    (kind "saddle-node"), the pair meets at a cusp near 4.4 rad/s, and the curves at
    3 rad/s are the turning points located on the speed branch computed there (1e-4)."""
    from rotorsfd.continuation.folds import locate_branch_fold

    cfg = api.load_config(Path(__file__).parents[2] / "examples" / "paper" /
                          "fig19_unstable_range.toml", ["unbalance[0].magnitude=144.02 g*mm"])
    result = api.run_bifurcation_curves(cfg, "base.pitching.value", 0.0, "6 rad/s",
                                        harmonics=3)
    assert result.success and result.start_period_doublings == []
    assert set(result.table["kind"].tolist()) == {"saddle-node"}
    (cusp,) = result.turns
    assert cusp.kind == "saddle-node" and 4.0 < cusp.value < 4.8
    system = build_system(cfg).with_parameter("base.pitching", 3.0)
    r = cfg.analysis.response
    lo, hi = r.speed_range.bounds(result.reference_speed)
    b = continue_periodic(system.periodic_problem("speed"), lo, hi, 3,
                          n_samples=result.fold.n_samples)
    folds = sorted(locate_branch_fold(b, int(i)).lam for i in b.folds())
    assert len(folds) == 2
    assert result.speeds_at("saddle-node", 3.0) == pytest.approx(folds, rel=1e-4)


def test_one_two_resonance_located_on_the_period_doubling_curve(curves):
    """Above the PD curve's turn a second multiplier passes -1 on it (the pair at -1 of
    the secondary Hopf that the NS curve from 1 g mm brings): located on the curve
    (re-solved there: the speed at that U within 1e-7) with the multiplier at -1 to the
    monodromy's accuracy (the zero is where the two nearest -1 sum to -2; the curve's own
    Newmark multiplier at T/400 is -1.0005 there)."""
    (r2,) = [c for c in curves.codim2 if c.type == "1:2 resonance"]
    assert r2.curve == "period-doubling" and "mu_j + 1" in r2.test
    assert abs(complex(r2.multiplier_re, r2.multiplier_im) + 1.0) < 1e-3
    assert curves.turns[0].value < r2.value < 3e-6
    on_pd = curves.speeds_at("period-doubling", r2.value)
    assert min(abs(on_pd - r2.speed_rad_s)) < 1e-7 * r2.speed_rad_s
    assert "1:2 resonance" in curves.summary()


@pytest.mark.slow
def test_neimark_sacker_curve_ends_on_the_period_doubling_curve(curves, tmp_path):
    """From 1 g mm the whirl onset is a secondary Hopf; its Neimark-Sacker curve runs up in
    U until theta = sigma / w reaches 1/2 (the pair meets at -1): a 1:2 resonance, its
    end extrapolated to theta = 1/2 from points at fixed theta, which lies on the
    period-doubling curve traced from 5 g mm (its speed re-solved at the end's U: 1.3e-5,
    i.e. 1.1e-3 g mm in U where the PD curve runs at 1.2e4 rad/s per g mm) and agrees
    with the 1:2 point located on that curve by the other test function (a second
    multiplier at -1; measured 4.5e-4 in U, 1.5e-6 in speed: the Newmark multipliers at
    T/400 against HB's theta). 6.5 s CPU."""
    result = api.run_bifurcation_curves(config(), "unbalance[0].magnitude", "1 g*mm",
                                        "3 g*mm")
    assert result.success, result.message
    assert result.start_period_doublings == [] and len(result.start_secondary_hopfs) == 1
    assert set(result.table["kind"].tolist()) == {"Neimark-Sacker"}
    (r2,) = result.codim2
    assert r2.type == "1:2 resonance" and r2.curve == "Neimark-Sacker"
    assert r2.test_value == 0.0
    assert curves.turns[0].value < r2.value < 3e-6
    on_pd = curves.speeds_at("period-doubling", r2.value)
    assert min(abs(on_pd - r2.speed_rad_s)) < 5e-5 * r2.speed_rad_s
    (r2_pd,) = [c for c in curves.codim2 if c.type == "1:2 resonance"]
    assert r2.speed_rad_s == pytest.approx(r2_pd.speed_rad_s, rel=1e-5)
    assert r2.value == pytest.approx(r2_pd.value, rel=2e-3)
    assert "curves.png" in result.write(tmp_path)


def test_a_curve_stopped_at_the_film_limit_is_a_result(curves):
    """A curve whose corrector stopped with its last orbit within 2 % of the validity
    limit (analysis.response.max_eccentricity) is a result that ends there, the element
    named (as a response branch at the film's limit); one stopped farther from it stays
    a failure. The last point's eccentricity is recomputed here from the table."""
    leg = dataclasses.replace(curves.pd_curves[0], success=False,
                              message="corrector failed: state limit reached")
    rows = np.flatnonzero((curves.table["kind"] == "period-doubling")
                          & (curves.table["curve"] == 0))
    eps = float(curves.table["max_eps"][rows[-1]])
    system = build_system(config())
    near = at_limit(leg, curves.pd_hb, system, eps / 0.99)
    assert near.success and f"= {eps:.3f}" in near.message
    assert "max_eccentricity" in near.message and "state limit" in near.message
    far = at_limit(leg, curves.pd_hb, system, eps / 0.9)
    assert not far.success and far.message == leg.message
