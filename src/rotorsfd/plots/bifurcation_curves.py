"""The two-parameter bifurcation chart: fold (saddle-node), period-doubling and
Neimark-Sacker curves of the speed response in the (Omega~, second parameter) plane,
their turning points and codimension-2 points (cusps, 1:1 and 1:2 resonances,
fold-flip, fold- and flip-Neimark-Sacker) marked, the legend in words beside the axes."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import axis_label, wrap

#: kind -> (legend words, colour, line style)
STYLE = {"saddle-node": ("saddle-node (fold)", "C0", "-"),
         "period-doubling": ("period doubling", "C3", "--"),
         "Neimark-Sacker": ("Neimark-Sacker (secondary Hopf: quasi-periodic)", "C2", "-.")}
TURN_WORDS = {"saddle-node": "cusp (fold pair meets)",
              "period-doubling": "turning point (period-doubling pair meets)",
              "Neimark-Sacker": "turning point (secondary Hopf pair meets)"}
#: codimension-2 type -> (legend words, marker, colour); a cusp is drawn as a turn
CODIM2 = {"1:1 resonance": ("1:1 resonance (multipliers meet at +1)", "D", "C1"),
          "1:2 resonance": ("1:2 resonance (secondary Hopf meets period doubling)", "s",
                            "k"),
          "fold-flip": ("fold-flip (saddle-node meets period doubling)", "P", "C4"),
          "fold-Neimark-Sacker": ("fold-Neimark-Sacker (saddle-node meets secondary "
                                  "Hopf)", "X", "C5"),
          "flip-Neimark-Sacker": ("flip-Neimark-Sacker (period doubling meets secondary "
                                  "Hopf)", "*",
                                  "C6")}
#: SI unit -> (unit shown, factor): an unbalance in g mm, not 5e-06 kg m
DISPLAY_UNITS = {"kg*m": ("g*mm", 1e6)}
#: ... and a dimensionless ratio (C/R, a damping ratio) in per cent, as configs write it
RATIO_DISPLAY = ("%", 100.0)


#: Axes box (width, height) of the figure, inches (fixed layout).
PANEL = (5.6, 4.0)


def bifurcation_curves_figure(kind: Any, curve: Any, speed_ratio: Any, value: Any, *,
                              turns: Sequence[tuple[str, float, float]] = (),
                              codim2: Sequence[tuple[str, float, float]] = (),
                              parameter: str, units: str, H: int, H2: int | None = None,
                              title: str = ""
                              ) -> Figure:
    """``curves.png``: the points (``speed_ratio``, ``value``) of each curve (``kind``
    and ``curve`` number them), ``turns`` as (kind, speed_ratio, value), the
    codimension-2 points ``codim2`` as (type, speed_ratio, value); a cusp in ``codim2``
    is drawn once, as the fold curve's turn."""
    kind, curve = np.asarray(kind, dtype=str), np.asarray(curve)
    ratio, value = np.asarray(speed_ratio, float), np.asarray(value, float)
    shown, factor = (RATIO_DISPLAY if units == "1" and parameter.endswith("ratio")
                     else DISPLAY_UNITS.get(units, (units, 1.0)))
    fig = Figure()
    ax = fig.subplots()
    for k, (words, colour, style) in STYLE.items():
        for j, c in enumerate(np.unique(curve[kind == k])):
            sel = (kind == k) & (curve == c)
            ax.plot(ratio[sel], factor * value[sel], style, lw=1.6, color=colour,
                    label=words if j == 0 else None)
    marks = {"saddle-node": ("v", "k", None), "period-doubling": ("o", "C3", "none"),
             "Neimark-Sacker": ("o", "C2", "none")}
    for k, (marker, colour, face) in marks.items():
        pts = [(r, v) for kk, r, v in turns if kk == k]
        if pts:
            r, v = np.array(pts).T
            ax.plot(r, factor * v, marker, ms=7, color=colour, mfc=face,
                    label=TURN_WORDS[k])
    for k, (words, marker, colour) in CODIM2.items():
        pts = [(r, v) for kk, r, v in codim2 if kk == k]
        if pts:
            r, v = np.array(pts).T
            ax.plot(r, factor * v, marker, ms=9, color=colour, mec="k", mew=0.6,
                    label=words, zorder=5)
    ax.set_xlabel(r"speed ratio $\tilde\Omega$")
    ax.xaxis.set_major_locator(MaxNLocator(5))   # a narrow speed range: no offset text
    ax.ticklabel_format(axis="x", useOffset=False)
    ax.set_ylabel(axis_label(parameter, shown))
    ax.set_title(wrap((f"{title}\n" if title else "") + "Bifurcation curves in "
                      rf"($\Omega$, {axis_label(parameter)}), H = {H}"
                      + (rf" (period doubling: {H2} harmonics of $\Omega$/2)" if H2 else ""),
                      80), fontsize=9)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    fixed_layout(fig, [[ax]], PANEL)
    return fig
