"""Every paper figure and the report page rendered from synthetic outcomes of both readings,
and their structure checked (issue 24 items 6-7): legends in the reader's terms (no case
id), a key for the line styles and markers, the symbols in mathtext (no ASCII ``Omega~``),
titles whole (never cut with "..."), legends beside the panels; report.html with one
paragraph per markdown paragraph, inline code as code (no backtick in the text), one
table with the columns of both readings, every figure embedded."""

from __future__ import annotations

import io
import re
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "plots"))
from figure_text import legend_labels, legends_over_panels, texts

from rotorsfd.paper.cases import CAL, CASES, FIGURES
from rotorsfd.paper.figures import draw
from rotorsfd.paper.report import DIAGNOSES, write_report
from rotorsfd.paper.run import Outcome

#: A case id in a text: fig7-u144, u360, w9, cal-..., damp-...
CASE_ID = re.compile(r"\b(fig\d+[a-z]?-|cal-|damp-|sens-|u\d{2,3}\b|w\d{1,2}\b)")


def _response(name: str) -> dict:
    s = np.linspace(0.5, 1.6, 40)
    bump = 1.0 / (1.0 + ((s - 1.05) / 0.05) ** 2)
    d = {"speed_ratio": s, "defl_1": bump, "defl_8": 1.5 * bump,
         "stable": (s < 1.02) | (s > 1.08), "H": 3, "clearance": 1.0,
         "bifurcations": [{"type": "saddle-node", "speed_ratio": 1.06, "point": 25},
                          {"type": "secondary-hopf", "speed_ratio": 1.3, "point": 35}]}
    for n in (1, 8):
        d[f"static_{n}_y"] = 0 * s
        for k in (1, 2, 3):
            d[f"amp_{n}_y_h{k}"] = d[f"defl_{n}"] / k ** 2
        for a in ("y", "z"):
            d[f"max_{n}_{a}"], d[f"min_{n}_{a}"] = bump, -bump
    t = np.linspace(0, 2 * np.pi, 65)
    d["orbits"] = [(x, 0.5 * np.cos(t), 0.5 * np.sin(t)) for x in (0.8, 1.03, 1.2, 1.5)]
    return d


def _run(ratio: float = 1.075) -> dict:
    t = np.linspace(0.0, 20 * np.pi, 2000)
    th = np.linspace(0.0, 2 * np.pi * 9.7, 100)
    return {"y": 0.85 * np.cos(t) - 0.15, "z": 0.85 * np.sin(t) - 0.15,
            "vy": 1.0 + 0.9 * np.sin(t), "py": -0.2 + 0.02 * np.cos(th),
            "pz": -0.2 + 0.02 * np.sin(th), "pvy": 1.0 + 0.02 * np.sin(th),
            "speed_ratio": ratio, "motion": "quasi-periodic", "steps": 800}


def _data(name: str) -> dict:
    kind = CASES[name].kind
    if kind in ("fold-curve", "width-sweep"):
        rate = np.linspace(0, 10, 11 if kind == "width-sweep" else 201)
        return {"rate": rate, "width": np.maximum(0.05 * (1 - rate / 7), 0)}
    if kind == "simulate":
        return _run()
    if kind == "chart":
        x, y = np.linspace(200.0, 340.0, 29), np.linspace(0.0, 0.5, 21)
        m = np.ones((29, 21))
        m[5:8, 12:] = 1.05
        return {"x": x, "y": y, "max_abs": m, "x_label": "base.pitching.frequency [rad/s]",
                "y_label": "base.pitching.angle_amplitude [rad]", "tol": 1e-5,
                "speed": 250.0}
    d = _response(name)
    if kind == "isola":
        d.update(second=_run(), runs=[_run(1.07), _run(1.065)], find=_run(),
                 runs_t200=[_run(1.07)])
    return d


def _outcomes(names) -> dict[str, Outcome]:
    out = {}
    for n in names:
        for name in (n, CAL + n):
            if name in CASES:
                numbers = {"bifurcations": [], "success": True, "end": "reached Omega~ = 1.6",
                           "peak_ratio": 1.05, "dominant": "1X", "disk_peaks": [1.1, 1.4],
                           "crit1": 811.3, "crit2": 2784.6, "motion": "period-1"}
                out[name] = Outcome(name, "ok", "", 1.0, numbers, _data(name))
    return out


@pytest.mark.parametrize("number", list(FIGURES))
def test_every_paper_figure_in_the_readers_terms(number):
    spec = FIGURES[number]
    outcomes = _outcomes(spec.cases)
    fig = draw(spec, outcomes)
    words = texts(fig)
    labels = legend_labels(fig)
    bad = [t for t in labels if CASE_ID.search(t)]
    assert not bad, f"case ids in the legend of Figure {number}: {bad}"
    assert not any("Omega~" in t or "|mu|" in t or "w_b" in t for t in words), words
    assert not any(t.rstrip().endswith(("...", "\u2026")) for t in words)
    assert any(t.startswith(f"Figure {number}:") for t in words)
    assert not legends_over_panels(fig), number
    if spec.plot in ("deflection", "harmonics", "directions", "yawing", "isola"):
        assert {"stable", "unstable", "saddle-node"} <= labels, labels
    calibrated = [c for c in spec.cases if CAL + c in CASES]
    if calibrated and spec.plot != "width":
        assert any(t.startswith("Calibrated reading") for t in words)
        assert any(t.startswith("Literal reading") for t in words)
    if spec.plot == "width" and calibrated:
        assert any(t.endswith(", calibrated") for t in labels)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=30)
    assert buf.getvalue()[:4] == b"\x89PNG"


def test_report_page_structure(tmp_path):
    names = list(dict.fromkeys(c for s in FIGURES.values() for c in s.cases))
    outcomes = _outcomes([*names, "modal"])
    pngs = {}
    for number in ("7", "19", "23"):
        buf = io.BytesIO()
        draw(FIGURES[number], outcomes).savefig(buf, format="png", dpi=20)
        pngs[number] = buf.getvalue()
    write_report(tmp_path, outcomes, pngs, elapsed=1.0, diagnoses=DIAGNOSES)
    md = (tmp_path / "report.md").read_text()
    page = (tmp_path / "report.html").read_text()
    text = re.sub(r"<code>.*?</code>", "", page, flags=re.S)
    assert "`" not in text
    assert "<code>examples/paper_rotor_calibrated.toml</code>" in page
    # one <p> per markdown paragraph (blank-line separated), not one per source line
    md_paragraphs = [b for b in re.split(r"\n\s*\n", md.split("## Our numbers")[0])
                     if b.strip() and not b.lstrip().startswith("#")]
    head = page.split("<h2>")[1] if "<h2>" in page else page
    assert len(re.findall(r"<p>", page.split("<h2>")[0])) == len(md_paragraphs)
    assert head
    # one comparison table with both readings' columns on every row
    tables = re.findall(r"<table>.*?</table>", page, flags=re.S)
    rows = re.findall(r"<tr>(.*?)</tr>", tables[0], flags=re.S)
    assert all(len(re.findall(r"<t[hd]", r)) == 9 for r in rows)
    assert len(re.findall(r'<img alt="Figure', page)) == 3
    for ascii_ in ("Omega~", "|mu|max", "w_by"):
        assert ascii_ not in text, ascii_
