"""The response figures mark a fold on the sheet it belongs to and explain their styles,
and are laid out without a layout engine (fixed axes boxes in inches) with every text
inside the figure, no panel's decorations over another panel, no legend over a panel or
over a label."""

import numpy as np
import pytest
from figure_text import fixed_layout_faults, labels_under_legends, legends_over_panels
from matplotlib.figure import Figure

from rotorsfd.plots.response import PANEL, mark_bifurcations, plot_multipliers, response_figures


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


def _table(nodes: dict[int, float], H: int = 3) -> dict:
    """A branch over Omega~ 0.6-1.4 with a resonance; node n's amplitude scaled by
    ``nodes[n]``, an unstable middle part."""
    x = np.linspace(0.6, 1.4, 81)
    y = 1.0 / np.sqrt((1 - x**2) ** 2 + 0.04)
    table = {"speed_ratio": x, "stable": (x < 0.95) | (x > 1.05)}
    for n, s in nodes.items():
        table[f"defl_{n}"] = s * y
        for d in ("y", "z"):
            table[f"static_{n}_{d}"] = 0.01 * s * x
            for k in range(1, H + 1):
                table[f"amp_{n}_{d}_h{k}"] = s * y / k**2
    return table


FOLDS = [{"type": "saddle-node", "speed_ratio": 0.95, "point": 35},
         {"type": "secondary-hopf", "speed_ratio": 1.05, "point": 45}]
TITLE = ("Frequency response of the stepped rotor with an SFD at node 1 (U = 144.02 g mm, "
         "C/R = 0.5 %, H = 3, stability on)")


@pytest.mark.parametrize("scales", [{1: 1.0, 8: 1.3}, {1: 1.0, 8: 20.0}])
def test_response_figures_fixed_layout(scales):
    figs = response_figures(_table(scales), x_name="speed_ratio",
                            x_label="speed_ratio", nodes=list(scales), directions=["y", "z"],
                            H=3, clearance=1.0, bifurcations=FOLDS, title=TITLE)
    assert set(figs) == {"response_deflection.png", "response_node1.png",
                         "response_node8.png"}
    panels = 1 if scales[8] < 4 else 2            # apart when they differ by > 4 times
    assert len(figs["response_deflection.png"].axes) == panels
    for name, fig in figs.items():
        assert fig.get_layout_engine() is None, name
        assert not fixed_layout_faults(fig), (name, fixed_layout_faults(fig))
        assert not legends_over_panels(fig), name
        assert not labels_under_legends(fig), (name, labels_under_legends(fig))
    # the axes boxes have the fixed size in inches
    fig = figs["response_node1.png"]
    W, H = fig.get_size_inches()
    for ax in fig.axes:
        pos = ax.get_position()
        assert pos.width * W == pytest.approx(PANEL[0]) and pos.height * H == pytest.approx(
            PANEL[1])


def test_multipliers_figure_fixed_layout():
    mu = np.concatenate([0.4 * np.exp(1j * np.linspace(0, 6, 12)), [-1.02]])
    fig = plot_multipliers(mu, where="Omega~ = 1.05", stable=False, title=TITLE)
    assert fig.get_layout_engine() is None
    assert not fixed_layout_faults(fig), fixed_layout_faults(fig)
    assert not legends_over_panels(fig)
    assert not labels_under_legends(fig), labels_under_legends(fig)
