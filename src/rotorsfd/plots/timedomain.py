"""Time-domain figures like the paper's Figure 23, and the brute-force bifurcation diagram.

Drawn from arrays the analyses computed (no physics here): displacements in units of the
SFD clearance C (y/C, z/C), velocities as vy / (C Omega), spectra against the frequency
ratio w / Omega. Panels: orbit with the clearance circle (journal), phase diagram
(y vs vy), Poincare section (y, z once per rotor period), amplitude spectrum.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.axes import Axes
from matplotlib.figure import Figure
from matplotlib.ticker import MaxNLocator

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import label, wrap

#: Axes boxes (width, height), inches (fixed layout): a panel of the 2 x 2 simulation
#: figure, a panel alone, a panel of the bifurcation diagram's stack.
PANEL_GRID, PANEL_ALONE, PANEL_STACK = (3.9, 3.0), (4.4, 3.5), (5.6, 2.2)


def section_limits(points: Any, orbit: Any = None, floor: float = 0.02,
                   pad: float = 0.15) -> tuple[float, float]:
    """Axis limits for Poincare points: their own span (so a torus 0.05 C across fills the
    panel), at least ``floor`` times the orbit's span (so a period-1 point is not blown up
    to its rounding scatter), padded by ``pad`` of the span on each side."""
    p = np.asarray(points, float).ravel()
    p = p[np.isfinite(p)]
    if p.size == 0:
        return -1.0, 1.0
    lo, hi = float(p.min()), float(p.max())
    ref = np.asarray(orbit, float).ravel() if orbit is not None else p
    ref = ref[np.isfinite(ref)]
    least = floor * float(ref.max() - ref.min()) if ref.size else 0.0
    least = least or 1e-3 * max(abs(lo), abs(hi), 1.0)
    if hi - lo < least:
        mid = 0.5 * (lo + hi)
        lo, hi = mid - 0.5 * least, mid + 0.5 * least
    return lo - pad * (hi - lo), hi + pad * (hi - lo)


def orbit_axes(ax: Axes, y: Any, z: Any, py: Any = None, pz: Any = None, *,
               clearance_circle: bool = False, unit: str = "C") -> Axes:
    """Orbit z against y; the unit circle (the clearance) when ``clearance_circle``."""
    ax.plot(y, z, "-", lw=0.6, color="C0")
    if py is not None:
        ax.plot(py, pz, ".", ms=4, color="C3")
    if clearance_circle:
        th = np.linspace(0.0, 2.0 * np.pi, 361)
        ax.plot(np.cos(th), np.sin(th), "k--", lw=0.8)
    ax.set_aspect("equal", adjustable="datalim")
    ax.set_xlabel(f"y [{unit}]")
    ax.set_ylabel(f"z [{unit}]")
    ax.set_title("orbit", fontsize=9)
    ax.grid(alpha=0.3)
    return ax


def phase_axes(ax: Axes, y: Any, vy: Any, py: Any = None, pvy: Any = None, *,
               unit: str = "C") -> Axes:
    """Phase diagram vy against y (Poincare points on it when given)."""
    ax.plot(y, vy, "-", lw=0.6, color="C0")
    if py is not None:
        ax.plot(py, pvy, ".", ms=4, color="C3")
    ax.set_xlabel(f"y [{unit}]")
    ax.set_ylabel(rf"$v_y / \Omega$ [{unit}]")
    ax.set_title("phase diagram", fontsize=9)
    ax.grid(alpha=0.3)
    return ax


def poincare_axes(ax: Axes, py: Any, pz: Any, y: Any = None, z: Any = None, *,
                  unit: str = "C") -> Axes:
    """Poincare section: (y, z) once per rotor period, on the scale of the points
    (:func:`section_limits`), over the orbit (grey) when given."""
    if y is not None:
        ax.plot(y, z, "-", lw=0.4, color="0.75")
    ax.plot(py, pz, ".", ms=5, color="C3")
    ax.set_xlim(*section_limits(py, y))
    ax.set_ylim(*section_limits(pz, z))
    ax.ticklabel_format(useOffset=False)
    ax.xaxis.set_major_locator(MaxNLocator(5))
    ax.set_xlabel(f"y [{unit}]")
    ax.set_ylabel(f"z [{unit}]")
    ax.set_title(f"Poincare section ({len(np.atleast_1d(py))} periods)", fontsize=9)
    ax.grid(alpha=0.3)
    return ax


def spectrum_axes(ax: Axes, frequency_ratio: Any, amplitude: Any, *, unit: str = "C",
                  max_ratio: float = 5.0) -> Axes:
    """Amplitude spectrum against w / Omega (log amplitude axis)."""
    r = np.asarray(frequency_ratio, float)
    a = np.asarray(amplitude, float)
    keep = (r > 0) & (r <= max_ratio)
    floor = 1e-9 * float(a[keep].max()) if np.any(keep) and a[keep].max() > 0 else 1e-300
    ax.semilogy(r[keep], np.maximum(a[keep], floor), "-", lw=0.8)
    ax.set_xlabel(r"$\omega / \Omega$")
    ax.set_ylabel(f"amplitude of y [{unit}]")
    ax.set_title("amplitude spectrum", fontsize=9)
    ax.set_xlim(0.0, max_ratio)
    ax.grid(alpha=0.3, which="both")
    return ax


def simulation_figures(*, y: Any, z: Any, vy: Any, py: Any, pz: Any, pvy: Any,
                       frequency_ratio: Any, amplitude: Any, clearance_circle: bool,
                       unit: str = "C", title: str = "") -> dict[str, Figure]:
    """``simulation.png`` (the four panels of Fig. 23) and each panel alone:
    ``orbit.png``, ``phase.png``, ``poincare.png``, ``spectrum.png``."""
    figs: dict[str, Figure] = {}
    fig = Figure()
    axs = fig.subplots(2, 2)
    orbit_axes(axs[0, 0], y, z, clearance_circle=clearance_circle, unit=unit)
    phase_axes(axs[0, 1], y, vy, py, pvy, unit=unit)
    poincare_axes(axs[1, 0], py, pz, y, z, unit=unit)
    spectrum_axes(axs[1, 1], frequency_ratio, amplitude, unit=unit)
    fig.suptitle(wrap(title, 110), fontsize=10)
    fixed_layout(fig, axs.tolist(), PANEL_GRID)
    figs["simulation.png"] = fig
    for name, draw in (
            ("orbit.png", lambda ax: orbit_axes(ax, y, z, clearance_circle=clearance_circle,
                                                unit=unit)),
            ("phase.png", lambda ax: phase_axes(ax, y, vy, py, pvy, unit=unit)),
            ("poincare.png", lambda ax: poincare_axes(ax, py, pz, y, z, unit=unit)),
            ("spectrum.png", lambda ax: spectrum_axes(ax, frequency_ratio, amplitude,
                                                      unit=unit))):
        f = Figure()
        ax = f.add_subplot()
        draw(ax)
        f.suptitle(wrap(title, 75), fontsize=9)
        fixed_layout(f, [[ax]], PANEL_ALONE)
        figs[name] = f
    return figs


def bifurcation_figure(table: Mapping[str, Any], *, nodes: Sequence[int],
                       x_name: str = "speed_ratio", x_label: str = r"$\tilde\Omega$",
                       scale: float = 1.0, unit: str = "C", title: str = "",
                       node_labels: Mapping[int, str] | None = None) -> Figure:
    """Poincare points y (per node, one panel each, each on its own scale) against the
    speed; the down sweep in red crosses under the up sweep's blue dots (so both show
    where they coincide; jumps and hysteresis show as their difference); one legend
    right of the panels."""
    nodes = list(nodes)
    fig = Figure()
    axs = np.atleast_1d(fig.subplots(len(nodes), 1, sharex=True))
    x = np.asarray(table[x_name], float)
    node = np.asarray(table["node"])
    direction = np.asarray(table["direction"])
    y = np.asarray(table["y"], float) / scale
    for ax, n in zip(axs, nodes, strict=True):
        for d, style, color, ms, z in (("down", "x", "C3", 5.0, 2), ("up", ".", "C0", 3.0, 3)):
            sel = (node == n) & (direction == d)
            if np.any(sel):
                ax.plot(x[sel], y[sel], style, ms=ms, color=color, zorder=z,
                        label=f"speed {d}", gid=f"sweep-{d}")
        ax.set_ylabel(f"y at {(node_labels or {}).get(n, f'node {n}')} [{unit}]")
        ax.grid(alpha=0.3)
    axs[-1].set_xlabel(label(x_label))
    handles, labels = axs[0].get_legend_handles_labels()
    order = sorted(range(len(labels)), key=lambda i: labels[i] != "speed up")
    axs[0].legend([handles[i] for i in order], [labels[i] for i in order], fontsize=8,
                  loc="upper left", bbox_to_anchor=(1.02, 1.0), borderaxespad=0.0)
    fig.suptitle(wrap(title or "Bifurcation diagram (Poincare points)", 90), fontsize=9)
    fixed_layout(fig, [[ax] for ax in axs], PANEL_STACK)
    return fig
