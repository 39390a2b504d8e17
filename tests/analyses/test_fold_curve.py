"""Fold curve of the paper rotor (U = 144.02 g mm, C/R = 0.485 %, H = 3) in (speed, base
pitching) and (speed, unbalance): against one-parameter speed branches; files and CLI."""

import csv
import json
from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.fold_curve import run_fold_curve
from rotorsfd.cli import main
from rotorsfd.continuation.folds import locate_branch_fold
from rotorsfd.harmonic import continue_periodic

ROOT = Path(__file__).resolve().parents[2]
CONFIG = ROOT / "examples" / "paper_rotor.toml"
U144 = "unbalance[0].magnitude=144.02 g*mm"
REF = 811.3


@pytest.fixture(scope="module")
def config():
    return api.load_config(CONFIG, [U144])


@pytest.fixture(scope="module")
def pitching(config):
    return run_fold_curve(config, "base.pitching.value", 0.0, "10 rad/s")


def one_parameter_folds(problem, n_samples: int) -> list[float]:
    """Located turning points of the speed branch over Omega~ 0.5 .. 1.6 [rad/s]."""
    b = continue_periodic(problem, 0.5 * REF, 1.6 * REF, 3, n_samples=n_samples)
    return sorted(locate_branch_fold(b, int(i)).lam for i in b.folds())


def test_start_folds_are_the_known_saddle_nodes(pitching):
    assert pitching.success, pitching.message
    np.testing.assert_allclose(sorted(np.array(pitching.start_folds) / REF),
                               [1.0527, 1.0593], atol=1e-4)


@pytest.mark.parametrize("w_by", [1.5, 3.0, 4.2])
def test_fold_curve_passes_through_one_parameter_folds(pitching, w_by):
    on_curve = pitching.speeds_at(w_by)
    expected = one_parameter_folds(pitching.hb.problem.first(w_by), pitching.n_samples)
    assert len(on_curve) == len(expected) == 2
    np.testing.assert_allclose(on_curve, expected, rtol=1e-4)


def test_cusp_ends_the_bistable_range(pitching):
    """One curve from the upper fold at w_by = 0 through the cusp back to the lower one;
    the bistability vanishes at the cusp (paper: below 4 rad/s; this model: ~4.4)."""
    assert len(pitching.curves) == 1 and len(pitching.cusps) == 1
    end = pitching.bistability_end
    assert end == pytest.approx(pitching.cusps[0].value)
    assert 4.0 < end < 5.0
    width = pitching.unstable_width([0.0, 0.5 * end, 1.01 * end, 10.0])
    assert width[0] == pytest.approx(1.0593 - 1.0527, abs=2e-4)
    assert 0 < width[1] < width[0]
    assert width[2] == width[3] == 0.0
    assert pitching.speeds_at(1.01 * end).size == 0


def test_fold_curve_in_the_unbalance(config):
    """Decreasing U from 144.02 g mm: the folds meet at a cusp; the curve passes through
    the folds of the speed branch at U = 120 g mm."""
    curve = run_fold_curve(config, "unbalance[0].magnitude", "144.02 g*mm", "60 g*mm")
    assert curve.success and len(curve.cusps) == 1, curve.message
    assert 60e-6 < curve.bistability_end < 144.02e-6
    U = 120e-6
    expected = one_parameter_folds(curve.hb.problem.first(U), curve.n_samples)
    np.testing.assert_allclose(curve.speeds_at(U), expected, rtol=1e-4)


def test_files(pitching, tmp_path):
    assert pitching.title and pitching.title.startswith("Paper")  # the config's, drawn
    paths = pitching.write(tmp_path)
    assert sorted(p.name for p in paths.values()) == sorted(pitching.FILES)
    with open(paths["fold_curve.csv"]) as f:
        rows = list(csv.DictReader(f))
    assert len(rows) == len(pitching.table["speed_rad_s"])
    assert {"curve", "segment", "base_pitching_rad_s", "speed_rad_s", "speed_ratio",
            "max_eps", "aliasing", "amp_8_m"} <= set(rows[0])
    info = json.loads(paths["fold_curve.json"].read_text())
    assert info["bistability_end"] == pytest.approx(pitching.bistability_end)
    assert len(info["cusps"]) == 1


def test_cli(tmp_path, capsys):
    out = tmp_path / "fc"
    status = main(["fold-curve", str(CONFIG), "--set", U144, "--from", "0 rad/s",
                   "--to", "6 rad/s", "-o", str(out)])
    assert status == 0
    assert "bistability vanishes at base.pitching" in capsys.readouterr().out
    assert (out / "fold_curve.csv").exists() and (out / "fold_curve.png").exists()


def test_cli_no_fold_at_the_start(tmp_path, capsys):
    status = main(["fold-curve", str(CONFIG), "--set", U144, "--from", "6 rad/s",
                   "--to", "10 rad/s", "-o", str(tmp_path / "x")])
    assert status == 2
    assert "no saddle-node" in capsys.readouterr().err


def test_no_cusp_in_the_range_gives_two_curves(config):
    """Up to 3 rad/s the pair persists: one curve per fold, both reach the end."""
    curve = run_fold_curve(config, "base.pitching.value", 0.0, 3.0)
    assert curve.success and len(curve.curves) == 2 and not curve.cusps
    assert curve.bistability_end is None
    for c in curve.curves:
        assert curve.hb.from_z(c.z[-1])[2] == pytest.approx(3.0)
    assert curve.unstable_width([3.0])[0] > 0
    assert "no cusp in the range" in curve.summary()


def test_n_samples_by_the_adaptive_rule_criterion():
    """The fold curve chooses N_f by the criterion of continue_periodic's adaptive rule
    (the sampling error in the units of the Newton test, <= the fold tolerance 1e-8 at
    every point). Paper rotor, Figure 19 config, U = 144.02 g mm, H = 3, w_by 0 .. 6: the
    old relative rule kept N_f = 32 (error up to 1.6e-7, cusp at 4.4097388 rad/s); the
    new one takes 64 and its cusp agrees with N_f = 1024 to 1e-10 relative (measured 8e-11;
    4.40972573 rad/s at Omega~ = 1.06006038)."""
    from rotorsfd.analyses.fold_curve import fold_curve
    from rotorsfd.continuation.folds import FoldOptions
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem

    cfg = api.load_config(ROOT / "examples" / "paper" / "fig19_unstable_range.toml", [U144])
    m = build_model(cfg)
    system = RotorSystem(m.rotor, m.elements, m.unbalances, m.base_motion)
    ref = api.reference_speed(cfg, system)
    speeds = cfg.analysis.response.speed_range.bounds(ref)
    runs = {N: fold_curve(system, speeds, "base.pitching", (0.0, 6.0), 3,
                          reference_speed=ref, n_samples=N) for N in (None, 1024)}
    ada, fine = runs[None], runs[1024]
    assert ada.success and len(ada.cusps) == len(fine.cusps) == 1, ada.message
    assert ada.n_samples == 64
    assert np.max(ada.table["aliasing"]) <= FoldOptions().tol
    assert ada.cusps[0].value == pytest.approx(fine.cusps[0].value, rel=1e-9)
    assert ada.cusps[0].value == pytest.approx(4.40972573, abs=1e-7)
    assert ada.cusps[0].speed_ratio == pytest.approx(fine.cusps[0].speed_ratio, rel=1e-10)
    np.testing.assert_allclose(ada.speeds_at(3.0), fine.speeds_at(3.0), rtol=1e-9)
