"""Frequency-response figures like the paper's: dimensionless amplitudes against
Omega~ = Omega / Omega_ref (or the continuation parameter, named in words).

The figures are drawn from the columns of ``branch.csv`` (no physics here): the deflection
r~ of every output node, and per node the static term X_0 / C and the harmonic amplitudes
|X_k| / C of each direction. Stable parts solid, unstable parts dashed (when a ``stable``
column is present); bifurcations marked (circle saddle-node, square period doubling,
triangle secondary Hopf, diamond pitchfork, down triangle transcritical, cross an untyped
branch point).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.lines import Line2D

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import label, mathtext, wrap

#: Axes boxes (width, height), inches: a panel of a stack, the deflection panel alone, the
#: multipliers' circle (fixed layout, :mod:`rotorsfd.plots.fixed_layout`).
PANEL, PANEL_ALONE, PANEL_CIRCLE = (5.6, 2.3), (5.6, 3.3), (3.9, 3.9)

MARKERS = {"saddle-node": "o", "period-doubling": "s", "secondary-hopf": "^",
           "pitchfork": "D", "transcritical": "v", "branch-point": "x"}


def styled_line(ax: Axes, x: Any, y: Any, stable: Any = None, **kw: Any) -> None:
    """Plot y(x): solid where ``stable`` (or everywhere if None), dashed elsewhere; the
    pieces share their end points so the curve stays connected."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if stable is None or len(x) < 2:
        ax.plot(x, y, "-", **kw)
        return
    s = np.asarray(stable, bool)
    label = kw.pop("label", None)
    color = kw.pop("color", None)
    start = 0
    for i in range(1, len(x) + 1):
        if i == len(x) or s[i] != s[start]:
            end = min(i + 1, len(x))
            (line,) = ax.plot(x[start:end], y[start:end], "-" if s[start] else "--",
                              color=color, label=label, **kw)
            color, label = line.get_color(), None
            start = i


def mark_bifurcations(ax: Axes, x: Any, y: Any, bifurcations: Sequence[Mapping[str, Any]],
                      x_key: str) -> None:
    """Markers at the bifurcations, at the branch point nearest in x among the points
    next to the bifurcation's bracket (``point``), so a fold marks the right sheet."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    for b in bifurcations:
        xb = float(b[x_key])
        near = np.arange(len(x))
        if b.get("point") is not None and not np.isnan(float(b["point"])):
            p = int(b["point"])
            near = near[max(p - 1, 0):p + 3]
        i = int(near[np.argmin(np.abs(x[near] - xb))])
        ax.plot([xb], [y[i]], MARKERS.get(b["type"], "x"), color="k", ms=6,
                mfc="none", zorder=5)


def key_handles(stable: Any, bifurcations: Sequence[Mapping[str, Any]] | None
                ) -> list[Line2D]:
    """Legend entries for the line styles (when some part is unstable) and for the
    bifurcation markers used."""
    handles = []
    if stable is not None and not np.all(np.asarray(stable, bool)):
        handles += [Line2D([], [], color="0.3", ls="-", label="stable"),
                    Line2D([], [], color="0.3", ls="--", label="unstable")]
    for kind in dict.fromkeys(b["type"] for b in bifurcations or ()):
        handles.append(Line2D([], [], ls="none", marker=MARKERS.get(kind, "x"), color="k",
                              mfc="none", label=kind))
    return handles


def key_legend(ax: Axes, stable: Any, bifurcations: Sequence[Mapping[str, Any]] | None
               ) -> None:
    """A second legend explaining the line styles and the bifurcation markers used."""
    handles = key_handles(stable, bifurcations)
    if handles:
        ax.add_artist(ax.legend(handles=handles, fontsize=8, loc="upper left"))


def outside_legend(fig: Figure, axes: Sequence[Axes], key: Sequence[Line2D] = (),
                   **kw: Any) -> None:
    """One legend for the figure, right of the top-right panel (never over a curve, nor
    over the figure title): the labelled curves of ``axes`` (each label once), then the
    style and marker ``key``."""
    handles, labels = [], []
    for ax in axes:
        for h, lab in zip(*ax.get_legend_handles_labels(), strict=True):
            if lab not in labels:
                handles.append(h)
                labels.append(lab)
    handles += list(key)
    labels += [h.get_label() for h in key]
    if handles and len(axes):
        corner = max(axes, key=lambda a: (round(a.get_position().x1, 3),
                                          a.get_position().y1))
        corner.legend(handles, labels, loc="upper left", bbox_to_anchor=(1.02, 1.0),
                      borderaxespad=0.0, fontsize=8, **kw)


def _peak(y: Any) -> float:
    y = np.asarray(y, float)
    return float(np.nanmax(y)) if y.size and np.any(np.isfinite(y)) else 0.0


def separate_scales(peaks: Sequence[float], ratio: float = 4.0) -> bool:
    """True when curves of these peak values do not share one axis well (the largest
    more than ``ratio`` times the smallest): a small one would be flat at the bottom."""
    p = [x for x in peaks if x > 0]
    return len(p) > 1 and max(p) > ratio * min(p)


def response_figures(table: Mapping[str, Any], *, x_name: str, x_label: str,
                     nodes: Sequence[int], directions: Sequence[str], H: int,
                     clearance: float,
                     bifurcations: Sequence[Mapping[str, Any]] | None = None,
                     title: str = "",
                     node_labels: Mapping[int, str] | None = None) -> dict[str, Figure]:
    """``response_deflection.png`` (r~ of every node; one panel per node when their
    amplitudes differ by more than 4 times) and ``response_node<n>.png`` (one panel per
    direction: X_0/C and |X_k|/C, k = 1..H); legends right of the panels.
    ``node_labels``: the nodes' names (default ``node <n>``; a multi-shaft rotor's
    ``hp node 3``)."""
    def name(n: int) -> str:
        return (node_labels or {}).get(n, f"node {n}")

    x = np.asarray(table[x_name], float)
    stable = table.get("stable")
    x_key = x_name if x_name in ("speed_ratio", "speed_rad_s") else "parameter"
    xlabel = label(x_label)
    key = key_handles(stable, bifurcations)
    figs: dict[str, Figure] = {}

    nodes = list(nodes)
    apart = separate_scales([_peak(table[f"defl_{n}"]) for n in nodes])
    rows = len(nodes) if apart else 1
    fig = Figure()
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    for k, n in enumerate(nodes):
        ax = axes[k if apart else 0]
        y = table[f"defl_{n}"]
        styled_line(ax, x, y, stable, label=name(n), lw=1.4, color=f"C{k}")
        if bifurcations:
            mark_bifurcations(ax, x, y, bifurcations, x_key)
    for ax in axes:
        ax.set_ylabel(r"$\tilde r = \max_t \sqrt{y^2 + z^2} / C$" if not apart else
                      r"$\tilde r$ = max$_t\,r / C$")
        ax.grid(alpha=0.3)
    axes[-1].set_xlabel(xlabel)
    fig.suptitle(wrap(title or "Frequency response", 90), fontsize=9)
    outside_legend(fig, axes, key)
    fixed_layout(fig, [[ax] for ax in axes], PANEL if apart else PANEL_ALONE)
    figs["response_deflection.png"] = fig

    for n in nodes:
        fig = Figure()
        axes = fig.subplots(len(directions), 1, sharex=True, squeeze=False)[:, 0]
        for ax, d in zip(axes, directions, strict=True):
            styled_line(ax, x, np.asarray(table[f"static_{n}_{d}"]) / clearance, stable,
                        label="static (0X)", lw=1.2, color="0.4")
            for k in range(1, H + 1):
                y = np.asarray(table[f"amp_{n}_{d}_h{k}"]) / clearance
                styled_line(ax, x, y, stable, label=f"{k}X", lw=1.4 if k == 1 else 1.0,
                            color=f"C{(k - 1) % 10}")
                if bifurcations and k == 1:
                    mark_bifurcations(ax, x, y, bifurcations, x_key)
            ax.set_ylabel(rf"$X_0/C$, $|X_k|/C$ ({d})")
            ax.grid(alpha=0.3)
            ax.set_title(f"{name(n)}, {d} direction", fontsize=9)
        axes[-1].set_xlabel(xlabel)
        fig.suptitle(wrap(title or "Harmonic amplitudes", 90), fontsize=9)
        outside_legend(fig, axes, key)
        fixed_layout(fig, [[ax] for ax in axes], PANEL)
        figs[f"response_node{n}.png"] = fig
    return figs


def plot_multipliers(multipliers: Any, *, where: str, max_multiplier: float | None = None,
                     stable: bool | None = None, title: str = "") -> Figure:
    """The Floquet multipliers of one branch point in the complex plane against the unit
    circle (``multipliers.png``): one marker per multiplier, the critical one (largest
    ``|mu|``) highlighted; ``where`` names the point (e.g. ``"Omega~ = 1.05"``) in the
    title, with ``|mu|max`` (default: the largest modulus given)."""
    mu = np.asarray(multipliers, dtype=complex).ravel()
    if mu.size == 0:
        raise ValueError("no multipliers to plot")
    i = int(np.argmax(np.abs(mu)))
    rest = np.delete(mu, i)
    mu_max = float(abs(mu[i])) if max_multiplier is None else float(max_multiplier)

    fig = Figure()
    ax = fig.add_subplot()
    theta = np.linspace(0.0, 2 * np.pi, 361)
    ax.plot(np.cos(theta), np.sin(theta), "-", color="0.5", lw=1.0, label="unit circle",
            gid="unit-circle")
    ax.axhline(0.0, color="0.85", lw=0.6, zorder=0)
    ax.axvline(0.0, color="0.85", lw=0.6, zorder=0)
    ax.plot(rest.real, rest.imag, "x", color="C0", ms=6, ls="none", label="multipliers",
            gid="multipliers")
    ax.plot([mu[i].real], [mu[i].imag], "o", color="C3", ms=9, mfc="none", mew=1.8,
            ls="none", label=rf"critical, $|\mu|$ = {abs(mu[i]):.4f}", gid="critical")
    r = max(1.15, 1.1 * float(np.abs(mu).max()))
    ax.set_xlim(-r, r)
    ax.set_ylim(-r, r)
    ax.set_aspect("equal")
    ax.set_xlabel(r"Re $\mu$")
    ax.set_ylabel(r"Im $\mu$")
    ax.grid(alpha=0.3)
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.13), fontsize=8, ncol=3)
    state = "" if stable is None else (" (stable)" if stable else " (unstable)")
    head = f"{wrap(title, 70)}\n" if title else ""
    ax.set_title(f"{head}{wrap('Floquet multipliers at ' + mathtext(where), 70)}\n"
                 rf"$|\mu|_{{max}}$ = {mu_max:.5f}{state}", fontsize=9)
    fixed_layout(fig, [[ax]], PANEL_CIRCLE)
    return fig
