"""The response's two entry paths are one resolution (issue 16 item 3):
``run_response(config)`` builds the system once and goes through
:meth:`ResponseInputs.from_system`, so ``run_response(build(config),
config.analysis.response)`` (a system with its section, the context an empty
configuration's: Omega_ref the first forward critical speed, stability on) gives the same
branch, multipliers and bifurcations, every array to 1e-12. On the small rotor of
tests/rotors.py; the reference speed is also checked against the modal analysis'
first critical speed, the start of the range against the section's values in SI."""

from __future__ import annotations

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.analyses.context import RunContext, build
from rotorsfd.analyses.response import run_response
from rotorsfd.analyses.response_inputs import ResponseInputs
from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import StabilityAnalysis


@pytest.fixture(scope="module")
def config(tmp_path_factory):
    path = small_rotor_toml(tmp_path_factory.mktemp("entry") / "small.toml",
                            reference="first_critical")
    return api.load_config(path, ["analysis.response.speed_range.start_ratio=0.6",
                                  "analysis.response.speed_range.stop_ratio=0.8"])


def _same_arrays(a, b) -> int:
    """Every variable and coordinate of the two Datasets equal to 1e-12; their count."""
    da, db = a.to_dataset(), b.to_dataset()
    assert set(da.variables) == set(db.variables)
    for name in da.variables:
        x, y = da[name].values, db[name].values
        assert x.shape == y.shape, name
        if np.issubdtype(x.dtype, np.number):
            scale = float(np.nanmax(np.abs(x))) if x.size and np.isfinite(x).any() else 0.0
            np.testing.assert_allclose(x, y, rtol=1e-12, atol=1e-12 * scale,
                                       equal_nan=True, err_msg=name)
        else:
            np.testing.assert_array_equal(x, y, err_msg=name)
    return len(da.variables)


def test_response_system_with_its_section_is_the_config(config):
    a = run_response(config, progress=False)
    b = run_response(build(config), config.analysis.response, progress=False)
    assert a.branch.n_points == b.branch.n_points > 5
    assert _same_arrays(a, b) > 10
    # stability on for both (the config has no [analysis.stability]; a system alone: on)
    assert a.stable is not None and b.stable is not None
    np.testing.assert_allclose(a.max_multiplier, b.max_multiplier, rtol=1e-12)
    assert a.bifurcations == b.bifurcations
    assert (a.nodes, a.directions, a.parameter, a.speed) == \
        (b.nodes, b.directions, b.parameter, b.speed) == ((1, 3), ("y", "z"), "speed", None)
    # Omega_ref: the modal analysis' first forward critical speed (a second computation)
    ref = api.run_modal(config).critical_speeds[0].speed_rad_s
    assert a.reference_speed == b.reference_speed == pytest.approx(ref, rel=1e-9)
    assert a.branch.lam[0] == pytest.approx(0.6 * ref, rel=1e-12)
    assert a.title == config.title and b.title == ""


def test_response_in_the_unbalance_system_path_is_the_config(config):
    """A parameter other than the speed: the range written with units in the section is
    converted once, by the same code, on both paths (40 g mm = 4e-5 kg m)."""
    cfg = api.with_values(config, {
        "analysis.response.parameter": "unbalance[0].magnitude",
        "analysis.response.speed_ratio": 0.9,
        "analysis.response.parameter_range": ["40 g*mm", "60 g*mm"],
        "analysis.stability.enabled": False})
    a = run_response(cfg, progress=False)
    b = run_response(build(cfg), cfg.analysis.response,
                     context=RunContext(stability=StabilityAnalysis(enabled=False)),
                     progress=False)
    assert a.branch.n_points == b.branch.n_points >= 2
    _same_arrays(a, b)
    assert a.stable is None and b.stable is None
    assert a.branch.lam[0] == b.branch.lam[0] == pytest.approx(4e-5, rel=1e-12)
    assert a.speed == b.speed == pytest.approx(0.9 * a.reference_speed, rel=1e-12)


def test_inputs_of_both_paths_are_equal(config):
    """The resolved inputs themselves (beyond the system object, the title and the
    configuration text) are equal field for field."""
    a = ResponseInputs.from_config(config)
    b = ResponseInputs.from_system(build(config), config.analysis.response)
    skip = {"system", "title", "config_toml"}
    for name in a.__dataclass_fields__:
        if name not in skip:
            assert getattr(a, name) == getattr(b, name), name
    assert a.stability is not None and a.harmonics == 3
    assert b.title == "" and b.config_toml == "" and a.config_toml


def test_response_inputs_bad_range_names_the_field(config):
    with pytest.raises(ConfigError, match=r"analysis\.response\.speed_range"):
        ResponseInputs.from_system(build(config), config.analysis.response, start=500.0,
                                   stop=500.0)
    with pytest.raises(ConfigError, match=r"analysis\.response\.speed: got None"):
        ResponseInputs.from_system(build(config), config.analysis.response,
                                   parameter="unbalance[0].magnitude", start=1e-5,
                                   stop=2e-5)
