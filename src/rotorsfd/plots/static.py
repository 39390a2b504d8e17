"""The static deflection along the shaft (``static_deflection.png``): y and z of every
node against its axial position, one line per speed (at most :data:`MAX_LINES`, evenly
picked; the legend says which speeds), in micrometres."""

from __future__ import annotations

from typing import Any

import numpy as np
from matplotlib import colormaps
from matplotlib.figure import Figure

from rotorsfd.plots.labels import wrap

#: speeds drawn at most (evenly picked from the list, the first and the last included)
MAX_LINES = 8


def static_figure(node_x: Any, speeds: Any, q: Any, *, reference_speed: float | None = None,
                  title: str = "") -> Figure:
    """Two panels, y and z [um] of the nodes at ``node_x`` [m] for each speed [rad/s]
    (``q`` (n_speeds, n_dof), DOFs ``[y, z, ty, tz]`` per node)."""
    node_x, speeds, q = (np.asarray(v, float) for v in (node_x, speeds, q))
    picked = np.unique(np.linspace(0, speeds.size - 1, min(MAX_LINES, speeds.size)
                                   ).round().astype(int))
    fig = Figure(figsize=(9.0, 5.6))
    top, bottom = fig.subplots(2, 1, sharex=True)
    cmap = colormaps["viridis"]
    for k, i in enumerate(picked):
        c = cmap(k / max(1, picked.size - 1))
        s = speeds[i]
        label = (rf"$\Omega$ = {s:.4g} rad/s" + (rf" ($\tilde\Omega$ = "
                                                 rf"{s / reference_speed:.3g})"
                                                 if reference_speed else ""))
        top.plot(node_x, q[i, 0::4] * 1e6, "-o", ms=3, color=c, label=label)
        bottom.plot(node_x, q[i, 1::4] * 1e6, "-o", ms=3, color=c)
    top.set_ylabel(r"$y$ (horizontal) [µm]")
    bottom.set_ylabel(r"$z$ (vertical) [µm]")
    bottom.set_xlabel(r"axial position $x$ [m]")
    for ax in (top, bottom):
        ax.grid(True, alpha=0.3)
        ax.axhline(0.0, color="0.5", lw=0.8)
    fig.legend(loc="center left", bbox_to_anchor=(0.71, 0.5), fontsize=8, frameon=False)
    fig.subplots_adjust(left=0.1, right=0.70, top=0.88, bottom=0.1, hspace=0.12)
    fig.suptitle(wrap(title or "Static deflection under constant base motion", 90),
                 fontsize=10)
    return fig
