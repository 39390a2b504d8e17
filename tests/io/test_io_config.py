"""Loading, validation, overrides and `config show` of configuration files."""

import json
import math
import tomllib
from pathlib import Path

import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import (
    config_from_dict,
    dump_config,
    load_config,
    parse_override,
    read_toml,
    show_config,
    with_values,
)
from rotorsfd.io.schema import Config, parameter_values, resolve_kind, split_path

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"


@pytest.fixture(scope="module")
def paper():
    return load_config(PAPER)


@pytest.fixture
def raw():
    return read_toml(PAPER)


def test_paper_example_values(paper):
    assert paper.rotor.n_nodes == 21
    assert paper.rotor.shaft[0].inner_radius == pytest.approx(20.65e-3)
    assert paper.materials["steel"].shear_modulus == pytest.approx(81.783e9)
    assert paper.unbalance[0].magnitude == pytest.approx(360.04e-6)
    sfd = paper.elements["sfd"]
    assert sfd.resolved_clearance == pytest.approx(0.127e-3)
    assert sfd.resolved_radius == pytest.approx(0.127e-3 / 0.00485)
    assert sfd.resolved_length == pytest.approx(0.325 * 2 * 0.127e-3 / 0.00485)
    assert paper.reference.speed == pytest.approx(811.3)
    assert paper.base.is_fixed and not paper.gravity.enabled


def test_defaults_filled_in(raw):
    del raw["analysis"]
    cfg = config_from_dict(raw)
    assert cfg.analysis.response.harmonics == "auto"
    assert cfg.analysis.response.start_harmonics == 3
    assert cfg.analysis.stability.intervals == 400
    assert cfg.elements["sfd"].cavitation == "pi"


@pytest.mark.parametrize(("override", "check"), [
    ('elements.sfd.clearance_ratio=0.61 %',
     lambda c: c.elements["sfd"].resolved_radius == pytest.approx(0.127e-3 / 0.0061)),
    ('elements.sfd.clearance_ratio="0.728 %"',
     lambda c: c.elements["sfd"].clearance_ratio == pytest.approx(0.00728)),
    ("unbalance[0].magnitude=144.02 g*mm", lambda c: c.unbalance[0].magnitude == pytest.approx(
        144.02e-6)),
    ("unbalance.0.magnitude=252e-6", lambda c: c.unbalance[0].magnitude == 252e-6),
    ("rotor.shaft[0].n_elements=10", lambda c: c.rotor.n_nodes == 11),
    ("analysis.response.harmonics=8", lambda c: c.analysis.response.harmonics == 8),
    ("elements.sfd.cavitation=none", lambda c: c.elements["sfd"].cavitation == "none"),
    ("gravity.enabled=true", lambda c: c.gravity.enabled),
    ("gravity.direction=[0, 1, 0]", lambda c: c.gravity.direction == [0, 1, 0]),
    ("reference.speed=first_critical", lambda c: c.reference.speed == "first_critical"),
    ("reference.speed=3000 rpm", lambda c: c.reference.speed == pytest.approx(100 * math.pi)),
    ("unbalance[1]={node = 8, magnitude = 1e-5}", lambda c: len(c.unbalance) == 2),
])
def test_set_overrides(raw, override, check):
    if override.startswith("rotor.shaft[0].n_elements"):
        raw["rotor"]["disks"][0]["node"] = 4
        raw["rotor"]["supports"][0]["node"] = 11
        raw["analysis"]["response"]["nodes"] = [1, 4]
    assert check(config_from_dict(raw, [override]))


def test_set_constant_pitching(raw):
    cfg = config_from_dict(raw, ["base.pitching.law=constant", "base.pitching.value=6 rad/s"])
    assert cfg.base.pitching.value == 6.0 and not cfg.base.is_fixed


@pytest.mark.parametrize(("override", "field"), [
    ("no_equals_sign", "--set"),
    ("=3", "--set"),
    ("elements.sfd.viscosity=", "elements.sfd.viscosity"),
    ("a..b=3", "a..b"),
    ("elements.sfd.node.x=3", "elements.sfd.node.x"),
    ("unbalance[5].node=3", "unbalance[5].node"),
])
def test_bad_set(raw, override, field):
    with pytest.raises(ConfigError) as info:
        config_from_dict(raw, [override])
    assert info.value.field == field


@pytest.mark.parametrize(("override", "field", "words"), [
    # wrong type
    ("rotor.shaft[0].n_elements=abc", "rotor.shaft[0].n_elements", "integer"),
    ("gravity.enabled=3", "gravity.enabled", "true or false"),
    # out of range
    ("elements.sfd.viscosity=-1", "elements.sfd.viscosity", "> 0"),
    ("elements.sfd.clearance_ratio=150 %", "elements.sfd.clearance_ratio", "< 1"),
    ("analysis.response.harmonics=0", "analysis.response.harmonics", "1 <= H <= 64"),
    # unknown key (with a suggestion)
    ("rotor.shaft[0].lenght=0.5", "rotor.shaft[0].lenght", "did you mean 'length'"),
    ("elements.sfd.clearence=1e-4", "elements.sfd.clearence", "unknown key"),
    # wrong choice
    ("elements.sfd.cavitation=half", "elements.sfd.cavitation", "'pi', 'none' or 'guembel'"),
    # bad node, bad material
    ("rotor.disks[0].node=22", "rotor.disks[0].node", "1..21"),
    ("elements.sfd.node=0", "elements.sfd.node", ">= 1"),
    ("rotor.shaft[0].material=alu", "rotor.shaft[0].material", "steel"),
    # cross-field checks
    ("rotor.shaft[0].inner_radius=40 mm", "rotor.shaft[0].inner_radius", "outer_radius"),
    ("rotor.disks[0].outer_radius=20 mm", "rotor.disks[0].inner_radius", "outer_radius"),
    # the SFD geometry forms: the table is named, with what was given (not the last field)
    ("elements.sfd.radius=30 mm", "elements.sfd", "got 'clearance, clearance_ratio and "
     "radius'; give exactly two of clearance, clearance_ratio, radius"),
    ("elements.sfd.length=20 mm", "elements.sfd", "got 'length and length_to_diameter'; "
     "give exactly one of length, length_to_diameter"),
    # booleans are TOML booleans: "yes", 1 and "true" are not
    ("gravity.enabled='yes'", "gravity.enabled", "got 'yes'; expected true or false"),
    ("gravity.enabled=1", "gravity.enabled", "got 1; expected true or false"),
    ("rotor.disks[0].mass=10", "rotor.disks[0].mass", "exactly one of"),
    ("base.pitching.law=harmonic", "base.pitching.frequency", "needs a frequency"),
    ("base.yawing.amplitude=1", "base.yawing.amplitude", "not used with law = 'off'"),
    ("rotor.damping.kind=modal", "rotor.damping.ratio", "needs the damping ratio"),
    ("rotor.damping.modes=4", "rotor.damping.modes", "not used with kind = 'none'"),
    ("analysis.response.parameter=base.pitching.valu", "analysis.response.speed",
     "needs exactly one fixed speed"),
    ("reference.speed=fast", "reference.speed", "first_critical"),
])
def test_bad_values_name_field(raw, override, field, words):
    with pytest.raises(ConfigError) as info:
        config_from_dict(raw, [override])
    assert info.value.field == field
    assert words in str(info.value)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize(("drop", "override", "field", "words"), [
    # L/D derived from the length: held to length_to_diameter's range
    ("length_to_diameter", "elements.sfd.length=3 furlongs", "elements.sfd.length",
     "got '3 furlongs'; gives L/D = L / (2R) = 11523.6 (R = 0.0261856 m); "
     "length_to_diameter must be 0 < value <= 10"),
    # C and R given: C/R derived, and C must stay below R
    ("clearance_ratio", "elements.sfd.radius=0.1 mm", "elements.sfd.clearance",
     "got '0.127 mm'; gives C = 0.000127 m >= R = 0.0001 m"),
])
def test_derived_sfd_values_in_range(raw, drop, override, field, words):
    del raw["elements"]["sfd"][drop]
    with pytest.raises(ConfigError) as info:
        config_from_dict(raw, [override])
    assert info.value.field == field
    assert words in str(info.value)


def test_derived_sfd_values_at_the_bound_pass(raw):
    del raw["elements"]["sfd"]["length_to_diameter"]
    radius = 0.127e-3 / 0.00485
    config = config_from_dict(raw, [f"elements.sfd.length={20 * radius!r}"])   # L/D = 10 exactly
    sfd = config.elements["sfd"]
    assert sfd.resolved_length / (2 * sfd.resolved_radius) == pytest.approx(10.0)


def test_missing_required(raw):
    del raw["elements"]["sfd"]["viscosity"]
    with pytest.raises(ConfigError, match=r"^elements\.sfd\.viscosity: got nothing; required: oil"):
        config_from_dict(raw)
    del raw["rotor"]
    with pytest.raises(ConfigError, match=r"^rotor: got nothing; required"):
        config_from_dict(raw)


def test_parameter_path_checked(raw):
    sets = ["analysis.response.speed_ratio=1.1", "analysis.response.parameter_range=[0, 10]"]
    cfg = config_from_dict(raw, ["analysis.response.parameter=base.pitching.value", *sets])
    assert cfg.analysis.response.parameter == "base.pitching.value"
    with pytest.raises(ConfigError, match="names no config field"):
        config_from_dict(raw, ["analysis.response.parameter=base.pitching.valu", *sets])
    with pytest.raises(ConfigError, match="not a scalar physical quantity"):
        config_from_dict(raw, ["analysis.response.parameter=elements.sfd.cavitation", *sets])


def test_missing_file_and_bad_toml(tmp_path):
    with pytest.raises(ConfigError, match="no such file"):
        load_config(tmp_path / "nope.toml")
    bad = tmp_path / "bad.toml"
    bad.write_text("[sfd\nnode = 1\n")
    with pytest.raises(ConfigError, match="valid TOML") as info:
        load_config(bad)
    assert "\n" not in str(info.value)


@pytest.mark.parametrize("fmt", ["toml", "json"])
def test_show_round_trips(paper, raw, fmt):
    text = show_config(paper, fmt)
    data = tomllib.loads(text) if fmt == "toml" else json.loads(text)
    again = config_from_dict(data)
    assert again == paper
    assert dump_config(again) == dump_config(paper)
    # a config with the alternative forms round-trips too
    variant = config_from_dict(raw, [
        "elements.sfd.clearance_ratio=0.61 %", "rotor.damping.kind=rayleigh",
        "rotor.damping.beta=1e-5",
        "base.pitching.law=harmonic", "base.pitching.frequency=20", "base.pitching.angle_amplitude"
        "=0.5 deg", "base.z.law=uniform_acceleration", "base.z.acceleration=-9.81",
        "unbalance[0].phase=30 deg"])
    text = show_config(variant, fmt)
    data = tomllib.loads(text) if fmt == "toml" else json.loads(text)
    assert config_from_dict(data) == variant


def test_show_is_si_with_derived_comment(paper):
    text = show_config(paper)
    assert "clearance = 0.000127" in text
    assert "# derived: C = 0.000127 m, R = 0.0261856 m" in text


def test_with_values(paper):
    cfg = with_values(paper, {"elements.sfd.clearance_ratio": "0.728 %",
                              "unbalance[0].magnitude": 252e-6})
    assert cfg.elements["sfd"].clearance_ratio == pytest.approx(0.00728)
    assert cfg.unbalance[0].magnitude == 252e-6
    assert paper.elements["sfd"].clearance_ratio == pytest.approx(0.00485)      # unchanged


def test_paths_and_kinds(paper):
    assert split_path("rotor.shaft[0].length") == ("rotor", "shaft", 0, "length")
    assert split_path("rotor.shaft.0.length") == ("rotor", "shaft", 0, "length")
    assert resolve_kind(paper, "unbalance[0].magnitude") == "unbalance"
    assert resolve_kind(paper, "base.pitching.value") == "angular_velocity"
    assert parameter_values(paper, "elements.sfd.clearance_ratio", ["0.485 %", 0.0061]) == \
        pytest.approx([0.00485, 0.0061])
    assert parameter_values(paper, "speed", ["3000 rpm"]) == pytest.approx([100 * math.pi])
    assert parse_override("a.b = 0.5 mm") == ("a.b", "0.5 mm")
    assert parse_override("a.b=[1, 2]") == ("a.b", [1, 2])


def _walk_properties(schema, defs):
    yield from schema.get("properties", {}).values()
    for d in defs.values():
        yield from d.get("properties", {}).values()


def test_every_quantity_documents_unit_and_range():
    schema = Config.model_json_schema()
    props = list(_walk_properties(schema, schema["$defs"]))
    quantities = [p for p in props if "kind" in p]
    assert len(quantities) > 60
    for p in quantities:
        unit = "dimensionless" if p["unit"] == "1" else p["unit"]
        assert f"[{unit}]" in p["description"]
        assert "allowed:" in p["description"]


def test_every_field_documented():
    from rotorsfd.io.reference import field_reference, markdown_reference

    docs = field_reference()
    assert len(docs) > 100
    assert all(d.description for d in docs), [d.path for d in docs if not d.description]
    table = markdown_reference()
    assert "| `clearance_ratio` | `1` | `-` | 0 < value < 1 |" in table  # in [sfd]
    assert "`shaft[].length`" in table


@pytest.mark.parametrize(("override", "field"), [
    ('analysis.sweep.axes[0]={parameter = "unbalance[0].magnitude", values = ["1 g*mm", '
     '"3 mm"]}', "analysis.sweep.axes[0].values[1]"),
    ('analysis.stability_chart.x={parameter = "base.pitching.frequency", start = "1 kg", '
     'stop = 3}', "analysis.stability_chart.x.start"),
    ('analysis.sweep.axes[0]={parameter = "elements.sfd.viscosty", start = 0, stop = 1}',
     "analysis.sweep.axes[0].parameter"),
])
def test_axis_values_checked(raw, override, field):
    with pytest.raises(ConfigError) as info:
        config_from_dict(raw, [override])
    assert info.value.field == field


def test_axis_values_si(raw):
    from rotorsfd.io.schema import axis_values

    cfg = config_from_dict(raw, [
        'analysis.sweep.axes[0]={parameter = "base.pitching.value", start = 0, '
        'stop = "10 rad/s", n = 11}',
        'analysis.sweep.axes[1]={parameter = "unbalance[0].magnitude", values = '
        '["144.02 g*mm", "252 g*mm", "360.04 g*mm"]}'])
    first, second = cfg.analysis.sweep.axes
    assert axis_values(cfg, first) == pytest.approx(list(range(11)))
    assert axis_values(cfg, second) == pytest.approx([144.02e-6, 252e-6, 360.04e-6])


def test_output_nodes_and_fixed_speeds(raw):
    cfg = config_from_dict(raw, ["analysis.response.nodes=[]",
                                 "analysis.simulate.speed_ratio=1.05"])
    assert cfg.output_nodes("response") == [1, 8]           # SFD and disk nodes
    assert cfg.output_nodes("simulate") == [1, 8]
    assert cfg.analysis.simulate.fixed_speed(811.3) == pytest.approx(1.05 * 811.3)
    cfg = config_from_dict(raw, ["analysis.response.nodes=[21]"])
    assert cfg.output_nodes() == [21]
