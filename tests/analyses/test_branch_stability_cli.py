"""``rotorsfd response`` on a small SFD rotor with a saddle-node pair writes the per-point
stability (branch.csv, branch.nc) and bifurcations.csv; ``enabled = false`` turns it off."""

from __future__ import annotations

import csv

import numpy as np

from rotors import small_rotor_toml
from rotorsfd.cli import main
from rotorsfd.io.branch_files import BIFURCATION_COLUMNS, read_branch


def test_response_writes_stability_and_bifurcations(tmp_path, capsys):
    config = small_rotor_toml(tmp_path / "small.toml", unbalance="100 g*mm")
    out = tmp_path / "out"
    assert main(["response", str(config), "-o", str(out), "--quiet"]) == 0
    with (out / "bifurcations.csv").open() as fh:
        rows = list(csv.DictReader(fh))
    assert tuple(rows[0]) == BIFURCATION_COLUMNS
    assert [r["type"] for r in rows] == ["saddle-node", "saddle-node"]
    with (out / "branch.csv").open() as fh:
        table = list(csv.DictReader(fh))
    stable = np.array([int(r["stable"]) for r in table])
    mm = np.array([float(r["max_multiplier"]) for r in table])
    x = np.array([float(r["speed_ratio"]) for r in table])
    assert np.array_equal(stable == 0, mm > 1 + 1e-5)
    hi, lo = (float(r["speed_ratio"]) for r in rows)
    assert lo < hi and np.all((x[stable == 0] >= lo) & (x[stable == 0] <= hi))
    for r in rows:
        assert float(r["nearest_multiplier_abs"]) > 1 and float(r["nearest_multiplier_re"]) > 1
        assert abs(float(r["located_multiplier_re"]) - 1) < 1e-3    # +1 at a fold
        assert r["status"] == "confirmed"
        assert float(r["speed_rad_s"]) == float(r["parameter"])
        assert abs(float(r["speed_ratio"]) * 800.0 - float(r["speed_rad_s"])) < 1e-9
    ds = read_branch(out / "branch.nc")
    count = ds["multiplier_count"].values
    mu = ds["multiplier_real"].values + 1j * ds["multiplier_imag"].values
    np.testing.assert_allclose(np.abs(mu[:, 0]), ds["max_multiplier"].values, rtol=1e-14)
    assert np.all(count >= 4) and np.all(count <= mu.shape[1])
    assert list(ds["bifurcation_type"].values) == ["saddle-node", "saddle-node"]


def test_stability_disabled(tmp_path):
    config = small_rotor_toml(tmp_path / "small.toml", unbalance="100 g*mm",
                              extra="\n[analysis.stability]\nenabled = false\n")
    out = tmp_path / "out"
    assert main(["response", str(config), "-o", str(out), "--quiet"]) == 0
    assert not (out / "bifurcations.csv").exists()
    with (out / "branch.csv").open() as fh:
        assert "stable" not in next(csv.reader(fh))
