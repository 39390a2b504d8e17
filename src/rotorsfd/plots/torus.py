"""Figures of a torus branch (a quasi-periodic response under a harmonic base law).

``torus_components.png``: per output node, the amplitudes ``|X_(k1,k2)| / C`` of the
strongest lines ``k1 Omega + k2 w_b`` (the radial amplitude ``sqrt(|X_y|^2 + |X_z|^2)``,
legends in words: "1X", "1X - 2 w_b", "1 w_b") against Omega~ (or the branch's parameter,
e.g. ``base.pitching.frequency [rad/s]``), and below the largest
Lyapunov exponent per rotor period where computed (filled: stable, open: unstable).

``torus_spectrum.png``: the 2D amplitude spectrum at one speed, per node a map over the
half lattice (k1 >= 0 along x, k2 along y), colour ``log10`` of the radial amplitude / C,
each cell labelled with its value. The cells (0, k2 < 0) are the conjugates of (0, -k2)
(the same line) and left blank.
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np
from matplotlib.colors import LogNorm
from matplotlib.figure import Figure

from rotorsfd.model.node_names import node_words
from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import mathtext, wrap

#: Axes box (width, height) of each panel of the lines figure, inches (fixed layout).
PANEL = (5.6, 2.6)


def component_label(k1: int, k2: int) -> str:
    """A line's name in the user's words: "1X", "1X - 2 w_b", "1 w_b", "static"."""
    if k1 == 0 and k2 == 0:
        return "static"
    if k1 == 0:
        return f"{k2} w_b"
    if k2 == 0:
        return f"{k1}X"
    return f"{k1}X {'+' if k2 > 0 else '-'} {abs(k2)} w_b"


#: lines drawn per node in torus_components.png (the strongest along the branch)
N_LINES = 6


def radial_amplitude(result: Any, node: int) -> np.ndarray:
    """(n_points, nk) ``sqrt(|X_y|^2 + |X_z|^2) / C`` of every lattice harmonic."""
    X = result.branch.X
    y, z = result.dof(node, "y"), result.dof(node, "z")
    return np.sqrt(np.abs(X[:, :, y]) ** 2 + np.abs(X[:, :, z]) ** 2) / result.clearance


def strongest(result: Any, node: int, count: int = N_LINES) -> list[int]:
    """Indices of the ``count`` lattice harmonics of largest peak radial amplitude."""
    peak = radial_amplitude(result, node).max(axis=0)
    return [int(i) for i in np.argsort(peak)[::-1][:count]]


def plot_torus_components(result: Any) -> Figure:
    """The strongest lines of every output node against Omega~, and the Lyapunov
    exponents (module docstring)."""
    b = result.branch
    x, xlabel = branch_axis(result)
    rows = len(result.nodes) + (1 if result.lyapunov else 0)
    fig = Figure()
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    plot_lines(axes, result, x, lambda k1, k2: mathtext(component_label(k1, k2)))
    if result.lyapunov:
        plot_lyapunov(axes[-1], result, x, " torus", "T")
    axes[-1].set_xlabel(xlabel)
    if result.is_speed:
        at = f"w_b = {float(b.wb[0]):.4g} rad/s"
    else:
        at = f"Omega~ = {float(b.omega[0]) / result.reference_speed:.4g}" + (
            "" if result.parameter.endswith(".frequency")
            else f", w_b = {float(b.wb[0]):.4g} rad/s")
    fig.suptitle(mathtext(wrap(f"{result.title or 'Quasi-periodic response'}: lines at "
                               f"k1 Omega + k2 w_b, {at}", 90)), fontsize=9)
    fixed_layout(fig, [[ax] for ax in axes], PANEL)
    return fig


def plot_lines(axes: Any, result: Any, x: np.ndarray,
               label: Callable[[int, int], str]) -> None:
    """Per output node (one axis each, named "node 12" or "hp node 3") the radial
    amplitudes / C of its strongest lines against x on a log scale, each named
    ``label(k1, k2)``."""
    for ax, n in zip(axes, result.nodes, strict=False):
        amp = radial_amplitude(result, n)
        for i in strongest(result, n):
            k1, k2 = (int(v) for v in result.branch.lattice.k[i])
            ax.plot(x, amp[:, i], "-", label=label(k1, k2))
        ax.set_yscale("log")
        ax.set_ylabel(f"{node_words(result.node_names, n)}: " + r"$|X_{k_1,k_2}|\,/\,C$")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7, ncols=2, loc="best", title="line", title_fontsize=7)


def plot_lyapunov(ax: Any, result: Any, x: np.ndarray, what: str, period: str) -> None:
    """The largest Lyapunov exponents per period ``period`` at the points where computed
    (filled: stable, open: unstable; "stable<what>" in the legend) with their error bars."""
    idx = sorted(result.lyapunov)
    lam = np.array([result.lyapunov[i].per_period for i in idx])
    err = np.array([result.lyapunov[i].uncertainty for i in idx])
    ok = np.array([result.lyapunov[i].stable for i in idx], dtype=bool)
    xi = x[idx]
    ax.errorbar(xi, lam, yerr=err, fmt="none", ecolor="0.5", capsize=2)
    ax.plot(xi[ok], lam[ok], "o", color="C0", label=f"stable{what}")
    ax.plot(xi[~ok], lam[~ok], "o", mfc="none", color="C3", label=f"unstable{what}")
    ax.axhline(0.0, color="k", lw=0.8)
    ax.set_ylabel(mathtext(f"largest Lyapunov exponent x {period}"))
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7, loc="best")


def branch_axis(result: Any) -> tuple[np.ndarray, str]:
    """The x values of a torus branch and their label: Omega~ for a speed branch, the
    parameter in SI (named by its config path) otherwise."""
    b = result.branch
    if result.is_speed:
        return b.omega / result.reference_speed, mathtext("Omega~ = Omega / Omega_ref")
    unit = "" if result.parameter_units == "1" else f" [{result.parameter_units}]"
    return np.asarray(b.lam, dtype=float), f"{result.parameter}{unit}"


def plot_torus_spectrum(result: Any, index: int) -> Figure:
    """The 2D amplitude spectrum of point ``index`` (module docstring)."""
    b = result.branch
    lat = b.lattice
    H1, H2 = lat.H1, lat.H2
    nodes = result.nodes
    fig = Figure()
    axes = fig.subplots(1, len(nodes), squeeze=False)[0]
    image = None
    floor = 1e-6
    for ax, n in zip(axes, nodes, strict=True):
        amp = radial_amplitude(result, n)[index]
        grid = np.full((2 * H2 + 1, H1 + 1), np.nan)
        for i, (k1, k2) in enumerate(lat.k):
            grid[int(k2) + H2, int(k1)] = max(float(amp[i]), floor)
        top = float(np.nanmax(grid))
        image = ax.imshow(grid, origin="lower", cmap="viridis", aspect="auto",
                          extent=(-0.5, H1 + 0.5, -H2 - 0.5, H2 + 0.5),
                          norm=LogNorm(vmin=max(floor, top * 1e-5), vmax=top))
        for i, (k1, k2) in enumerate(lat.k):
            text = f"{amp[i]:.2g}" if amp[i] > 1e-12 * top else "0"   # round-off: 0
            ax.text(int(k1), int(k2), text, ha="center", va="center",
                    fontsize=6, color="w" if amp[i] < 0.3 * top else "k")
        ax.set_xticks(range(H1 + 1), [f"{k}X" for k in range(H1 + 1)])
        ax.set_yticks(range(-H2, H2 + 1), [f"{k:+d} " + r"$\omega_b$" if k else "0"
                                          for k in range(-H2, H2 + 1)])
        ax.set_xlabel(r"$k_1$ (multiples of $\Omega$)")
        ax.set_title(f"node {n}", fontsize=8)
    axes[0].set_ylabel(r"$k_2$ (multiples of $\omega_b$)")
    bars = []
    if image is not None:
        cax = fig.add_axes((0.0, 0.0, 0.1, 0.1), label="<colorbar>")
        fig.colorbar(image, cax=cax, label=r"$\sqrt{|X_y|^2 + |X_z|^2}\,/\,C$")
        bars.append((cax, list(axes)))
    ratio = b.omega[index] / result.reference_speed
    at = f"Omega~ = {ratio:.4g}" if result.is_speed else \
        f"{result.at(index)}, Omega~ = {ratio:.4g}"
    fig.suptitle(mathtext(wrap(f"Amplitude spectrum at {at} (the line at "
                               "k1 Omega + k2 w_b; blank: the conjugate of the mirrored "
                               "cell)", 90)), fontsize=9)
    fixed_layout(fig, [list(axes)], (1.1 * (H1 + 1), 0.55 * (2 * H2 + 1)), colorbars=bars)
    return fig
