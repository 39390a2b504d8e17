"""The basin plot of an attractor census: every start at its two first initial-state
coordinates, coloured by the attractor it reached; the legend says in words what each
attractor is and how many starts reached it."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

from matplotlib.figure import Figure

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import wrap

MARKERS = "osD^v<>ph*"


#: Axes box (width, height) of the figure, inches (fixed layout).
PANEL = (6.2, 4.4)


def _legend(census: Any, i: int, a: Any) -> str:
    p, se = census.fraction(a)
    what = {"contact": "hit the clearance (contact)",
            "failed": "integration failed",
            "quasi-periodic": "quasi-periodic (a torus)",
            "chaotic": "irregular (chaotic)"}.get(a.motion, f"periodic, {a.motion}")
    where = ""
    if a.points.size and a.period is not None:
        where = ", Poincare point (" + ", ".join(f"{x:.2f}" for x in a.points[0][:2]) + ")"
    stab = ""
    if "hb_stable" in a.hb:
        stab = ", stable by Floquet" if a.hb["hb_stable"] else ", unstable by Floquet"
    return f"motion {i + 1}: {what}{where}{stab}; {100 * p:.0f} +- {100 * se:.0f} % of starts"


def basin_figure(census: Any, coordinate_names: Sequence[str] | None = None,
                 title: str = "") -> Figure:
    """``basins.png``: the starts over coordinates 0 and 1 of ``census.coords`` (named by
    ``coordinate_names``), one colour and marker per attractor."""
    names = list(coordinate_names or ["first initial coordinate",
                                      "second initial coordinate"])
    fig = Figure()
    ax = fig.subplots()
    lab = census.labels()
    X = census.coords
    for i, a in enumerate(census.attractors):
        sel = lab == i
        ax.scatter(X[sel, 0], X[sel, 1], s=18, marker=MARKERS[i % len(MARKERS)],
                   color=f"C{i % 10}", label=_legend(census, i, a))
    ax.set_xlabel(names[0])
    ax.set_ylabel(names[1])
    ratio = f", speed ratio {census.speed_ratio:.4g}" if census.speed_ratio else ""
    ax.set_title(wrap(f"{title}\nWhere {census.n_starts} starts end up "
                      f"({census.speed:.5g} rad/s{ratio})" if title else
                      f"Where {census.n_starts} starts end up ({census.speed:.5g} rad/s"
                      f"{ratio})"), fontsize=10)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.12), fontsize=8, frameon=False)
    fixed_layout(fig, [[ax]], PANEL)
    return fig
