"""Task kinds: unstable intervals along a branch, the response summary from the documented
ResponseResult fields, and tiny real response / simulate sweeps on a small rotor."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from sweep_helpers import sweep_toml

from rotorsfd.io.config import load_config
from rotorsfd.studies import load_sweep, run_sweep, unstable_intervals
from rotorsfd.studies.tasks import intervals_text, response_output


def test_unstable_interval_boundaries_from_multipliers():
    x = [1.0, 2.0, 3.0, 4.0, 5.0]
    stable = [True, True, False, False, True]
    mm = [0.9, 0.95, 1.1, 1.2, 0.8]
    (lo, hi), = unstable_intervals(x, stable, mm)
    assert lo == pytest.approx(2 + 1 / 3, rel=1e-14) and hi == pytest.approx(4.5, rel=1e-14)
    assert unstable_intervals(x, [True] * 5, mm) == []
    assert unstable_intervals(x, [False] * 5) == [(1.0, 5.0)]


def test_unstable_interval_of_a_fold_pair_uses_located_folds():
    # an S-curve: up to 1.2, back to 1.05 (middle branch unstable), up again
    x = [1.0, 1.1, 1.2, 1.15, 1.05, 1.1, 1.3]
    stable = [True, True, True, False, False, True, True]
    assert unstable_intervals(x, stable, bifurcations_x=[1.21, 1.04]) == [(1.04, 1.21)]
    # without located folds: midpoints, still inside the bistable range
    (lo, hi), = unstable_intervals(x, stable)
    assert (lo, hi) == (1.05, pytest.approx(1.175, rel=1e-14))


def test_unstable_interval_uses_the_bifurcation_point_index():
    # points straddle both turning points symmetrically: no x tolerance would match them
    x = [1.0, 1.1, 1.195, 1.195, 1.1, 1.06, 1.06, 1.2]
    stable = [True, True, True, False, False, False, True, True]
    assert unstable_intervals(x, stable, bifurcations_x=[1.2, 1.055],
                              bifurcations_point=[3, 5]) == [(1.055, 1.2)]
    (lo, hi), = unstable_intervals(x, stable, bifurcations_x=[1.2, 1.055])
    assert (lo, hi) == (pytest.approx(1.06, rel=1e-14), pytest.approx(1.195, rel=1e-14))


def test_overlapping_intervals_merge():
    x = [1.0, 2.0, 3.0, 2.5, 1.5, 4.0, 5.0, 6.0]
    stable = [True, False, True, False, True, True, False, False]
    iv = unstable_intervals(x, stable)
    assert iv == [(1.5, 2.75), (4.5, 6.0)]   # [1.5, 2.5] and [2.0, 2.75] merged
    assert intervals_text(iv) == "1.5:2.75;4.5:6.0" and intervals_text([]) == "none"


def _fake_result(stability: bool = True) -> SimpleNamespace:
    ref = 800.0
    ratio = np.array([0.6, 0.8, 1.0, 1.1, 1.05, 1.2, 1.4])
    r = np.array([0.1, 0.3, 0.8, 0.9, 0.6, 0.5, 0.2])
    branch = SimpleNamespace(n_points=7, lam=ratio * ref, folds=lambda: np.array([2, 3]))
    bifs = [{"type": "saddle-node", "speed_ratio": 1.11, "parameter": 1.11 * ref},
            {"type": "saddle-node", "speed_ratio": 1.04, "parameter": 1.04 * ref},
            {"type": "secondary-hopf", "speed_ratio": 0.7, "parameter": 0.7 * ref}]
    return SimpleNamespace(
        branch=branch, is_speed=True, speeds=ratio * ref, reference_speed=ref,
        parameter="speed", nodes=(1, 3), deflection=lambda n: r * n,
        stable=np.array([True, False, True, False, False, True, True]) if stability
        else None,
        max_multiplier=np.array([0.9, 1.05, 0.95, 1.3, 1.2, 0.9, 0.8]) if stability
        else None,
        bifurcations=bifs if stability else None, success=True, message="done")


def test_response_summary_from_result_fields():
    out = response_output(_fake_result())
    s = out.scalars
    assert out.status == "ok" and out.message == ""
    assert (s["n_saddle_node"], s["n_period_doubling"], s["n_secondary_hopf"]) == (2, 0, 1)
    assert s["n_unstable_points"] == 3
    # point 1 (0.8) unstable between 0.6 and 1.0: the Hopf at 0.7 starts it, the |mu| = 1
    # estimate (0.9) ends it (no bifurcation left for it: one-to-one, nearest first);
    # points 3-4 between the folds 1.04 and 1.11
    got = [tuple(map(float, iv.split(":"))) for iv in s["unstable_intervals"].split(";")]
    np.testing.assert_allclose(got, [(0.7, 0.9), (1.04, 1.11)], rtol=1e-14)
    assert s["unstable_width_speed_ratio"] == pytest.approx(0.2 + 0.07, rel=1e-12)
    assert s["peak_defl_3"] == pytest.approx(2.7) and s["peak_speed_ratio_3"] == 1.1
    assert s["peak_stable_1"] is False
    assert out.arrays["bifurcation_type"].data.tolist() == ["saddle-node", "saddle-node",
                                                            "secondary-hopf"]
    assert out.arrays["branch_stable"].data.dtype == np.int8


def test_response_summary_counts_branch_points_by_type():
    res = _fake_result()
    res.bifurcations = [
        *res.bifurcations,
        {"type": "pitchfork", "speed_ratio": 1.3, "parameter": 1.3 * 800.0},
        {"type": "branch-point", "speed_ratio": 0.65, "parameter": 0.65 * 800.0}]
    s = response_output(res).scalars
    assert (s["n_pitchfork"], s["n_transcritical"], s["n_branch_point"]) == (1, 0, 1)
    assert s["n_saddle_node"] == 2      # a branch point is not counted as a fold


def test_counted_types_include_every_branch_point_kind():
    from rotorsfd.stability.branch_result import BRANCH_POINT_KINDS
    from rotorsfd.studies.tasks import BIFURCATION_TYPES

    assert BIFURCATION_TYPES[3:] == BRANCH_POINT_KINDS


def test_response_summary_without_stability_marks_missing():
    out = response_output(_fake_result(stability=False))
    assert out.scalars["n_saddle_node"] is None
    assert out.scalars["unstable_width_speed_ratio"] is None
    assert out.status == "ok" and "no stability" in out.message


AXES_2x2 = """
[[analysis.sweep.axes]]
parameter = "elements.sfd.clearance_ratio"
values = ["0.45 %", "0.5 %"]

[[analysis.sweep.axes]]
parameter = "unbalance[0].magnitude"
values = ["40 g*mm", "60 g*mm"]
"""


def test_real_fold_pair_gives_the_bistable_width(tmp_path):
    from rotorsfd.analyses.response import run_response

    config = load_config(sweep_toml(tmp_path / "rotor.toml", ""),
                         ["unbalance[0].magnitude=150 g*mm"])
    result = run_response(config, progress=False)
    folds = sorted(b["speed_ratio"] for b in result.bifurcations
                   if b["type"] == "saddle-node")
    assert len(folds) == 2
    s = response_output(result).scalars
    assert s["n_saddle_node"] == 2 and s["n_unstable_points"] > 0
    assert s["unstable_intervals"] == intervals_text([tuple(folds)])
    assert s["unstable_width_speed_ratio"] == folds[1] - folds[0]


def test_tiny_real_response_sweep(tmp_path):
    config = load_config(sweep_toml(tmp_path / "rotor.toml", AXES_2x2))
    result = run_sweep(config, directory=tmp_path / "out", workers=2, progress=False)
    assert result.complete, result.summary()
    run_sweep(config, directory=tmp_path / "serial", workers=1, progress=False)
    for name in ("sweep.nc", "summary.csv"):     # real floats: same bits on every executor
        assert (tmp_path / "out" / name).read_bytes() == \
            (tmp_path / "serial" / name).read_bytes()
    ds = load_sweep(tmp_path / "out")
    assert (ds["status"].values <= 1).all(), ds["message"].values
    peak = ds["peak_defl_3"].values
    assert np.all(np.isfinite(peak)) and np.all(peak > 0)
    assert np.all(peak[:, 1] > peak[:, 0])               # more unbalance, larger peak
    n = ds["n_branch_point"].values
    assert np.all(n == ds["branch_points"].values) and n.min() > 10
    assert ds["branch_points"].dtype == np.int32             # complete: no fill, no cast
    # stability from run_response: counts, widths, per-point flags and multipliers
    assert ds["n_saddle_node"].dtype == np.int32 and (ds["message"] == "").all()
    assert np.all(ds["unstable_width_speed_ratio"].values >= 0)
    stable = ds["branch_stable"].values[0, 0, :n[0, 0]]
    assert set(stable.tolist()) <= {0, 1}
    assert np.all(ds["branch_max_multiplier"].values[0, 0, :n[0, 0]] > 0)
    ratio = ds["branch_speed_ratio"].values
    assert ratio[0, 0, 0] == pytest.approx(0.6) and np.nanmax(ratio) == pytest.approx(1.4)


def test_tiny_simulate_sweep(tmp_path):
    config = load_config(sweep_toml(tmp_path / "rotor.toml"), [
        "analysis.simulate.speed_ratio=1.0", "analysis.simulate.periods=30",
        "analysis.simulate.poincare_periods=10", "analysis.simulate.steps_per_period=64"])
    result = run_sweep(config, {"unbalance[0].magnitude": ["40 g*mm", "60 g*mm"]},
                       "simulate", directory=tmp_path / "out", workers=1, progress=False)
    assert result.counts()["ok"] == 2, result.summary()
    ds = load_sweep(tmp_path / "out")
    assert ds.sizes["poincare"] == 10
    assert ds["max_defl_1"].values[1] > ds["max_defl_1"].values[0]
    assert set(ds["motion"].values.tolist()) <= {"periodic", "period-n", "quasi-periodic",
                                                 "chaotic", "unclassified"}


@pytest.mark.slow
def test_response_sweep_on_process_cluster_equals_serial(tmp_path):
    distributed = pytest.importorskip("distributed")
    from rotorsfd.studies import DaskExecutor

    config = load_config(sweep_toml(tmp_path / "rotor.toml", AXES_2x2))
    run_sweep(config, directory=tmp_path / "serial", workers=1, progress=False)
    with distributed.LocalCluster(n_workers=2, threads_per_worker=1, processes=True,
                                  host="127.0.0.1", dashboard_address=None) as cluster, \
            DaskExecutor(cluster.scheduler_address) as ex:
        run_sweep(config, directory=tmp_path / "dask", executor=ex, progress=False)
    for name in ("sweep.nc", "summary.csv", "sweep.json"):
        assert (tmp_path / "dask" / name).read_bytes() == \
            (tmp_path / "serial" / name).read_bytes()


def test_stability_chart_sweep_equals_direct_charts(tmp_path):
    from pathlib import Path

    from rotorsfd.analyses.stability_chart import run_stability_chart
    from rotorsfd.io.config import with_values

    example = Path(__file__).resolve().parents[2] / "examples" / "fig6_duchemin_pitching.toml"
    config = load_config(example, ["analysis.stability_chart.x.n=4",
                                   "analysis.stability_chart.y.n=3"])
    result = run_sweep(config, {"analysis.stability_chart.speed": [200.0, 250.0]},
                       "stability-chart", directory=tmp_path, workers=1, progress=False)
    assert result.counts()["ok"] == 2, result.summary()
    ds = load_sweep(tmp_path)
    assert ds["chart_max_multiplier"].shape == (2, 4, 3)
    direct = run_stability_chart(with_values(config, {"analysis.stability_chart.speed": 250.0}))
    np.testing.assert_array_equal(ds["chart_max_multiplier"].values[1], direct.chart.max_abs)
    assert ds["max_multiplier"].values[1] == direct.chart.max_abs.max()
    assert ds["unstable_points"].values[1] == int((~direct.chart.stable).sum())
    assert str(ds["chart_x"].values[0]) == "base.pitching.frequency"
