"""The paper's family examples extend examples/paper_rotor.toml: resolved, they carry its
rotor, SFD (C/R aside), supports and analysis settings unchanged (the support stiffnesses
are fitted there) and differ only in what they state."""

from __future__ import annotations

from pathlib import Path

import pytest

from rotorsfd.io.config import dump_config, load_config, read_toml

EXAMPLES = Path(__file__).parents[2] / "examples"
CASES = {"pitching": ("pitching", 6.0), "rolling": ("rolling", 10.0),
         "yawing": ("yawing", 6.0)}
FAMILY = ["paper_pitching", "paper_rolling", "paper_yawing", "paper_unbalance",
          "paper_clearance"]


def _resolved(name: str) -> dict:
    return dump_config(load_config(EXAMPLES / f"{name}.toml"))


@pytest.mark.parametrize("name", FAMILY)
def test_family_extends_paper_rotor(name):
    raw = read_toml(EXAMPLES / f"{name}.toml")
    assert raw["extends"] == "paper_rotor.toml"
    # only what differs is stated: no rotor, materials or supports of its own
    assert not {"materials", "rotor", "gravity", "reference"} & set(raw)
    ref, ex = _resolved("paper_rotor"), _resolved(name)
    for table in ("materials", "rotor", "gravity", "reference"):
        assert ex[table] == ref[table], f"[{table}] of {name} differs from paper_rotor.toml"
    sfd = {k: v for k, v in ex["elements"]["sfd"].items() if k != "clearance_ratio"}
    assert sfd == {k: v for k, v in ref["elements"]["sfd"].items() if k != "clearance_ratio"}
    for table in ("modal", "stability", "simulate"):
        assert ex["analysis"][table] == ref["analysis"][table], table
    response = {k: v for k, v in ex["analysis"]["response"].items()
                if k not in ("harmonics", "max_eccentricity")}
    assert response == {k: v for k, v in ref["analysis"]["response"].items()
                        if k not in ("harmonics", "max_eccentricity")}


@pytest.mark.parametrize("name", sorted(CASES))
def test_base_motion_example(name):
    ref, ex = _resolved("paper_rotor"), _resolved(f"paper_{name}")
    assert ex["analysis"] == ref["analysis"] and ex["elements"]["sfd"] == ref["elements"]["sfd"]
    config = load_config(EXAMPLES / f"paper_{name}.toml")
    assert config.unbalance[0].magnitude == pytest.approx(144.02e-6)
    component, rate = CASES[name]
    for c in ("rolling", "pitching", "yawing", "x", "y", "z"):
        law = getattr(config.base, c)
        if c == component:
            assert law.law == "constant" and law.value == pytest.approx(rate)
        else:
            assert law.law == "off"


def test_unbalance_and_clearance_examples():
    u = load_config(EXAMPLES / "paper_unbalance.toml")
    assert u.analysis.response.harmonics == 8
    assert u.unbalance[0].magnitude == pytest.approx(252e-6)
    assert u.base.pitching.value == pytest.approx(6.0)
    c = load_config(EXAMPLES / "paper_clearance.toml")
    assert c.analysis.response.harmonics == 8
    assert c.analysis.response.max_eccentricity == pytest.approx(0.995)
    assert c.elements["sfd"].clearance_ratio == pytest.approx(0.00728)
    assert c.base.pitching.value == pytest.approx(10.0)
    # C fixed: R and L follow C/R
    ref = load_config(EXAMPLES / "paper_rotor.toml")
    sfd, sfd_ref = c.elements["sfd"], ref.elements["sfd"]
    assert sfd.resolved_clearance == pytest.approx(sfd_ref.resolved_clearance, rel=1e-12)
    assert sfd.resolved_radius == pytest.approx(sfd_ref.resolved_radius * 0.485 / 0.728,
                                                rel=1e-9)
