"""The comparison report: :func:`write_report` writes ``report.md`` (the rows of
:mod:`rotorsfd.paper.compare`, the explanations of :mod:`rotorsfd.paper.explanations`, the
figures, the cases), a self-contained ``report.html`` (figures as base64 PNG) and
``results.json``, each atomically.
"""

from __future__ import annotations

import base64
import re
from collections.abc import Mapping, Sequence
from pathlib import Path

from rotorsfd.io import atomic
from rotorsfd.paper.cases import Outcome
from rotorsfd.paper.compare import Row, comparison_rows
from rotorsfd.paper.explanations import DIAGNOSES, explanations, relevant_diagnoses

#: Names of the split-out modules, importable from here as before the split.
__all__ = ["DIAGNOSES", "Row", "comparison_rows", "html_symbols", "render_html",
           "render_markdown", "write_report"]


def _table_md(rows: Sequence[Row], calibrated: bool = True) -> str:
    """The comparison table; the calibrated columns when that reading ran."""
    head = ["section", "quantity", "paper", "literal", "difference", "verdict"]
    if calibrated:
        head += ["calibrated", "difference", "verdict"]
    out = ["| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    for r in rows:
        q = r.quantity + (f" ({r.note})" if r.note else "")
        cells = [r.section, q, r.paper, r.ours, r.difference, r.verdict]
        if calibrated:
            cells += [r.calibrated, r.cal_difference, r.cal_verdict]
        out.append("| " + " | ".join(c.replace("|", "\\|") for c in cells) + " |")
    return "\n".join(out)


def _differences(rows: Sequence[Row]) -> list[Row]:
    return [r for r in rows if "differs" in (r.verdict, r.cal_verdict)]


def _count(rows: Sequence[Row], verdict_of: str) -> tuple[int, int, int]:
    """(compared with the paper, predictions among them, predictions that differ) of one
    reading's verdicts (``verdict`` or ``cal_verdict``)."""
    v = [getattr(r, verdict_of) for r in rows]
    compared = [x for x in v if x in ("agrees", "close", "differs", "fitted")]
    pred = [x for x in compared if x != "fitted"]
    return len(compared), len(pred), sum(x == "differs" for x in pred)


#: What the two readings are (the report's header).
READINGS_TEXT = """\
Two readings of the paper's rotor. **Literal**: what the paper states, no
structural damping, the two unstated support stiffnesses fitted to its critical speeds
(`examples/paper_rotor.toml`). **Calibrated**: one damping parameter added, the modal
damping ratio 0.2197 % fitted to Table 1's upper fold at U = 360.04 g mm, and the
stiffnesses re-fitted with it to the critical speeds
(`examples/paper_rotor_calibrated.toml`, fitted by `rotorsfd calibrate`). In each
reading a number it was fitted to is marked `fitted`; every other number is a prediction
with its error."""


def render_markdown(rows: Sequence[Row], figures: Mapping[str, str],
                    outcomes: Mapping[str, Outcome], elapsed: float | None = None,
                    diagnoses: Mapping[str, str] | None = None) -> str:
    """report.md: summary, comparison table, differences, explanations, figures, cases."""
    cal = any(r.cal_verdict != "not run" for r in rows)
    parts = [f"{len(outcomes)} cases, {len(rows)} rows"]
    for name, field, ran in (("Literal", "verdict", any(r.verdict != "not run"
                                                         for r in rows)),
                             ("Calibrated", "cal_verdict", cal)):
        if ran:
            n, p, d = _count(rows, field)
            parts.append(f"{name} reading: {n} values compared with the paper, {p} of "
                         f"them predictions, {d} of those differ")
    summary = ". ".join(parts)
    lines = ["# rotorsfd against Zhang et al. 2025 (Appl. Sci. 15, 1186)", "",
             summary + (f"; run time {elapsed:.0f} s." if elapsed is not None else "."), ""]
    if cal:
        lines += [READINGS_TEXT, ""]
    lines += ["## Our numbers beside the paper's", "", _table_md(rows, cal), "",
              "## Where we differ from the paper", ""]
    for r in _differences(rows):
        what = f"literal {r.ours} ({r.verdict})"
        if cal:
            what += f", calibrated {r.calibrated} ({r.cal_verdict})"
        lines.append(f"- **{r.section}, {r.quantity}**: paper {r.paper}, {what}.")
    diagnoses = relevant_diagnoses(diagnoses or {}, outcomes)
    if diagnoses:
        lines += ["", "Diagnoses:", ""]
        lines += [f"- **{k}**: {v}" for k, v in diagnoses.items()]
    lines += ["", "## Choices and sensitivity", "", explanations(outcomes), "## Figures", ""]
    for number, path in figures.items():
        lines += [f"### Figure {number}", "", f"![Figure {number}]({path})", ""]
    lines += ["## Cases", "", "| case | status | time [s] | message |", "|---|---|---|---|"]
    for o in outcomes.values():
        lines.append(f"| {o.name} | {o.status} | {o.elapsed:.1f} | "
                     f"{o.message[:160].replace('|', '/')} |")
    return "\n".join(lines) + "\n"


#: ASCII spellings of the report's text -> HTML (outside code).
HTML_SYMBOLS: tuple[tuple[str, str], ...] = (
    (r"Omega~", "\u03a9\u0303"), (r"Omega_ref", "\u03a9<sub>ref</sub>"),
    (r"Omega", "\u03a9"), (r"\|mu\|max", "|\u03bc|<sub>max</sub>"), (r"\|mu\|", "|\u03bc|"),
    (r"w_b([xyz])", "\u03c9<sub>b<1></sub>"), (r"w_b", "\u03c9<sub>b</sub>"),
    (r"r~", "r\u0303"), (r"A0", "A<sub>0</sub>"), (r"eps", "\u03b5"),
    (r"mu", "\u03bc"), (r"N_f", "N<sub>f</sub>"), (r"\+/-", "\u00b1"), (r"<=", "\u2264"),
    (r"->", "\u2192"),
)
_HTML_PATTERNS = [(re.compile(rf"(?<![A-Za-z]){a}(?![A-Za-z])"), b)
                  for a, b in HTML_SYMBOLS]
_CODE_OR_TAG = re.compile(r"(<code>.*?</code>|<[^>]*>)", re.S)


def html_symbols(page: str) -> str:
    """``Omega~`` -> Ω̃, ``|mu|max`` -> |μ|<sub>max</sub>, ``w_by`` -> ω<sub>by</sub> ...
    in the text of an HTML fragment (not in code, not in tags)."""
    pieces = _CODE_OR_TAG.split(page)
    for i in range(0, len(pieces), 2):
        p = pieces[i].replace("&lt;=", "<=").replace("-&gt;", "->")
        for pattern, sub in _HTML_PATTERNS:
            p = pattern.sub(lambda m, s=sub: s.replace("<1>", m.group(m.lastindex or 0)), p)
        p = re.sub(r"\^(\d+)", r"<sup>\1</sup>", p)
        pieces[i] = p.replace("<=", "&lt;=").replace("->", "-&gt;")
    return "".join(pieces)


def _markdown_to_html(text: str) -> str:
    """CommonMark-like markdown (tables, no raw HTML: a ``<`` in a message is text)."""
    # deferred: markdown is heavy (loaded only when this runs)
    import markdown

    md = markdown.Markdown(extensions=["tables"], output_format="html")
    md.preprocessors.deregister("html_block")
    md.inlinePatterns.deregister("html")
    return md.convert(text)


def render_html(markdown: str, figures: Mapping[str, bytes]) -> str:
    """report.html: the markdown rendered (paragraphs joined across source lines, inline
    code as code, tables), the symbols written as symbols, the figures embedded (base64)."""
    body = html_symbols(_markdown_to_html(markdown))

    def embed(m: re.Match[str]) -> str:
        png = figures.get(m.group(1))
        if png is None:
            return ""
        b64 = base64.b64encode(png).decode("ascii")
        return f'<img alt="Figure {m.group(1)}" src="data:image/png;base64,{b64}"'

    body = re.sub(r'<img alt="Figure ([^"]+)" src="[^"]*"', embed, body)
    style = ("body{font-family:sans-serif;max-width:1200px;margin:auto;padding:1em;"
             "line-height:1.4}table{border-collapse:collapse;font-size:90%}"
             "td,th{border:1px solid #ccc;padding:2px 6px;vertical-align:top}"
             "code{background:#f3f3f3;padding:0 2px}img{max-width:100%}")
    return ("<!DOCTYPE html><html><head><meta charset='utf-8'><title>rotorsfd paper "
            f"report</title><style>{style}</style></head><body>\n{body}\n</body></html>\n")


def write_report(directory: str | Path, outcomes: Mapping[str, Outcome],
                 figures: Mapping[str, bytes], *, elapsed: float | None = None,
                 diagnoses: Mapping[str, str] | None = None) -> dict[str, Path]:
    """Write ``fig<N>.png``, ``report.md``, ``report.html`` and ``results.json``
    atomically into ``directory``; returns the paths."""
    out = Path(directory)
    paths: dict[str, Path] = {}
    names = {}
    for number, png in figures.items():
        name = f"fig{number}.png"
        paths[name] = atomic.write_bytes(out / name, png)
        names[number] = name
    rows = comparison_rows(outcomes)
    md = render_markdown(rows, names, outcomes, elapsed, diagnoses)
    paths["report.md"] = atomic.write_text(out / "report.md", md)
    paths["report.html"] = atomic.write_text(out / "report.html", render_html(md, figures))
    paths["results.json"] = atomic.write_json(out / "results.json", {
        "rows": [vars(r) for r in rows],
        "cases": {k: {"status": o.status, "message": o.message, "elapsed_s": o.elapsed,
                      "numbers": atomic.json_safe(o.numbers)} for k, o in outcomes.items()}})
    return paths
