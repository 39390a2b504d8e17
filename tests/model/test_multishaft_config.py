"""The multi-shaft config (issue 20 item 1): [[rotor.shafts]], [[rotor.intershaft]], the
intershaft_sfd element kind, global node numbering in the order of the shafts, and the
bad inputs (a node of the wrong shaft, a speed ratio <= 0, ...)."""

from __future__ import annotations

import copy
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.io.config import config_from_dict, read_toml
from rotorsfd.model.build import build_system
from rotorsfd.model.multishaft import MultiShaftRotor

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "dual_spool.toml"


@pytest.fixture(scope="module")
def raw() -> dict:
    return read_toml(EXAMPLE)


def _with(raw: dict, edit) -> dict:
    out = copy.deepcopy(raw)
    edit(out)
    return out


def test_example_builds_the_two_shafts_at_their_ratio(raw: dict) -> None:
    system = build_system(config_from_dict(raw))
    rotor = system.rotor
    assert isinstance(rotor, MultiShaftRotor)
    assert rotor.n_nodes == 18 and [s.name for s in rotor.shafts] == ["lp", "hp"]
    assert rotor.node_x[17] == pytest.approx(rotor.node_x[8]) == pytest.approx(0.8)
    assert rotor.node_x[13] == pytest.approx(0.4)
    g_lp, g_hp = (g.toarray() for g in rotor.shaft_gyroscopic)
    np.testing.assert_allclose(rotor.G, g_lp + 1.8 * g_hp, rtol=0, atol=1e-15)
    assert np.all(g_hp[:52] == 0.0) and np.all(g_lp[52:] == 0.0)
    # the intershaft bearing and the SFD centring springs
    k = rotor.K
    assert k[32, 68] == pytest.approx(-2e7, rel=1e-12)      # y of node 9, y of node 18
    assert rotor.supports[-2:][0].kyy == 4e6 and rotor.supports[-1].node == 14
    assert [e.nodes for e in system.elements] == [(1,), (14,)]
    assert rotor.dof_names[68] == "y@hp:5"


def test_single_shaft_examples_build_a_plain_rotor() -> None:
    for name in ("paper_rotor.toml", "journal_bearing_rotor.toml"):
        rotor = build_system(config_from_dict(read_toml(EXAMPLE.parent / name))).rotor
        assert type(rotor).__name__ == "Rotor"


def test_intershaft_sfd_from_config(raw: dict) -> None:
    def edit(r: dict) -> None:
        del r["rotor"]["intershaft"]
        r["elements"]["isfd"] = dict(kind="intershaft_sfd", node=9, outer_node=18,
                                     viscosity="0.01 Pa*s", radius="45 mm", length="12 mm",
                                     clearance="0.08 mm", centring_stiffness="2e7 N/m")
    system = build_system(config_from_dict(_with(raw, edit)))
    e = system.elements["isfd"]
    assert e.kind == "intershaft_sfd" and e.dofs.tolist() == [32, 33, 68, 69]
    k = system.rotor.K
    assert k[32, 68] == pytest.approx(-2e7, rel=1e-12) and k[33, 69] == k[32, 68]
    assert system.nl_dofs.tolist() == [0, 1, 52, 53, 32, 33, 68, 69]


@pytest.mark.parametrize(("edit", "match"), [
    (lambda r: r["rotor"]["shafts"][1].update(speed_ratio=0.0), "speed_ratio"),
    (lambda r: r["rotor"]["shafts"][1].update(speed_ratio=-1.0), "speed_ratio"),
    (lambda r: r["rotor"]["shafts"][0].update(speed_ratio=2.0), "first shaft's ratio"),
    (lambda r: r["rotor"]["shafts"][1]["disks"][0].update(node=5), "node of shaft 'hp', 14..18"),
    (lambda r: r["rotor"]["shafts"][0]["supports"][0].update(node=14),
     "node of shaft 'lp', 1..13"),
    (lambda r: r["rotor"]["intershaft"][0].update(outer_node=3), "another shaft"),
    (lambda r: r["rotor"]["intershaft"][0].update(outer_node=19), "1..18"),
    (lambda r: r["rotor"]["shafts"][1].update(name="lp"), "distinct"),
    (lambda r: r.update(base={"pitching": {"law": "constant", "value": 0.5}}),
     "rotating base"),
    (lambda r: r["rotor"].update(shaft=r["rotor"]["shafts"][0]["sections"]), "exactly one"),
    (lambda r: r["elements"].update(isfd=dict(kind="intershaft_sfd", node=3, outer_node=7,
                                              viscosity=0.01, radius=0.04, length=0.01,
                                              clearance=1e-4)), "another shaft"),
])
def test_bad_input_is_one_line_naming_the_field(raw: dict, edit, match: str) -> None:
    with pytest.raises(ConfigError, match=match) as err:
        config_from_dict(_with(raw, edit))
    assert "\n" not in str(err.value)


def test_intershaft_needs_shafts() -> None:
    raw = read_toml(EXAMPLE.parent / "journal_bearing_rotor.toml")
    raw["rotor"]["intershaft"] = [dict(node=2, outer_node=5, stiffness=1e6)]
    with pytest.raises(ConfigError, match="several shafts"):
        config_from_dict(raw)
