"""The fold-curve figure (the paper's Figure 19 kind): the saddle-nodes' Omega~ against a
second parameter with the bistable region shaded and the cusps marked, and the unstable
width below; the parameter named in words with its unit, symbols in mathtext, the legend
beside the panels.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import axis_label, wrap

#: Axes box (width, height) of each panel, inches (fixed layout).
PANEL = (5.6, 2.9)


def fold_curve_figure(value: Any, speed_ratio: Any, curve: Any, *, grid: Any, lo: Any,
                      hi: Any, count: Any, cusps: Sequence[tuple[float, float]] = (),
                      parameter: str, units: str, H: int, title: str = "") -> Figure:
    """``fold_curve.png``: the points (``value``, ``speed_ratio``) of each fold curve
    (``curve`` numbers them); the envelope ``lo``..``hi`` on ``grid`` shaded where
    ``count`` >= 2 saddle-nodes (bistable) and its width hi - lo below; ``cusps`` as
    (value, speed_ratio)."""
    value, ratio, curve = (np.asarray(a) for a in (value, speed_ratio, curve))
    grid, lo, hi, count = (np.asarray(a, float) for a in (grid, lo, hi, count))
    fig = Figure()
    ax, ax2 = fig.subplots(2, 1, sharex=True)
    for k, c in enumerate(np.unique(curve)):
        sel = curve == c
        ax.plot(value[sel], ratio[sel], "-", lw=1.5, color="C0",
                label="fold curve (saddle-nodes)" if k == 0 else None)
    bistable = count >= 2
    ax.fill_between(grid, lo, hi, where=bistable, color="C1", alpha=0.25, lw=0,
                    label="bistable (middle branch unstable)")
    units_words = "" if units == "1" else " " + units.replace("**", "^").replace("*", " ")
    for k, (v, s) in enumerate(cusps):
        ax.plot([v], [s], "kv", ms=7, label=f"cusp at {v:.4g}{units_words}" if k < 3
                else None)
    ax.set_ylabel(r"$\tilde\Omega$ of the saddle-nodes")
    ax.set_title(wrap((f"{title}\n" if title else "") + "Fold curve in "
                      rf"($\Omega$, {axis_label(parameter)}), H = {H}", 80), fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    ax2.plot(grid, np.where(bistable, hi - lo, 0.0), "-", color="C1")
    ax2.set_xlabel(axis_label(parameter, units))
    ax2.set_ylabel(r"unstable width in $\tilde\Omega$")
    ax2.grid(alpha=0.3)
    fixed_layout(fig, [[ax], [ax2]], PANEL)
    return fig
