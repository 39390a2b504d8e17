"""The field reference of configuration files, generated from the schema (so the
documentation cannot drift from the code).

``rotorsfd config fields`` prints it; ``python -m rotorsfd.io.reference --update README.md``
rewrites the block between the README markers and ``--check README.md`` exits 1 when that
block differs from the schema.

Each field's unit and allowed range come from the schema: :func:`rotorsfd.io.schema.quantity`
and :func:`~rotorsfd.io.schema.integer` write ``"<doc> [<unit>]; allowed: <range>"`` into the
description, and hand-written descriptions follow the same convention. Literal and boolean
fields list their values from the annotation.
"""

from __future__ import annotations

import argparse
import csv
import io
import json
import re
import sys
import types
import typing
from collections.abc import Iterator, Sequence
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

from annotated_types import Ge, Le, MaxLen, MinLen
from pydantic import BaseModel
from pydantic.fields import FieldInfo
from pydantic_core import PydanticUndefined

from rotorsfd.io.config import unwrap
from rotorsfd.io.schema import Config

BEGIN = "<!-- config-reference:begin -->"
END = "<!-- config-reference:end -->"
UPDATE_COMMAND = "python -m rotorsfd.io.reference --update README.md"

#: top-level tables whose sub-tables get a section each (one per analysis)
SPLIT = ("analysis",)

#: the ``extends`` key, read by :mod:`rotorsfd.io.config` before validation (not a schema field)
EXTENDS_DESCRIPTION = ("path of a config file this one builds on, relative to this file; its "
                       "tables are merged key by key, values and lists replaced")

_DESCRIPTION = re.compile(r"^(?P<doc>.*?)(?: \[(?P<unit>[^\]]+)\])?; allowed: (?P<allowed>.*)$",
                          re.S)


@dataclass(frozen=True)
class FieldDoc:
    """One documented leaf field.

    ``path`` is the full dotted path (``[]`` marks a list of tables, ``<name>`` a key of
    a table of tables), ``section`` the TOML table it is written in (``""``: top level)
    and ``key`` the path relative to that table. ``unit`` is the SI unit (``"1"``:
    dimensionless; ``""``: not a physical quantity), ``default`` the default in TOML
    syntax (``"required"``; ``"-"``: not set), ``allowed`` the allowed values or range.
    """

    path: str
    section: str
    key: str
    unit: str
    default: str
    allowed: str
    description: str


@dataclass(frozen=True)
class SectionDoc:
    """One section of the reference: a top-level table (or one analysis) and its fields."""

    name: str  # dotted table path; "" for the top-level keys
    header: str  # as written in TOML: "[rotor]", "[[unbalance]]", "[materials.<name>]"
    intro: str
    tables: tuple[str, ...]  # one line per nested table: "`[[rotor.shaft]]`: ..."
    fields: tuple[FieldDoc, ...]


# ---- reading the schema -----------------------------------------------------------------------


def _one_line(text: str | None) -> str:
    """The first paragraph of a docstring on one line (RST ``x`` made Markdown `x`)."""
    para = (text or "").strip().split("\n\n")[0]
    return " ".join(para.split()).replace("``", "`")


def _first_sentence(text: str | None) -> str:
    line = _one_line(text)
    m = re.search(r"(?<=\.)\s", line)
    return line[: m.start()] if m else line


def _toml(value: Any) -> str:
    """``value`` in TOML syntax (``"-"`` for None: not set)."""
    if value is None:
        return "-"
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        return f"{value:.6g}"
    if isinstance(value, str):
        return json.dumps(value)
    if isinstance(value, list | tuple):
        return "[" + ", ".join(_toml(v) for v in value) + "]"
    return str(value)


def _split_annotated(annotation: Any) -> tuple[Any, FieldInfo | None]:
    """(type, FieldInfo) of an ``Annotated[type, ..., Field(...)]`` list item."""
    if typing.get_origin(annotation) is typing.Annotated:
        base, *meta = typing.get_args(annotation)
        infos = [m for m in meta if isinstance(m, FieldInfo)]
        return base, (infos[-1] if infos else None)
    return annotation, None


def _length_text(metadata: Sequence[Any]) -> str:
    low = next((m.min_length for m in metadata if isinstance(m, MinLen)), None)
    high = next((m.max_length for m in metadata if isinstance(m, MaxLen)), None)
    if low is not None and low == high:
        return f"exactly {low}"
    if low and high is not None:
        return f"{low} to {high}"
    if low:
        return f"at least {low}"
    if high is not None:
        return f"at most {high}"
    return ""


def _integer_range(metadata: Sequence[Any]) -> str:
    """``">= 1"``, ``"1 <= value <= 2000"`` from the Ge / Le constraints of an int field."""
    low = next((m.ge for m in metadata if isinstance(m, Ge)), None)
    high = next((m.le for m in metadata if isinstance(m, Le)), None)
    if low is not None and high is not None:
        return f"{low} <= value <= {high}"
    if low is not None:
        return f">= {low}"
    return f"<= {high}" if high is not None else "any value"


def _parse_description(description: str | None) -> tuple[str, str, str]:
    """(doc, unit, allowed) of ``"<doc> [<unit>]; allowed: <allowed>"`` (parts may be "")."""
    m = _DESCRIPTION.match(description or "")
    if not m:
        return description or "", "", ""
    return m["doc"], m["unit"] or "", m["allowed"]


def _unit(info: FieldInfo | None, parsed_unit: str) -> str:
    extra = info.json_schema_extra if info is not None else None
    unit = str(extra.get("unit", "")) if isinstance(extra, dict) else ""
    unit = unit or parsed_unit
    return "1" if unit == "dimensionless" else unit


def _allowed(annotation: Any, info: FieldInfo | None) -> tuple[str, str]:
    """(unit, allowed values or range) of a field or list item."""
    _, parsed_unit, allowed = _parse_description(info.description if info else None)
    unit = _unit(info, parsed_unit)
    ann = unwrap(annotation)
    origin = typing.get_origin(ann)
    if ann is int and info is not None:
        allowed = _integer_range(info.metadata)
        return unit, f"integer {allowed}" if allowed[0] in "<>" else f"integer, {allowed}"
    if allowed:
        return unit, allowed
    if origin is typing.Literal:
        return unit, ", ".join(_toml(a) for a in typing.get_args(ann))
    if ann is bool:
        return unit, "true, false"
    if ann is str:
        return unit, "any string"
    if origin is list:
        item_unit, item = _allowed(*_split_annotated(typing.get_args(ann)[0]))
        length = _length_text(info.metadata if info else [])
        items = "item" if length.endswith(" 1") else "items"
        return unit or item_unit, (f"list of {length} {items}" if length else "list") + (
            f"; each {item}" if item else "")
    if ann is float:
        return unit, "any value"
    return unit, ""


def _default(info: FieldInfo, parent_default: BaseModel | None, name: str) -> str:
    if parent_default is not None:
        return _toml(getattr(parent_default, name))
    if info.is_required():
        return "required"
    default = info.default
    if default is PydanticUndefined or isinstance(default, BaseModel):
        return "-"
    return _toml(default)


def _kind_tables(annotation: Any) -> list[tuple[str, type[BaseModel]]]:
    """[(kind, model), ...] of a table of tables told apart by their ``kind`` field (the
    ``[elements.<name>]`` tables, one model per registered kind); [] for any other field."""
    ann = unwrap(annotation)
    if typing.get_origin(ann) is not dict:
        return []
    inner = typing.get_args(ann)[-1]
    while typing.get_origin(inner) is typing.Annotated:   # keep the union of kinds
        inner = typing.get_args(inner)[0]
    members = typing.get_args(inner) if typing.get_origin(inner) in (
        typing.Union, types.UnionType) else (inner,)
    out = []
    for m in members:
        if not (isinstance(m, type) and issubclass(m, BaseModel) and "kind" in m.model_fields
                and typing.get_origin(m.model_fields["kind"].annotation) is typing.Literal):
            return []
        out.append((typing.get_args(m.model_fields["kind"].annotation)[0], m))
    return out


def _model_of(annotation: Any) -> tuple[type[BaseModel] | None, str]:
    """(model, container) of a field holding tables: container is "", "list" or "dict"
    (None for the tables of several kinds, :func:`_kind_tables`)."""
    if _kind_tables(annotation):
        return None, ""
    ann = unwrap(annotation)
    if isinstance(ann, type) and issubclass(ann, BaseModel):
        return ann, ""
    origin = typing.get_origin(ann)
    if origin in (list, dict):
        inner = unwrap(typing.get_args(ann)[-1])
        if isinstance(inner, type) and issubclass(inner, BaseModel):
            return inner, "list" if origin is list else "dict"
    return None, ""


def _child_path(path: str, name: str, container: str) -> str:
    base = f"{path}.{name}" if path else name
    return {"list": f"{base}[]", "dict": f"{base}.<name>"}.get(container, base)


def _header(path: str, container: str) -> str:
    table = path.removesuffix("[]")
    return f"[[{table}]]" if container == "list" else f"[{table}]"


def _leaves(model: type[BaseModel], path: str, section: str,
            default: BaseModel | None) -> Iterator[FieldDoc]:
    for name, info in model.model_fields.items():
        if _kind_tables(info.annotation):   # documented in a section per kind
            continue
        sub, container = _model_of(info.annotation)
        child = _child_path(path, name, container)
        if sub is not None:
            sub_default = getattr(default, name) if default is not None else info.default
            yield from _leaves(sub, child, section,
                               sub_default if isinstance(sub_default, BaseModel)
                               and not container else None)
            continue
        unit, allowed = _allowed(info.annotation, info)
        doc, _, _ = _parse_description(info.description)
        key = child[len(section) + 1:] if section else child
        yield FieldDoc(child, section, key, unit, _default(info, default, name), allowed, doc)


def _table_entries(model: type[BaseModel], path: str) -> Iterator[tuple[str, Any, str]]:
    """(header, group key, text) of every nested table of ``model``, parents first."""
    for name, info in model.model_fields.items():
        sub, container = _model_of(info.annotation)
        if sub is None:
            continue
        child = _child_path(path, name, container)
        notes = _notes(info)
        text = f"{f' ({notes})' if notes else ''}: {_first_sentence(sub.__doc__)}"
        yield f"`{_header(child, container)}`", (sub, path, text), text
        yield from _table_entries(sub, child)


def _tables(model: type[BaseModel], path: str) -> list[str]:
    """One line per nested table of ``model``; sibling tables of one model and the same
    notes in a row share a line (``[base.x]``, ``[base.y]``, ``[base.z]``)."""
    lines: list[tuple[list[str], Any, str]] = []
    for header, key, text in _table_entries(model, path):
        if lines and lines[-1][1] == key:
            lines[-1][0].append(header)
        else:
            lines.append(([header], key, text))
    return [", ".join(headers) + text for headers, _, text in lines]


def _notes(info: FieldInfo) -> str:
    """The field's own description, 'required' and the number of tables, joined by '; '."""
    notes = [_one_line(info.description).rstrip(".")] if info.description else []
    notes += ["required"] if info.is_required() else []
    length = _length_text(info.metadata)
    notes += [f"{length} table{'' if length.endswith(' 1') else 's'}"] if length else []
    return "; ".join(notes)


def sections(model: type[BaseModel] = Config) -> list[SectionDoc]:
    """The reference, one section per top-level table (one per table of ``SPLIT`` tables),
    with the ``extends`` key first."""
    extends = FieldDoc("extends", "", "extends", "", "-", "a file path", EXTENDS_DESCRIPTION)
    top = [extends] + [f for f in _leaves(model, "", "", None) if "." not in f.path]
    out = [SectionDoc("", "top-level keys", _one_line(model.__doc__) + " These keys come "
                      "before the first table.", (), tuple(top))]
    for name, info in model.model_fields.items():
        for kind, part in _kind_tables(info.annotation):
            section = f"{name}.<{kind}>"
            intro = (f"{_one_line(part.__doc__)} One table per element of this kind, "
                     f"[{name}.<any name>] with kind = \"{kind}\"; the name labels its "
                     "results.")
            out.append(SectionDoc(section, f"[{section}]", intro,
                                  tuple(_tables(part, section)),
                                  tuple(_leaves(part, section, section, None))))
        sub, container = _model_of(info.annotation)
        if sub is None:
            continue
        default = info.default if isinstance(info.default, BaseModel) else None
        if name in SPLIT:
            parts = [(f"{name}.{n}", i, *_model_of(i.annotation))
                     for n, i in sub.model_fields.items()]
            parent_default = default
        else:
            parts = [(name, info, sub, container)]
            parent_default = None
        for path, part_info, part, part_container in parts:
            if part is None:
                raise TypeError(f"{path}: a leaf inside a split table")
            part_default = (getattr(parent_default, path.rsplit(".", 1)[1])
                            if parent_default is not None else default)
            section = _child_path("", path, part_container)
            notes = _notes(part_info)
            intro = _one_line(part.__doc__) + (f" {notes[0].upper()}{notes[1:]}." if notes
                                               else "")
            fields = tuple(_leaves(part, section, section,
                                   part_default if not part_container else None))
            out.append(SectionDoc(section, _header(section, part_container), intro,
                                  tuple(_tables(part, section)), fields))
    return out


def field_reference(model: type[BaseModel] = Config) -> list[FieldDoc]:
    """Every documented field: ``extends`` then every leaf field of ``model``, depth first,
    in declaration order."""
    return [f for s in sections(model) for f in s.fields]


# ---- output --------------------------------------------------------------------------------


def _md(text: str) -> str:
    """Plain text made safe inside a Markdown table cell."""
    text = text.replace("\\", "\\\\").replace("|", "\\|").replace("*", "\\*")
    text = text.replace("~", "\\~")
    return re.sub(r"<(?=[A-Za-z/!?])", r"\\<", text)


def _code(text: str) -> str:
    return "`" + text.replace("|", "\\|") + "`" if text else ""


def _md_prose(text: str) -> str:
    """Like :func:`_md` but keeps `code spans` (from the docstrings) as they are."""
    parts = text.split("`")
    return "`".join(p if i % 2 else _md(p) for i, p in enumerate(parts))


LEGEND = ("Values are SI numbers in the unit shown, or strings with units (`\"0.127 mm\"`, "
          "`\"3000 rpm\"`, `\"90 deg\"`); unit `1` means dimensionless. Default `required`: "
          "the key must be given when its table is; `-`: not set (an alternative form or "
          "an optional setting). `[]` in a key marks a list of tables (`[[...]]` in TOML).")


def markdown_reference(heading: str = "###") -> str:
    """The field reference as Markdown: a legend, then one table per section."""
    lines = [LEGEND]
    for s in sections():
        title = s.header if s.name == "" else f"`{s.header}`"
        lines += ["", f"{heading} {title}", "", _md_prose(s.intro)]
        if s.tables:
            lines += [""] + [f"- {_md_prose(t)}" for t in s.tables]
        lines += ["", "| field | unit | default | allowed | description |",
                  "|---|---|---|---|---|"]
        lines += [f"| {_code(f.key)} | {_code(f.unit)} | {_code(f.default)} | "
                  f"{_md(f.allowed)} | {_md(f.description)} |" for f in s.fields]
    return "\n".join(lines) + "\n"


def csv_reference() -> str:
    """The field reference as CSV, one row per field (header: the FieldDoc attributes)."""
    out = io.StringIO()
    names = list(FieldDoc.__dataclass_fields__)
    writer = csv.DictWriter(out, names, lineterminator="\n")
    writer.writeheader()
    writer.writerows(asdict(f) for f in field_reference())
    return out.getvalue()


def json_reference() -> str:
    """The field reference as a JSON list of objects (the FieldDoc attributes)."""
    return json.dumps([asdict(f) for f in field_reference()], indent=1) + "\n"


FORMATS = {"markdown": markdown_reference, "csv": csv_reference, "json": json_reference}


# ---- the README block ------------------------------------------------------------------------


class MarkerError(ValueError):
    """The file lacks the begin/end markers (or has them out of order or twice)."""


def _block_span(text: str) -> tuple[int, int]:
    """(start, end) of the text between the markers."""
    if text.count(BEGIN) != 1 or text.count(END) != 1:
        raise MarkerError(f"needs exactly one {BEGIN!r} and one {END!r} line")
    start = text.index(BEGIN) + len(BEGIN)
    end = text.index(END)
    if end < start:
        raise MarkerError(f"{END!r} comes before {BEGIN!r}")
    return start, end


def block() -> str:
    """The text that belongs between the markers."""
    return "\n\n" + markdown_reference() + "\n"


def updated(text: str) -> str:
    """``text`` with the block between the markers replaced by the generated reference."""
    start, end = _block_span(text)
    return text[:start] + block() + text[end:]


def is_current(text: str) -> bool:
    """True when the block between the markers equals the generated reference."""
    start, end = _block_span(text)
    return text[start:end] == block()


def main(argv: Sequence[str] | None = None) -> int:
    """``--update FILE`` / ``--check FILE``; with neither, print the reference."""
    parser = argparse.ArgumentParser(prog="python -m rotorsfd.io.reference",
                                     description=__doc__.split("\n\n")[0])
    action = parser.add_mutually_exclusive_group()
    action.add_argument("--update", metavar="FILE", type=Path,
                        help=f"rewrite the text between {BEGIN} and {END}")
    action.add_argument("--check", metavar="FILE", type=Path,
                        help="exit 1 if the text between the markers is not current")
    parser.add_argument("--format", choices=sorted(FORMATS), default="markdown",
                        help="output format when printing (default: markdown)")
    args = parser.parse_args(argv)
    path = args.update or args.check
    if path is None:
        sys.stdout.write(FORMATS[args.format]())
        return 0
    try:
        with path.open(encoding="utf-8", newline="") as f:
            text = f.read()
        if args.update:
            new = updated(text)
            if new != text:
                with path.open("w", encoding="utf-8", newline="") as f:
                    f.write(new)
            return 0
        if is_current(text):
            return 0
    except (OSError, MarkerError) as exc:
        print(f"{path}: {exc}", file=sys.stderr)
        return 2
    print(f"{path}: the configuration reference is out of date; run: "
          f"python -m rotorsfd.io.reference --update {path}", file=sys.stderr)
    return 1


if __name__ == "__main__":
    sys.exit(main())
