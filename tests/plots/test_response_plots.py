"""The response figures mark a fold on the sheet it belongs to and explain their styles."""

import numpy as np
from matplotlib.figure import Figure

from rotorsfd.plots.response import mark_bifurcations, response_figures


def _s_curve() -> tuple[np.ndarray, np.ndarray]:
    # An S-shaped branch: x goes 1.0 -> 1.1 -> 1.0 -> 1.1 while y falls from 3 to 0, so
    # the lower fold (x = 1.0, point 20, y = 1) shares its x with the start (y = 3).
    s = np.linspace(0.0, 3.0, 31)
    x = np.where(s < 1.0, s, np.where(s < 2.0, 2.0 - s, s - 2.0)) * 0.1 + 1.0
    y = 3.0 - s
    return x, y


def test_fold_marker_sits_on_its_own_sheet():
    x, y = _s_curve()
    fold = {"type": "saddle-node", "speed_ratio": 1.0, "point": 20}
    fig = Figure()
    ax = fig.add_subplot()
    mark_bifurcations(ax, x, y, [fold], "speed_ratio")
    (marker,) = ax.lines
    assert marker.get_ydata()[0] == 1.0          # point 20, not the first point (y = 3)


def test_deflection_figure_has_style_and_marker_key():
    x, y = _s_curve()
    stable = (np.arange(x.size) < 10) | (np.arange(x.size) > 20)
    table = {"speed_ratio": x, "stable": stable, "defl_1": y,
             "static_1_y": 0 * y, "amp_1_y_h1": y, "static_1_z": 0 * y, "amp_1_z_h1": y}
    folds = [{"type": "saddle-node", "speed_ratio": 1.1, "point": 10},
             {"type": "saddle-node", "speed_ratio": 1.0, "point": 20}]
    figs = response_figures(table, x_name="speed_ratio", x_label="x", nodes=[1],
                            directions=["y", "z"], H=1, clearance=1.0, bifurcations=folds)
    fig = figs["response_deflection.png"]
    labels = {t.get_text() for legend in fig.findobj(lambda a: a.__class__.__name__ == "Legend")
              for t in legend.get_texts()}
    assert {"stable", "unstable", "saddle-node", "node 1"} <= labels


def test_branch_points_get_their_own_markers():
    x, y = _s_curve()
    rows = [{"type": "saddle-node", "speed_ratio": 1.1, "point": 10},
            {"type": "pitchfork", "speed_ratio": 1.05, "point": 5},
            {"type": "transcritical", "speed_ratio": 1.02, "point": 25}]
    fig = Figure()
    ax = fig.add_subplot()
    mark_bifurcations(ax, x, y, rows, "speed_ratio")
    markers = [line.get_marker() for line in ax.lines]
    assert markers == ["o", "D", "v"]      # none drawn with the untyped cross
