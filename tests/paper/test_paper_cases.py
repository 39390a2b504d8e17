"""The case registry: every case's config loads, the figures name known cases, and the
paper examples carry the rotor of examples/paper_rotor.toml unchanged."""

from __future__ import annotations

import pytest

from rotorsfd.io.config import load_config, read_toml
from rotorsfd.paper.cases import (
    CASES,
    CLAIMS,
    EXTRA_CASES,
    FIGURES,
    KINDS,
    examples_dir,
    select,
)

EXAMPLES = examples_dir()


@pytest.mark.parametrize("name", sorted(CASES))
def test_case_config_loads(name):
    case = CASES[name]
    assert case.kind in KINDS
    for quick in (False, True):
        load_config(EXAMPLES / case.config,
                    [*case.overrides, *(case.quick if quick else ())])


def test_figures_and_claims_name_known_cases():
    for spec in FIGURES.values():
        assert spec.cases and all(c in CASES for c in spec.cases), spec.number
    for claim in CLAIMS:
        assert claim.case in CASES, claim
    assert all(c in CASES for c in EXTRA_CASES)


def test_select():
    specs, cases = select(["7"])
    assert [s.number for s in specs] == ["7"]
    assert {c.name for c in cases} == {"modal", "fig7-u72", "fig7-u144", "fig7-u360"}
    specs, cases = select(None, quick=True)
    assert [s.number for s in specs] == ["7"]
    specs, cases = select(None)
    assert len(specs) == len(FIGURES) and len(cases) >= 40
    with pytest.raises(KeyError, match="no figure 99"):
        select(["99"])


SAME = ("materials", "rotor", "gravity", "reference")


@pytest.mark.parametrize("name", ["paper_unbalance.toml", "paper_clearance.toml"])
def test_paper_examples_keep_the_rotor(name):
    ref, ex = read_toml(EXAMPLES / "paper_rotor.toml"), read_toml(EXAMPLES / name)
    for table in SAME:
        assert ex[table] == ref[table], f"[{table}] of {name} differs from paper_rotor.toml"
    sfd = {k: v for k, v in ex["sfd"].items() if k != "clearance_ratio"}
    assert sfd == {k: v for k, v in ref["sfd"].items() if k != "clearance_ratio"}
    assert ex["analysis"]["stability"] == ref["analysis"]["stability"]
    assert ex["analysis"]["simulate"] == ref["analysis"]["simulate"]
    assert ex["analysis"]["response"]["harmonics"] == 8
