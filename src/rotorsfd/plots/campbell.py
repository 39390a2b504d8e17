"""The Campbell diagram (``campbell.png``): damped natural frequencies against the spin
speed, forward whirl solid, backward dashed, the nX excitation lines dotted, the critical
speeds (where a forward branch meets 1X) marked and written; the legend right of the
panel and the title wrapped, so neither covers nor loses anything.
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import wrap

#: the spools' excitation lines (none red or blue: those are the whirl branches)
LINE_COLORS = ("tab:green", "tab:orange", "tab:purple", "tab:brown")
STYLE = {"forward": {"color": "tab:blue", "ls": "-"},
         "backward": {"color": "tab:red", "ls": "--"}}


#: Axes box (width, height) of the figure, inches (fixed layout).
PANEL = (5.6, 3.8)


def campbell_axes(ax: Axes, speeds: Any, frequencies: Any, whirl: Any, *,
                  critical: Sequence[float] = (), harmonics: Sequence[float] = (1.0,),
                  title: str = "", lines: Sequence[tuple[float, str]] = (),
                  marks: Sequence[tuple[float, float]] = (), xlabel: str = "") -> Axes:
    """Draw the diagram on ``ax``: ``frequencies[i, j]`` (rad/s) of branch j at
    ``speeds[i]``, ``whirl[i, j]`` "forward" or "backward"; ``critical`` speeds (rad/s,
    on the 1X line) marked and labelled. A dual-spool rotor passes its spools' excitation
    lines as ``lines`` ((slope, label): ``w = slope Omega``, drawn instead of
    ``harmonics`` then), their critical speeds as ``marks`` ((speed, frequency)) and the
    spool's speed as ``xlabel``."""
    speeds = np.asarray(speeds, float)
    freq = np.asarray(frequencies, float)
    whirl = np.asarray(whirl)
    labelled: set[str] = set()
    for j in range(freq.shape[1]):
        for kind, st in STYLE.items():
            y = np.where(whirl[:, j] == kind, freq[:, j], np.nan)
            if np.all(np.isnan(y)):
                continue
            ax.plot(speeds, y, label=None if kind in labelled else f"{kind} whirl", **st)
            labelled.add(kind)
    for h in harmonics if not lines else ():
        ax.plot(speeds, h * speeds, color="0.4", ls=":", label=rf"{h:g}X ($\omega = "
                rf"{h:g}\,\Omega$)" if h != 1 else r"1X ($\omega = \Omega$)")
    for k, (h, label) in enumerate(lines):
        ax.plot(speeds, h * speeds, color=LINE_COLORS[k % len(LINE_COLORS)], ls=":", lw=1.6,
                label=label)
    for k, (c, w) in enumerate(marks):
        ax.plot([c], [w], "ko", ms=5, label="critical speed" if k == 0 else None)
        ax.annotate(f"{c:.1f} rad/s", (c, w), textcoords="offset points", xytext=(6, -12),
                    fontsize=8)
    for k, c in enumerate(critical):
        ax.plot([c], [c], "ko", ms=5, label="critical speed" if k == 0 else None)
        ax.annotate(f"{c:.1f} rad/s", (c, c), textcoords="offset points", xytext=(6, -12),
                    fontsize=8)
    top = float(np.nanmax(freq)) * 1.05 if freq.size and np.any(np.isfinite(freq)) else 1.0
    ax.set_ylim(0.0, top)
    ax.set_xlim(float(speeds.min()), float(speeds.max()))
    ax.set_xlabel(xlabel or r"spin speed $\Omega$ [rad/s]")
    ax.set_ylabel(r"damped natural frequency $\omega$ [rad/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    ax.set_title(wrap(title or "Campbell diagram", 70), fontsize=9)
    return ax


def campbell_figure(speeds: Any, frequencies: Any, whirl: Any, *,
                    critical: Sequence[float] = (), harmonics: Sequence[float] = (1.0,),
                    title: str = "", **spools: Any) -> Figure:
    """``campbell.png``: :func:`campbell_axes` on a figure of its own (``spools``: its
    ``lines``, ``marks``, ``xlabel``)."""
    fig = Figure()
    ax = campbell_axes(fig.add_subplot(), speeds, frequencies, whirl, critical=critical,
                       harmonics=harmonics, title=title, **spools)
    fixed_layout(fig, [[ax]], PANEL)
    return fig
