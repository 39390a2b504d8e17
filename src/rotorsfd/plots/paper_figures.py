"""The paper's figures assembled from plain data (:class:`~rotorsfd.plots.paper_panels.Curve`)
in a fixed layout: every axes box has the size of its kind of panel (inches), the
margins are computed from the rows, columns, title lines and the legends' widths (one
text measurement, no layout engine at each draw). One block of panels per reading, the
calibrated one below the literal, each under its heading."""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import Any

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.gridspec import GridSpec

from rotorsfd.plots import paper_panels as pp
from rotorsfd.plots.labels import wrap
from rotorsfd.plots.paper_panels import ABOVE, BELOW, LEFT, PANEL, TITLE_LINE, Curve

Draw = Callable[[Figure, GridSpec, Sequence[Curve], Mapping[str, Any]], None]
DRAW: dict[str, Draw] = {
    "deflection": pp.draw_deflection, "harmonics": pp.draw_harmonics,
    "orbits": pp.draw_orbits, "yawing": pp.draw_yawing, "width": pp.draw_width,
    "directions": pp.draw_directions, "timedomain": pp.draw_timedomain,
    "chart": pp.draw_chart, "isola": pp.draw_isola}
HEADING = 0.32            # a reading's heading, inches
RIGHT_PAD = 0.25          # right of the last column's legend, inches
COLOUR_BAR = 0.75         # the chart's colour bar label and ticks right of its cell, inches
TICK_OVERHANG = 0.2       # half the last x tick label ("-0.165") right of the axes, inches


def shape(kind: str, curves: Sequence[Curve], options: Mapping[str, Any]
          ) -> tuple[int, int]:
    """(rows, columns) of panels of one reading."""
    nodes = len(options.get("nodes", [1, 8]))
    if kind == "isola":
        return 2, 1 + max(len(r) for r in pp.isola_rows(curves))
    return {"deflection": (1, nodes), "harmonics": (1, nodes * len(curves)),
            "yawing": (1, 2), "directions": (1, 2),
            "timedomain": (len(curves), 3)}.get(kind, (1, 1))


def _lines(text: str) -> int:
    return text.count("\n") + 1 if text else 0


def _right_of_panels(fig: Figure, gs: GridSpec, cols: int) -> list[float]:
    """Per column, how far (inches) its legends reach right of their axes: the legend's
    width measured, plus its 2 % offset; 0 without one."""
    renderer = FigureCanvasAgg(fig).get_renderer()
    out = [0.0] * cols
    for ax in fig.axes:
        ss = ax.get_subplotspec()
        lg = ax.get_legend()
        if ss is None or lg is None or ss.get_topmost_subplotspec().get_gridspec() is not gs:
            continue
        box, panel = lg.get_window_extent(renderer), ax.get_window_extent(renderer)
        if box.x0 < panel.x1:               # under its axes (the isola's key), not right
            continue
        c = ss.get_topmost_subplotspec().colspan.stop - 1
        out[c] = max(out[c], (box.x1 - panel.x1) / fig.dpi)
    return out


def paper_figure(kind: str, readings: Sequence[tuple[str, Sequence[Curve]]], title: str,
                 options: Mapping[str, Any] | None = None) -> Figure:
    """One figure of ``kind`` (a key of :data:`DRAW`): per (heading, curves) of
    ``readings`` a block of panels under its heading (none when empty), the whole under
    ``title`` (wrapped at 110 characters)."""
    options = options or {}
    w, h = PANEL[kind]
    fig = Figure()
    blocks = []
    for heading, curves in readings:
        rows, cols = shape(kind, curves, options)
        gs = fig.add_gridspec(rows, cols)
        DRAW[kind](fig, gs, curves, options)
        titles = [0] * rows
        for ax in fig.axes:
            ss = ax.get_subplotspec()
            if ss is not None and ss.get_topmost_subplotspec().get_gridspec() is gs:
                r = ss.get_topmost_subplotspec().rowspan.start
                titles[r] = max(titles[r], _lines(ax.get_title()))
        blocks.append((heading, gs, rows, cols, titles))
    sup = fig.suptitle(wrap(title, 110), fontsize=10, va="top")
    heads = [fig.text(0.5, 0.0, b[0], ha="center", va="top", fontsize=9, fontweight="bold")
             if b[0] else None for b in blocks]
    renderer = FigureCanvasAgg(fig).get_renderer()
    width = max(1.05 * t.get_window_extent(renderer).width / fig.dpi + 2 * RIGHT_PAD
                for t in [sup, *filter(None, heads)])   # the titles whole (5 %: small dpi)
    top_in = 0.14 + 0.2 * _lines(sup.get_text())
    plan = []
    for (heading, gs, rows, cols, titles), text in zip(blocks, heads, strict=True):
        extra = _right_of_panels(fig, gs, cols)
        gap = LEFT + max(extra[:-1], default=0.0)
        right = max(extra[-1], COLOUR_BAR if kind == "chart" else TICK_OVERHANG) + RIGHT_PAD
        above = [ABOVE + TITLE_LINE * n for n in titles]
        vgap = BELOW + max(above[1:], default=0.0)
        head = HEADING if heading else 0.0
        height = head + above[0] + rows * h + (rows - 1) * vgap + BELOW
        width = max(width, LEFT + cols * w + (cols - 1) * gap + right)
        plan.append((text, gs, cols, gap, vgap, head + above[0], top_in, height))
        top_in += height
    fig.set_size_inches(width, top_in + 0.05)
    W, H = fig.get_size_inches()
    for text, gs, cols, gap, vgap, above, y0, height in plan:
        if text is not None:
            text.set_y(1 - (y0 + 0.06) / H)
        gs.update(left=LEFT / W, right=(LEFT + cols * w + (cols - 1) * gap) / W,
                  top=1 - (y0 + above) / H, bottom=1 - (y0 + height - BELOW) / H,
                  wspace=gap / w, hspace=vgap / h)
    for ax in fig.axes:
        ss = ax.get_subplotspec()
        if ss is not None:
            ax.set_position(ss.get_position(fig))
    sup.set_y(1 - 0.07 / H)
    return fig
