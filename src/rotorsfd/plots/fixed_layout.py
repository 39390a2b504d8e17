"""A fixed layout for a grid of panels: every axes box has a given size in inches, and the
figure is sized around them from one measurement of what each panel draws outside its box
(tick labels, axis labels, title, a legend right of it), with no layout engine at each draw
(issue 17 item 5: constrained layout was 19 % of a ``paper --quick`` run). The panels of
:mod:`rotorsfd.plots.paper_figures` are laid out the same way from fixed margins.

For rows r and columns c of panels (w x h inches), with ``L_c, R_c`` the largest widths a
column's panels draw left and right of their boxes and ``T_r, B_r`` the heights above and
below a row's boxes::

    x_0 = PAD + L_0,   x_{c+1} = x_c + w + R_c + GAP + L_{c+1},
    y_0 = PAD + S + T_0,   y_{r+1} = y_r + h + B_r + GAP + T_{r+1}     (from the top)

S the height of the figure title (with a gap); the width is also at least the title's.
A colour bar (its own axes, drawn with ``fig.colorbar(mappable, cax=cax)``) is a box
``BAR`` wide, ``BAR_GAP`` right of the panels it belongs to and as tall as they span; its
ticks and label count as what those panels draw on their right. The axes keep their size
in inches from the measurement on, so their ticks (chosen from the axis length) and the
measured margins stay what was measured.
"""

from __future__ import annotations

from collections.abc import Sequence

from matplotlib.axes import Axes
from matplotlib.backends.backend_agg import FigureCanvasAgg
from matplotlib.figure import Figure

#: Margin around the content and gap between panels' decorations, inches.
PAD, GAP = 0.12, 0.15
#: Room provisionally left around each panel while it is measured, inches.
ROOM = 4.0
#: A colour bar's width and its gap to its panels, inches.
BAR, BAR_GAP = 0.16, 0.12


def _place_bars(fig: Figure, colorbars: Sequence[tuple[Axes, Sequence[Axes]]]) -> None:
    """Each colour bar's axes right of the boxes of its panels, as tall as they span."""
    W = fig.get_size_inches()[0]
    for cax, owners in colorbars:
        boxes = [ax.get_position() for ax in owners]
        x1 = max(b.x1 for b in boxes)
        y0, y1 = min(b.y0 for b in boxes), max(b.y1 for b in boxes)
        cax.set_position([x1 + BAR_GAP / W, y0, BAR / W, y1 - y0])


def fixed_layout(fig: Figure, grid: Sequence[Sequence[Axes | None]],
                 panel: tuple[float, float],
                 colorbars: Sequence[tuple[Axes, Sequence[Axes]]] = ()) -> None:
    """Size ``fig`` and place the axes of ``grid`` (rows of axes, None for an empty cell)
    as boxes of ``panel = (w, h)`` inches (module docstring); the figure title
    (``fig.suptitle``) centred above them; ``colorbars``: (colour bar axes, the panels it
    belongs to) pairs, each bar right of its panels."""
    rows, cols = len(grid), max(len(r) for r in grid)
    w, h = panel
    fig.set_layout_engine(None)
    W0, H0 = cols * (w + 2 * ROOM), rows * (h + 2 * ROOM)
    fig.set_size_inches(W0, H0)
    cells = [(r, c, ax) for r, row in enumerate(grid) for c, ax in enumerate(row)
             if ax is not None]
    for r, c, ax in cells:          # every box at its final size: ticks as they will be
        ax.set_position([(ROOM + c * (w + 2 * ROOM)) / W0,
                         1 - (ROOM + r * (h + 2 * ROOM) + h) / H0, w / W0, h / H0])
    _place_bars(fig, colorbars)
    renderer = FigureCanvasAgg(fig).get_renderer()
    dpi = fig.dpi
    left, right = [0.0] * cols, [0.0] * cols
    above, below = [0.0] * rows, [0.0] * rows
    where = {id(ax): (r, c) for r, c, ax in cells}
    for r, c, ax in cells:
        box, tight = ax.get_window_extent(renderer), ax.get_tightbbox(renderer)
        left[c] = max(left[c], (box.x0 - tight.x0) / dpi)
        right[c] = max(right[c], (tight.x1 - box.x1) / dpi)
        above[r] = max(above[r], (tight.y1 - box.y1) / dpi)
        below[r] = max(below[r], (box.y0 - tight.y0) / dpi)
    for cax, owners in colorbars:   # the bar and its labels right of its last column
        c = max(where[id(ax)][1] for ax in owners)
        x1 = max(ax.get_window_extent(renderer).x1 for ax in owners)
        right[c] = max(right[c], (cax.get_tightbbox(renderer).x1 - x1) / dpi)
    sup = next((t for t in fig.texts if fig.get_suptitle()
                and t.get_text() == fig.get_suptitle()), None)
    title_w = title_h = 0.0
    if sup:
        ext = sup.get_window_extent(renderer)
        title_w, title_h = ext.width / dpi, ext.height / dpi + GAP
    xs = [PAD + left[0]]
    for c in range(1, cols):
        xs.append(xs[-1] + w + right[c - 1] + GAP + left[c])
    content = xs[-1] + w + right[-1] + PAD
    width = max(content, title_w + 2 * PAD)
    shift = 0.5 * (width - content)          # the panels centred under a wider title
    ys = [PAD + title_h + above[0]]
    for r in range(1, rows):
        ys.append(ys[-1] + h + below[r - 1] + GAP + above[r])
    height = ys[-1] + h + below[-1] + PAD
    fig.set_size_inches(width, height)
    for r, c, ax in cells:
        ax.set_position([(shift + xs[c]) / width, 1 - (ys[r] + h) / height, w / width,
                         h / height])
    _place_bars(fig, colorbars)
    if sup:
        sup.set_ha("center")
        sup.set_va("top")
        sup.set_position((0.5, 1 - PAD / height))
