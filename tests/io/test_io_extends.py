"""Config inheritance: ``extends = "base.toml"`` (relative to the file that contains it)."""

from __future__ import annotations

import tomllib
from pathlib import Path

import pytest

from rotorsfd.cli import main
from rotorsfd.errors import ConfigError
from rotorsfd.io.config import (
    config_from_dict,
    load_config,
    merge_tables,
    read_config,
    read_toml,
    show_config,
)

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"


def _write(path: Path, text: str) -> Path:
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)
    return path


def test_merge_tables_recursive_and_wholesale():
    base = {"a": {"b": 1, "c": {"d": 2, "e": 3}}, "arr": [1, 2, 3],
            "tables": [{"x": 1}, {"x": 2}], "s": "base"}
    top = {"a": {"c": {"e": 30}, "f": 4}, "arr": [9], "tables": [{"y": 5}], "new": True}
    out = merge_tables(base, top)
    assert out == {"a": {"b": 1, "c": {"d": 2, "e": 30}, "f": 4}, "arr": [9],
                   "tables": [{"y": 5}], "s": "base", "new": True}
    # the inputs are not modified
    assert base["a"]["c"]["e"] == 3 and top["a"] == {"c": {"e": 30}, "f": 4}
    # a table replaces a scalar and a scalar a table
    assert merge_tables({"k": 1}, {"k": {"v": 2}}) == {"k": {"v": 2}}
    assert merge_tables({"k": {"v": 2}}, {"k": 1}) == {"k": 1}


def test_extends_merges_into_the_paper_rotor(tmp_path):
    child = _write(tmp_path / "sub" / "child.toml", f'''
extends = "{PAPER.as_posix()}"
title = "child"
[elements.sfd]
kind = "sfd"
clearance_ratio = "0.61 %"
[[unbalance]]
node = 5
magnitude = "100 g*mm"
[base]
pitching = {{ law = "constant", value = "6 rad/s" }}
[analysis.response]
harmonics = 8
''')
    raw = read_config(child)
    assert "extends" not in raw
    config = load_config(child)
    ref = load_config(PAPER)
    assert config.title == "child"
    # a key of [sfd] changed, the others kept
    assert config.elements["sfd"].clearance_ratio == pytest.approx(0.0061)
    assert config.elements["sfd"].viscosity == ref.elements["sfd"].viscosity
    assert config.elements["sfd"].centring_stiffness == ref.elements["sfd"].centring_stiffness
    # [[unbalance]] replaced wholesale (one entry, at node 5)
    assert len(config.unbalance) == 1
    assert config.unbalance[0].node == 5
    assert config.unbalance[0].magnitude == pytest.approx(100e-6)
    assert config.base.pitching.law == "constant"
    assert config.analysis.response.harmonics == 8
    assert config.analysis.response.speed_range == ref.analysis.response.speed_range
    assert config.rotor == ref.rotor and config.materials == ref.materials


def test_relative_path_from_a_subfolder_and_chain(tmp_path):
    _write(tmp_path / "base.toml", PAPER.read_text())
    _write(tmp_path / "family" / "mid.toml", '''
extends = "../base.toml"
[[unbalance]]
node = 8
magnitude = "252 g*mm"
[analysis.response]
harmonics = 8
''')
    leaf = _write(tmp_path / "family" / "figs" / "leaf.toml", '''
extends = "../mid.toml"
[analysis.response]
max_eccentricity = 0.995
''')
    config = load_config(leaf)
    assert config.unbalance[0].magnitude == pytest.approx(252e-6)
    assert config.analysis.response.harmonics == 8
    assert config.analysis.response.max_eccentricity == pytest.approx(0.995)
    assert config.rotor.n_nodes == 21
    # overrides apply after the chain is resolved
    config = load_config(leaf, ["analysis.response.harmonics=5"])
    assert config.analysis.response.harmonics == 5
    # config show prints the merged configuration, which validates without extends
    shown = tomllib.loads(show_config(load_config(leaf)))
    assert "extends" not in shown
    assert config_from_dict(shown) == load_config(leaf)


def test_config_from_dict_needs_base_dir(tmp_path):
    _write(tmp_path / "base.toml", PAPER.read_text())
    raw = {"extends": "base.toml", "title": "from a dict"}
    with pytest.raises(ConfigError, match=r"^extends: got 'base.toml'; .*base_dir"):
        config_from_dict(raw)
    config = config_from_dict(raw, ["elements.sfd.clearance_ratio=0.728 %"], base_dir=tmp_path)
    assert config.title == "from a dict"
    assert config.elements["sfd"].clearance_ratio == pytest.approx(0.00728)


def test_cycle_is_an_error(tmp_path):
    a = _write(tmp_path / "a.toml", 'extends = "sub/b.toml"\ntitle = "a"\n')
    _write(tmp_path / "sub" / "b.toml", 'extends = "../a.toml"\n')
    with pytest.raises(ConfigError) as info:
        load_config(a)
    msg = str(info.value)
    assert msg.startswith("extends: got '../a.toml'; a cycle: a.toml -> b.toml -> a.toml")
    assert "\n" not in msg
    selfref = _write(tmp_path / "self.toml", 'extends = "self.toml"\n')
    with pytest.raises(ConfigError, match=r"a cycle: self\.toml -> self\.toml"):
        load_config(selfref)


@pytest.mark.parametrize("value, match", [
    ('"nothere.toml"', r"^extends: got 'nothere.toml'; no such file: .*nothere.toml"),
    ("3", r"^extends: got 3; must be a string"),
    ('["a.toml"]', r"^extends: got \['a.toml'\]; must be a string"),
    ('""', r"^extends: got ''; must be a string"),
])
def test_bad_extends(tmp_path, value, match):
    child = _write(tmp_path / "child.toml", f"extends = {value}\n")
    with pytest.raises(ConfigError, match=match):
        load_config(child)


def test_missing_base_in_the_middle_of_a_chain_names_its_file(tmp_path):
    _write(tmp_path / "mid.toml", 'extends = "gone.toml"\n')
    leaf = _write(tmp_path / "leaf.toml", 'extends = "mid.toml"\n')
    with pytest.raises(ConfigError, match=r"gone.toml.*\(in .*mid.toml\)"):
        load_config(leaf)


def test_read_toml_stays_raw(tmp_path):
    child = _write(tmp_path / "c.toml", f'extends = "{PAPER.as_posix()}"\n')
    assert read_toml(child) == {"extends": PAPER.as_posix()}


@pytest.mark.parametrize("text", ['extends = "missing.toml"\n', 'extends = 1\n',
                                  'extends = "c.toml"\n'])
def test_cli_exit_2_with_one_line(tmp_path, capsys, text):
    child = _write(tmp_path / "c.toml", text)
    assert main(["config", "show", str(child)]) == 2
    err = capsys.readouterr().err.strip()
    assert len(err.splitlines()) == 1
    assert "extends" in err


def test_cli_config_show_prints_the_merged_config(tmp_path, capsys):
    child = _write(tmp_path / "c.toml", f'extends = "{PAPER.as_posix()}"\n'
                   '[analysis.response]\nharmonics = 8\n')
    assert main(["config", "show", str(child)]) == 0
    shown = tomllib.loads(capsys.readouterr().out)
    assert shown["analysis"]["response"]["harmonics"] == 8
    assert shown["elements"]["sfd"]["viscosity"] == pytest.approx(0.0051)
