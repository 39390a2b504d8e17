"""Load, override, validate and show configurations.

``load_config("rotor.toml", overrides=["elements.sfd.clearance_ratio=0.61 %"]) -> Config``.
An override is ``KEY=VALUE``: KEY a dotted path into the TOML (``rotor.shaft[0].length``
or ``rotor.shaft.0.length``; lists are indexed from 0), VALUE a TOML value or, if it is not
one, a bare string (so ``0.61 %`` and ``none`` need no quotes). Every problem is raised as
one :class:`~rotorsfd.errors.ConfigError` naming the field, the value and what is allowed.

Inheritance: a top-level ``extends = "base.toml"`` (a path relative to the folder of the
file that contains it; chains allowed) reads that file first and merges this file's tables
into it key by key, recursively; scalars and arrays (arrays of tables such as
``[[unbalance]]`` included) replace the base's wholesale. :func:`load_config` and
:func:`read_config` resolve it before the overrides and the validation.
:func:`config_from_dict` resolves it only when given ``base_dir`` (the folder a relative
``extends`` is taken from); without it a dict that still holds ``extends`` is an error.
"""

from __future__ import annotations

import difflib
import json
import math
import tomllib
import types
import typing
from collections.abc import Iterable, Mapping, Sequence
from pathlib import Path
from typing import Any

from pydantic import BaseModel, ValidationError

from rotorsfd.elements import KINDS
from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import Config, split_path


class _Missing:
    def __repr__(self) -> str:
        return "nothing"


MISSING = _Missing()


# ---- loading ---------------------------------------------------------------------------------


def read_toml(path: str | Path) -> dict[str, Any]:
    """The raw TOML table of ``path``; ConfigError if missing or not valid TOML."""
    p = Path(path)
    try:
        data = p.read_bytes()
    except FileNotFoundError:
        raise ConfigError("config file", str(path), "no such file") from None
    except OSError as exc:
        raise ConfigError("config file", str(path), f"cannot be read ({exc.strerror})") \
            from None
    try:
        return tomllib.loads(data.decode("utf-8"))
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise ConfigError("config file", str(path), f"must be valid TOML: {exc}") from None


def load_config(path: str | Path, overrides: Iterable[str] = ()) -> Config:
    """Read (``extends`` resolved), override (``KEY=VALUE`` strings) and validate the TOML
    configuration."""
    return config_from_dict(read_config(path), overrides)


EXTENDS = "extends"


def read_config(path: str | Path) -> dict[str, Any]:
    """The raw table of the TOML file ``path`` with its ``extends`` chain resolved: the
    base file(s) first, this file's tables merged into them (:func:`merge_tables`)."""
    return _resolve_extends(read_toml(path), Path(path).parent, (Path(path),))


def merge_tables(base: Mapping[str, Any], top: Mapping[str, Any]) -> dict[str, Any]:
    """``base`` with ``top`` merged into it: tables key by key, recursively; any other
    value of ``top`` (scalar, array, array of tables) replaces the base's wholesale."""
    out = _deep_copy(base)
    for key, value in top.items():
        if isinstance(value, Mapping) and isinstance(out.get(key), dict):
            out[key] = merge_tables(out[key], value)
        else:
            out[key] = _deep_copy(value)
    return out


def _resolve_extends(raw: Mapping[str, Any], base_dir: Path,
                     chain: tuple[Path, ...]) -> dict[str, Any]:
    """``raw`` (read from ``chain[-1]``, or a dict when ``chain`` is empty) merged into the
    config its ``extends`` names, relative to ``base_dir``."""
    if EXTENDS not in raw:
        return _deep_copy(raw)
    value = raw[EXTENDS]
    where = f" (in {chain[-1]})" if chain else ""
    if not isinstance(value, str) or not value.strip():
        raise ConfigError(EXTENDS, value, "must be a string: the path of the base config "
                          f"file, relative to the folder of the file that contains it{where}")
    path = base_dir / value
    if not path.is_file():
        raise ConfigError(EXTENDS, value, f"no such file: {path} (the path is relative to "
                          f"the folder of the file that contains it{where})")
    seen = [p.resolve() for p in chain]
    if path.resolve() in seen:
        cycle = " -> ".join(p.name for p in (*chain[seen.index(path.resolve()):], path))
        raise ConfigError(EXTENDS, value, f"a cycle: {cycle}; a config may extend another "
                          "only if that one does not lead back to it")
    base = _resolve_extends(read_toml(path), path.parent, (*chain, path))
    return merge_tables(base, {k: v for k, v in raw.items() if k != EXTENDS})


def config_from_dict(raw: Mapping[str, Any], overrides: Iterable[str] = (),
                     base_dir: str | Path | None = None) -> Config:
    """Validate a raw (TOML-like) dict after applying ``KEY=VALUE`` overrides. A top-level
    ``extends`` is resolved relative to ``base_dir``; without ``base_dir`` it is an error
    (a dict does not know which folder its path is relative to)."""
    if EXTENDS in raw:
        if base_dir is None:
            raise ConfigError(EXTENDS, raw[EXTENDS], "config_from_dict cannot resolve it: "
                              "pass base_dir (the folder the path is relative to) or use "
                              "load_config(path)")
        raw = _resolve_extends(raw, Path(base_dir), ())
    data = _deep_copy(raw)
    for item in overrides:
        key, value = parse_override(item)
        set_path(data, key, value)
    return validate(data)


def validate(data: Mapping[str, Any]) -> Config:
    """``Config.model_validate`` with the first error turned into one ConfigError."""
    try:
        config = Config.model_validate(data)
    except ValidationError as exc:
        raise to_config_error(exc, data) from None
    _strict_booleans(Config, data, ())
    return config


def _strict_booleans(model: type[BaseModel], data: Any, where: tuple[Any, ...],
                     root: Any = None) -> None:
    """ConfigError for a true/false field given anything but a TOML boolean: pydantic
    takes ``"yes"``, ``"off"``, ``1`` and ``"false"`` (a string, hence truthy to a reader)
    as booleans; a config must say ``true`` or ``false``. ``root``: the whole raw config
    (default ``data``)."""
    if not isinstance(data, Mapping):
        return
    root = data if root is None else root
    for key, value in data.items():
        info = model.model_fields.get(key) if isinstance(key, str) else None
        if info is None:
            continue
        annotation = unwrap(info.annotation)
        path = (*where, key)
        if annotation is bool and not isinstance(value, bool):
            desc = _description(list(path), root)
            raise ConfigError(_join(path), value, "expected true or false"
                              + (f": {desc}" if desc else ""))
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            _strict_booleans(annotation, value, path, root)
        elif typing.get_origin(annotation) in (list, dict):
            items = value.items() if isinstance(value, Mapping) else \
                enumerate(value) if isinstance(value, list) else ()
            for k, v in items:
                item = table_model(typing.get_args(annotation)[-1], v)
                if isinstance(item, type) and issubclass(item, BaseModel):
                    _strict_booleans(item, v, (*path, k), root)


def with_values(config: Config, values: Mapping[str, Any]) -> Config:
    """A new validated Config with the fields at the dotted paths set to ``values``
    (SI numbers or strings with units): the entry point of parameter studies."""
    data = dump_config(config)
    for key, value in values.items():
        set_path(data, key, value)
    return validate(data)


# ---- overrides -------------------------------------------------------------------------------


def parse_override(item: str) -> tuple[str, Any]:
    """``"a.b=0.5 mm"`` -> ``("a.b", "0.5 mm")``; the value is read as TOML if it is."""
    key, sep, text = item.partition("=")
    key, text = key.strip(), text.strip()
    if not sep or not key:
        raise ConfigError("--set", item,
                          "expected KEY=VALUE, e.g. elements.sfd.clearance_ratio=0.61%")
    if not text:
        raise ConfigError(key, item, "--set needs a value after '='")
    try:
        value = tomllib.loads(f"v = {text}")["v"]
    except tomllib.TOMLDecodeError:
        value = text
    return key, value


def set_path(data: dict[str, Any], key: str, value: Any) -> None:
    """Set ``data`` at dotted ``key`` (creating tables; index len(list) appends a table)."""
    try:
        parts = split_path(key)
    except ValueError as exc:
        raise ConfigError(key, value, f"--set needs a dotted path: {exc}") from None
    node: Any = data
    for i, part in enumerate(parts):
        last = i == len(parts) - 1
        where = _join(parts[:i]) or "the top level"
        if isinstance(part, str):
            if not isinstance(node, dict):
                raise ConfigError(key, value, f"{where} is not a table")
            if last:
                node[part] = value
            else:
                node = node.setdefault(part, [] if isinstance(parts[i + 1], int) else {})
        else:
            if not isinstance(node, list):
                raise ConfigError(key, value, f"{where} is not a list")
            if part == len(node):  # one past the end appends (a new [[table]])
                node.append({})
            if not 0 <= part < len(node):
                raise ConfigError(key, value, f"index {part} out of range: {where} has "
                                  f"{len(node)} entries (indices from 0)")
            if last:
                node[part] = value
            else:
                node = node[part]


def get_path(config: Config, key: str) -> Any:
    """The resolved value (SI) at dotted ``key``, or None if that field is not set."""
    return _lookup(dump_config(config), split_path(key))[1]


# ---- errors ----------------------------------------------------------------------------------


def _join(loc: Iterable[Any]) -> str:
    out = ""
    for part in loc:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out


def _lookup(data: Any, loc: Iterable[Any]) -> tuple[bool, Any]:
    """(found, value) at the key sequence ``loc`` of nested dicts and lists."""
    for part in loc:
        try:
            data = data[part]
        except (KeyError, IndexError, TypeError):
            return False, None
    return True, data


def table_model(annotation: Any, table: Any) -> Any:
    """The model of one table of a field: for tables of several kinds (a union of models
    told apart by their ``kind``, the ``[elements.<name>]`` tables) the member whose kind
    the table names; otherwise :func:`unwrap`."""
    inner = annotation
    while typing.get_origin(inner) is typing.Annotated:
        inner = typing.get_args(inner)[0]
    if typing.get_origin(inner) in (typing.Union, types.UnionType) and isinstance(
            table, Mapping):
        for member in typing.get_args(inner):
            fields = getattr(member, "model_fields", {})
            if "kind" in fields and fields["kind"].default == table.get("kind"):
                return member
    return unwrap(annotation)


def unwrap(annotation: Any) -> Any:
    """The model or container inside Optional / Annotated."""
    while True:
        origin = typing.get_origin(annotation)
        if origin is typing.Annotated:
            annotation = typing.get_args(annotation)[0]
        elif origin in (typing.Union, types.UnionType):
            args = [a for a in typing.get_args(annotation) if a is not type(None)]
            models = [a for a in args if isinstance(a, type) and issubclass(a, BaseModel)]
            annotation = models[0] if models else args[0]
        else:
            return annotation


def _schema_at(loc: Sequence[Any], data: Any = None
               ) -> tuple[type[BaseModel] | None, Any]:
    """(model class holding the last field of ``loc``, that field's FieldInfo or None);
    ``data`` (the raw tables) picks the model of a table of several kinds."""
    model: Any = Config
    info = None
    holder = None
    for i, part in enumerate(loc):
        if isinstance(model, type) and issubclass(model, BaseModel):
            info = model.model_fields.get(part) if isinstance(part, str) else None
            if info is None:
                return model, None
            holder, model = model, unwrap(info.annotation)
        elif typing.get_origin(model) in (list, dict):
            model = table_model(typing.get_args(model)[-1], _lookup(data, loc[:i + 1])[1])
        else:
            return holder, info
    return holder, info


def _without_tags(loc: Sequence[Any], data: Any) -> list[Any]:
    """``loc`` without the tags pydantic adds inside unions: a member type of a union field
    (``harmonics: int | 'auto'`` tags ``'int'``, ``"literal['auto']"``) and the kind of a
    table of several kinds (``elements.front.sfd.viscosity``)."""
    out: list[Any] = []
    for i, p in enumerate(loc):
        if i == len(loc) - 1 and i > 0 and isinstance(p, str) and (
                p in ("int", "float", "str", "bool") or p.startswith("literal[")):
            continue
        found, table = _lookup(data, out)
        if (i > 0 and isinstance(p, str) and found and isinstance(table, Mapping)
                and table.get("kind") == p and p not in table):
            continue
        out.append(p)
    return out


def _description(loc: list[Any], data: Any = None) -> str:
    _, info = _schema_at(loc, data)
    if info is None:
        return ""
    if info.description:
        return info.description
    annotation = unwrap(info.annotation)
    if isinstance(annotation, type) and issubclass(annotation, BaseModel) and annotation.__doc__:
        return annotation.__doc__.strip().splitlines()[0].replace("``", "")
    return ""


_RANGE = {"greater_than": ">", "greater_than_equal": ">=", "less_than": "<",
          "less_than_equal": "<="}
_TYPES = {
    "int_type": "an integer", "int_parsing": "an integer", "int_from_float": "an integer",
    "float_type": "a number", "float_parsing": "a number", "bool_type": "true or false",
    "bool_parsing": "true or false", "string_type": "a string", "list_type": "a list",
    "dict_type": "a table", "model_type": "a table", "model_attributes_type": "a table",
}


def to_config_error(exc: ValidationError, data: Any) -> ConfigError:
    """The first pydantic error as one ConfigError: dotted field, value, what is allowed
    (an unknown key first: it is often the misspelling of a missing one)."""
    errors = exc.errors()
    err = next((e for e in errors if e["type"] == "extra_forbidden"), errors[0])
    loc = _without_tags(err["loc"], data)
    ctx = err.get("ctx") or {}
    kind = err["type"]
    if kind == "rotorsfd" and "path" in ctx:
        loc += list(ctx["path"])
    found, value = _lookup(data, loc)
    if kind == "rotorsfd" and "path" in ctx and not ctx["path"]:
        found = False  # an error about the table as a whole: its value says what was given
    if not found:
        value = ctx.get("value", err.get("input", MISSING))
        value = MISSING if value is None else value
    if kind in ("union_tag_invalid", "union_tag_not_found"):   # the kind of a table
        tag = ctx.get("discriminator", "'kind'").strip("'")
        found, value = _lookup(data, [*loc, tag])
        kinds = ctx.get("expected_tags") or ", ".join(repr(k) for k in KINDS)
        return ConfigError(_join([*loc, tag]), value if found else MISSING,
                           f"required, the element's kind: {kinds}" if not found
                           else f"allowed: {kinds}")
    field = _join(loc) or "config"
    desc = _description(loc, data)
    if kind == "missing":
        return ConfigError(field, MISSING, f"required: {desc}" if desc else "required")
    if kind == "extra_forbidden":
        holder, _ = _schema_at(loc, data)  # the model that lacks the key
        allowed = sorted(holder.model_fields) if holder is not None else []
        near = difflib.get_close_matches(str(loc[-1]), allowed, n=1)
        hint = f"; did you mean {near[0]!r}?" if near else ""
        return ConfigError(field, value, f"unknown key{hint} (allowed here: "
                           f"{', '.join(allowed)})")
    if kind == "literal_error":
        return ConfigError(field, value, f"allowed: {ctx.get('expected')}")
    if kind in _RANGE:
        bound = next(iter(ctx.values()))
        doc = desc.split("; allowed:")[0]
        return ConfigError(field, value, f"must be {_RANGE[kind]} {bound}"
                           + (f" ({doc})" if doc else ""))
    if kind in _TYPES:
        return ConfigError(field, value, f"expected {_TYPES[kind]}"
                           + (f": {desc}" if desc else ""))
    if kind in ("too_short", "too_long"):
        return ConfigError(field, value, err["msg"].replace("List", "list").replace(
            "Dictionary", "table") + (f" ({desc})" if desc else ""))
    if kind == "string_pattern_mismatch":
        return ConfigError(field, value, desc or err["msg"])
    return ConfigError(field, value, err["msg"])


# ---- show ------------------------------------------------------------------------------------


def dump_config(config: Config) -> dict[str, Any]:
    """Plain dict of the resolved configuration (SI numbers, defaults filled in; alternative
    forms that were not used are left out, so the dict validates again to ``config``)."""
    return config.model_dump(mode="json", exclude_none=True)


def derived_values(config: Config) -> dict[str, str]:
    """Quantities derived from the configuration, shown as comments by ``config show``."""
    m = config.rotor.matrices
    out = {"rotor": f"{config.rotor.n_nodes} nodes, "
                    f"{sum(s.n_elements for s in config.rotor.shaft)} shaft elements, "
                    f"length {sum(s.length for s in config.rotor.shaft):.6g} m"
           if m is None else f"{config.rotor.n_nodes} nodes, given by matrices "
                             f"({m.file or m.mass})"}
    if config.rotor.shafts:
        out["rotor"] = f"{config.rotor.n_nodes} nodes, shafts " + ", ".join(
            f"{s.name} (nodes {lo}..{hi}, speed ratio {s.speed_ratio:g})"
            for s, (lo, hi) in zip(config.rotor.shafts, config.rotor.shaft_ranges(),
                                   strict=True))
    for name, table in config.elements.items():
        text = table.derived_text() if hasattr(table, "derived_text") else ""
        if text:
            out[f"elements.{name}"] = text
    return out


def show_config(config: Config, fmt: str = "toml") -> str:
    """The resolved configuration as TOML (with derived values as comments) or JSON."""
    data = dump_config(config)
    if fmt == "json":
        return json.dumps(data, indent=2) + "\n"
    if fmt != "toml":
        raise ConfigError("--format", fmt, "allowed: 'toml' or 'json'")
    header = ["# rotorsfd resolved configuration: SI units (m, kg, s, rad, N, Pa)"]
    return "\n".join(header) + "\n" + to_toml(data, comments=derived_values(config))


def to_toml(data: Mapping[str, Any], comments: Mapping[str, str] | None = None) -> str:
    """TOML text of a nested dict of scalars, lists and tables."""
    lines: list[str] = []
    _emit_table(lines, data, (), dict(comments or {}))
    return "\n".join(lines).strip() + "\n"


def _is_table_list(value: Any) -> bool:
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def _emit_table(lines: list[str], table: Mapping[str, Any], path: tuple[str, ...],
                comments: dict[str, str], array: bool = False) -> None:
    name = ".".join(_toml_key(p) for p in path)
    scalars = {k: v for k, v in table.items()
               if not isinstance(v, dict) and not _is_table_list(v)}
    note = comments.get(".".join(path))
    if path and (array or scalars or note or not table):
        lines.append("")
        lines.append(f"[[{name}]]" if array else f"[{name}]")
    if note:
        lines.append(f"# derived: {note}")
    for key, value in scalars.items():
        lines.append(f"{_toml_key(key)} = {_toml_value(value)}")
    for key, value in table.items():
        if isinstance(value, dict):
            _emit_table(lines, value, (*path, key), comments)
        elif _is_table_list(value):
            for item in value:
                _emit_table(lines, item, (*path, key), comments, array=True)


def _toml_key(key: str) -> str:
    return key if key.replace("_", "a").replace("-", "a").isalnum() else json.dumps(key)


def _toml_value(value: Any) -> str:
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, int):
        return str(value)
    if isinstance(value, float):
        if math.isnan(value):
            return "nan"
        if math.isinf(value):
            return "inf" if value > 0 else "-inf"
        return repr(value)
    if isinstance(value, str):
        return json.dumps(value, ensure_ascii=False)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    if isinstance(value, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(v)}"
                               for k, v in value.items()) + "}"
    raise TypeError(f"cannot write {type(value).__name__} as TOML")


def _deep_copy(value: Any) -> Any:
    if isinstance(value, Mapping):
        return {k: _deep_copy(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_deep_copy(v) for v in value]
    return value
