"""The base-motion examples carry the rotor of examples/paper_rotor.toml unchanged (the
support stiffnesses are fitted there) and differ only in unbalance, base and title."""

from __future__ import annotations

from pathlib import Path

import pytest

from rotorsfd.io.config import load_config, read_toml

EXAMPLES = Path(__file__).parents[2] / "examples"
CASES = {"pitching": ("pitching", 6.0), "rolling": ("rolling", 10.0),
         "yawing": ("yawing", 6.0)}


@pytest.mark.parametrize("name", sorted(CASES))
def test_example_matches_paper_rotor(name):
    ref, ex = read_toml(EXAMPLES / "paper_rotor.toml"), read_toml(EXAMPLES / f"paper_{name}.toml")
    for table in ("materials", "rotor", "sfd", "gravity", "reference", "analysis"):
        assert ex[table] == ref[table], f"[{table}] differs from paper_rotor.toml"
    assert set(ex) == set(ref)
    config = load_config(EXAMPLES / f"paper_{name}.toml")
    assert config.unbalance[0].magnitude == pytest.approx(144.02e-6)
    component, rate = CASES[name]
    for c in ("rolling", "pitching", "yawing", "x", "y", "z"):
        law = getattr(config.base, c)
        if c == component:
            assert law.law == "constant" and law.value == pytest.approx(rate)
        else:
            assert law.law == "off"
