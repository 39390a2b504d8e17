"""The panels of the paper's figures, drawn from plain data: each case a :class:`Curve`
(its table of arrays, legend label and colour, resolved by :mod:`rotorsfd.paper.figures`);
no physics and no case tables here. Each ``draw_<kind>`` fills the cells of one grid of
panels (:class:`matplotlib.gridspec.GridSpec`, laid out by
:mod:`rotorsfd.plots.paper_figures`)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.gridspec import GridSpec
from matplotlib.lines import Line2D
from matplotlib.ticker import MaxNLocator

from rotorsfd.plots.chart import chart_axes
from rotorsfd.plots.response import key_handles, mark_bifurcations, outside_legend, styled_line
from rotorsfd.plots.timedomain import section_limits

YMAX = 6.0        # deflection axes clipped here (r~ near journal contact can reach 500)
XLABEL = r"$\tilde\Omega = \Omega / \Omega_{ref}$ ($\Omega_{ref}$ = 811.3 rad/s)"
#: A legend right of its panel (the layout leaves room for it).
RIGHT = {"loc": "upper left", "bbox_to_anchor": (1.02, 1.0), "borderaxespad": 0}
#: The fixed layout, inches: left of a column (tick labels and y label), below a row (tick
#: labels and x label), above a row's axes per title line and without one.
LEFT, BELOW, TITLE_LINE, ABOVE = 0.85, 0.62, 0.17, 0.14
#: Axes box (width, height) in inches of each kind of panel.
PANEL = {"deflection": (4.1, 3.1), "harmonics": (3.8, 3.1), "orbits": (3.8, 3.8),
         "yawing": (4.2, 3.3), "width": (5.6, 3.4), "directions": (4.6, 3.3),
         "timedomain": (2.9, 2.1), "chart": (6.0, 4.0), "isola": (2.7, 2.5)}


@dataclass(frozen=True)
class Curve:
    """One case's outcome as drawn: ``data`` (plain arrays and numbers of its table),
    ``label`` (its legend entry among the figure's cases), ``color`` (None: the axes'
    cycle), ``title`` (the case in its own words, for a panel of it alone), ``group`` (a
    calibrated curve takes its group's literal colour), ``calibrated``, ``dotted``."""

    data: Mapping[str, Any]
    label: str
    color: str | None = None
    title: str = ""
    group: str = ""
    calibrated: bool = False
    dotted: bool = False


def key(curves: Sequence[Curve]) -> list[Line2D]:
    """The style and marker key of all the branches drawn."""
    stable = np.concatenate([np.asarray(c.data.get("stable", []), bool) for c in curves]
                            or [np.ones(0, bool)])
    bifs = [b for c in curves for b in c.data.get("bifurcations") or ()]
    return key_handles(stable if stable.size else None, bifs)


def where(node: int) -> str:
    return f"node {node} ({'SFD' if node == 1 else 'disk'})"


def draw_deflection(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
                    options: Mapping[str, Any]) -> None:
    """r~ = max_t r / C of each case against Omega~, one panel per node."""
    axes = []
    for k, node in enumerate(options.get("nodes", [1, 8])):
        ax = fig.add_subplot(gs[0, k])
        axes.append(ax)
        for c in curves:
            x, y = c.data["speed_ratio"], c.data[f"defl_{node}"]
            styled_line(ax, x, y, c.data.get("stable"), label=c.label, lw=1.3, color=c.color)
            if c.data["bifurcations"]:
                mark_bifurcations(ax, x, y, c.data["bifurcations"], "speed_ratio")
        if max(float(np.max(c.data[f"defl_{node}"])) for c in curves) > YMAX:
            ax.set_ylim(0, YMAX)   # a branch running into the locked-SFD resonance
        ax.set_xlabel(XLABEL)
        ax.set_ylabel(rf"$\tilde r$ at node {node}")
        ax.set_title(where(node), fontsize=9)
        ax.grid(alpha=0.3)
    outside_legend(fig, axes, key(curves))


def draw_harmonics(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
                   options: Mapping[str, Any]) -> None:
    """|X_0|/C and |X_k|/C (y) of each case and node, one panel each."""
    panels = [(c, n) for c in curves for n in options.get("nodes", [1, 8])]
    axes = []
    for k, (c, node) in enumerate(panels):
        ax = fig.add_subplot(gs[0, k])
        axes.append(ax)
        d = c.data
        x, st, C = d["speed_ratio"], d.get("stable"), float(d["clearance"])
        static = np.abs(d[f"static_{node}_y"]) / C
        styled_line(ax, x, static, st, label=r"$|X_0|/C$ (static)", color="k", lw=1.2)
        top = float(np.max(static))
        for h in range(1, d["H"] + 1):
            y = d[f"amp_{node}_y_h{h}"] / C
            if h <= 3 or np.max(y) > 1e-3:
                styled_line(ax, x, y, st, label=f"{h}X", lw=1.1, color=f"C{(h - 1) % 10}")
            if h == 1 and d["bifurcations"]:
                mark_bifurcations(ax, x, y, d["bifurcations"], "speed_ratio")
            top = max(top, float(np.max(y)))
        if top > YMAX:   # the disk near journal contact
            ax.set_ylim(0, YMAX)
        ax.set_xlabel(XLABEL)
        ax.set_ylabel(r"harmonic amplitude $|X_k|/C$ (y)")
        what = c.label if len(curves) > 1 else ""
        ax.set_title(f"{what}, {where(node)}" if what else where(node), fontsize=9)
        ax.grid(alpha=0.3)
    outside_legend(fig, axes, key(curves))


def orbits(ax: Axes, c: Curve) -> None:
    """Journal orbits at a few speeds inside the clearance circle y^2 + z^2 = C^2; the
    legend right of the circle (never over an orbit)."""
    t = np.linspace(0, 2 * np.pi, 200)
    ax.plot(np.cos(t), np.sin(t), "r-", lw=0.8, label="clearance")
    for s, y, z in c.data["orbits"]:
        ax.plot(y, z, lw=1.1, label=rf"$\tilde\Omega$ = {s:.2f}")
        ax.plot([y.mean()], [z.mean()], "k.", ms=3)
    ax.set_aspect("equal")
    ax.xaxis.set_major_locator(MaxNLocator(5))   # tick labels apart on a 3.8 in circle
    ax.set_xlabel("y / C")
    ax.set_ylabel("z / C")
    ax.set_title(f"{c.title}: SFD orbits (dot: orbit centre)", fontsize=9)
    ax.legend(fontsize=7, **RIGHT)


def draw_orbits(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
                options: Mapping[str, Any]) -> None:
    orbits(fig.add_subplot(gs[0, 0]), curves[0])


def draw_yawing(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
                options: Mapping[str, Any]) -> None:
    """r~ at the SFD of each yawing rate, and the orbits of the curve of group
    ``options["orbit"]`` (default the first)."""
    ax = fig.add_subplot(gs[0, 0])
    for c in curves:
        styled_line(ax, c.data["speed_ratio"], c.data["defl_1"], c.data.get("stable"),
                    label=c.label, lw=1.3, color=c.color)
    ax.set_xlabel(XLABEL)
    ax.set_ylabel(r"$\tilde r$ at the SFD node")
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    marks = key(curves)
    ax.legend(handles + marks, labels + [h.get_label() for h in marks], fontsize=7, **RIGHT)
    shown = next((c for c in curves if c.group == options.get("orbit")), curves[0])
    orbits(fig.add_subplot(gs[0, 1]), shown)


def draw_width(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
               options: Mapping[str, Any]) -> None:
    """The unstable width against the pitching rate, both readings on one axes (the
    calibrated curves in the colour of their literal one, thick and pale), and the
    published points ``options["references"]`` ({label: (rates, widths)})."""
    ax = fig.add_subplot(gs[0, 0])
    colours: dict[str, str] = {}
    both = any(c.calibrated for c in curves) and any(not c.calibrated for c in curves)
    for c in curves:
        d = c.data
        label = c.label + (": journal contact, no fold" if np.all(np.isnan(d["width"]))
                           else "")
        style = "-o" if len(d["rate"]) < 30 else ":" if c.dotted else "-"
        if c.calibrated:
            ax.plot(d["rate"], d["width"], style, ms=4, lw=3.0, alpha=0.45,
                    color=colours.get(c.group), label=label + ", calibrated")
        else:
            (line,) = ax.plot(d["rate"], d["width"], style, ms=3,
                              label=label + (", literal" if both else ""))
            colours[c.group] = line.get_color()
    for name, (x, y) in options.get("references", {}).items():
        ax.plot(x, y, "x--", color="gray", label=name)
    ax.set_xlabel(r"pitching rate $\omega_{by}$ [rad/s]")
    ax.set_ylabel(r"unstable range in $\tilde\Omega$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, **RIGHT)


def draw_directions(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
                    options: Mapping[str, Any]) -> None:
    """max_t and min_t of y / C and z / C at the SFD node, one panel per direction."""
    axes = []
    for k, name in enumerate(("y", "z")):
        ax = fig.add_subplot(gs[0, k])
        axes.append(ax)
        for c in curves:
            d = c.data
            for side in ("max", "min"):
                y = d[f"{side}_1_{name}"]
                label = c.label if len(curves) > 1 else "max and min"
                styled_line(ax, d["speed_ratio"], y, d.get("stable"), color=c.color,
                            label=label if side == "max" else None, lw=1.2)
                if d["bifurcations"]:
                    mark_bifurcations(ax, d["speed_ratio"], y, d["bifurcations"],
                                      "speed_ratio")
        ax.set_xlabel(XLABEL)
        ax.set_ylabel(f"{name} / C at the SFD node")
        ax.set_title(("horizontal (y)" if name == "y" else "vertical (z)")
                     + ": max and min over a period", fontsize=9)
        ax.grid(alpha=0.3)
    outside_legend(fig, axes, key(curves))


def draw_timedomain(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
                    options: Mapping[str, Any]) -> None:
    """Per run: the orbit (z against y), the phase orbit (y' / (C Omega) against y) and
    the Poincare section."""
    for i, c in enumerate(curves):
        d = c.data
        ax = fig.add_subplot(gs[i, 0])
        ax.plot(d["y"], d["z"], lw=0.5)
        ax.plot(d["py"], d["pz"], "r.", ms=3)
        ax.set_aspect("equal", adjustable="datalim")
        step = f", T/{d['steps']}" if "steps" in d else ""
        ax.set_title(rf"$\tilde\Omega$ = {d['speed_ratio']:.3f}{step}: orbit "
                     f"({d['motion']})", fontsize=9)
        ax.set_xlabel("y / C")
        ax.set_ylabel("z / C")
        ax = fig.add_subplot(gs[i, 1])
        ax.plot(d["y"], d["vy"], lw=0.5)
        ax.set_xlabel("y / C")
        ax.set_ylabel(r"$\dot y / (C \Omega)$")
        ax.set_title("phase", fontsize=9)
        section(fig.add_subplot(gs[i, 2]), d)


def section(ax: Axes, d: Mapping[str, Any], fontsize: float = 9) -> None:
    """Poincare points (y, y' / (C Omega)) on their own scale (a torus 0.05 C across fills
    the panel; a period-1 point keeps 2 % of the phase plane around it), over the phase
    orbit in grey."""
    ax.plot(d["y"], d["vy"], "-", lw=0.4, color="0.8")
    ax.plot(d["py"], d["pvy"], "k.", ms=3)
    ax.set_xlim(*section_limits(d["py"], d["y"]))
    ax.set_ylim(*section_limits(d["pvy"], d["vy"]))
    ax.ticklabel_format(useOffset=False)
    ax.xaxis.set_major_locator(MaxNLocator(4))
    ax.set_xlabel("y / C")
    ax.set_ylabel(r"$\dot y / (C \Omega)$")
    ax.set_title(f"Poincare section ({len(np.atleast_1d(d['py']))} periods)",
                 fontsize=fontsize)


def isola_rows(curves: Sequence[Curve]) -> list[list[Mapping[str, Any]]]:
    """The time-domain runs on the isola: top row at the converged step (from the isola's
    HB orbit, then down the isola), bottom row at the paper's T/200."""
    iso = next((c for c in curves if "runs" in c.data), None)
    if iso is None:
        return [[], []]
    return [[iso.data["second"], *iso.data["runs"]],
            [iso.data["find"], *iso.data.get("runs_t200", [])]]


def draw_isola(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
               options: Mapping[str, Any]) -> None:
    """Main branch and isola (disk deflection) top left, their key below it, then the
    Poincare sections of the time-domain runs on the isola (:func:`isola_rows`)."""
    ax = fig.add_subplot(gs[0, 0])
    for i, c in enumerate(curves):
        x, y = c.data["speed_ratio"], c.data["defl_8"]
        styled_line(ax, x, y, c.data.get("stable"), lw=1.3, color=f"C{i % 10}",
                    label="isola (from its HB orbit)" if "runs" in c.data else "main branch")
        if c.data["bifurcations"]:
            mark_bifurcations(ax, x, y, c.data["bifurcations"], "speed_ratio")
    ax.set_xlim(1.0, 1.12)
    shown = [np.asarray(c.data["defl_8"])[(c.data["speed_ratio"] >= 1.0)
                                          & (c.data["speed_ratio"] <= 1.12)] for c in curves]
    top = min(max((float(v.max()) for v in shown if v.size), default=YMAX), YMAX)
    low = min((float(v.min()) for v in shown if v.size), default=0.0)
    ax.set_ylim(low - 0.08 * (top - low), top + 0.08 * (top - low))   # not the contact
    # resonance far above the window
    ax.set_xlabel(XLABEL)
    ax.set_ylabel(r"$\tilde r$ at node 8 (disk)")
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    marks = key(curves)
    below = -(BELOW + ABOVE + TITLE_LINE) / PANEL["isola"][1]   # the empty cell under it
    ax.legend(handles + marks, labels + [h.get_label() for h in marks], fontsize=7,
              loc="upper left", bbox_to_anchor=(0.0, below), borderaxespad=0)
    for i, runs in enumerate(isola_rows(curves)):
        for k, d in enumerate(runs):
            ax = fig.add_subplot(gs[i, k + 1])
            section(ax, d, fontsize=8)
            step = f"T/{d['steps']}, " if "steps" in d else ""
            ax.set_title(rf"{step}$\tilde\Omega$ = {d['speed_ratio']:.3f}: {d['motion']}",
                         fontsize=8)


def draw_chart(fig: Figure, gs: GridSpec, curves: Sequence[Curve],
               options: Mapping[str, Any]) -> None:
    d = curves[0].data
    chart_axes(fig.add_subplot(gs[0, 0]), d["x"], d["y"], d["max_abs"],
               x_label=d["x_label"], y_label=d["y_label"], tol=float(d.get("tol", 1e-5)),
               speed=d.get("speed", 250.0))
