"""Brute-force bifurcation diagram of a small rotor with an HB fold pair: the up and down
sweeps differ inside the fold interval of the HB branch and agree outside it; the files
and the CLI."""

from __future__ import annotations

import csv

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.bifurcation_diagram import run_bifurcation_diagram, sweep_speeds
from rotorsfd.cli import main

C = 0.127e-3
REF = 800.0
DIAGRAM = ["analysis.bifurcation_diagram.speed_range.start_ratio=1.0",
           "analysis.bifurcation_diagram.speed_range.stop_ratio=1.3",
           "analysis.bifurcation_diagram.speed_range.n=13",
           "analysis.bifurcation_diagram.settle_periods=300",
           "analysis.bifurcation_diagram.record_periods=20"]


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    """U = 200 g mm: the HB branch (H = 3) folds at Omega~ ~1.121 and ~1.190."""
    tmp = tmp_path_factory.mktemp("bifurcation")
    path = small_rotor_toml(tmp / "small.toml", unbalance="200 g*mm",
                            reference=f"{REF} rad/s")
    config = api.load_config(path, DIAGRAM)
    response = api.run_response(config, progress=False)
    folds = response.speeds[np.asarray(response.branch.folds(), dtype=int)] / REF
    diagram = run_bifurcation_diagram(config, progress=False)
    return path, folds, diagram, tmp


def test_hysteresis_inside_the_fold_interval_only(case) -> None:
    """Per speed, the journal's Poincare radius of the two sweeps: different (> 0.1 C)
    at some speed inside the fold interval [lo, hi] of the HB branch, equal (< 1e-3 C)
    at every speed outside [lo - 0.01, hi + 0.01]."""
    _, folds, diagram, _ = case
    assert folds.size == 2
    lo, hi = float(folds.min()), float(folds.max())
    assert 1.10 < lo < hi < 1.21
    assert diagram.success and not diagram.contacts
    radius: dict[tuple[str, float], float] = {}
    for p in diagram.points:
        assert p.motion == "period-1" and p.poincare_t.size == 20
        j = diagram.nodes.index(1)
        r = np.hypot(p.poincare_q[:, j, 0], p.poincare_q[:, j, 1])
        assert np.ptp(r) < 1e-3 * C                    # settled
        radius[(p.direction, round(p.speed / REF, 6))] = float(r.mean())
    ratios = sorted({x for _, x in radius})
    diff = {x: abs(radius[("up", x)] - radius[("down", x)]) for x in ratios}
    inside = [x for x in ratios if lo <= x <= hi]
    outside = [x for x in ratios if x < lo - 0.01 or x > hi + 0.01]
    assert inside and len(outside) >= 8
    assert max(diff[x] for x in inside) > 0.1 * C
    assert max(diff[x] for x in outside) < 1e-3 * C
    # up sweep on the upper (large) branch, down sweep on the lower one
    x = max(inside, key=lambda k: diff[k])
    assert radius[("up", x)] > radius[("down", x)]


def test_files(case) -> None:
    _, _, diagram, tmp = case
    paths = diagram.write(tmp / "out")
    assert {p.name for p in paths.values()} >= {"diagram.csv", "speeds.csv", "diagram.png"}
    with (tmp / "out" / "diagram.csv").open() as fh:
        rows = list(csv.reader(fh))
    assert rows[0] == ["direction", "speed_rad_s", "speed_ratio", "node", "period", "y", "z",
                       "vy", "vz"]
    assert len(rows) - 1 == 26 * 20 * len(diagram.nodes)
    assert {r[0] for r in rows[1:]} == {"up", "down"}
    with (tmp / "out" / "speeds.csv").open() as fh:
        speeds = list(csv.DictReader(fh))
    assert len(speeds) == 26 and speeds[0]["direction"] == "up"
    assert float(speeds[13]["speed_ratio"]) == pytest.approx(1.3)
    # the default step control ("auto"): every speed recorded at a step whose last
    # halving moved the journal orbit by less than step_tolerance = 1e-3 C
    assert diagram.settings["steps_per_period"] == "auto"
    for row in speeds:
        assert int(row["steps_per_period"]) in (400, 800, 1600, 3200)
        assert 0.0 <= float(row["step_error"]) < 1e-3
        assert row["step_converged"] in ("1", "True")
    assert "time step (auto): T/" in diagram.summary()


def _cli_sets(n: int) -> list[str]:
    """--set arguments: the DIAGRAM settings, n speeds, a short up sweep."""
    sets = [*DIAGRAM, f"analysis.bifurcation_diagram.speed_range.n={n}",
            "analysis.bifurcation_diagram.settle_periods=20",
            "analysis.bifurcation_diagram.direction=up"]
    return [a for s in sets for a in ("--set", s)]


def test_cli(case, tmp_path) -> None:
    path = case[0]
    status = main(["bifurcation-diagram", str(path), "-o", str(tmp_path), "-q",
                   *_cli_sets(3)])
    assert status == 0
    with (tmp_path / "speeds.csv").open() as fh:
        assert [r["direction"] for r in csv.DictReader(fh)] == ["up"] * 3
    assert (tmp_path / "diagram.png").stat().st_size > 0


def test_sweep_order() -> None:
    runs = sweep_speeds(3.0, 1.0, 3, "up-down")
    assert runs == [("up", 1.0), ("up", 2.0), ("up", 3.0), ("down", 3.0), ("down", 2.0),
                    ("down", 1.0)]
    assert sweep_speeds(1.0, 3.0, 2, "down") == [("down", 3.0), ("down", 1.0)]


def test_cli_start_choice(case, tmp_path) -> None:
    path = case[0]
    sets = _cli_sets(2)
    starts = {}
    for start in ("hb", "displaced"):
        out = tmp_path / start
        status = main(["bifurcation-diagram", str(path), "-o", str(out), "-q",
                       "--start", start, *sets])
        assert status == 0
        with (out / "speeds.csv").open() as fh:
            starts[start] = [r["start"] for r in csv.DictReader(fh)]
    assert starts == {"hb": ["hb", "previous"], "displaced": ["displaced", "previous"]}
