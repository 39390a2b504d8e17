"""The paper's figures drawn from case outcomes (plain arrays; no physics here)."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import numpy as np
from matplotlib.figure import Figure

from rotorsfd.paper.cases import FigureSpec
from rotorsfd.paper.run import Outcome
from rotorsfd.plots.response import mark_bifurcations, styled_line

YMAX = 6.0        # deflection axes clipped here (r~ near journal contact can reach 500)
XLABEL = r"$\tilde\Omega = \Omega / 811.3$ rad/s"


def _label(name: str) -> str:
    return name.split("-", 1)[1] if "-" in name else name


def _ok(outcomes: Mapping[str, Outcome], spec: FigureSpec) -> list[Outcome]:
    return [outcomes[c] for c in spec.cases if c in outcomes and outcomes[c].data]


def _deflection(spec: FigureSpec, res: list[Outcome]) -> Figure:
    nodes = spec.options.get("nodes", [1, 8])
    fig = Figure(figsize=(5.5 * len(nodes), 4.2), layout="constrained")
    for k, node in enumerate(nodes):
        ax = fig.add_subplot(1, len(nodes), k + 1)
        for o in res:
            d = o.data
            x, y = d["speed_ratio"], d[f"defl_{node}"]
            styled_line(ax, x, y, d.get("stable"), label=_label(o.name), lw=1.3)
            if d["bifurcations"]:
                mark_bifurcations(ax, x, y, d["bifurcations"], "speed_ratio")
        top = max(float(np.max(o.data[f"defl_{node}"])) for o in res)
        if top > YMAX:   # a branch running into the locked-SFD resonance
            ax.set_ylim(0, YMAX)
        ax.set_xlabel(XLABEL)
        ax.set_ylabel(rf"$\tilde r$ at node {node}")
        ax.set_title(f"node {node} ({'SFD' if node == 1 else 'disk'})", fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return fig


def _harmonics(spec: FigureSpec, res: list[Outcome]) -> Figure:
    nodes = spec.options.get("nodes", [1, 8])
    panels = [(o, n) for o in res for n in nodes]
    fig = Figure(figsize=(5.2 * len(panels), 4.2), layout="constrained")
    for k, (o, node) in enumerate(panels):
        ax = fig.add_subplot(1, len(panels), k + 1)
        d = o.data
        x, st = d["speed_ratio"], d.get("stable")
        styled_line(ax, x, np.abs(d[f"static_{node}_y"]) / _clearance(d, node),
                    st, label="|X0|", color="k", lw=1.2)
        for h in range(1, d["H"] + 1):
            y = d[f"amp_{node}_y_h{h}"] / _clearance(d, node)
            if h <= 3 or np.max(y) > 1e-3:
                styled_line(ax, x, y, st, label=f"{h}X", lw=1.1)
        ax.set_xlabel(XLABEL)
        ax.set_ylabel("harmonic amplitude (y) / C")
        ax.set_title(f"{_label(o.name)}, node {node}", fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return fig


def _clearance(d: Mapping[str, Any], node: int) -> float:
    """C from the table: defl = r / C and the y harmonics in metres."""
    return float(d["clearance"])


def _orbits(ax: Any, o: Outcome) -> None:
    t = np.linspace(0, 2 * np.pi, 200)
    ax.plot(np.cos(t), np.sin(t), "r-", lw=0.8)
    for s, y, z in o.data["orbits"]:
        ax.plot(y, z, lw=1.1, label=f"{s:.2f}")
        ax.plot([y.mean()], [z.mean()], "k.", ms=3)
    ax.set_aspect("equal")
    ax.set_xlabel("y / C")
    ax.set_ylabel("z / C")
    ax.set_title(f"{_label(o.name)}: SFD orbits", fontsize=9)
    ax.legend(fontsize=7, title=r"$\tilde\Omega$", title_fontsize=7)


def _orbit_fig(spec: FigureSpec, res: list[Outcome]) -> Figure:
    fig = Figure(figsize=(5, 5), layout="constrained")
    _orbits(fig.add_subplot(), res[0])
    return fig


def _yawing(spec: FigureSpec, res: list[Outcome]) -> Figure:
    fig = Figure(figsize=(11, 4.4), layout="constrained")
    ax = fig.add_subplot(1, 2, 1)
    for o in res:
        d = o.data
        styled_line(ax, d["speed_ratio"], d["defl_1"], d.get("stable"),
                    label=_label(o.name), lw=1.3)
    ax.set_xlabel(XLABEL)
    ax.set_ylabel(r"$\tilde r$ at the SFD node")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    six = [o for o in res if o.name.endswith("w6")] or res[:1]
    _orbits(fig.add_subplot(1, 2, 2), six[0])
    return fig


def _width(spec: FigureSpec, res: list[Outcome]) -> Figure:
    fig = Figure(figsize=(6, 4.2), layout="constrained")
    ax = fig.add_subplot()
    for o in res:
        d = o.data
        label = (o.name.replace("damp-fig19-", "0.2 % damping, ").replace("fig19-", "")
                 .replace("-paper-h", ", paper's H"))
        if np.all(np.isnan(d["width"])):
            label += ": journal contact, no fold"
        style = "-o" if len(d["rate"]) < 30 else ":" if "paper-h" in o.name else "-"
        ax.plot(d["rate"], d["width"], style, ms=3, label=label)
    paper = {"U = 252 (paper)": ([0, 7], [0.041, 0.0]),
             "U = 360.04 (paper)": ([0, 10], [0.195, 0.119])}
    for name, (x, y) in paper.items():
        ax.plot(x, y, "x--", color="gray", label=name)
    ax.set_xlabel(r"pitching rate $\omega_{by}$ [rad/s]")
    ax.set_ylabel(r"unstable range in $\tilde\Omega$")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    return fig


def _directions(spec: FigureSpec, res: list[Outcome]) -> Figure:
    fig = Figure(figsize=(11, 4.4), layout="constrained")
    for k, d_name in enumerate(("y", "z")):
        ax = fig.add_subplot(1, 2, k + 1)
        for i, o in enumerate(res):
            d = o.data
            for side in ("max", "min"):
                y = d[f"{side}_1_{d_name}"]
                styled_line(ax, d["speed_ratio"], y, d.get("stable"), color=f"C{i}",
                            label=_label(o.name) if side == "max" else None, lw=1.2)
                if d["bifurcations"]:
                    mark_bifurcations(ax, d["speed_ratio"], y, d["bifurcations"],
                                      "speed_ratio")
        ax.set_xlabel(XLABEL)
        ax.set_ylabel(f"{d_name} / C at the SFD node (max and min over a period)")
        ax.set_title("horizontal (y)" if d_name == "y" else "vertical (z)", fontsize=9)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    return fig


def _timedomain(spec: FigureSpec, res: list[Outcome]) -> Figure:
    fig = Figure(figsize=(12, 3.1 * len(res)), layout="constrained")
    for i, o in enumerate(res):
        d = o.data
        ax = fig.add_subplot(len(res), 3, 3 * i + 1)
        ax.plot(d["y"], d["z"], lw=0.5)
        ax.plot(d["py"], d["pz"], "r.", ms=3)
        ax.set_aspect("equal")
        step = f", T/{d['steps']}" if "steps" in d else ""
        ax.set_title(f"Omega~ = {d['speed_ratio']:.3f}{step}: orbit ({d['motion']})",
                     fontsize=9)
        ax.set_xlabel("y / C")
        ax.set_ylabel("z / C")
        ax = fig.add_subplot(len(res), 3, 3 * i + 2)
        ax.plot(d["y"], d["vy"], lw=0.5)
        ax.set_xlabel("y / C")
        ax.set_ylabel(r"$\dot y / (C \Omega)$")
        ax.set_title("phase", fontsize=9)
        ax = fig.add_subplot(len(res), 3, 3 * i + 3)
        ax.plot(d["py"], d["pvy"], "k.", ms=3)
        ax.set_xlim(*_span(d["y"]))       # the phase plane's scale: one point looks
        ax.set_ylim(*_span(d["vy"]))      # like one point
        ax.set_xlabel("y / C")
        ax.set_ylabel(r"$\dot y / (C \Omega)$")
        ax.set_title("Poincare section", fontsize=9)
    return fig


def _isola(spec: FigureSpec, res: list[Outcome]) -> Figure:
    """Main branch and isola (disk deflection), then the Poincare sections of the
    time-domain runs on the isola (y, y' / (C Omega)): top row at the converged step
    (from the isola's HB orbit at 1.075, then down the isola), bottom row at the paper's
    T/200 (from the start that found the isola)."""
    iso = next((o for o in res if "runs" in o.data), None)
    rows = ([[iso.data["second"], *iso.data["runs"]],
             [iso.data["find"], *iso.data.get("runs_t200", [])]] if iso else [[], []])
    cols = 1 + max(len(r) for r in rows)
    fig = Figure(figsize=(5.5 + 3.0 * (cols - 1), 7.6), layout="constrained")
    ax = fig.add_subplot(2, cols, 1)
    for o in res:
        d = o.data
        x, y = d["speed_ratio"], d["defl_8"]
        styled_line(ax, x, y, d.get("stable"), lw=1.3,
                    label="isola (from the orbit)" if o is iso else f"main ({_label(o.name)})")
        if d["bifurcations"]:
            mark_bifurcations(ax, x, y, d["bifurcations"], "speed_ratio")
    ax.set_xlim(1.0, 1.12)
    ax.set_xlabel(XLABEL)
    ax.set_ylabel(r"$\tilde r$ at node 8 (disk)")
    ax.grid(alpha=0.3)
    ax.legend(fontsize=7)
    for i, runs in enumerate(rows):
        for k, d in enumerate(runs):
            ax = fig.add_subplot(2, cols, i * cols + k + 2)
            ax.plot(d["py"], d["pvy"], "k.", ms=3)
            if d["motion"] == "period-1":      # one point: show it on the phase plane's scale
                ax.set_xlim(*_span(d["y"]))
                ax.set_ylim(*_span(d["vy"]))
            ax.set_xlabel("y / C")
            ax.set_ylabel(r"$\dot y / (C \Omega)$")
            step = f"T/{d['steps']}" if "steps" in d else ""
            ax.set_title(f"{step}, Omega~ = {d['speed_ratio']:.3f}: {d['motion']}",
                         fontsize=8)
    return fig


def _span(x: Any) -> tuple[float, float]:
    lo, hi = float(np.min(x)), float(np.max(x))
    pad = 0.05 * (hi - lo) or 1e-3
    return lo - pad, hi + pad


def _chart(spec: FigureSpec, res: list[Outcome]) -> Figure:
    fig = Figure(figsize=(6.5, 4.8), layout="constrained")
    ax = fig.add_subplot()
    d = res[0].data
    unstable = np.asarray(d["max_abs"]) > 1 + 1e-5
    ax.pcolormesh(d["x"], d["y"], unstable.T.astype(float), cmap="Blues", vmin=0, vmax=1.3,
                  shading="nearest")
    ax.set_xlabel(d["x_label"])
    ax.set_ylabel(d["y_label"])
    ax.set_title("unstable (blue), Omega = 250 rad/s", fontsize=9)
    return fig


PLOTS = {"deflection": _deflection, "harmonics": _harmonics, "orbits": _orbit_fig,
         "yawing": _yawing, "width": _width, "directions": _directions,
         "timedomain": _timedomain, "chart": _chart, "isola": _isola}


def draw(spec: FigureSpec, outcomes: Mapping[str, Outcome]) -> Figure | None:
    """The figure of ``spec`` (None when none of its cases gave data)."""
    res = _ok(outcomes, spec)
    if not res:
        return None
    fig = PLOTS[spec.plot](spec, res)
    fig.suptitle(f"Figure {spec.number}: {spec.title}", fontsize=10)
    return fig
