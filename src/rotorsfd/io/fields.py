"""Field helpers of the configuration schema: quantities with units and ranges, nodes, names.

Every physical field is declared with :func:`quantity`: its kind (SI unit) and allowed range
go into the field's description, so the generated documentation cannot drift. Shared by
:mod:`rotorsfd.io.schema` and the config models of the nonlinear elements
(:mod:`rotorsfd.elements`).
"""

from typing import Annotated, Any

from pydantic import BaseModel, BeforeValidator, ConfigDict, Field
from pydantic_core import PydanticCustomError

from rotorsfd.io.units import KINDS, UnitError, to_si


def fail(path: str | tuple[str | int, ...], value: Any, allowed: str) -> PydanticCustomError:
    """A validation error about ``path`` (relative to the model that raises it)."""
    if isinstance(path, str):
        path = tuple(path.split("."))
    return PydanticCustomError("rotorsfd", "{allowed}", {"path": path, "value": value,
                                                         "allowed": allowed})


def range_text(unit: str, gt: float | None = None, ge: float | None = None,
               lt: float | None = None, le: float | None = None) -> str:
    """``"> 0 m"``, ``"0 < value < 1"``, ``"any value"``."""
    u = "" if unit == "1" else f" {unit}"
    low = (f"{gt:g} <", f"> {gt:g}") if gt is not None else (
        (f"{ge:g} <=", f">= {ge:g}") if ge is not None else None)
    high = f"< {lt:g}" if lt is not None else (f"<= {le:g}" if le is not None else None)
    if low and high:
        return f"{low[0]} value {high}{u}"
    if low:
        return f"{low[1]}{u}"
    if high:
        return f"{high}{u}"
    return "any value"


def in_range(x: float, gt, ge, lt, le) -> bool:
    return ((gt is None or x > gt) and (ge is None or x >= ge)
            and (lt is None or x < lt) and (le is None or x <= le))


def quantity(kind: str, doc: str, *, gt: float | None = None, ge: float | None = None,
             lt: float | None = None, le: float | None = None, optional: bool = False) -> Any:
    """Annotated float field of physical ``kind`` (a key of ``units.KINDS``) in SI.

    Accepts an SI number or a string with units; checks the dimension and the range.
    """
    unit = KINDS[kind].unit
    allowed_range = range_text(unit, gt, ge, lt, le)

    def parse(value: Any) -> Any:
        if value is None and optional:
            return None
        try:
            si = to_si(value, kind)
        except UnitError as exc:
            raise PydanticCustomError("rotorsfd", "{allowed}",
                                      {"allowed": str(exc), "value": value}) from None
        if not in_range(si, gt, ge, lt, le):
            shown = f" (it is {si:.6g}{'' if unit == '1' else ' ' + unit})" \
                if isinstance(value, str) else ""
            raise PydanticCustomError("rotorsfd", "{allowed}", {
                "allowed": f"must be {allowed_range}{shown}", "value": value})
        return si

    unit_text = "dimensionless" if unit == "1" else unit
    description = f"{doc} [{unit_text}]; allowed: {allowed_range}"
    extra = {"unit": unit, "kind": kind}
    return Annotated[
        float | None if optional else float,
        BeforeValidator(parse),
        Field(description=description, json_schema_extra=extra),
    ]


def integer(doc: str, *, ge: int | None = None, le: int | None = None,
            optional: bool = False) -> Any:
    """Annotated int field (``None`` allowed if ``optional``) with its range in the
    description."""
    return Annotated[int | None if optional else int,
                     Field(ge=ge, le=le,
                           description=f"{doc}; allowed: {range_text('1', ge=ge, le=le)}")]


NODE = integer("node number (1-based, as in the paper)", ge=1)
NAME_PATTERN = r"^[A-Za-z_][A-Za-z0-9_\-]*$"
NAME = Annotated[str, Field(pattern=NAME_PATTERN,
                            description="name of a [materials.<name>] table; allowed: "
                                        "letters, digits, '_' and '-', starting with a "
                                        "letter or '_'")]
LABEL = Annotated[str, Field(description="a free label, used in messages and plots")]
CALLABLE = Annotated[str | None, Field(
    pattern=r"^[A-Za-z_][\w.]*:[A-Za-z_]\w*$",
    description="a Python function f(t) (importable, e.g. from the config file's folder); "
                "allowed: 'module:function'")]


class Section(BaseModel):
    """Base of every config table: unknown keys are errors, values are frozen."""

    model_config = ConfigDict(extra="forbid", frozen=True)


def given_fields(model: BaseModel, names: tuple[str, ...]) -> list[str]:
    return [n for n in names if getattr(model, n) is not None]


def exactly_one_form(model: BaseModel, forms: dict[str, tuple[str, ...]],
                      required: dict[str, tuple[str, ...]] | None = None) -> str:
    """The one form (a named group of optional fields) given in ``model``; error if none or
    several are given, or if a field of ``required[form]`` (default: all) is missing."""
    required = required or forms
    used = {name: given_fields(model, fields) for name, fields in forms.items()}
    chosen = [name for name, fields in used.items() if fields]
    text_forms = " or ".join("(" + ", ".join(f) + ")" for f in required.values())
    if len(chosen) != 1:
        first = used[chosen[1]][0] if len(chosen) > 1 else next(iter(required.values()))[0]
        value = getattr(model, first)
        raise fail(first, value, f"give exactly one of {text_forms}")
    form = chosen[0]
    for name in required[form]:
        if getattr(model, name) is None:
            raise fail(name, None, f"required with {', '.join(used[form])}: "
                       f"give all of ({', '.join(required[form])})")
    return form


def and_list(names: list[str]) -> str:
    """``"a, b and c"``."""
    return ", ".join(names[:-1]) + " and " + names[-1] if len(names) > 1 else "".join(names)

