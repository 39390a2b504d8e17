"""The comparison report: our numbers beside the paper's, the figures, the explanations.

:func:`comparison_rows` turns the claims of :mod:`rotorsfd.paper.cases` and the case
outcomes into rows (quantity, paper, ours, difference, verdict); :func:`write_report`
writes ``report.md`` and a self-contained ``report.html`` (figures as base64 PNG) and
``results.json``, each atomically.
"""

from __future__ import annotations

import base64
import fnmatch
import math
import re
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.io import atomic
from rotorsfd.paper.cases import CAL, CLAIMS, Claim, Outcome, literal_name
from rotorsfd.plots.chart import describe, unstable_regions

SHORT = {"saddle-node": "SN", "secondary-hopf": "SH", "period-doubling": "PD"}


@dataclass(frozen=True)
class Row:
    """One line of the comparison table: the paper's value, ours in the literal reading
    (``ours``, ``difference``, ``verdict``) and in the calibrated one (``calibrated``,
    ``cal_difference``, ``cal_verdict``; "not run" when the calibrated case did not run).
    A verdict is ``fitted`` where the reading's fit used this number (not a prediction)."""

    section: str
    quantity: str
    paper: str
    ours: str
    difference: str
    verdict: str          # agrees, close, differs, ours only, fitted, not run
    note: str = ""
    calibrated: str = "not run"
    cal_difference: str = ""
    cal_verdict: str = "not run"


def _fmt(x: Any) -> str:
    if x is None:
        return "none"
    if isinstance(x, float):
        return "none" if math.isnan(x) else f"{x:.5g}"
    return str(x)


def _bifs(rows: Sequence[Sequence[Any]]) -> str:
    if not rows:
        return "none"
    return "; ".join(f"{SHORT.get(t, t)} {s:.4f} (|mu| {m:.4f})" for t, s, m, *_ in rows)


def _numeric(claim: Claim, ours: float) -> tuple[str, str]:
    p = float(claim.paper)  # type: ignore[arg-type]
    d = ours - p
    rel = d / p if p else float("inf")
    band = claim.band
    verdict = "ours only" if band is None else ("agrees" if abs(rel) <= band else "differs")
    return f"{d:+.4g} ({100 * rel:+.2f} %)", verdict


def _value(claim: Claim, outcomes: Mapping[str, Outcome]) -> tuple[str, str, str]:
    """(ours, difference, verdict) of a claim."""
    o = outcomes.get(claim.case)
    if o is None:
        return "not run", "", "not run"
    if o.status == "error" or not o.numbers:
        return f"{o.status}: {o.message[:120]}", "", "differs"
    n = o.numbers
    key, _, ref = claim.key.partition(":")
    other = outcomes.get(ref)
    if key == "bifurcations":
        ours = _bifs(n["bifurcations"])
        if not n.get("success", True):
            ours += f" [{n['end']}]"
        types = [b[0] for b in n["bifurcations"]]
        want = str(claim.paper)
        if claim.paper is None:
            return ours, "", "ours only"
        if want.startswith("none"):
            ok = not types
        elif "pair" in want:
            ok = types.count("saddle-node") >= 2
        else:
            ok = "saddle-node" in types
        return ours, "same" if ok else "differs qualitatively", "agrees" if ok else "differs"
    if key == "tab3":
        return _table3(claim, n)
    if key == "disk_peaks":
        peaks = n.get("disk_peaks", [])
        ours = ", ".join(f"{p:.3f}" for p in peaks) or "no peak"
        if isinstance(claim.paper, float):
            if not peaks:
                return ours, "no peak", "differs"
            if "second peak" in claim.quantity:       # the second peak, not the nearest
                if len(peaks) < 2:
                    end = "" if n.get("success", True) else f"; {n['end']}"
                    return ours + end, "no second peak", "differs"
                peaks = peaks[1:2]
            best = min(peaks, key=lambda p: abs(p - claim.paper))
            if abs(best - claim.paper) > 0.05:
                end = "" if n.get("success", True) else f"; {n['end']}"
                return ours + end, "no peak near", "differs"
            diff, verdict = _numeric(claim, best)
            return ours, diff, verdict
        ok = len(peaks) >= 2
        return ours, "same" if ok else "one peak only", "agrees" if ok else "differs"
    if key == "peak_shift_vs" and other and other.numbers:
        d = n["peak_ratio"] - other.numbers["peak_ratio"]
        word = "lower" if d < 0 else "higher" if d > 0 else "same"
        return (f"peak at {n['peak_ratio']:.4f} vs {other.numbers['peak_ratio']:.4f} ({word})",
                f"{d:+.4f}", "agrees" if word == claim.paper else "differs")
    if key == "same_as" and other and other.data and o.data:
        a, b = o.data, other.data
        x = np.linspace(max(a["speed_ratio"].min(), b["speed_ratio"].min()),
                        min(a["speed_ratio"].max(), b["speed_ratio"].max()), 200)
        diff = np.max(np.abs(np.interp(x, a["speed_ratio"], a["defl_1"])
                             - np.interp(x, b["speed_ratio"], b["defl_1"])))
        return (f"max |r~ yaw - r~ pitch| = {diff:.1e}", f"{diff:.1e}",
                "agrees" if diff < 1e-3 else "differs")
    if key == "fold_shift" and other and other.numbers:
        m = other.numbers
        if "sn_hi" not in n or "sn_hi" not in m:
            return _bifs(n["bifurcations"]), "", "ours only"
        return (f"SN {n['sn_hi']:.5f} / {n['sn_lo']:.5f}",
                f"{n['sn_hi'] - m['sn_hi']:+.5f} / {n['sn_lo'] - m['sn_lo']:+.5f}", "ours only")
    if key.startswith("poincare"):          # poincare[_<prefix>]: a journal position
        p = key.removeprefix("poincare")[1:]
        if n.get(p + "poincare_y") is None:
            return "none", "", "ours only"
        ours = (f"({n[p + 'poincare_y']:+.4f}, {n[p + 'poincare_z']:+.4f}) C at T/"
                f"{n[p + 'steps_per_period']}; eps there {n[p + 'eps_poincare']:.4f}, max "
                f"over the orbit {n[p + 'eps_max']:.4f}")
        if n.get(p + "step_check") is not None:
            ours += f"; halving the step moves the orbit {n[p + 'step_check']:.2g} C"
        return ours, "", "ours only"
    if key == "motion" or key.startswith("motion_"):
        alias = {"motion_second": "second_motion", "motion_find": "find_motion"}
        ours = str(n.get(alias.get(key, key)))
        ly = n.get("lyapunov_" + key.removeprefix("motion_"))
        if ly is not None:
            ours += f" (Lyapunov {ly:+.2g}/period)"
        if claim.paper is None:
            return ours, "", "ours only"
        want = str(claim.paper).split(" ")[0]
        ok = ours.startswith(want)
        return ours, "same" if ok else "differs qualitatively", "agrees" if ok else "differs"
    if key == "end_rate":
        v = n.get("end_rate")
        if v is None:
            return "bistable to the end of the range", "", "differs"
        if isinstance(claim.paper, float):
            d = v - claim.paper
            # the paper has no fold pair from its rate claim.paper on (a grid of 1-2 rad/s
            # steps): ours agrees if the cusp lies in the grid step below it; a cusp above
            # it means our model is still bistable at the paper's rate
            ok = claim.paper - 2.0 < v <= claim.paper
            return f"{v:.4f}", f"{d:+.3f} rad/s", "agrees" if ok else "differs"
        return f"{v:.4f}", "", "ours only"
    v = n.get(key)
    if v is None:
        why = n.get(f"{key}_why") or n.get("end")
        extra = f" [{why}]" if why else ""
        return "none" + extra, "no such point", "differs" if claim.paper is not None else ""
    if isinstance(claim.paper, float) and isinstance(v, (int, float)):
        diff, verdict = _numeric(claim, float(v))
        if isinstance(claim.paper, float) and claim.band is None and "mu" in key:
            verdict = "close" if abs(v - claim.paper) < 0.02 else "differs"
        return _fmt(float(v)), diff, verdict
    if isinstance(claim.paper, str):
        if claim.paper == "small" and isinstance(v, float):
            return f"{v:.4f}", "", "agrees" if 0 < v < 0.02 else "differs"
        if claim.paper == "none" and isinstance(v, float):   # an unstable width
            return (f"{v:.3g}", "same" if v == 0 else "a fold pair remains",
                    "agrees" if v == 0 else "differs")
        ok = str(v) == claim.paper
        return _fmt(v), "same" if ok else "differs", "agrees" if ok else "differs"
    return _fmt(v), "", "ours only"


def _table3(claim: Claim, n: Mapping[str, Any]) -> tuple[str, str, str]:
    """Nearest bifurcation of our branch to a Table 3 point."""
    target = float(claim.paper)  # type: ignore[arg-type]
    rows = n.get("bifurcations", [])
    if not rows:
        return "none", "no bifurcation", "differs"
    t, s, m, re, im = min(rows, key=lambda b: abs(b[1] - target))
    ours = f"{SHORT.get(t, t)} {s:.4f} (|mu| {m:.4f}" + (
        f", {re:.4f} {'+' if im >= 0 else '-'} {abs(im):.4f}i)" if abs(im) > 1e-9 else ")")
    want = "SH" if "Hopf" in claim.quantity else "SN"
    d = s - target
    ok = SHORT.get(t, t) == want and abs(d) <= 5e-3 * target
    return ours, f"{d:+.4f} (nearest)", "agrees" if ok else "differs"


def readings(outcomes: Mapping[str, Outcome]) -> dict[str, dict[str, Outcome]]:
    """The outcomes of each reading by their literal case names: ``literal`` (the cases
    without prefix) and ``calibrated`` (the ``cal-*`` cases, prefix removed)."""
    return {"literal": {k: o for k, o in outcomes.items() if not k.startswith(CAL)},
            "calibrated": {literal_name(k): o for k, o in outcomes.items()
                           if k.startswith(CAL)}}


def _judged(claim: Claim, reading: str, outcomes: Mapping[str, Outcome]
            ) -> tuple[str, str, str]:
    """(ours, difference, verdict) of a claim in one reading; ``fitted`` for the numbers
    the reading's fit used (they agree by construction: not a prediction)."""
    if claim.case not in outcomes:
        return "not run", "", "not run"
    ours, diff, verdict = _value(claim, outcomes)
    if reading in claim.fitted and verdict in ("agrees", "close", "ours only"):
        verdict = "fitted"
    return ours, diff, verdict


def comparison_rows(outcomes: Mapping[str, Outcome],
                    claims: Sequence[Claim] = CLAIMS) -> list[Row]:
    """A row per claim whose case ran in either reading (:func:`readings`)."""
    by = readings(outcomes)
    rows = []
    for c in claims:
        if c.case not in by["literal"] and c.case not in by["calibrated"]:
            continue
        ours, diff, verdict = _judged(c, "literal", by["literal"])
        cal, cdiff, cverdict = _judged(c, "calibrated", by["calibrated"])
        paper = "-" if c.paper is None else _fmt(c.paper)
        rows.append(Row(c.section, c.quantity, paper, ours, diff, verdict, c.note,
                        cal, cdiff, cverdict))
    return rows


# ---- explanations -----------------------------------------------------------------------------

#: Our choices, each with the cases it concerns (fnmatch patterns; () for every report).
CHOICES: dict[str, tuple[tuple[str, ...], str]] = {
    "Support stiffnesses (not in the paper)": ((), """\
The SFD centring spring (10.325 MN/m) and the
right support (9.551 MN/m) are fitted so that the first two forward critical speeds of the
linear rotor (film off) are the paper's 811.3 and 2784.6 rad/s (met to 1e-10). Two targets
fix two stiffnesses, so the choice is unique for this model; the sensitivity rows rerun the
U = 144.02 g mm fold pair with each stiffness changed by +/-5 %."""),
    "Figure 6 rotor (not in the paper)": (("fig6",), """\
The Duchemin rotor is taken as the Lalanne-Ferraris
single-disk rotor (0.4 m shaft, 0.02 m diameter, disk 0.15/0.01 m radius x 0.03 m at L/3,
pinned ends as 1e9 N/m bearings, no damping); see `examples/fig6_duchemin_pitching.toml`.
The three main zones are parametric resonances of the first mode pair at Omega = 250 rad/s:
as A0 -> 0 they tend to the base-frame frequencies 254, 278 and 302 rad/s, and their width
shrinks as A0^2, so on a finite grid they show only from some A0 up. Without the original
data the zone positions cannot be compared number by number."""),
    "|mu|max at a bifurcation": (("fig7-*", "sens-*", "fig1[07]-*", "fig12-*", "fig16-*",
                                  "fig2[14]-*"), """\
A multiplier crosses +1 exactly at a fold, so the value in
Table 1 is the largest multiplier at a computed point near it: it depends on the
continuation step (ours: the modulus of the critical multiplier at the nearest computed
point on the unstable side, `nearest_multiplier_abs` in `bifurcations.csv`; the multiplier
at the located fold itself, `located_multiplier_re`, is +1 up to the Floquet error), as
the paper's does. The rows marked "close" are within 0.02."""),
    "Harmonics and aliasing": ((), """\
H = 3 for U <= 144.02 g mm, H = 8 for U = 252 and 360.04 g mm
and for section 4.3, as in the paper; N_f is chosen free of aliasing by rotorsfd."""),
    "Journal contact": ((), """\
Every response case continues until the SFD eccentricity reaches
0.995 (default limiter 0.95). Where the paper's branch folds back while ours keeps rising
to the clearance, our branch ends at contact; the row says where."""),
}

#: The cases each diagnosis of :data:`DIAGNOSES` concerns (fnmatch patterns): a report lists
#: a diagnosis only when one of its cases ran (a diagnosis not named here: always).
DIAGNOSIS_CASES: dict[str, tuple[str, ...]] = {
    "Journal contact instead of a fold (U = 360.04 g mm: Table 1, Figs. 17-19, 24)":
        ("fig7-u360", "fig17-u360-*", "fig19-u360", "fig24-u360"),
    "Figure 19 widths, U = 252 g mm (0.058 vs 0.041) and the end of bistability":
        ("fig19-*",),
    "Figure 15, second disk peak near Omega~ 1.40 (w_by = 9 rad/s)": ("fig12-w9", "fig12-w10"),
    "Figure 21, C/R = 0.485 % stable in the paper": ("fig21-cr0.485",),
    "Table 3 and Figure 23 (C/R = 0.728 %)": ("fig21-cr0.728", "fig23-*"),
    "|mu|max at the folds": ("fig7-u144", "fig7-u360", "sens-*", "fig19-*", "fig17-*"),
}


def _ran(patterns: Sequence[str], outcomes: Mapping[str, Outcome]) -> bool:
    """Whether a case matching one of ``patterns`` ran in either reading."""
    return not patterns or any(fnmatch.fnmatchcase(literal_name(name), p)
                               for name in outcomes for p in patterns)


def relevant_diagnoses(diagnoses: Mapping[str, str], outcomes: Mapping[str, Outcome]
                       ) -> dict[str, str]:
    """The diagnoses whose cases ran (:data:`DIAGNOSIS_CASES`): a quick or single-figure
    report does not explain figures it did not draw."""
    return {k: v for k, v in diagnoses.items() if _ran(DIAGNOSIS_CASES.get(k, ()), outcomes)}


def chart_sentence(outcomes: Mapping[str, Outcome]) -> str:
    """What the Figure 6 chart shows, from its grid (zones, how far down, islands)."""
    o = outcomes.get("fig6")
    if o is None or not o.data:
        return ""
    d = o.data
    units = str(d.get("y_label", "")).partition("[")[2].rstrip("] ")
    shown = describe(unstable_regions(d["x"], d["y"], d["max_abs"]), "A0", units,
                     mu="|mu|", ringed=False)
    nx, ny = np.shape(d["max_abs"])
    return f"On this run's {nx} x {ny} grid the chart shows {shown}."


def explanations(outcomes: Mapping[str, Outcome]) -> str:
    """The paragraphs of :data:`CHOICES` whose cases ran."""
    out = []
    for title, (patterns, text) in CHOICES.items():
        if _ran(patterns, outcomes):
            extra = f" {chart_sentence(outcomes)}" if "Figure 6" in title else ""
            out.append(f"**{title}.** {text}{extra}")
    return "\n\n".join(out) + "\n"


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


#: Our diagnosis of the qualitative differences (from the full run; see docs/paper.md).
DIAGNOSES: dict[str, str] = {
    "Journal contact instead of a fold (U = 360.04 g mm: Table 1, Figs. 17-19, 24)":
        "in the literal reading our upper branch rises until the journal reaches the "
        "clearance at Omega~ = 1.3121 for every pitching rate. That speed is the first "
        "critical speed of the rotor pinned at the SFD (1065.1 rad/s = 1.3129 Omega_ref; "
        "`rotorsfd modal --set elements.sfd.centring_stiffness=1e11`): when the film "
        "locks, nothing damps that mode, since the literal model has no structural "
        "damping. Changing the support stiffnesses only moves the contact with that "
        "resonance (right support 12 MN/m: contact at 1.367), never gives a fold. The "
        "calibrated reading adds one modal damping ratio, fitted to the upper fold "
        "(0.2197 %, upper fold 1.2822 against 1.2820): its lower fold 1.1151 is a "
        "prediction, 0.84 % below the paper's 1.1245 (the lower fold hardly moves with "
        "the damping, so no modal damping meets both), and the saddle-node pairs of "
        "Figures 17 (9 rad/s) and 24 come back. The paper most probably has some "
        "structural or support damping it does not state.",
    "Figure 19 widths, U = 252 g mm (0.058 vs 0.041) and the end of bistability":
        "the fold curve (two-parameter continuation) is exact for the HB equations of a "
        "given H, and its cusp moves with H: U = 144.02 g mm 4.4097 rad/s at H = 3 "
        "(Table 1's H), 4.37895 / 4.37904 / 4.37903 at H = 8 / 12 / 16; U = 252 g mm "
        "7.7267 at H = 8 (the paper's H), 7.7655 / 7.7744 / 7.7751 / 7.7751 at H = 12 / "
        "16 / 20 / 24. The converged cusps, 4.379 and 7.775 rad/s, lie above the rates "
        "from which the paper has no fold pair (4 and 7 rad/s): our model is still "
        "bistable there, with a narrow pair (width 7.0e-4 in Omega~ at 4 rad/s for "
        "U = 144.02, 1.1e-3 at H = 3; 0.0122 at 7 rad/s for U = 252). That is a "
        "difference, not a grid effect. The wider range at U = 252 (0.058 at 0 rad/s, "
        "the same at every H) points to the same missing damping: the calibrated reading "
        "(damping fitted to Table 1's U = 360.04 fold only) predicts the U = 252 width "
        "at 0 rad/s as 0.0414 (paper 0.041), the U = 144.02 cusp at 3.79 rad/s (paper: "
        "no fold pair from 4 rad/s), the U = 252 cusp at 7.12 rad/s (paper 7; width "
        "8e-4 left at 7 rad/s) and the U = 360.04 widths 0.167 / 0.105 at 0 / 10 rad/s "
        "(paper 0.195 / 0.119).",
    "Figure 15, second disk peak near Omega~ 1.40 (w_by = 9 rad/s)":
        "at 9 rad/s the disk's 1X amplitude has a weak second maximum at Omega~ 1.392 "
        "(1.397 calibrated; paper 1.40), 3 % of the main peak above the trough before "
        "it, and the branch then runs to contact at 1.545 after a fold at 1.560; at 10 "
        "rad/s the second peak is strong (1.359). An earlier peak finder asked for 5 % "
        "and reported no second peak at 9 rad/s. The static offset from the "
        "gyroscopic moment Ip Omega w_by is held by the centring spring, which the paper "
        "does not give: the second peak's height depends on it (a 10 % softer spring "
        "makes it strong at 9 rad/s, 1.362).",
    "Figure 21, C/R = 0.485 % stable in the paper":
        "ours has a very narrow saddle-node pair at Omega~ 1.154-1.155 (width 0.0008) and "
        "ends at contact at 1.497: the first is below the resolution of the paper's "
        "branch, the second the missing damping again.",
    "Table 3 and Figure 23 (C/R = 0.728 %)":
        "in the literal reading (no damping) our branch has a period-doubling range "
        "1.0266-1.0487 (the time "
        "domain at Omega~ 1.04 confirms the period-2 motion), a weak secondary Hopf at "
        "1.2819 and contact at 1.3089; no saddle-nodes. In the calibrated reading "
        "(0.2197 % modal damping, fitted to Table 1 only) the paper's pattern appears: "
        "saddle-nodes at 1.149-1.156 with a secondary Hopf at 1.154 (paper D-F "
        "1.166-1.176, B 1.0982) and an upper fold at 1.2625 (paper C 1.2977), the "
        "pattern, not the numbers; its time domain is period-1 at all five speeds (T/800; "
        "the damping removes the period-doubling range and the isola). "
        "The time domain runs at T/800 (converged: T/1600 moves the journal's Poincare "
        "points by at most 2.5e-3 C) and at the paper's T/200, which this close to "
        "contact (eccentricity up to 0.99) moves the orbit by 0.02-0.06 C. From the "
        "paper's 1 um start both land on the main branch, period-1 at 1.05 and 1.075. The "
        "model has a second, separate branch: an isola. At T/200 (only there) the start "
        "on the HB orbit shifted by half a period lands near a second period-1 orbit; "
        "the branch through it (H = 16) closes on itself between folds 1.0259 and "
        "1.0939, stable by Floquet from a secondary Hopf at 1.0641 (multiplier -0.36 + "
        "0.93i) to near the upper fold, period doublings at 1.0275 and 1.0550 on its "
        "unstable part. Started on the isola's HB orbit at 1.075, the T/800 run stays on "
        "it (journal at the Poincare point (-0.226, -0.902) C, eccentricity 0.930 there, "
        "0.993 at most over the orbit; T/1600 (-0.224, -0.902); the T/200 orbit is 0.017 "
        "C off). Down the isola at the converged step (each speed from the previous "
        "state): period-1 at 1.07 and 1.067, a torus near a 1:10 resonance (Poincare "
        "points along a closed curve; the classifier may call it period-10) at 1.065, "
        "period-3 at 1.062: the time domain's secondary Hopf lies between 1.065 and 1.067 "
        "(Floquet, H = 16: 1.0641). At T/200 the same runs give a torus at 1.07, "
        "period-10 locking at 1.065 and an irregular section at 1.06 -- the paper's "
        "sequence at its own step. So the paper's quasi-periodic and chaotic motions may "
        "depend on its time step; in our converged model they sit on the isola at 1.062-"
        "1.065, 0.01-0.03 lower in Omega~ than Table 3 A and B (the unstated support "
        "stiffnesses move folds by about 0.01). 0.2-0.5 % damping removes the isola, so "
        "damping is not the explanation here.",
    "|mu|max at the folds":
        "a multiplier is exactly +1 at a fold; the value at the nearest computed point "
        "depends on the step (paper and ours). Not a model difference.",
}
