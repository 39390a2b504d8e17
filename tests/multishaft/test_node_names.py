"""Shaft-wise node names in results (issue 20 item 1): a multi-shaft rotor's files carry
``shaft`` / ``shaft_node`` beside the global node numbers and its texts say ``hp node 3``;
the mapping is checked against the shafts' node ranges counted here from the TOML
itself (not through the schema); a single-shaft rotor's files and texts are unchanged."""

from __future__ import annotations

import csv
import tomllib
from pathlib import Path

import numpy as np
import pytest
import xarray as xr

from rotorsfd.model.node_names import NodeNames, node_words

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
DUAL = EXAMPLES / "dual_spool_unbalance.toml"
#: the torus branch through 150 ... 152 rad/s in 4 points, no Lyapunov exponents
SHORT = ("analysis.response.speed_range.start=150 rad/s",
         "analysis.response.speed_range.stop=152 rad/s",
         "analysis.response.step_initial=0.3", "analysis.response.step_max=0.5",
         "analysis.stability.enabled=false")


def expected_mapping() -> dict[int, tuple[str, int]]:
    """global node -> (shaft, local node), from dual_spool.toml's raw tables: each shaft
    has sum(n_elements) + 1 nodes, numbered on in the order of the shafts."""
    raw = tomllib.loads((EXAMPLES / "dual_spool.toml").read_text())
    out, g = {}, 0
    for shaft in raw["rotor"]["shafts"]:
        for local in range(1, sum(s["n_elements"] for s in shaft["sections"]) + 2):
            g += 1
            out[g] = (shaft["name"], local)
    return out


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open() as fh:
        return list(csv.DictReader(fh))


def test_names_match_the_shafts_node_ranges() -> None:
    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_system

    config = load_config(DUAL)
    want = expected_mapping()
    assert len(want) == 18 and want[13] == ("lp", 13) and want[14] == ("hp", 1)
    for source in (config.rotor, build_system(config).rotor):
        names = NodeNames.of(source)
        assert names is not None and names.names == ("lp", "hp")
        for g, (shaft, local) in want.items():
            assert names.locate(g) == (shaft, local)
            assert names.global_node(shaft, local) == g
        assert names.words(17) == "hp node 4" and names.label(17) == "hp:4"
    with pytest.raises(ValueError, match=r"1\.\.18"):
        names.locate(19)
    with pytest.raises(ValueError, match=r"nodes 1\.\.5"):
        names.global_node("hp", 6)


def test_dual_spool_torus_files_name_the_shafts(tmp_path: Path) -> None:
    """torus.nc gains shaft / shaft_node per DOF, nodes.csv the legend of torus.csv's
    columns, the summary and the plot's labels say ``hp node 1``."""
    from rotorsfd.api import run_response
    from rotorsfd.io.config import load_config

    result = run_response(load_config(DUAL, overrides=SHORT), progress=False)
    assert result.nodes == (1, 14, 17)
    paths = result.write(tmp_path, plots=False)
    want = expected_mapping()
    with xr.open_dataset(paths["torus.nc"]) as ds:
        node = ds["node"].values
        assert ds["shaft"].dims == ("dof",) and ds["shaft_node"].dims == ("dof",)
        assert list(ds["shaft"].values) == [want[int(n)][0] for n in node]
        np.testing.assert_array_equal(ds["shaft_node"].values,
                                      [want[int(n)][1] for n in node])
        assert "at hp node 4 /" in ds["defl_17"].attrs["long_name"]
    legend = _rows(paths["nodes.csv"])
    assert [(int(r["node"]), r["shaft"], int(r["shaft_node"]), r["label"])
            for r in legend] == [(1, "lp", 1, "lp:1"), (14, "hp", 1, "hp:1"),
                                 (17, "hp", 4, "hp:4")]
    header = next(csv.reader(paths["torus.csv"].open()))
    assert "defl_14" in header          # the columns keep the global numbers
    text = result.summary()
    assert "lp node 1: max r~" in text and "hp node 4: max r~" in text
    assert "node 14" not in text


def test_dual_spool_simulation_names_the_shafts(tmp_path: Path) -> None:
    """timeseries.nc: shaft / shaft_node along node, dof_shaft / dof_shaft_node along
    dof; poincare.csv: shaft, shaft_node columns."""
    from rotorsfd.analyses.simulate import run_simulation
    from rotorsfd.io.config import load_config

    result = run_simulation(load_config(DUAL), 160.0, periods=6, poincare_periods=4,
                            record_periods=2, lyapunov_periods=0, nodes=(2, 15),
                            steps_per_period=64, progress=False)
    paths = result.write(tmp_path, plots=False)
    want = expected_mapping()
    with xr.open_dataset(paths["timeseries.nc"]) as ds:
        assert list(ds["node"].values) == [2, 15]
        assert list(ds["shaft"].values) == ["lp", "hp"]
        assert list(ds["shaft_node"].values) == [2, 2]
        dof = ds["dof"].values
        assert list(ds["dof_shaft"].values) == [want[int(d) // 4 + 1][0] for d in dof]
        np.testing.assert_array_equal(ds["dof_shaft_node"].values,
                                      [want[int(d) // 4 + 1][1] for d in dof])
    rows = _rows(paths["poincare.csv"])
    assert rows and all((r["shaft"], int(r["shaft_node"])) == want[int(r["node"])]
                        for r in rows)
    assert result.plot()["simulation.png"] is not None


def test_single_shaft_files_unchanged(tmp_path: Path) -> None:
    """No shaft coordinates, no nodes.csv, ``node 8`` in texts: as before."""
    from rotorsfd.analyses.response_result import ResponseResult
    from rotorsfd.api import run_response
    from rotorsfd.io.config import load_config

    config = load_config(EXAMPLES / "paper_rotor.toml", overrides=(
        "analysis.response.speed_range.start_ratio=0.5",
        "analysis.response.speed_range.stop_ratio=0.52",
        "analysis.response.harmonics=3", "analysis.stability.enabled=false"))
    result = run_response(config, progress=False)
    assert isinstance(result, ResponseResult) and result.node_names is None
    paths = result.write(tmp_path, plots=False)
    assert "nodes.csv" not in paths and not (tmp_path / "nodes.csv").exists()
    with xr.open_dataset(paths["branch.nc"]) as ds:
        assert not {"shaft", "shaft_node", "dof_shaft"} & set(ds.variables)
    assert node_words(None, 8) == "node 8"
    assert all(f"node {n}: max r~" in result.summary() for n in result.nodes)


def test_output_nodes_by_shaft_name(tmp_path: Path) -> None:
    """``nodes = ["hp:4", 2]`` is global node 17 and 2; a wrong shaft or node exits 2 with
    one line naming the field."""
    from rotorsfd import cli
    from rotorsfd.errors import ConfigError
    from rotorsfd.io.config import load_config

    config = load_config(DUAL, overrides=('analysis.response.nodes=["hp:4", 2, "lp:13"]',
                                          'analysis.simulate.nodes=["hp:1"]'))
    assert config.analysis.response.nodes == [17, 2, 13]
    assert config.analysis.simulate.nodes == [14]
    for bad, words in (('["ip:2"]', "no shaft 'ip'"), ('["hp:6"]', "nodes 1..5"),
                       ('["hp"]', "<shaft>:<node of that shaft>")):
        with pytest.raises(ConfigError, match=r"analysis\.response\.nodes") as info:
            load_config(DUAL, overrides=(f"analysis.response.nodes={bad}",))
        assert words in str(info.value)
    with pytest.raises(ConfigError, match="a node number"):
        load_config(EXAMPLES / "paper_rotor.toml",
                    overrides=('analysis.response.nodes=["hp:1"]',))
    assert cli.main(["response", str(DUAL), "-o", str(tmp_path), "-q", "--set",
                     'analysis.response.nodes=["ip:2"]']) == 2


def test_dual_spool_periodic_branch_names_the_shafts(tmp_path: Path) -> None:
    """One spool's unbalance (dual_spool.toml): the periodic branch.nc gains shaft /
    shaft_node per DOF; the output node given as "hp:4"."""
    from rotorsfd.api import run_response
    from rotorsfd.io.config import load_config

    config = load_config(EXAMPLES / "dual_spool.toml", overrides=(
        "analysis.response.speed_range.start=150 rad/s",
        "analysis.response.speed_range.stop=151 rad/s", "analysis.response.harmonics=1",
        'analysis.response.nodes=["hp:4", 2]', "analysis.stability.enabled=false"))
    result = run_response(config, progress=False)
    assert result.nodes == (17, 2)
    paths = result.write(tmp_path, plots=False)
    want = expected_mapping()
    with xr.open_dataset(paths["branch.nc"]) as ds:
        assert list(ds["shaft"].values) == [want[int(n)][0] for n in ds["node"].values]
        np.testing.assert_array_equal(ds["shaft_node"].values,
                                      [want[int(n)][1] for n in ds["node"].values])
        assert "at hp node 4 /" in ds["defl_17"].attrs["long_name"]
    assert [r["label"] for r in _rows(paths["nodes.csv"])] == ["hp:4", "lp:2"]
    assert result.summary().splitlines()[1].startswith("hp node 4: max r~")
