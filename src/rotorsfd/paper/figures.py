"""The paper's figures drawn from case outcomes (plain arrays; no physics here)."""

from __future__ import annotations

import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from rotorsfd.paper.cases import CAL, CASES, FigureSpec, Outcome, literal_name
from rotorsfd.plots.chart import chart_axes
from rotorsfd.plots.labels import settings, wrap
from rotorsfd.plots.response import key_handles, mark_bifurcations, outside_legend, styled_line
from rotorsfd.plots.timedomain import section_limits

YMAX = 6.0        # deflection axes clipped here (r~ near journal contact can reach 500)
XLABEL = r"$\tilde\Omega = \Omega / \Omega_{ref}$ ($\Omega_{ref}$ = 811.3 rad/s)"


def case_label(name: str, spec: FigureSpec | None = None) -> str:
    """A case in the reader's terms: the settings that tell it from the other cases of
    ``spec`` ("U = 72.008 g mm", "$\\omega_{by}$ = 2 rad/s"), not its id."""
    case = CASES.get(name)
    if case is None:
        return name
    others = [CASES[c].overrides for c in (spec.cases if spec else ()) if c in CASES]
    common = set.intersection(*map(set, others)) if len(others) > 1 else set()
    words = settings(case.overrides, common)
    if not words:                       # e.g. the diagnosis case of a figure's file
        m = re.search(r"fig(\d+)", name) or re.search(r"fig0*(\d+)", Path(case.config).stem)
        words = f"Figure {m.group(1)} case" if m else name
    return words


def _colour(spec: FigureSpec, o: Outcome, i: int) -> str:
    """A case's colour: by its literal case's place in the figure, so a case has the same
    colour in both readings' rows."""
    name = literal_name(o.name)
    return f"C{(spec.cases.index(name) if name in spec.cases else i) % 10}"


def _key(res: list[Outcome]) -> list[Any]:
    """The style and marker key of all the branches drawn."""
    stable = np.concatenate([np.asarray(o.data.get("stable", []), bool) for o in res]
                            or [np.ones(0, bool)])
    bifs = [b for o in res for b in o.data.get("bifurcations") or ()]
    return key_handles(stable if stable.size else None, bifs)


def _ok(outcomes: Mapping[str, Outcome], spec: FigureSpec) -> list[Outcome]:
    return [outcomes[c] for c in spec.cases if c in outcomes and outcomes[c].data]


def _deflection(spec: FigureSpec, res: list[Outcome], fig: Any) -> None:
    nodes = spec.options.get("nodes", [1, 8])
    axes = []
    for k, node in enumerate(nodes):
        ax = fig.add_subplot(1, len(nodes), k + 1)
        axes.append(ax)
        for i, o in enumerate(res):
            d = o.data
            x, y = d["speed_ratio"], d[f"defl_{node}"]
            styled_line(ax, x, y, d.get("stable"), label=case_label(o.name, spec), lw=1.3,
                        color=_colour(spec, o, i))
            if d["bifurcations"]:
                mark_bifurcations(ax, x, y, d["bifurcations"], "speed_ratio")
        top = max(float(np.max(o.data[f"defl_{node}"])) for o in res)
        if top > YMAX:   # a branch running into the locked-SFD resonance
            ax.set_ylim(0, YMAX)
        ax.set_xlabel(XLABEL)
        ax.set_ylabel(rf"$\tilde r$ at node {node}")
        ax.set_title(f"node {node} ({'SFD' if node == 1 else 'disk'})", fontsize=9)
        ax.grid(alpha=0.3)
    outside_legend(fig, axes, _key(res))


def _harmonics(spec: FigureSpec, res: list[Outcome], fig: Any) -> None:
    nodes = spec.options.get("nodes", [1, 8])
    panels = [(o, n) for o in res for n in nodes]
    axes = []
    for k, (o, node) in enumerate(panels):
        ax = fig.add_subplot(1, len(panels), k + 1)
        axes.append(ax)
        d = o.data
        x, st = d["speed_ratio"], d.get("stable")
        styled_line(ax, x, np.abs(d[f"static_{node}_y"]) / _clearance(d, node),
                    st, label=r"$|X_0|/C$ (static)", color="k", lw=1.2)
        top = float(np.max(np.abs(d[f"static_{node}_y"]))) / _clearance(d, node)
        for h in range(1, d["H"] + 1):
            y = d[f"amp_{node}_y_h{h}"] / _clearance(d, node)
            if h <= 3 or np.max(y) > 1e-3:
                styled_line(ax, x, y, st, label=f"{h}X", lw=1.1, color=f"C{(h - 1) % 10}")
            if h == 1 and d["bifurcations"]:
                mark_bifurcations(ax, x, y, d["bifurcations"], "speed_ratio")
            top = max(top, float(np.max(y)))
        if top > YMAX:   # the disk near journal contact
            ax.set_ylim(0, YMAX)
        ax.set_xlabel(XLABEL)
        ax.set_ylabel(r"harmonic amplitude $|X_k|/C$ (y)")
        what = case_label(o.name, spec) if len(res) > 1 else ""
        where = f"node {node} ({'SFD' if node == 1 else 'disk'})"
        ax.set_title(f"{what}, {where}" if what else where, fontsize=9)
        ax.grid(alpha=0.3)
    outside_legend(fig, axes, _key(res))


def _clearance(d: Mapping[str, Any], node: int) -> float:
    """C from the table: defl = r / C and the y harmonics in metres."""
    return float(d["clearance"])


def _orbits(ax: Any, o: Outcome) -> None:
    """Journal orbits at a few speeds inside the clearance circle; the legend right of
    the circle (never over an orbit)."""
    t = np.linspace(0, 2 * np.pi, 200)
    ax.plot(np.cos(t), np.sin(t), "r-", lw=0.8, label="clearance")
    for s, y, z in o.data["orbits"]:
        ax.plot(y, z, lw=1.1, label=rf"$\tilde\Omega$ = {s:.2f}")
        ax.plot([y.mean()], [z.mean()], "k.", ms=3)
    ax.set_aspect("equal")
    ax.set_xlabel("y / C")
    ax.set_ylabel("z / C")
    ax.set_title(f"{case_label(o.name)}: SFD orbits (dot: orbit centre)", fontsize=9)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)


def _orbit_fig(spec: FigureSpec, res: list[Outcome], fig: Any) -> None:
    _orbits(fig.add_subplot(), res[0])


def _yawing(spec: FigureSpec, res: list[Outcome], fig: Any) -> None:
    ax = fig.add_subplot(1, 2, 1)
    for i, o in enumerate(res):
        d = o.data
        styled_line(ax, d["speed_ratio"], d["defl_1"], d.get("stable"),
                    label=case_label(o.name, spec), lw=1.3, color=_colour(spec, o, i))
    ax.set_xlabel(XLABEL)
    ax.set_ylabel(r"$\tilde r$ at the SFD node")
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    key = _key(res)
    ax.legend(handles + key, labels + [h.get_label() for h in key], fontsize=7,
              loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)
    six = [o for o in res if o.name.endswith("w6")] or res[:1]
    _orbits(fig.add_subplot(1, 2, 2), six[0])


def _width(spec: FigureSpec, res: list[Outcome], fig: Any,
           cal: list[Outcome] | None = None) -> None:
    """The unstable width against the pitching rate, both readings on one axes (the
    calibrated curves in the colour of their literal one, thick and pale)."""
    ax = fig.add_subplot()
    colours: dict[str, str] = {}
    for o in [*res, *(cal or [])]:
        d = o.data
        lit = literal_name(o.name)
        case = CASES.get(lit)
        h = case.note.split(" (")[0].split(",")[0] if case else ""
        label = case_label(lit) + (f", {h}" if h.startswith("H = ") else "")
        if np.all(np.isnan(d["width"])):
            label += ": journal contact, no fold"
        style = "-o" if len(d["rate"]) < 30 else ":" if "paper-h" in o.name else "-"
        if o.name.startswith(CAL):
            (line,) = ax.plot(d["rate"], d["width"], style, ms=4, lw=3.0, alpha=0.45,
                              color=colours.get(lit), label=label + ", calibrated")
        else:
            (line,) = ax.plot(d["rate"], d["width"], style, ms=3,
                              label=label + (", literal" if cal else ""))
            colours[lit] = line.get_color()
    paper = {"U = 252 g mm (paper)": ([0, 7], [0.041, 0.0]),
             "U = 360.04 g mm (paper)": ([0, 10], [0.195, 0.119])}
    for name, (x, y) in paper.items():
        ax.plot(x, y, "x--", color="gray", label=name)
    ax.set_xlabel(r"pitching rate $\omega_{by}$ [rad/s]")
    ax.set_ylabel(r"unstable range in $\tilde\Omega$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7, loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0)


def _directions(spec: FigureSpec, res: list[Outcome], fig: Any) -> None:
    axes = []
    for k, d_name in enumerate(("y", "z")):
        ax = fig.add_subplot(1, 2, k + 1)
        axes.append(ax)
        for i, o in enumerate(res):
            d = o.data
            for side in ("max", "min"):
                y = d[f"{side}_1_{d_name}"]
                label = case_label(o.name, spec) if len(res) > 1 else "max and min"
                styled_line(ax, d["speed_ratio"], y, d.get("stable"), color=_colour(spec, o, i),
                            label=label if side == "max" else None, lw=1.2)
                if d["bifurcations"]:
                    mark_bifurcations(ax, d["speed_ratio"], y, d["bifurcations"],
                                      "speed_ratio")
        ax.set_xlabel(XLABEL)
        ax.set_ylabel(f"{d_name} / C at the SFD node")
        ax.set_title(("horizontal (y)" if d_name == "y" else "vertical (z)")
                     + ": max and min over a period", fontsize=9)
        ax.grid(alpha=0.3)
    outside_legend(fig, axes, _key(res))


def _timedomain(spec: FigureSpec, res: list[Outcome], fig: Any) -> None:
    for i, o in enumerate(res):
        d = o.data
        ax = fig.add_subplot(len(res), 3, 3 * i + 1)
        ax.plot(d["y"], d["z"], lw=0.5)
        ax.plot(d["py"], d["pz"], "r.", ms=3)
        ax.set_aspect("equal", adjustable="datalim")
        step = f", T/{d['steps']}" if "steps" in d else ""
        ax.set_title(rf"$\tilde\Omega$ = {d['speed_ratio']:.3f}{step}: orbit "
                     f"({d['motion']})", fontsize=9)
        ax.set_xlabel("y / C")
        ax.set_ylabel("z / C")
        ax = fig.add_subplot(len(res), 3, 3 * i + 2)
        ax.plot(d["y"], d["vy"], lw=0.5)
        ax.set_xlabel("y / C")
        ax.set_ylabel(r"$\dot y / (C \Omega)$")
        ax.set_title("phase", fontsize=9)
        ax = fig.add_subplot(len(res), 3, 3 * i + 3)
        _section(ax, d)


def _section(ax: Any, d: Mapping[str, Any], fontsize: float = 9) -> None:
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


def _isola(spec: FigureSpec, res: list[Outcome], fig: Any) -> None:
    """Main branch and isola (disk deflection), then the Poincare sections of the
    time-domain runs on the isola (y, y' / (C Omega)): top row at the converged step
    (from the isola's HB orbit at 1.075, then down the isola), bottom row at the paper's
    T/200 (from the start that found the isola)."""
    iso = next((o for o in res if "runs" in o.data), None)
    rows = ([[iso.data["second"], *iso.data["runs"]],
             [iso.data["find"], *iso.data.get("runs_t200", [])]] if iso else [[], []])
    cols = 1 + max(len(r) for r in rows)
    ax = fig.add_subplot(2, cols, 1)
    for i, o in enumerate(res):
        d = o.data
        x, y = d["speed_ratio"], d["defl_8"]
        styled_line(ax, x, y, d.get("stable"), lw=1.3, color=f"C{i % 10}",
                    label="isola (from its HB orbit)" if o is iso else "main branch")
        if d["bifurcations"]:
            mark_bifurcations(ax, x, y, d["bifurcations"], "speed_ratio")
    ax.set_xlim(1.0, 1.12)
    shown = [np.asarray(o.data["defl_8"])[(o.data["speed_ratio"] >= 1.0)
                                          & (o.data["speed_ratio"] <= 1.12)] for o in res]
    top = min(max((float(v.max()) for v in shown if v.size), default=YMAX), YMAX)
    low = min((float(v.min()) for v in shown if v.size), default=0.0)
    ax.set_ylim(low - 0.08 * (top - low), top + 0.08 * (top - low))   # not the contact
    # resonance far above the window
    ax.set_xlabel(XLABEL)
    ax.set_ylabel(r"$\tilde r$ at node 8 (disk)")
    ax.grid(alpha=0.3)
    handles, labels = ax.get_legend_handles_labels()
    key = _key(res)
    fig.legend(handles + key, labels + [h.get_label() for h in key], fontsize=7,
               loc="outside lower left", ncol=3)
    for i, runs in enumerate(rows):
        for k, d in enumerate(runs):
            ax = fig.add_subplot(2, cols, i * cols + k + 2)
            _section(ax, d, fontsize=8)
            step = f"T/{d['steps']}, " if "steps" in d else ""
            ax.set_title(rf"{step}$\tilde\Omega$ = {d['speed_ratio']:.3f}: {d['motion']}",
                         fontsize=8)


def _chart(spec: FigureSpec, res: list[Outcome], fig: Any) -> None:
    ax = fig.add_subplot()
    d = res[0].data
    chart_axes(ax, d["x"], d["y"], d["max_abs"], x_label=d["x_label"],
               y_label=d["y_label"], tol=float(d.get("tol", 1e-5)),
               speed=d.get("speed", 250.0))


def _size(spec: FigureSpec, res: list[Outcome]) -> tuple[float, float]:
    """(width, height) in inches of one reading's panels."""
    nodes = len(spec.options.get("nodes", [1, 8]))
    if spec.plot == "isola":
        iso = next((o for o in res if "runs" in o.data), None)
        n = max(1 + len(iso.data["runs"]), 1 + len(iso.data.get("runs_t200", []))) \
            if iso else 1
        return 6.5 + 3.0 * n, 7.8
    return {"deflection": (5.0 * nodes + 2.2, 4.4),
            "harmonics": (4.8 * nodes * len(res) + 1.6, 4.4),
            "orbits": (6.4, 5.0), "yawing": (12.0, 4.6), "width": (10.0, 4.6),
            "directions": (12.5, 4.6), "timedomain": (12.0, 3.1 * len(res)),
            "chart": (7.4, 5.4)}[spec.plot]


PLOTS = {"deflection": _deflection, "harmonics": _harmonics, "orbits": _orbit_fig,
         "yawing": _yawing, "width": _width, "directions": _directions,
         "timedomain": _timedomain, "chart": _chart, "isola": _isola}

#: Row titles of a figure drawn in both readings.
READING_TITLES = {"literal": "Literal reading (no structural damping)",
                  "calibrated": "Calibrated reading (modal damping 0.2197 %, "
                                "examples/paper_rotor_calibrated.toml)"}


def draw(spec: FigureSpec, outcomes: Mapping[str, Outcome]) -> Figure | None:
    """The figure of ``spec`` (None when none of its cases gave data): one row of panels
    per reading that ran (the calibrated one below the literal; Figure 19's widths of
    both readings on one axes)."""
    res = _ok(outcomes, spec)
    cal = [outcomes[CAL + c] for c in spec.cases
           if CAL + c in outcomes and outcomes[CAL + c].data]
    if not res and not cal:
        return None
    plot = PLOTS[spec.plot]
    if spec.plot == "width":
        fig = Figure(figsize=_size(spec, res or cal), layout="constrained")
        _width(spec, res, fig, cal)
    elif res and cal:
        w, h = _size(spec, res)
        w2, h2 = _size(spec, cal)
        fig = Figure(figsize=(max(w, w2), h + h2 + 0.6), layout="constrained")
        top, bottom = fig.subfigures(2, 1, height_ratios=[h, h2])
        for sub, rows, reading in ((top, res, "literal"), (bottom, cal, "calibrated")):
            plot(spec, rows, sub)
            sub.suptitle(READING_TITLES[reading], fontsize=9, fontweight="bold")
    else:
        rows = res or cal
        fig = Figure(figsize=_size(spec, rows), layout="constrained")
        plot(spec, rows, fig)
    title = f"Figure {spec.number}: {spec.title}"
    if cal and not res:                # the calibrated reading alone: said in the title
        title += f"\n{READING_TITLES['calibrated']}"
    fig.suptitle(wrap(title, 110), fontsize=10)
    return fig
