"""A second branch (period-2, or from a branch point) drawn over the response figures of
:func:`rotorsfd.plots.response.response_figures`, from plain arrays (no physics here)."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from matplotlib.figure import Figure
from matplotlib.lines import Line2D
from numpy.typing import NDArray

from rotorsfd.plots.response import key_handles, outside_legend, styled_line


def draw_second_branch(figures: Mapping[str, Figure], x: NDArray[np.float64],
                       stable: NDArray[np.bool_] | None,
                       deflection: Mapping[int, NDArray[np.float64]],
                       amplitude: Mapping[tuple[int, str], NDArray[np.float64]], *,
                       nodes: Sequence[int], directions: Sequence[str], legend: str,
                       amplitude_legend: str, main_stable: NDArray[np.bool_] | None = None,
                       bifurcations: Sequence[Mapping[str, Any]] = (),
                       pieces: Sequence[NDArray[np.bool_]] | None = None) -> None:
    """Draw a second branch over the main branch's figures: ``deflection[n]`` (r~) in
    ``response_deflection.png``, ``amplitude[n, d]`` (/C) in each
    ``response_node<n>.png`` panel, black, dashed where not ``stable``, each of ``pieces``
    (masks of the points, default all) its own line; the legends redone with the main
    branch's key (``main_stable``, ``bifurcations``)."""
    masks = pieces or [np.ones(len(x), dtype=bool)]
    both = [a for a in (main_stable, stable) if a is not None]
    key = key_handles(np.concatenate(both) if both else None, bifurcations)
    key.insert(0, Line2D([], [], color="k", lw=1.1, label=legend))

    def lines(ax: Any, y: NDArray[np.float64]) -> None:
        for p in masks:
            styled_line(ax, x[p], y[p], None if stable is None else stable[p],
                        color="k", lw=1.1)

    fig = figures.get("response_deflection.png")
    if fig is not None:
        axes = fig.axes[: len(nodes)] if len(fig.axes) >= len(nodes) else fig.axes
        for k, n in enumerate(nodes):
            lines(axes[k] if len(axes) == len(nodes) else axes[0], deflection[n])
        outside_legend(fig, axes, key)
    for n in nodes:
        fig = figures.get(f"response_node{n}.png")
        if fig is None:
            continue
        axes = [a for a in fig.axes if a.get_title()]
        for ax, d in zip(axes, directions, strict=False):
            lines(ax, amplitude[(n, d)])
        sub = Line2D([], [], color="k", lw=1.1, label=amplitude_legend)
        outside_legend(fig, axes, [sub, *key[1:]])
