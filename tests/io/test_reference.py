"""The generated configuration reference (README "Configuration reference" section)."""

from __future__ import annotations

import json
import re
import types
import typing
from collections import Counter
from pathlib import Path

import pytest
from pydantic import BaseModel

from rotorsfd import cli
from rotorsfd.io import reference
from rotorsfd.io.config import unwrap
from rotorsfd.io.schema import AnalysisConfig, Config
from rotorsfd.io.units import KINDS

README = Path(__file__).resolve().parents[2] / "README.md"


def _leaves(model: type[BaseModel], prefix: str = "") -> dict[str, typing.Any]:
    """Every leaf field of ``model`` -> its FieldInfo, walked here independently of the
    reference module (lists of tables: ``[]``, tables of tables: ``.<name>``, tables of
    several kinds: ``.<kind>``)."""
    out: dict[str, typing.Any] = {}
    for name, info in model.model_fields.items():
        path = f"{prefix}.{name}" if prefix else name
        ann = unwrap(info.annotation)
        origin = typing.get_origin(ann)
        inner = typing.get_args(ann)[-1] if origin in (list, dict) else None
        while typing.get_origin(inner) is typing.Annotated:     # keep a union of kinds
            inner = typing.get_args(inner)[0]
        kinds = typing.get_args(inner) if typing.get_origin(inner) in (
            typing.Union, types.UnionType) else (inner,)
        if origin is dict and all(isinstance(k, type) and issubclass(k, BaseModel)
                                  and "kind" in k.model_fields for k in kinds):
            for k in kinds:   # tables of several kinds: one group per kind, ".<kind>"
                kind = typing.get_args(k.model_fields["kind"].annotation)[0]
                out.update(_leaves(k, f"{path}.<{kind}>"))
        elif isinstance(ann, type) and issubclass(ann, BaseModel):
            out.update(_leaves(ann, path))
        elif isinstance(inner := unwrap(inner), type) and issubclass(inner, BaseModel):
            out.update(_leaves(inner, path + ("[]" if origin is list else ".<name>")))
        else:
            out[path] = info
    return out


LEAVES = _leaves(Config)
DOCS = {f.path: f for f in reference.field_reference()}


def _rendered_paths(markdown: str) -> list[str]:
    """Full dotted paths of the table rows of the Markdown reference, from its section
    headings and the (relative) keys of its rows."""
    paths, section = [], None
    for line in markdown.splitlines():
        if line.startswith("### "):
            m = re.fullmatch(r"### `\[\[?([^\]]+)\]\]?`", line)
            section = m[1] + ("[]" if line.startswith("### `[[") else "") if m else ""
        elif line.startswith("| `"):
            key = line.split("`")[1]
            assert section is not None, line
            paths.append(f"{section}.{key}" if section else key)
    return paths


def test_readme_block_is_current():
    text = README.read_text(encoding="utf-8")
    assert reference.is_current(text), (
        f"README.md's configuration reference differs from the schema; run: "
        f"{reference.UPDATE_COMMAND}")


def test_every_leaf_field_appears_exactly_once():
    rendered = Counter(_rendered_paths(reference.markdown_reference()))
    expected = Counter([*LEAVES, "extends"])
    assert rendered == expected
    assert len(LEAVES) > 150
    assert reference.field_reference()[0].path == "extends"
    assert Counter(f.path for f in reference.field_reference()) == expected  # csv / json


def test_sections_one_per_table_and_per_analysis():
    headers = [s.header for s in reference.sections()]
    assert headers[0] == "top-level keys"
    for name in ("[rotor]", "[elements.<sfd>]", "[base]", "[gravity]", "[reference]",
                 "[[unbalance]]", "[materials.<name>]"):
        assert name in headers
    assert [h for h in headers if h.startswith("[analysis")] == [
        f"[analysis.{n}]" for n in AnalysisConfig.model_fields]
    for s in reference.sections():
        assert s.intro and "\n" not in s.intro, s.header
        assert s.fields, s.header
        assert all(f.section == s.name for f in s.fields)
    assert not any(h.startswith("[base.") for h in headers)  # base stays one section


def test_every_field_has_description_and_allowed():
    for path, doc in DOCS.items():
        assert doc.description, path
        assert doc.allowed, path
        assert "allowed:" not in doc.description, path  # split off into its own column
        assert doc.default, path


def test_every_quantity_has_unit_and_range():
    quantities = {p: i for p, i in LEAVES.items()
                  if isinstance(i.json_schema_extra, dict) and "kind" in i.json_schema_extra}
    assert len(quantities) > 60
    for path, info in quantities.items():
        doc = DOCS[path]
        assert doc.unit == KINDS[info.json_schema_extra["kind"]].unit, path
        assert re.fullmatch(r"any value|[<>]=? \S+.*|\S+ <=? value <=? \S+.*", doc.allowed), \
            (path, doc.allowed)
        assert f"[{doc.unit}]" not in doc.description, path


def test_every_integer_states_its_range():
    ints = {p: i for p, i in LEAVES.items() if unwrap(i.annotation) is int}
    assert len(ints) > 15
    for path, info in ints.items():
        allowed = DOCS[path].allowed
        assert allowed.startswith("integer"), (path, allowed)
        bounds = {type(m).__name__: getattr(m, type(m).__name__.lower())
                  for m in info.metadata}
        for name, value in bounds.items():  # Ge / Le from the pydantic metadata
            assert re.search(rf"{'>=' if name == 'Ge' else '<='} {value}\b", allowed) or \
                re.search(rf"\b{value} <= value" if name == "Ge" else rf"value <= {value}\b",
                          allowed), (path, allowed)
    assert DOCS["analysis.simulate.periods"].allowed == "integer, 1 <= value <= 10000000"


def test_every_literal_lists_its_values():
    found = 0
    for path, info in LEAVES.items():
        ann = unwrap(info.annotation)
        if typing.get_origin(ann) is list:
            ann = unwrap(typing.get_args(ann)[0])
        if typing.get_origin(ann) is not typing.Literal:
            continue
        found += 1
        for value in typing.get_args(ann):
            assert json.dumps(value) in DOCS[path].allowed, (path, value)
    assert found >= 15
    assert DOCS["elements.<sfd>.cavitation"].allowed == '"pi", "none", "guembel"'
    assert DOCS["gravity.enabled"].allowed == "true, false"


def test_defaults_of_nested_tables_come_from_the_default_instance():
    # SpeedRange's own start_ratio is unset; each analysis sets its own default range
    analysis = AnalysisConfig()
    for path, doc in DOCS.items():
        if not path.startswith("analysis.") or "[]" in path or doc.default == "required":
            continue
        *parents, name = path.split(".")[1:]
        table = analysis
        for part in parents:
            table = getattr(table, part) if table is not None else None
        if table is not None:  # fields of an optional table (None): the class defaults
            assert doc.default == reference._toml(getattr(table, name)), path
    assert DOCS["analysis.bifurcation_diagram.speed_range.start_ratio"].default == "0.9"
    assert DOCS["analysis.modal.speed_range.stop_ratio"].default == "4"
    assert DOCS["rotor.shaft[].length"].default == "required"
    assert DOCS["reference.speed"].default == '"first_critical"'
    assert DOCS["reference.speed"].unit == "rad/s"


def test_markdown_cells_are_escaped():
    md = reference.markdown_reference()
    for line in md.splitlines():
        if line.startswith("| `"):
            cells = re.split(r"(?<!\\)\|", line)[1:-1]
            assert len(cells) == 5, line
    assert "\\<name>" in md  # '<name>' would be read as an HTML tag
    assert "\\|mu\\|" in md


_SAMPLE = ("# Title\r\n\nsome text é ∂ with a CRLF line above\n\n## Configuration reference\n\n"
           f"{reference.BEGIN}\nstale text\n{reference.END}\n\n## After\n\ntrailing, no newline")


def _parts(text: str) -> tuple[str, str]:
    start = text.index(reference.BEGIN) + len(reference.BEGIN)
    return text[:start], text[text.index(reference.END):]


def test_update_is_idempotent_and_keeps_the_rest(tmp_path):
    path = tmp_path / "README.md"
    path.write_bytes(_SAMPLE.encode())
    assert reference.main(["--check", str(path)]) == 1
    assert reference.main(["--update", str(path)]) == 0
    once = path.read_bytes()
    assert _parts(once.decode()) == _parts(_SAMPLE)  # byte-identical outside the markers
    assert b"\r\n" in once and b"stale text" not in once
    assert "| `clearance_ratio` | `1` | `-` | 0 < value < 1 |" in once.decode()
    assert reference.main(["--check", str(path)]) == 0
    assert reference.main(["--update", str(path)]) == 0
    assert path.read_bytes() == once


def test_check_fails_on_a_modified_copy(tmp_path, capsys):
    path = tmp_path / "README.md"
    path.write_text(reference.updated(_SAMPLE), encoding="utf-8")
    assert reference.main(["--check", str(path)]) == 0
    text = path.read_text(encoding="utf-8")
    path.write_text(text.replace("| `harmonics` |", "| `harmonix` |"), encoding="utf-8")
    capsys.readouterr()
    assert reference.main(["--check", str(path)]) == 1
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "--update" in err
    path.write_text(text.replace(reference.END, ""), encoding="utf-8")
    assert reference.main(["--check", str(path)]) == 2  # markers missing: not a drift


@pytest.mark.parametrize("fmt", ["markdown", "csv", "json"])
def test_cli_config_fields(fmt, capsys):
    assert cli.main(["config", "fields", "--format", fmt]) == 0
    out = capsys.readouterr().out
    if fmt == "json":
        rows = json.loads(out)
        assert [r["path"] for r in rows] == list(DOCS)
    elif fmt == "csv":
        assert out.count("\n") == len(DOCS) + 1
    else:
        assert out == reference.markdown_reference()
