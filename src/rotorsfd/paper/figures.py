"""The paper's figures: the cases' outcomes resolved into plain data (legend labels in the
reader's terms, colours by case, the published widths) and drawn by
:func:`rotorsfd.plots.paper_figures.paper_figure` (all matplotlib code is in plots/)."""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING

from rotorsfd.paper.cases import CAL, CASES, FigureSpec, Outcome, literal_name
from rotorsfd.plots.labels import settings
from rotorsfd.plots.paper_figures import paper_figure
from rotorsfd.plots.paper_panels import Curve

if TYPE_CHECKING:
    from matplotlib.figure import Figure

#: Row titles of a figure drawn in both readings.
READING_TITLES = {"literal": "Literal reading (no structural damping)",
                  "calibrated": "Calibrated reading (modal damping 0.2197 %, "
                                "examples/paper_rotor_calibrated.toml)"}
#: The paper's unstable widths in Omega~ against the pitching rate (Figure 19).
PAPER_WIDTHS = {"U = 252 g mm (paper)": ([0, 7], [0.041, 0.0]),
                "U = 360.04 g mm (paper)": ([0, 10], [0.195, 0.119])}


def case_label(name: str, spec: FigureSpec | None = None) -> str:
    """A case in the reader's terms: the settings that tell it from the other cases of
    ``spec`` ("U = 72.008 g mm", "$\\omega_{by}$ = 2 rad/s"), not its id."""
    case = CASES.get(name)
    if case is None:
        return name
    others = [CASES[c].overrides for c in (spec.cases if spec else ()) if c in CASES]
    common = set.intersection(*map(set, others)) if len(others) > 1 else set()
    words = settings(case.overrides, common)
    if not words:                       # e.g. the diagnosis case of a figure's file
        m = re.search(r"fig(\d+)", name) or re.search(r"fig0*(\d+)", Path(case.config).stem)
        words = f"Figure {m.group(1)} case" if m else name
    return words


def curve(spec: FigureSpec, o: Outcome, i: int) -> Curve:
    """``o`` as drawn in ``spec``: labelled by its settings, coloured by its literal case's
    place in the figure (a case has the same colour in both readings' rows)."""
    lit = literal_name(o.name)
    case = CASES.get(lit)
    label = case_label(o.name, spec)
    if spec.plot == "width":            # the harmonics count said (H = ...) when given
        h = case.note.split(" (")[0].split(",")[0] if case else ""
        label = case_label(lit) + (f", {h}" if h.startswith("H = ") else "")
    return Curve(o.data, label, f"C{(spec.cases.index(lit) if lit in spec.cases else i) % 10}",
                 title=case_label(o.name), group=lit, calibrated=o.name.startswith(CAL),
                 dotted="paper-h" in o.name)


def draw(spec: FigureSpec, outcomes: Mapping[str, Outcome]) -> Figure | None:
    """The figure of ``spec`` (None when none of its cases gave data): one row of panels
    per reading that ran (the calibrated one below the literal; Figure 19's widths of
    both readings on one axes)."""
    res = [outcomes[c] for c in spec.cases if c in outcomes and outcomes[c].data]
    cal = [outcomes[CAL + c] for c in spec.cases
           if CAL + c in outcomes and outcomes[CAL + c].data]
    if not res and not cal:
        return None
    lit, calibrated = ([curve(spec, o, i) for i, o in enumerate(rows)] for rows in (res, cal))
    options = dict(spec.options)
    if spec.plot == "width":
        readings = [("", [*lit, *calibrated])]
        options["references"] = PAPER_WIDTHS
    elif res and cal:
        readings = [(READING_TITLES["literal"], lit),
                    (READING_TITLES["calibrated"], calibrated)]
    else:
        readings = [("", lit or calibrated)]
    if spec.plot == "yawing":           # the orbits of the 6 rad/s case
        options["orbit"] = next((c for c in spec.cases if c.endswith("w6")), "")
    title = f"Figure {spec.number}: {spec.title}"
    if cal and not res:                # the calibrated reading alone: said in the title
        title += f"\n{READING_TITLES['calibrated']}"
    return paper_figure(spec.plot, readings, title, options)
