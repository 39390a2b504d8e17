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
