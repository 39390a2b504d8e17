"""Results files say what made them (issue 24 item 8): branch.nc, timeseries.nc and
chart.nc carry the rotorsfd version and the resolved configuration as TOML, which reads
back into the same configuration; branch.nc holds the plotted deflections and coordinates
on every dimension."""

from __future__ import annotations

import tomllib

import numpy as np
import xarray as xr

from rotors import chart_rotor_raw, small_rotor_toml
from rotorsfd import __version__, api
from rotorsfd.io.config import config_from_dict


def _same_config(text: str, config) -> None:
    assert config_from_dict(tomllib.loads(text)).model_dump() == config.model_dump()


def test_branch_nc_carries_config_version_and_deflections(tmp_path):
    config = api.load_config(small_rotor_toml(tmp_path / "small.toml"),
                             ["analysis.stability.enabled=false"])
    result = api.run_response(config, progress=False)
    result.write(tmp_path / "out", plots=False)
    with xr.open_dataset(tmp_path / "out" / "branch.nc") as ds:
        assert ds.attrs["rotorsfd_version"] == __version__
        _same_config(ds.attrs["config_toml"], config)
        table = result.table()
        for n in result.nodes:
            np.testing.assert_array_equal(ds[f"defl_{n}"].values, table[f"defl_{n}"])
            assert ds[f"defl_{n}"].attrs["units"] == "1"
        assert "unknown" in ds.coords and ds["unknown"].attrs["long_name"]


def test_timeseries_nc_carries_config_and_version(tmp_path):
    config = api.load_config(small_rotor_toml(tmp_path / "small.toml"))
    result = api.run_simulation(config, speed_ratio=0.9, periods=30, poincare_periods=10,
                                steps_per_period=64, lyapunov_periods=0, progress=False)
    result.write(tmp_path / "sim", plots=False)
    with xr.open_dataset(tmp_path / "sim" / "timeseries.nc") as ds:
        assert ds.attrs["rotorsfd_version"] == __version__
        _same_config(ds.attrs["config_toml"], config)


def test_chart_nc_carries_config_and_version(tmp_path):
    raw = chart_rotor_raw()
    config = config_from_dict(raw)
    result = api.run_stability_chart(config, x=("base.pitching.angle_amplitude", [0.0, 0.1]),
                                     y=("base.pitching.frequency", [280.0, 300.0]),
                                     progress=False)
    result.write(tmp_path / "chart")
    with xr.open_dataset(tmp_path / "chart" / "chart.nc") as ds:
        assert ds.attrs["rotorsfd_version"] == __version__
        _same_config(ds.attrs["config_toml"], config)
