"""``dual_spool_response.png``: the two-frequency response of a dual-spool rotor along its
speed line. Per output node the strongest lines ``k1 Omega_LP + k2 Omega_HP`` (radial
amplitude / C, legends in the spools' words: "1X LP", "1X HP", "2X LP - 1X HP") against
Omega_LP~, a second axis on top in Omega_HP; below, the largest Lyapunov exponent per LP
period where computed (filled: stable, open: unstable)."""

from __future__ import annotations

from typing import Any

from matplotlib.figure import Figure

from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.labels import wrap
from rotorsfd.plots.torus import plot_lines, plot_lyapunov

#: Axes box (width, height) of each panel, inches (fixed layout).
PANEL = (5.6, 2.6)


def spool_label(k1: int, k2: int) -> str:
    """A line's name: "static", "1X LP", "1X HP", "1X LP + 1X HP", "2X LP - 1X HP"."""
    if k1 == 0 and k2 == 0:
        return "static"
    parts = [f"{k1}X LP"] if k1 else []
    if k2:
        parts.append(f"{abs(k2)}X HP" if parts or k2 > 0 else f"-{abs(k2)}X HP")
    return parts[0] if len(parts) == 1 else f"{parts[0]} {'+' if k2 > 0 else '-'} {parts[1]}"


def plot_dual_spool_response(result: Any) -> Figure:
    """The figure of the module docstring for a
    :class:`~rotorsfd.analyses.dual_spool_response.DualSpoolResponseResult`."""
    b = result.branch
    x = b.omega / result.reference_speed
    rows = len(result.nodes) + (1 if result.lyapunov else 0)
    fig = Figure()
    axes = fig.subplots(rows, 1, sharex=True, squeeze=False)[:, 0]
    plot_lines(axes, result, x, spool_label)
    ratio, ref = result.ratio, result.reference_speed
    top = axes[0].secondary_xaxis("top", functions=(lambda v: v * ratio * ref,
                                                    lambda v: v / (ratio * ref)))
    top.set_xlabel(r"$\Omega_{HP}$ [rad/s]", fontsize=8)
    if result.lyapunov:
        plot_lyapunov(axes[-1], result, x, "", "T_LP")
    axes[-1].set_xlabel(r"$\tilde\Omega_{LP} = \Omega_{LP} / \Omega_{ref}$, "
                        rf"$\Omega_{{ref}}$ = {ref:.4g} rad/s")
    fig.suptitle(wrap(f"{result.title or 'Dual-spool response'}: lines k1 Omega_LP + "
                      f"k2 Omega_HP, Omega_HP = {ratio:g} Omega_LP", 90), fontsize=9)
    fixed_layout(fig, [[ax] for ax in axes], PANEL)
    return fig
