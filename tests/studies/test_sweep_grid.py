"""The grid over dotted config paths: values in SI (unit strings converted), stable point
ids, the config of each point, errors naming the field."""

from __future__ import annotations

import pytest
from sweep_helpers import sweep_toml

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import get_path, load_config
from rotorsfd.studies.grid import (
    config_digest,
    grid_from_axes,
    grid_from_config,
    parse_axis,
    point_key,
)


@pytest.fixture
def config(tmp_path):
    return load_config(sweep_toml(tmp_path / "rotor.toml"))


def test_grid_from_config_axes(config):
    grid = grid_from_config(config)
    assert grid.shape == (2, 3)
    assert [a.path for a in grid.axes] == ["elements.sfd.clearance_ratio", "unbalance[0].magnitude"]
    assert grid.axes[0].values == pytest.approx((0.004, 0.005), rel=1e-15)
    assert grid.axes[1].values == pytest.approx((4e-5, 5e-5, 6e-5), rel=1e-12)
    assert [a.units for a in grid.axes] == ["1", "kg*m"]
    assert [a.name for a in grid.axes] == ["elements_sfd_clearance_ratio", "unbalance_0_magnitude"]


def test_point_ids_c_order_and_stable(config):
    grid = grid_from_config(config)
    pts = list(grid.points())
    assert [p.point_id for p in pts] == [f"{i:06d}" for i in range(6)]
    assert [p.indices for p in pts] == [(i, j) for i in range(2) for j in range(3)]
    assert list(grid.points()) == pts   # same ids and values on every call
    digest = config_digest(config, "synthetic")
    assert point_key(digest, pts[4]) == point_key(config_digest(config, "synthetic"), pts[4])
    assert point_key(digest, pts[4]) != point_key(digest, pts[5])
    assert point_key(config_digest(config, "response"), pts[4]) != point_key(digest, pts[4])


def test_config_at_sets_dotted_paths_with_units(tmp_path):
    config = load_config(sweep_toml(tmp_path / "rotor.toml"),
                         ["base.pitching.law=constant", "base.pitching.value=0"])
    grid = grid_from_axes(config, {
        "base.pitching.value": ["3 rad/s", 6.0],
        "unbalance[0].magnitude": ["144.02 g*mm"],
        "elements.sfd.clearance_ratio": ["0.61 %"],
        "rotor.supports[0].stiffness": ["2e7 N/m"],
    })
    assert grid.shape == (2, 1, 1, 1)
    for p in grid.points():
        c = grid.config_at(config, p)
        assert c.base.pitching.value == p.as_dict()["base.pitching.value"]
        assert c.unbalance[0].magnitude == pytest.approx(144.02e-6, rel=1e-12)
        assert c.elements["sfd"].clearance_ratio == pytest.approx(0.0061, rel=1e-12)
        assert c.rotor.supports[0].stiffness == 2e7
        # untouched
        assert get_path(c, "elements.sfd.clearance") == config.elements["sfd"].clearance
    assert [p.as_dict()["base.pitching.value"] for p in grid.points()] == [3.0, 6.0]


def test_bad_axes_name_the_field(config):
    with pytest.raises(ConfigError, match="speed"):
        grid_from_axes(config, {"speed": [100.0]})
    with pytest.raises(ConfigError, match="names no config field"):
        grid_from_axes(config, {"sfd.clearance_ratioo": [0.004]})
    with pytest.raises(ConfigError, match="unbalance"):
        grid_from_axes(config, {"unbalance[0].magnitude": ["3 m"]})
    with pytest.raises(ConfigError, match="one axis"):
        grid_from_axes(config, {"elements.sfd.clearance_ratio": [0.004],
                                "elements.sfd.clearance_ratio ": [0.005]})


def test_out_of_range_value_is_a_config_error_at_that_point(config):
    grid = grid_from_axes(config, {"elements.sfd.clearance_ratio": [0.004, 1.5]})
    pts = list(grid.points())
    grid.config_at(config, pts[0])
    with pytest.raises(ConfigError, match="clearance_ratio"):
        grid.config_at(config, pts[1])


def test_parse_axis():
    assert parse_axis("elements.sfd.clearance_ratio=0.4 %, 0.5 %") == (
        "elements.sfd.clearance_ratio", ["0.4 %", "0.5 %"])
    assert parse_axis("base.pitching.value=0,3.5,6") == ("base.pitching.value", [0, 3.5, 6])
    with pytest.raises(ConfigError):
        parse_axis("elements.sfd.clearance_ratio=")
