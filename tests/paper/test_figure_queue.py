"""The paper's figures drawn while the cases run (``FigureQueue``): a figure is drawn as
soon as the last of its cases ends, from exactly the outcomes it shows, so its PNG is the
same bytes as the figure drawn after the whole run; figures come out in the order of the
specs whatever order the cases end in."""

from __future__ import annotations

import io
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from test_every_figure import _outcomes

from rotorsfd.paper.cases import FIGURES
from rotorsfd.paper.figures import draw
from rotorsfd.paper.run import FigureQueue

SPECS = [FIGURES[n] for n in ("7", "9", "19", "23b")]


def _png(spec, outcomes) -> bytes:
    buf = io.BytesIO()
    draw(spec, outcomes).savefig(buf, format="png", dpi=110)
    return buf.getvalue()


def test_figures_drawn_as_their_cases_end_are_those_drawn_after_the_run():
    outcomes = _outcomes([c for s in SPECS for c in s.cases])
    names = list(outcomes)
    queue = FigureQueue(SPECS, names)
    order = names[::-1]                          # another order than the specs'
    drawn_at = {}
    for i, name in enumerate(order):
        queue.add(outcomes[name])
        for number in queue.done:
            drawn_at.setdefault(number, i)
    for spec in SPECS:    # drawn right after the last of its cases (both readings) ended
        last = max(order.index(n) for n in queue.needs[spec.number])
        assert drawn_at[spec.number] == last, spec.number
        assert {n.removeprefix("cal-") for n in queue.needs[spec.number]} == set(spec.cases)
    pngs = queue.pngs()
    assert list(pngs) == [s.number for s in SPECS]
    for spec in SPECS:
        assert pngs[spec.number] == _png(spec, outcomes), spec.number


def test_a_figure_whose_cases_did_not_run_is_left_out():
    outcomes = _outcomes(FIGURES["7"].cases)
    queue = FigureQueue([FIGURES["7"], FIGURES["19"]], list(outcomes))
    for o in outcomes.values():
        queue.add(o)
    assert list(queue.pngs()) == ["7"]
