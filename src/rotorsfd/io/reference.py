"""The field reference of configuration files, generated from the schema (so the
documentation cannot drift from the code): ``rotorsfd config fields``."""

from __future__ import annotations

import typing
from dataclasses import dataclass
from typing import Any

from pydantic import BaseModel
from pydantic_core import PydanticUndefined

from rotorsfd.io.config import unwrap
from rotorsfd.io.schema import Config


@dataclass(frozen=True)
class FieldDoc:
    """One documented field: dotted path (``[]`` marks a list of tables), type, unit,
    default and description (with the allowed range)."""

    path: str
    type: str
    unit: str
    default: str
    description: str


def _type_text(annotation: Any, unit: str) -> str:
    ann = unwrap(annotation)
    if unit:
        return "quantity"
    if typing.get_origin(ann) is typing.Literal:
        return " \\| ".join(repr(a) for a in typing.get_args(ann))
    if typing.get_origin(ann) is list:
        return f"list of {_type_text(typing.get_args(ann)[0], '')}"
    return getattr(ann, "__name__", str(ann)).replace("typing.", "")


def _default_text(info: Any) -> str:
    if info.is_required():
        return "required"
    default = info.default
    if default is PydanticUndefined or default is None:
        return "-"
    if isinstance(default, BaseModel):
        return "-"
    return repr(default)


def field_reference(model: type[BaseModel] = Config, prefix: str = "") -> list[FieldDoc]:
    """Every leaf field of ``model``, depth first, in declaration order."""
    out: list[FieldDoc] = []
    for name, info in model.model_fields.items():
        path = f"{prefix}.{name}" if prefix else name
        ann = unwrap(info.annotation)
        origin = typing.get_origin(ann)
        inner = unwrap(typing.get_args(ann)[-1]) if origin in (list, dict) else None
        if isinstance(ann, type) and issubclass(ann, BaseModel):
            out += field_reference(ann, path)
        elif isinstance(inner, type) and issubclass(inner, BaseModel):
            out += field_reference(inner, f"{path}[]" if origin is list else f"{path}.<name>")
        else:
            extra = info.json_schema_extra if isinstance(info.json_schema_extra, dict) else {}
            unit = str(extra.get("unit", ""))
            out.append(FieldDoc(path, _type_text(info.annotation, unit), unit,
                                _default_text(info), info.description or ""))
    return out


def markdown_reference() -> str:
    """The field reference as a Markdown table."""
    lines = ["| field | type | SI unit | default | description |", "|---|---|---|---|---|"]
    for f in field_reference():
        desc = f.description.replace("|", "\\|")
        lines.append(f"| `{f.path}` | {f.type} | {f.unit or ''} | {f.default} | {desc} |")
    return "\n".join(lines) + "\n"
