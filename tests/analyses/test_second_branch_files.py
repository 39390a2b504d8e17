"""``response --switch-at pd:N`` and ``bp:N`` give one result type
(:class:`~rotorsfd.analyses.response_second_branch.SecondBranchResult`) written in one
layout: a ``leg`` column, then the columns of ``branch.csv`` (harmonic tags ``h<j>`` of
the speed, ``h<k>_2`` of Omega/2 and ``sub_<n>`` on the period-2 branch only), and
``branch.nc``'s layout with ``leg`` and the same switch attributes.

Cases: the period-2 branch at the first period doubling of the journal-bearing rotor
(examples/journal_bearing_rotor.toml, its half-speed whirl locking near 1043 rad/s), the
second branch at the first pitchfork of tests/data/issue21_branch_point.toml. Checks: the
CSV header and the netCDF variables against the layout spelled out here (not read from the
code), the same normalised layout for both switches, and every column and coefficient read
back from the files equal to the in-memory result (1e-12 relative; the CSV keeps floats at
full precision).
"""

from __future__ import annotations

import csv
import re
from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.response_branch_switch import run_branch_switch
from rotorsfd.analyses.response_second_branch import SecondBranchResult
from rotorsfd.analyses.response_switch import run_switch
from rotorsfd.model import dofs

ROOT = Path(__file__).parents[2]
JOURNAL = ROOT / "examples" / "journal_bearing_rotor.toml"
CASE = ROOT / "tests" / "data" / "issue21_branch_point.toml"

#: Attributes both switches write (the switch's own come on top: pd_* / branch_point_*).
COMMON_ATTRS = {"branch", "switch", "switched_at", "period", "bifurcation_parameter",
                "outcome", "elapsed_s", "run_title", "clearance_m"}


@pytest.fixture(scope="module")
def written(tmp_path_factory) -> dict[str, tuple[SecondBranchResult, Path]]:
    cfg = api.load_config(str(JOURNAL), ['analysis.response.speed_range={start="1000 '
                                         'rad/s", stop="1100 rad/s"}',
                                         "analysis.stability.enabled=true"])
    pd = api.run_second_branch(api.run_response(cfg, progress=False), "pd", 1, max_points=25)
    bp = api.run_second_branch(api.run_response(api.load_config(str(CASE)), progress=False),
                               "bp", 1)
    assert api.second_branch_switch("pd")[1] is run_switch
    assert api.second_branch_switch("bp")[1] is run_branch_switch
    out = {}
    for name, res in (("pd", pd), ("bp", bp)):
        d = tmp_path_factory.mktemp(name)
        res.write(d)
        out[name] = (res, d)
    return out


def read_csv(path: Path) -> tuple[list[str], dict[str, np.ndarray]]:
    with path.open() as f:
        rows = list(csv.reader(f))
    header, body = rows[0], rows[1:]
    return header, {k: np.array([float(r[j]) for r in body]) for j, k in enumerate(header)}


def expected_header(res: SecondBranchResult) -> list[str]:
    """The layout written out: leg, [parameter], speeds, per node and direction the static
    part and every harmonic's amplitude, per node r~ (and the subharmonic part at period
    2), the elements' diagnostics (the names of the main branch.csv's), stability."""
    m, p, H = res.main, res.period, res.branch.H
    cols = ["leg", *([] if m.is_speed else [m.parameter_column]), "speed_rad_s",
            "speed_ratio"]
    for n in m.nodes:
        for d in m.directions:
            cols.append(f"static_{n}_{d}")
            cols += [f"amp_{n}_{d}_h{k // p}" if k % p == 0 else f"amp_{n}_{d}_h{k}_{p}"
                     for k in range(1, H + 1)]
    for n in m.nodes:
        cols += [f"defl_{n}"] + ([f"sub_{n}"] if p > 1 else [])
    names = [e.name for e in m.system.elements]
    diagnostics = [c for c in m.table() if any(c.endswith(f"_{e}") for e in names)]
    assert len(diagnostics) >= len(names)            # branch.csv's, in its order
    return [*cols, *diagnostics, "stable", "max_multiplier"]


def normalised(names: list[str], elements: list[str]) -> list[str]:
    """Column / variable names with nodes, directions, harmonics and the elements'
    diagnostics (which depend on the element's kind) as placeholders, repeats dropped
    (the layout independent of the model)."""
    out: list[str] = []
    for name in names:
        for e in elements:
            name = re.sub(rf"^\w+_{re.escape(e)}$", "<diagnostic>_<e>", name)
        name = re.sub(r"_h\d+(_\d+)?$", "_h<k>", name)
        name = re.sub(r"_\d+_[yz](?=_|$)", "_<n>_<d>", name)
        name = re.sub(r"_\d+$", "_<n>", name)
        if name not in out:
            out.append(name)
    return out


def test_both_switches_write_one_layout(written):
    import xarray as xr

    layouts, variables = {}, {}
    for name, (res, d) in written.items():
        nc, csv_name = res.files
        assert (nc, csv_name) == {"pd": ("branch_period2.nc", "branch_period2.csv"),
                                  "bp": ("branch_bp1.nc", "branch_bp1.csv")}[name]
        header, _ = read_csv(d / csv_name)
        assert header == expected_header(res)
        elements = [e.name for e in res.main.system.elements]
        layouts[name] = normalised([h for h in header if not h.startswith("sub_")],
                                   elements)
        with xr.open_dataset(d / nc) as ds:
            assert COMMON_ATTRS <= set(ds.attrs)
            assert set(res.attrs) <= set(ds.attrs)
            assert ds.attrs["switched_at"] == f"{name}:1"
            assert ds.attrs["switch"] == {"pd": "period-doubling", "bp": "branch-point"}[name]
            assert ds.sizes["harmonic"] == res.branch.H + 1
            assert ("sub_1" in ds) == (name == "pd")
            variables[name] = sorted(normalised(
                [v for v in ds.data_vars if not v.startswith("sub_")], elements))
    assert layouts["pd"] == layouts["bp"]
    assert variables["pd"] == variables["bp"]


def test_files_read_back_equal_the_result(written):
    import xarray as xr

    from rotorsfd.io.branch_files import coefficients

    for res, d in written.values():
        nc, csv_name = res.files
        _, tab = read_csv(d / csv_name)
        mine = res.table()
        assert list(tab) == list(mine)
        for k, v in mine.items():
            v = np.asarray(v, dtype=float)
            assert np.allclose(tab[k], v, rtol=1e-12, atol=0.0), k
        b = res.branch
        with xr.open_dataset(d / nc) as ds:
            X = coefficients(ds)
            assert np.max(np.abs(X - b.X)) <= 1e-12 * np.max(np.abs(b.X))
            assert np.allclose(ds["parameter"].values, b.lam, rtol=1e-12, atol=0)
            assert np.allclose(ds["speed_rad_s"].values, res.speeds, rtol=1e-12, atol=0)
            assert np.array_equal(ds["leg"].values, res.leg)
            assert np.array_equal(ds["stable"].values.astype(bool), res.stable)
            assert np.allclose(ds["max_multiplier"].values, res.max_multiplier,
                               rtol=1e-12, atol=0)
            for n in res.main.nodes:
                assert np.allclose(ds[f"defl_{n}"].values, mine[f"defl_{n}"], rtol=1e-12,
                                   atol=0)
                if res.period > 1:
                    assert np.allclose(ds[f"sub_{n}"].values, mine[f"sub_{n}"],
                                       rtol=1e-12, atol=0)
            assert ds.attrs["bifurcation_parameter"] == res.bifurcation_parameter


def test_period_two_speeds_are_twice_the_fundamental(written):
    """Independent of the table: the rotor speed is twice the frequency of the period-2
    branch's harmonic 1, and its odd harmonics carry the subharmonic part."""
    res, _ = written["pd"]
    b = res.branch
    assert np.allclose(res.speeds, 2.0 * b.frequency, rtol=1e-15)
    tab = res.table()
    n = res.main.nodes[0]
    Xy, Xz = b.X[:, 1::2, dofs.dof_index(n, "y")], b.X[:, 1::2, dofs.dof_index(n, "z")]
    ref = np.sqrt((np.abs(Xy) ** 2).sum(1) + (np.abs(Xz) ** 2).sum(1)) / res.main.clearance
    assert np.allclose(tab[f"sub_{n}"], ref, rtol=1e-12)
    assert np.allclose(tab[f"amp_{n}_y_h1_2"], np.abs(b.X[:, 1, dofs.dof_index(n, "y")]),
                       rtol=1e-15)
    assert np.allclose(tab[f"amp_{n}_y_h1"], np.abs(b.X[:, 2, dofs.dof_index(n, "y")]),
                       rtol=1e-15)
