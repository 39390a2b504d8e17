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

from rotorsfd.plots.labels import wrap

STYLE = {"forward": {"color": "tab:blue", "ls": "-"},
         "backward": {"color": "tab:red", "ls": "--"}}


def campbell_axes(ax: Axes, speeds: Any, frequencies: Any, whirl: Any, *,
                  critical: Sequence[float] = (), harmonics: Sequence[float] = (1.0,),
                  title: str = "") -> Axes:
    """Draw the diagram on ``ax``: ``frequencies[i, j]`` (rad/s) of branch j at
    ``speeds[i]``, ``whirl[i, j]`` "forward" or "backward"; ``critical`` speeds (rad/s,
    on the 1X line) marked and labelled."""
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
    for h in harmonics:
        ax.plot(speeds, h * speeds, color="0.4", ls=":", label=rf"{h:g}X ($\omega = "
                rf"{h:g}\,\Omega$)" if h != 1 else r"1X ($\omega = \Omega$)")
    for k, c in enumerate(critical):
        ax.plot([c], [c], "ko", ms=5, label="critical speed" if k == 0 else None)
        ax.annotate(f"{c:.1f} rad/s", (c, c), textcoords="offset points", xytext=(6, -12),
                    fontsize=8)
    top = float(np.nanmax(freq)) * 1.05 if freq.size and np.any(np.isfinite(freq)) else 1.0
    ax.set_ylim(0.0, top)
    ax.set_xlim(float(speeds.min()), float(speeds.max()))
    ax.set_xlabel(r"spin speed $\Omega$ [rad/s]")
    ax.set_ylabel(r"damped natural frequency $\omega$ [rad/s]")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=8, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    ax.set_title(wrap(title or "Campbell diagram", 70), fontsize=9)
    return ax


def campbell_figure(speeds: Any, frequencies: Any, whirl: Any, *,
                    critical: Sequence[float] = (), harmonics: Sequence[float] = (1.0,),
                    title: str = "") -> Figure:
    """``campbell.png``: :func:`campbell_axes` on a figure of its own."""
    fig = Figure(figsize=(8.5, 5), layout="constrained")
    campbell_axes(fig.add_subplot(), speeds, frequencies, whirl, critical=critical,
                  harmonics=harmonics, title=title)
    return fig
