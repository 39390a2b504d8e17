"""Provenance (issue 23 item 3): run.json in every results folder (the resolved config,
versions, git revision, dependencies, command line), the same in the netCDF attributes, and
CF-style ``units`` and ``long_name`` on every netCDF variable."""

from __future__ import annotations

import argparse
import dataclasses
import json
import re
import tomllib
from importlib import metadata
from pathlib import Path

import pytest
import xarray as xr

from rotors import chart_rotor_raw, small_rotor_toml
from rotorsfd import __version__, api, cli
from rotorsfd.cli import app
from rotorsfd.io import provenance
from rotorsfd.io.config import config_from_dict

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"


def test_dependency_versions_are_the_installed_ones():
    versions = provenance.dependency_versions()
    assert set(versions) == {"numpy", "scipy", "numba", "xarray", "pydantic", "pint",
                             "matplotlib"}
    for name, version in versions.items():
        assert version == metadata.version(name)


def test_git_revision_of_this_checkout_or_none():
    provenance.git_revision.cache_clear()
    rev, dirty = provenance.git_revision()
    top = provenance.package_dir().parents[1]
    if (top / ".git").exists() and (top / "pyproject.toml").is_file():
        assert re.fullmatch(r"[0-9a-f]{40}", rev) and isinstance(dirty, bool)
    else:
        assert rev is None and dirty is None


def test_no_checkout_or_no_git_gives_none_without_failing(tmp_path, monkeypatch):
    monkeypatch.setattr(provenance, "package_dir", lambda: tmp_path)   # not a checkout
    provenance.git_revision.cache_clear()
    assert provenance.git_revision() == (None, None)
    assert provenance.netcdf_attrs()["git_revision"] == "none"
    monkeypatch.setenv("PATH", str(tmp_path))                         # no git at all
    monkeypatch.setattr(provenance, "package_dir", lambda: Path(__file__).parent)
    provenance.git_revision.cache_clear()
    assert provenance.git_revision() == (None, None)
    provenance.git_revision.cache_clear()


def test_command_line_is_recorded_and_forgotten():
    assert provenance.command_line() == provenance.LIBRARY_CALL
    provenance.set_invocation("response", ["response", "a b.toml", "-o", "out"])
    try:
        assert provenance.command_line() == "rotorsfd response 'a b.toml' -o out"
        assert provenance.netcdf_attrs()["command_line"] == provenance.command_line()
    finally:
        provenance.clear_invocation()
    assert provenance.invocation() is None


@pytest.mark.parametrize("name", sorted(n for n, s in cli.COMMANDS.items() if s.output))
def test_every_command_that_writes_a_folder_writes_run_json(name, tmp_path, monkeypatch):
    """The shared place (cli.app.run_marked) writes run.json for any command, with the
    config as resolved (after --set) and the analysis options."""
    spec = dataclasses.replace(cli.COMMANDS[name], handler=lambda args, config: (
        (args.output / "result.csv").write_text("a\n") and 0))
    config = (api.load_config(PAPER, ["analysis.response.harmonics=2"]) if spec.config
              else None)
    out = tmp_path / "out"
    argv = [name, str(PAPER), "--set", "analysis.response.harmonics=2", "-o", str(out)]
    args = argparse.Namespace(config=str(PAPER), overrides=argv[3:4], output=out,
                              quiet=True, _command=spec, _parser=None)
    provenance.set_invocation(name, argv)
    try:
        assert app.run_marked(spec, args, config) == 0
    finally:
        provenance.clear_invocation()
    record = json.loads((out / provenance.RUN_FILE).read_text())
    assert sorted(p.name for p in out.iterdir()) == ["result.csv", "run.json"]
    assert record["command"] == name and record["argv"] == argv
    assert record["command_line"].startswith(f"rotorsfd {name} ")
    assert record["rotorsfd_version"] == __version__
    assert record["dependencies"] == provenance.dependency_versions()
    assert record["options"] == {"output": str(out), "quiet": True}
    if spec.config:
        saved = config_from_dict(tomllib.loads(record["config_toml"]))
        assert saved.model_dump() == config.model_dump()
        assert saved.analysis.response.harmonics == 2
        assert record["config_path"] == str(PAPER.absolute())
    else:
        assert record["config_toml"] is None


# ---- CF attributes on every variable of the three netCDF files ---------------------------


def _missing_cf(path: Path) -> list[str]:
    with xr.open_dataset(path) as ds:
        return [f"{path.name}:{name} lacks {attr}"
                for name, var in {**ds.data_vars, **ds.coords}.items()
                for attr in ("units", "long_name") if attr not in var.attrs
                or (attr == "long_name" and not var.attrs[attr])]


@pytest.fixture(scope="module")
def small_config(tmp_path_factory):
    return small_rotor_toml(tmp_path_factory.mktemp("cf") / "small.toml")


@pytest.mark.slow
def test_branch_nc_variables_have_units_and_long_name(small_config, tmp_path):
    """With stability (multipliers, bifurcation table) and the element columns."""
    config = api.load_config(small_config, ["analysis.response.harmonics=1"])
    result = api.run_response(config, progress=False)
    result.write(tmp_path, plots=False)
    with xr.open_dataset(tmp_path / "branch.nc") as ds:
        assert "multiplier_real" in ds and ds.attrs["git_revision"]
        assert ds.attrs["command_line"] == provenance.LIBRARY_CALL
    assert _missing_cf(tmp_path / "branch.nc") == []


@pytest.mark.slow
def test_timeseries_nc_variables_have_units_and_long_name(small_config, tmp_path):
    config = api.load_config(small_config)
    result = api.run_simulation(config, speed_ratio=0.9, periods=20, poincare_periods=5,
                                steps_per_period=64, lyapunov_periods=0, progress=False)
    result.write(tmp_path, plots=False)
    assert _missing_cf(tmp_path / "timeseries.nc") == []


@pytest.mark.slow
def test_chart_nc_variables_have_units_and_long_name(tmp_path):
    raw = chart_rotor_raw()
    result = api.run_stability_chart(config_from_dict(raw),
                                     x=("base.pitching.angle_amplitude", [0.0, 0.1]),
                                     y=("base.pitching.frequency", [280.0, 300.0]),
                                     progress=False)
    result.write(tmp_path)
    assert _missing_cf(tmp_path / "chart.nc") == []
    with xr.open_dataset(tmp_path / "chart.nc") as ds:
        assert ds.attrs["rotorsfd_version"] == __version__ and "git_revision" in ds.attrs


def test_sweep_nc_carries_version_revision_and_command_line(tmp_path):
    from rotorsfd.studies import SyntheticTask, run_sweep

    config = api.load_config(small_rotor_toml(tmp_path / "rotor.toml"))
    run_sweep(config, {"elements.sfd.clearance_ratio": ["0.4 %", "0.5 %"]}, SyntheticTask(),
              directory=tmp_path / "sweep", workers=1, progress=False)
    with xr.open_dataset(tmp_path / "sweep" / "sweep.nc") as ds:
        assert {k: ds.attrs[k] for k in ("rotorsfd_version", "git_revision",
                                         "command_line")} == provenance.netcdf_attrs()
