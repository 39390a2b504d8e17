"""Unit strings parse to SI; wrong dimensions are errors that name the field."""

import math

import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import config_from_dict
from rotorsfd.io.units import UnitError, to_si


@pytest.mark.parametrize(("text", "kind", "si"), [
    ("5 mil", "length", 1.27e-4),                  # thousandth of an inch, not an angle
    ("5mil", "length", 1.27e-4),
    ("0.61%", "ratio", 0.0061),
    ("0.127 mm", "length", 1.27e-4),
    ("1 um", "length", 1e-6),
    ("1 µm", "length", 1e-6),
    ("360.04 g*mm", "unbalance", 3.6004e-4),
    ("0.5 oz*in", "unbalance", 0.5 * 0.028349523125 * 0.0254),
    ("0.485 %", "ratio", 0.00485),
    ("0.325", "ratio", 0.325),
    ("6 rad/s", "angular_velocity", 6.0),
    ("3000 rpm", "angular_velocity", 100 * math.pi),
    ("50 Hz", "angular_velocity", 100 * math.pi),     # Hz = rev/s for rates
    ("10 deg/s", "angular_velocity", math.radians(10)),
    ("90 deg", "angle", math.pi / 2),
    ("211 GPa", "modulus", 211e9),
    ("7810 kg/m^3", "density", 7810.0),
    ("0.0051 Pa*s", "viscosity", 0.0051),
    ("3 N/mm", "stiffness", 3000.0),
    ("1e7", "stiffness", 1e7),                      # no units: SI
    (1e7, "stiffness", 1e7),
    (3, "length", 3.0),
])
def test_units_to_si(text, kind, si):
    assert to_si(text, kind) == pytest.approx(si, rel=1e-12)


@pytest.mark.parametrize(("text", "kind", "words"), [
    ("5 kg", "length", "is a mass"),
    ("5 mm", "ratio", "is a length"),
    ("3 N/mm", "length", "is a stiffness"),
    ("abc", "length", "cannot read"),
    (True, "length", "boolean"),
    ("nan", "length", "finite"),
])
def test_unit_errors(text, kind, words):
    with pytest.raises(UnitError, match=words):
        to_si(text, kind)


def _minimal(**shaft):
    section = {"length": 0.5, "n_elements": 4, "outer_radius": "20 mm", "material": "steel"}
    section.update(shaft)
    return {"materials": {"steel": {"density": 7800, "young_modulus": 2e11,
                                    "poisson_ratio": 0.3}},
            "rotor": {"shaft": [section],
                      "supports": [{"node": 1, "stiffness": 1e7}, {"node": 5, "stiffness": 1e7}]}}


def test_dimension_mismatch_names_field():
    with pytest.raises(ConfigError) as info:
        config_from_dict(_minimal(length="5 kg"))
    assert info.value.field == "rotor.shaft[0].length"
    assert info.value.value == "5 kg"
    assert "length in m" in str(info.value)


def test_units_in_config_are_si():
    cfg = config_from_dict(_minimal(length="23.6 in", outer_radius="5 mil"))
    assert cfg.rotor.shaft[0].length == pytest.approx(0.59944)
    assert cfg.rotor.shaft[0].outer_radius == pytest.approx(1.27e-4)
