"""run_response on a small rotor: branch.csv has the documented columns, its values agree
with branch.nc, r~ respects its amplitude bounds, optional stability is written."""

from __future__ import annotations

import csv
import math

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.response import max_radius
from rotorsfd.io.branch_files import (
    LEGACY_BIFURCATION_COLUMNS,
    coefficients,
    read_branch,
)
from rotorsfd.model.dofs import dof_index

C = 0.127e-3


@pytest.fixture(scope="module")
def written(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("response")
    config = api.load_config(small_rotor_toml(tmp / "small.toml"))
    result = api.run_response(config, progress=False)
    paths = result.write(tmp / "out")
    with (tmp / "out" / "branch.csv").open() as fh:
        rows = list(csv.reader(fh))
    table = {name: np.array([float(r[i]) for r in rows[1:]])
             for i, name in enumerate(rows[0])}
    return result, paths, rows[0], table, read_branch(tmp / "out" / "branch.nc")


def test_columns_documented_order(written):
    result, paths, header, _, _ = written
    expected = ["speed_rad_s", "speed_ratio"]
    for n in (1, 3):
        for d in ("y", "z"):
            expected += [f"static_{n}_{d}"] + [f"amp_{n}_{d}_h{k}" for k in (1, 2, 3)]
    expected += ["defl_1", "defl_3", "eps_max_sfd", "harmonics", "truncation_error",
                 "stable", "max_multiplier", "floquet_intervals",
                 "multiplier_error", "floquet_modes", "max_multiplier_outside"]
    # stability (step-controlled) on by default
    assert header == expected
    assert sorted(paths) == ["bifurcations.csv", "branch.csv", "branch.nc",
                             "multipliers.png", "response_deflection.png",
                             "response_node1.png", "response_node3.png"]
    assert not [p for p in paths["branch.csv"].parent.iterdir() if p.name.startswith(".")]
    assert result.success and result.branch.n_points > 20


def test_element_eccentricity_is_the_deflection_at_its_node(written):
    """The SFD at node 1 (housing centred): its eps_max from 1024 samples of the orbit
    equals defl_1, the Newton-refined maximum radius over C, to the grid's error."""
    _, _, _, table, _ = written
    np.testing.assert_allclose(table["eps_max_sfd"], table["defl_1"], rtol=2e-5)
    assert np.all(table["eps_max_sfd"] <= table["defl_1"] * (1 + 1e-12))
    var = written[4]["eps_max_sfd"]                    # in branch.nc too, described
    np.testing.assert_allclose(var.values, table["eps_max_sfd"], rtol=1e-12)
    assert var.attrs["units"] == "1" and "SFD 'sfd' at node 1" in var.attrs["long_name"]


def test_csv_matches_netcdf(written):
    result, _, _, table, ds = written
    X = coefficients(ds)
    assert X.shape == (result.branch.n_points, 4, result.system.n_dof)
    np.testing.assert_array_equal(X, result.branch.X)
    assert np.all(ds["X_imag"].values[:, 0, :] == 0.0)
    np.testing.assert_array_equal(table["speed_rad_s"], ds["speed_rad_s"].values)
    np.testing.assert_allclose(table["speed_ratio"], table["speed_rad_s"] / 800.0, rtol=1e-15)
    for n in (1, 3):
        for d in ("y", "z"):
            j = dof_index(n, d)
            assert ds["node"].values[j] == n and ds["direction"].values[j] == d
            np.testing.assert_array_equal(table[f"static_{n}_{d}"], X[:, 0, j].real)
            for k in (1, 2, 3):
                np.testing.assert_array_equal(table[f"amp_{n}_{d}_h{k}"], np.abs(X[:, k, j]))
    assert ds.attrs["H"] == 3 and ds.attrs["success"] == 1
    assert ds.attrs["reference_speed_rad_s"] == 800.0
    assert math.isclose(ds.attrs["clearance_m"], C)
    for name, col in table.items():
        assert np.all(np.isfinite(col)), name


def test_deflection_bounds(written):
    """mean r^2 (Parseval) <= max r^2 <= (sum_k |X_k|)^2 per direction; and r~ is the
    maximum of the sampled time series (a fine sample comes within 1e-6)."""
    result, _, _, table, _ = written
    X = result.branch.X
    for n in (1, 3):
        Xy, Xz = X[:, :, dof_index(n, "y")], X[:, :, dof_index(n, "z")]
        mean_r2 = Xy[:, 0].real ** 2 + Xz[:, 0].real ** 2 + 0.5 * np.sum(
            np.abs(Xy[:, 1:]) ** 2 + np.abs(Xz[:, 1:]) ** 2, axis=1)
        upper = np.hypot(np.abs(Xy).sum(1), np.abs(Xz).sum(1))
        r = table[f"defl_{n}"] * C
        assert np.all(r >= np.sqrt(mean_r2) * (1 - 1e-12))
        assert np.all(r >= np.hypot(Xy[:, 0].real, Xz[:, 0].real))
        # at the time where the first harmonic's part of y peaks, y >= |Xy_1| - the rest
        rest = np.abs(Xy).sum(1) - np.abs(Xy[:, 1])
        assert np.all(r >= (np.abs(Xy[:, 1]) - rest) * (1 - 1e-12))
        assert np.all(r <= upper * (1 + 1e-12))
        for i in range(0, result.branch.n_points, 7):
            _, q = result.branch.time_series(i, n_t=4096)
            sampled = np.hypot(q[:, dof_index(n, "y")], q[:, dof_index(n, "z")]).max()
            assert sampled <= r[i] * (1 + 1e-12)
            assert sampled >= r[i] * (1 - 1e-6)


def test_max_radius_closed_forms():
    a, b, s = 2.0, 0.5, 0.7
    # circle y = a cos, z = a sin; ellipse; offset ellipse y = s + a cos t
    Xy = np.array([[0, a, 0], [0, a, 0], [s, a, 0]], dtype=complex)
    Xz = np.array([[0, -1j * a, 0], [0, -1j * b, 0], [0, -1j * b, 0]])
    np.testing.assert_allclose(max_radius(Xy, Xz), [a, a, s + a], rtol=1e-14)
    # y = cos t + cos 2t: max 2 at t = 0 (phase shifted so it is not on the grid)
    ph = np.exp(1j * 0.123)
    np.testing.assert_allclose(max_radius(np.array([0, ph, ph**2]), np.zeros(3)), 2.0,
                               rtol=1e-14)


def test_stability_columns_and_bifurcations(written, tmp_path):
    result, _, _, _, _ = written
    n = result.branch.n_points
    stable = np.arange(n) % 5 != 0
    mu = np.tile([0.5 + 0.1j, 0.5 - 0.1j, 1.01], (n, 1))
    rows = [{"type": "saddle-node", "speed_rad_s": 900.0, "speed_ratio": 900 / 800,
             "parameter": 900.0, "max_multiplier": 1.0, "multiplier_re": 1.0,
             "multiplier_im": 0.0}]
    with_st = result.with_stability(stable, np.abs(mu).max(1), mu, rows)
    paths = with_st.write(tmp_path)
    with paths["branch.csv"].open() as fh:
        data = list(csv.DictReader(fh))
    assert [int(r["stable"]) for r in data] == stable.astype(int).tolist()
    assert float(data[0]["max_multiplier"]) == pytest.approx(1.01)
    with paths["bifurcations.csv"].open() as fh:
        bif = list(csv.reader(fh))
    # rows given without the located multiplier and the check keep the legacy columns
    assert tuple(bif[0]) == LEGACY_BIFURCATION_COLUMNS and bif[1][0] == "saddle-node"
    ds = read_branch(paths["branch.nc"])
    assert ds["stable"].values.tolist() == stable.astype(int).tolist()
    np.testing.assert_array_equal(ds["multiplier_real"].values + 1j
                                  * ds["multiplier_imag"].values, mu)
    assert ds["bifurcation_type"].values.tolist() == ["saddle-node"]
    with pytest.raises(ValueError, match="entries"):
        result.with_stability(stable[:-1], np.ones(n - 1))


def test_stability_hook_fills_arrays(tmp_path):
    """A stability hook's per-point results end up in the result (one per point)."""
    from rotorsfd.analyses.response import PointStability

    config = api.load_config(small_rotor_toml(tmp_path / "s.toml"),
                             ["analysis.response.speed_range.stop_ratio=0.8"])
    seen = []

    def hook(point):
        seen.append(point.index)
        return PointStability(point.lam < 600.0, 0.9, np.array([0.9, 0.1j]))

    result = api.run_response(config, progress=False, stability=hook)
    assert seen == list(range(result.branch.n_points))
    assert result.stable.tolist() == (result.branch.lam < 600.0).tolist()
    assert result.multipliers.shape == (result.branch.n_points, 2)
    assert "stable" in result.table() and "max_multiplier" in result.table()


def test_floquet_basis_recorded(written):
    """Which basis max_multiplier covers (issue 22 item 4): the attribute, the modes kept
    and the left-out modes' multiplier, a stable structural mode (0 < |mu| <= 1 + 1e-9)."""
    _, _, _, table, ds = written
    assert ds.attrs["floquet_basis"].startswith("craig-bampton")
    assert np.all(table["floquet_modes"] >= 0)
    out = table["max_multiplier_outside"]
    assert np.all(np.isfinite(out)) and np.all(out <= 1 + 1e-9)
    np.testing.assert_array_equal(ds["max_multiplier_outside"].values, out)
