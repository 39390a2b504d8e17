"""The words of the figures: one symbol style (matplotlib mathtext), settings and config
paths in the user's terms, titles wrapped instead of cut.

:func:`mathtext` turns the ASCII spellings the analyses use in their text (``Omega~``,
``|mu|max``, ``w_by``) into mathtext (``$\\tilde\\Omega$``, ...); :func:`setting` writes a
``path=value`` override as "U = 72.008 g mm" or "$\\omega_{by}$ = 2 rad/s";
:func:`axis_label` a config path and its unit as words ("pitching frequency
$\\omega_b$ [rad/s]"); :func:`wrap` breaks a long title into lines.
"""

from __future__ import annotations

import re
import textwrap

#: ASCII spelling -> mathtext, longest first (applied outside existing $...$ pieces).
SYMBOLS: tuple[tuple[str, str], ...] = (
    (r"Omega~", r"\tilde\Omega"),
    (r"Omega_ref", r"\Omega_{ref}"),
    (r"Omega", r"\Omega"),
    (r"\|mu\|max", r"|\mu|_{max}"),
    (r"\|mu\|", r"|\mu|"),
    (r"w_b([xyz])", r"\omega_{b<1>}"),
    (r"w_b", r"\omega_b"),
    (r"r~", r"\tilde r"),
    (r"A0", r"A_0"),
)
_PATTERNS = [(re.compile(rf"(?<![A-Za-z\\]){a}(?![A-Za-z])"), b) for a, b in SYMBOLS]

#: Fields of an SFD element (so ``elements[0].clearance_ratio`` reads as the SFD's).
_SFD_FIELDS = ("clearance", "clearance_ratio", "centring_stiffness", "radius", "length",
               "viscosity", "node", "max_eccentricity")

#: Base components and the name of their rate in the paper.
_RATES = {"rolling": r"$\omega_{bx}$", "pitching": r"$\omega_{by}$", "yawing": r"$\omega_{bz}$"}

#: Config fields in words: the last part of a path (after the base component if any).
_FIELDS = {
    "unbalance.magnitude": "U",
    "sfd.clearance_ratio": "C/R",
    "sfd.clearance": "C",
    "sfd.centring_stiffness": "SFD centring spring",
    "rotor.supports.stiffness": "support stiffness",
    "rotor.damping.ratio": "modal damping ratio",
    "analysis.simulate.speed_ratio": r"$\tilde\Omega$",
    "analysis.simulate.speed": r"$\Omega$",
    "speed": r"spin speed $\Omega$",
    "speed_ratio": r"$\tilde\Omega = \Omega / \Omega_{ref}$",
    "frequency": r"base frequency $\omega_b$",
    "angle_amplitude": r"amplitude $A_0$",
    "amplitude": "amplitude",
    "value": "rate",
}

_BASE_FIELDS = {"frequency": r"frequency $\omega_b$", "angle_amplitude": r"amplitude $A_0$"}


def mathtext(text: str) -> str:
    """``text`` with the ASCII symbols in mathtext; pieces already in ``$...$`` are kept."""
    pieces = text.split("$")
    for i in range(0, len(pieces), 2):          # the even pieces are outside $...$
        p = pieces[i]
        for pattern, sub in _PATTERNS:
            p = pattern.sub(lambda m, s=sub: "$" + s.replace("<1>", m.group(m.lastindex or 0))
                            + "$", p)
        pieces[i] = p
    return "$".join(pieces).replace("$$", "")


def wrap(text: str, width: int = 80) -> str:
    """A title broken into lines of at most ``width`` characters (existing line breaks
    kept), never cut: "a long title ..." loses what the reader needs."""
    return "\n".join(textwrap.fill(line, width, break_on_hyphens=False) or line
                     for line in mathtext(text).split("\n"))


def _unindexed(path: str) -> str:
    """The path without list indices, an element's fields under ``sfd.`` (as
    ``elements.sfd.clearance`` or ``elements[0].clearance``: the SFD is the element)."""
    p = re.sub(r"\[\d+\]", "", path.strip())
    if p.startswith("elements."):
        rest = p.removeprefix("elements.")
        p = rest if rest.startswith("sfd.") else f"sfd.{rest.split('.', 1)[-1]}" \
            if rest.split(".", 1)[0] not in _SFD_FIELDS else f"sfd.{rest}"
    return p


def field_words(path: str) -> str:
    """The name of the field at a config path in words: ``base.pitching.frequency`` ->
    "pitching base frequency $\\omega_b$", ``unbalance[0].magnitude`` -> "U"."""
    p = _unindexed(path)
    if p in _FIELDS:
        return _FIELDS[p]
    parts = p.split(".")
    if parts[0] == "base" and len(parts) == 2 and parts[1] in _RATES:
        return _RATES[parts[1]]
    if parts[0] == "base" and len(parts) >= 3 and parts[1] in _RATES:
        if parts[-1] == "value":
            return _RATES[parts[1]]
        return f"{parts[1]} " + _BASE_FIELDS.get(parts[-1], parts[-1].replace("_", " "))
    return _FIELDS.get(parts[-1], parts[-1].replace("_", " "))


#: Longer names for an axis than for a legend entry.
_AXIS_NAMES = {"U": "unbalance U", "C/R": "clearance ratio C/R", "C": "clearance C"}


def axis_label(path: str, units: str = "") -> str:
    """An axis label for a config path: words and the unit in brackets."""
    u = units.strip().replace("**", "^").replace("*", " ")
    words = field_words(path)
    p = _unindexed(path).split(".")
    if p[0] == "base" and (len(p) == 2 or p[-1] == "value") and p[1] in _RATES:
        words = f"{p[1]} rate {words}"
    words = _AXIS_NAMES.get(words, words)
    return words + (f" [{u}]" if u and u not in ("1", "dimensionless") else "")


_PATH_LABEL = re.compile(r"^\s*([A-Za-z_][\w\[\]]*(?:\.[\w\[\]]+)+)\s*(?:\[(.*)\])?\s*$")


def label(text: str) -> str:
    """An axis label as given, in words when it is a config path ("base.pitching.value
    [rad/s]" -> "$\\omega_{by}$ [rad/s]"), symbols in mathtext."""
    m = _PATH_LABEL.match(text)
    if m and "$" not in text:
        return axis_label(m.group(1), m.group(2) or "")
    return mathtext(text)


def _number(value: str) -> str:
    v = value.strip().strip("\"'")
    try:
        return f"{float(v):.6g}"
    except ValueError:
        return v.replace("*", " ")


def setting(override: str) -> str:
    """A ``path=value`` override in words: "unbalance[0].magnitude=72.008 g*mm" ->
    "U = 72.008 g mm"; "base.pitching.value=2 rad/s" -> "$\\omega_{by}$ = 2 rad/s";
    "analysis.simulate.steps_per_period=200" -> "T/200"; "" for the damping kind."""
    path, _, value = override.partition("=")
    p = _unindexed(path)
    if p == "rotor.damping.kind":
        return ""
    if p == "analysis.simulate.steps_per_period":
        return f"T/{_number(value)}"
    if p == "rotor.damping.ratio":
        try:
            return f"{100 * float(value):.3g} % modal damping"
        except ValueError:
            return f"modal damping {value}"
    return f"{field_words(path)} = {_number(value)}"


def settings(overrides: tuple[str, ...] | list[str], common: set[str] | None = None) -> str:
    """The overrides not in ``common`` in words, joined by commas."""
    words = [setting(o) for o in overrides if not common or o not in common]
    return ", ".join(w for w in words if w)
