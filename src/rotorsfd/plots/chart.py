"""Stability charts (the paper's Figure 6): unstable points of a two-parameter grid shaded
by max |mu|, with a title that says what the chart shows (how many zones, how far down
they reach, the isolated points and their |mu|), computed from the grid.

A point is unstable when max |mu| > 1 + tol; a region is a 4-connected set of unstable
points; a region smaller than ``ZONE_FRACTION`` of the grid (at least 3 points: 10 on a
100 x 100 grid) is an island (drawn ringed so that a single-point speck is seen), so that
the zones of a coarse grid are not called islands.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.colors import Normalize
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator
from scipy import ndimage

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import label, wrap

#: Axes box (width, height) of the chart figure, inches (fixed layout).
PANEL = (5.0, 3.9)

ZONE_FRACTION = 1e-3   # regions of this fraction of the grid (>= 3 points) are zones


@dataclass(frozen=True)
class Region:
    """A connected set of unstable grid points."""

    n_points: int
    x_range: tuple[float, float]
    y_range: tuple[float, float]
    max_abs: float
    centre: tuple[float, float]
    grid_points: int = 0        # the size of the grid it was found on

    @property
    def is_island(self) -> bool:
        """Smaller than ``ZONE_FRACTION`` of its grid (and than 3 points at least)."""
        return self.n_points < max(3, round(ZONE_FRACTION * self.grid_points))


def unstable_regions(x: Any, y: Any, max_abs: Any, tol: float = 1e-5) -> list[Region]:
    """The 4-connected regions of max |mu| > 1 + tol on the grid (``max_abs[i, j]`` at
    ``x[i], y[j]``), largest first."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    m = np.asarray(max_abs, float)
    lab, n = ndimage.label(m > 1.0 + tol)
    out = []
    for k in range(1, n + 1):
        i, j = np.nonzero(lab == k)
        out.append(Region(int(i.size), (float(x[i].min()), float(x[i].max())),
                          (float(y[j].min()), float(y[j].max())), float(m[i, j].max()),
                          (float(x[i].mean()), float(y[j].mean())), int(m.size)))
    return sorted(out, key=lambda r: -r.n_points)


def describe(regions: list[Region], y_name: str, y_units: str = "", *,
             mu: str = r"$|\mu|$", ringed: bool = True) -> str:
    """What the chart shows in one or two lines: the zones and how far down in y they
    reach, the islands and their |mu| (``mu``: how to write it)."""
    if not regions:
        return "no unstable point on the grid"
    zones = [r for r in regions if not r.is_island]
    islands = [r for r in regions if r.is_island]
    u = f" {y_units}" if y_units else ""
    parts = []
    if zones:
        low = sorted(r.y_range[0] for r in zones)
        reach = f"{low[0]:.3g}" if len(low) == 1 or low[0] == low[-1] else \
            f"{low[0]:.3g}-{low[-1]:.3g}"
        parts.append(f"{len(zones)} unstable zone{'s' * (len(zones) > 1)} down to "
                     f"{y_name} = {reach}{u}")
    if islands:
        mus = sorted(r.max_abs for r in islands)
        value = f"{mus[0]:.5g}" if len(mus) == 1 else f"{mus[0]:.5g}-{mus[-1]:.5g}"
        sizes = sorted(r.n_points for r in islands)
        size = f"{sizes[0]}" if sizes[0] == sizes[-1] else f"{sizes[0]}-{sizes[-1]}"
        ring = "ringed; " if ringed else ""
        parts.append(f"{len(islands)} island{'s' * (len(islands) > 1)} of {size} "
                     f"point{'s' * (sizes[-1] > 1)} ({ring}max {mu} {value})")
    return "; ".join(parts)


def chart_axes(ax: Axes, x: Any, y: Any, max_abs: Any, *, x_label: str, y_label: str,
               tol: float = 1e-5, speed: float | None = None, title: str = "",
               cax: Axes | None = None) -> Axes:
    """Unstable points shaded by max |mu| (white: stable), the boundary max |mu| = 1 + tol
    in black, islands ringed, a colour bar with round ticks (in ``cax`` when given, else
    space taken from ``ax``); the title says what is shown (:func:`describe`). Labels given
    as config paths ("base.pitching.frequency [rad/s]") are written in words."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    m = np.asarray(max_abs, float)
    stable = m <= 1.0 + tol
    X, Y = np.meshgrid(x, y, indexing="ij")
    if np.any(~stable):
        top = max(float(m[~stable].max()), 1.0 + 2.0 * tol)
        norm = Normalize(vmin=1.0 - 0.25 * (top - 1.0), vmax=top)
        mesh = ax.pcolormesh(X, Y, np.where(stable, np.nan, m), shading="nearest",
                             cmap="Blues", norm=norm)
        where = {"ax": ax} if cax is None else {"cax": cax}
        bar = ax.figure.colorbar(mesh, **where,
                                 ticks=MaxNLocator(6, steps=[1, 2, 2.5, 5, 10]))
        bar.set_label(r"max $|\mu|$ (Floquet multiplier) of the unstable points")
        if min(m.shape) > 1:
            ax.contour(X, Y, m, levels=[1.0 + tol], colors="k", linewidths=0.6)
    regions = unstable_regions(x, y, m, tol)
    islands = [r for r in regions if r.is_island]
    if islands:
        ax.plot([r.centre[0] for r in islands], [r.centre[1] for r in islands], "o",
                ms=11, mfc="none", mec="C3", mew=1.0, ls="none", gid="islands")
    ax.set_xlim(x.min(), x.max())
    ax.set_ylim(y.min(), y.max())
    ax.set_xlabel(label(x_label))
    ax.set_ylabel(label(y_label))
    y_words, _, y_units = label(y_label).partition(" [")
    y_name = y_words.split()[-1] if y_words.split()[-1].startswith("$") else y_words
    head = f"{wrap(title, 80)}\n" if title else ""
    at = "" if speed is None else rf", $\Omega$ = {speed:.6g} rad/s"
    shown = describe(regions, y_name, y_units.rstrip("]"))
    ax.set_title(head + wrap(f"{int((~stable).sum())} of {m.size} points unstable (max "
                             rf"$|\mu|$ > 1 + {tol:g}){at}: {shown}", 80), fontsize=9)
    return ax


def chart_figure(x: Any, y: Any, max_abs: Any, *, x_path: str, y_path: str,
                 x_units: str = "", y_units: str = "", tol: float = 1e-5,
                 speed: float | None = None, title: str = "") -> Figure:
    """``chart.png``: :func:`chart_axes` on its own figure (axes named in words)."""
    fig = Figure()
    ax = fig.add_subplot()
    unstable = bool(np.any(np.asarray(max_abs, float) > 1.0 + tol))   # a colour bar
    cax = fig.add_axes((0.0, 0.0, 0.1, 0.1), label="<colorbar>") if unstable else None
    chart_axes(ax, x, y, max_abs, x_label=f"{x_path} [{x_units}]" if x_units else x_path,
               y_label=f"{y_path} [{y_units}]" if y_units else y_path,
               tol=tol, speed=speed, title=title, cax=cax)
    fixed_layout(fig, [[ax]], PANEL, colorbars=[(cax, [ax])] if cax is not None else ())
    return fig


__all__ = ["Region", "chart_axes", "chart_figure", "describe",
           "unstable_regions"]
