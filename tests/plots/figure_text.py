"""Helpers of the figure tests: every text of a figure, whether legends overlap panels, and
what a fixed layout got wrong (texts clipped, decorations over another panel)."""

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


def fixed_layout_faults(fig: Figure) -> list[str]:
    """What a fixed layout got wrong, measured on the drawn figure: a text or legend
    reaching outside the figure (clipped), or a panel's decorations (ticks, labels, title)
    over another panel's frame."""
    fig.set_dpi(40)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    r = canvas.get_renderer()
    page = fig.bbox
    out = []
    # the figure's own texts (title, headings), the legends and every panel with what it
    # draws around it (ticks shown, labels, title)
    boxes = [(a.get_text(), a.get_window_extent(r)) for a in fig.findobj(Text)
             if a.get_text() and (a in fig.texts or a.get_text() == fig.get_suptitle())]
    boxes += [("legend", a.get_window_extent(r)) for a in fig.findobj(Legend)]
    boxes += [(ax.get_title() or ax.get_ylabel(), ax.get_tightbbox(r)) for ax in fig.axes]
    for name, b in boxes:
        if b.x0 < page.x0 - 1 or b.x1 > page.x1 + 1 or b.y0 < page.y0 - 1 \
                or b.y1 > page.y1 + 1:
            out.append(f"outside: {name}")
    panels = [ax for ax in fig.axes if ax.get_label() != "<colorbar>"]
    for ax in panels:
        tight = ax.get_tightbbox(r)
        for other in panels:
            if other is not ax and tight.overlaps(other.get_window_extent(r)):
                out.append(f"over a panel: {ax.get_title()!r} on {other.get_title()!r}")
    return out


def labels_under_legends(fig: Figure) -> list[str]:
    """Axis labels, titles and the figure title that a legend covers."""
    fig.set_dpi(40)
    canvas = FigureCanvasAgg(fig)
    canvas.draw()
    r = canvas.get_renderer()
    texts = [t for ax in fig.axes for t in (ax.xaxis.label, ax.yaxis.label, ax.title)]
    texts += list(fig.texts)
    return [t.get_text() for lg in legends(fig) for t in texts
            if t.get_visible() and t.get_text()
            and lg.get_window_extent(r).overlaps(t.get_window_extent(r))]
