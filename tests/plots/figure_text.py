"""Helpers of the figure tests: every text of a figure, and whether legends overlap panels."""

from __future__ import annotations

from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure
from matplotlib.legend import Legend
from matplotlib.text import Text


def texts(fig: Figure) -> list[str]:
    """Every visible text of the figure (titles, labels, ticks, legends)."""
    fig.set_dpi(40)
    FigureCanvasAgg(fig).draw()
    return [t.get_text() for t in fig.findobj(Text) if t.get_visible() and t.get_text()]


def legends(fig: Figure) -> list[Legend]:
    return [a for a in fig.findobj(Legend) if a.get_visible()]


def legend_labels(fig: Figure) -> set[str]:
    return {t.get_text() for lg in legends(fig) for t in lg.get_texts()}


def legends_over_panels(fig: Figure) -> list[tuple[str, str]]:
    """(legend, panel) pairs whose boxes overlap (a legend over the curves)."""
    fig.set_dpi(40)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    renderer = canvas.get_renderer()
    out = []
    for lg in legends(fig):
        box = lg.get_window_extent(renderer)
        for ax in fig.axes:
            if ax.get_label() == "<colorbar>":
                continue
            if box.overlaps(ax.get_window_extent(renderer)):
                out.append((lg.get_texts()[0].get_text() if lg.get_texts() else "?",
                            ax.get_title()))
    return out
