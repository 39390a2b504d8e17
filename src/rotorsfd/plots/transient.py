"""Figures of a transient run (run-up, coast-down, a blade loss, a shock): the orbit radius
against speed and time with the steady-state branch over it, and the waterfall.

Drawn from arrays the analysis computed: radii in units of the clearance C where the node
has one (r/C), else in micrometres; the waterfall's frequency in Hz with the order lines
1X, 2X (k Omega(t) / 2 pi) and the rotor's natural frequencies (forward whirl) along the
run.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import wrap

#: Axes boxes (width, height), inches (fixed layout): a panel of the envelope figure, the
#: waterfall.
PANEL_ENVELOPE, PANEL_WATERFALL = (3.6, 2.1), (5.6, 3.8)


def envelope_figure(*, t: Any, speed: Any, radius: Mapping[int, Any],
                    clearances: Mapping[int, float], events: Sequence[float] = (),
                    branch: Mapping[int, tuple[Any, Any, Any]] | None = None,
                    title: str = "") -> Figure:
    """One row per node: its orbit radius against speed (left, with the steady branch
    ``branch[node] = (speed, radius, stable)`` over it) and against time (right, events
    marked); r / C where the node has a clearance, else micrometres."""
    nodes = list(radius)
    fig = Figure()
    axes = np.atleast_2d(fig.subplots(len(nodes), 2, squeeze=False))
    for row, node in zip(axes, nodes, strict=True):
        c = clearances.get(node)
        scale, unit = (1.0 / c, "r / C") if c else (1e6, "r [µm]")
        r = np.asarray(radius[node]) * scale
        left, right = row
        left.plot(speed, r, "-", lw=0.5, color="C0", label="transient")
        right.plot(t, r, "-", lw=0.5, color="C0")
        if branch and node in branch:
            w, rb, stable = (np.asarray(x) for x in branch[node])
            left.plot(w, np.where(stable > 0.5, rb * scale, np.nan), "-", lw=1.6, color="C1",
                      alpha=0.8, label="steady branch, stable")
            unstable = np.where(stable > 0.5, np.nan, rb * scale)
            if np.any(np.isfinite(unstable)):
                left.plot(w, unstable, "--", lw=1.2, color="C1", alpha=0.8,
                          label="steady branch, unstable")
        for te in events:
            right.axvline(te, color="k", lw=0.8, ls=":",
                          label="unbalance event" if te == events[0] else None)
        left.set_ylabel(f"node {node}: {unit}")
        for ax in row:
            ax.grid(alpha=0.3)
        left.legend(fontsize=7, loc="best")
        if events:
            right.legend(fontsize=7, loc="best")
    axes[-1, 0].set_xlabel(r"speed $\Omega$ [rad/s]")
    axes[-1, 1].set_xlabel("time [s]")
    if title:
        fig.suptitle(wrap(title, 100), fontsize=10)
    fixed_layout(fig, axes.tolist(), PANEL_ENVELOPE)
    return fig


def waterfall_figure(*, time: Any, frequency_hz: Any, amplitude: Any, node: int,
                     t: Any, speed: Any, natural: tuple[Any, Any] | None = None,
                     orders: Sequence[int] = (1, 2), unit_scale: float = 1e6,
                     unit: str = "µm", title: str = "") -> Figure:
    """The forward-whirl waterfall of ``node`` (amplitude over time and frequency, log
    colour), order lines ``k Omega(t) / 2 pi`` and the natural frequencies ``natural =
    (speeds [rad/s], frequencies [rad/s] (n_speeds, n_modes))`` mapped onto the run's
    time through Omega(t)."""
    fig = Figure()
    ax = fig.subplots()
    t, speed = np.asarray(t), np.asarray(speed)
    f_max = 1.3 * max(orders) * float(speed.max()) / (2 * np.pi)
    if natural is not None and np.size(natural[1]):
        f_max = max(f_max, 1.1 * float(np.min(natural[1])) / (2 * np.pi))
    f = np.asarray(frequency_hz)
    a = np.asarray(amplitude) * unit_scale
    keep = (f >= 0.0) & (f <= f_max)
    floor = max(float(np.max(a)) * 1e-3, 1e-30)
    mesh = ax.pcolormesh(np.asarray(time), f[keep], np.maximum(a[:, keep], floor).T,
                         shading="nearest", norm=LogNorm(vmin=floor, vmax=max(a.max(), floor
                                                                          * 10)),
                         cmap="viridis")
    cax = fig.add_axes((0.0, 0.0, 0.1, 0.1), label="<colorbar>")
    fig.colorbar(mesh, cax=cax, label=f"forward whirl amplitude [{unit}]")
    styles = ["-", "--", "-.", ":"]
    for i, k in enumerate(orders):
        ax.plot(t, k * speed / (2 * np.pi), styles[i % 4], color="w", lw=1.0,
                label=f"{k}X")
    if natural is not None:
        ws, wn = (np.asarray(x) for x in natural)
        first = True
        for j in range(wn.shape[1]):
            fn = np.interp(speed, ws, wn[:, j]) / (2 * np.pi)
            if fn.min() > f_max:
                continue
            ax.plot(t, fn, "-", color="tab:red", lw=0.9, alpha=0.8,
                    label="natural frequencies (forward)" if first else None)
            first = False
    ax.set_ylim(0.0, f_max)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("frequency [Hz]")
    ax.legend(fontsize=7, loc="upper left", facecolor="0.25", labelcolor="w", framealpha=0.8)
    ax.set_title(wrap(title or f"waterfall of node {node}", 90), fontsize=10)
    fixed_layout(fig, [[ax]], PANEL_WATERFALL, colorbars=[(cax, [ax])])
    return fig
