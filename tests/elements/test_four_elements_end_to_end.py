"""A rotor with four nonlinear elements of two kinds (issue 15 item 4): two SFDs, a rub at
the front SFD's node (a bumper inside the film clearance) and a seal rub at the disk; every
analysis runs end to end from the command line and names each element in its results."""

from __future__ import annotations

import csv
import json

import pytest

from rotors import SMALL_ROTOR
from rotorsfd.cli import main

pytestmark = pytest.mark.slow

ELEMENTS = """
[elements.rear]
kind = "sfd"
node = 5
viscosity = "0.0051 Pa*s"
clearance = "0.127 mm"
clearance_ratio = "0.5 %"
length_to_diameter = 0.325
centring_stiffness = "1e7 N/m"

[elements.bumper]
kind = "rub"
node = 1
clearance = "0.08 mm"
contact_stiffness = "2e7 N/m"
friction = 0.1

[elements.seal]
kind = "rub"
node = 3
clearance = "0.6 mm"
contact_stiffness = "5e6 N/m"
friction = 0.2
"""


@pytest.fixture(scope="module")
def config(tmp_path_factory):
    text = SMALL_ROTOR.format(unbalance="150 g*mm", base="", reference="800 rad/s")
    text = text.replace('[[rotor.supports]]\nnode = 5\nstiffness = "1e7 N/m"\n', "")
    path = tmp_path_factory.mktemp("four") / "four.toml"
    path.write_text(text.replace("[[unbalance]]", ELEMENTS + "\n[[unbalance]]"))
    return path


def _rows(path):
    with path.open() as fh:
        return list(csv.DictReader(fh))


def test_every_analysis_runs_and_names_the_elements(config, tmp_path):
    assert main(["config", "check", str(config)]) == 0
    out = tmp_path / "response"
    assert main(["response", str(config), "-o", str(out), "--quiet"]) == 0
    rows = _rows(out / "branch.csv")
    for key in ("eps_max_sfd", "eps_max_rear", "force_max_bumper", "penetration_max_seal",
                "contact_fraction_bumper", "stable"):
        assert key in rows[0], key
    assert max(float(r["force_max_bumper"]) for r in rows) > 0.0   # the bumper is hit

    sim = tmp_path / "simulate"
    assert main(["simulate", str(config), "-o", str(sim), "--speed-ratio", "1.0",
                 "--set", "analysis.simulate.periods=300",
                 "--set", "analysis.simulate.poincare_periods=20",
                 "--set", "analysis.simulate.steps_per_period=200",
                 "--lyapunov-periods", "0", "--quiet"]) == 0
    summary = json.loads((sim / "summary.json").read_text())
    assert {"eps_max_sfd", "eps_max_rear", "force_max_bumper"} <= set(summary["elements"])

    bd = tmp_path / "bd"
    assert main(["bifurcation-diagram", str(config), "-o", str(bd), "--quiet",
                 "--set", "analysis.bifurcation_diagram.speed_range="
                          "{start_ratio = 0.9, stop_ratio = 1.1, n = 2}",
                 "--set", "analysis.bifurcation_diagram.settle_periods=50",
                 "--set", "analysis.bifurcation_diagram.record_periods=10",
                 "--set", "analysis.simulate.steps_per_period=200"]) == 0

    st = tmp_path / "static"
    assert main(["static", str(config), "-o", str(st), "--quiet"]) == 0

    fc = tmp_path / "fold"       # the folds of the 300 g mm branch, traced in the unbalance
    assert main(["fold-curve", str(config), "-o", str(fc), "--quiet",
                 "--parameter", "unbalance[0].magnitude", "--from", "150 g*mm",
                 "--to", "300 g*mm", "--set", "unbalance[0].magnitude=300 g*mm"]) == 0
    assert float(_rows(fc / "fold_curve.csv")[0]["max_eps"]) > 0.5

    sw = tmp_path / "sweep"
    assert main(["sweep", str(config), "-o", str(sw), "--quiet", "--workers", "1",
                 "--axis", "elements.seal.clearance=0.5 mm,0.6 mm",
                 "--task", "response"]) == 0
    assert len(_rows(sw / "summary.csv")) == 2
