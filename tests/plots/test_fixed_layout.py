"""Every figure of plots/ outside the paper's (those: test_paper_figures.py) and the response
figures (test_response_plots.py) is laid out without a layout engine (fixed axes boxes in
inches, plots/fixed_layout.py): every text inside the figure, no panel's decorations over
another panel, no legend over a panel's frame beside it or over a label or title."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np
import pytest
from figure_text import fixed_layout_faults, labels_under_legends, legends_over_panels
from matplotlib.figure import Figure

from rotorsfd.plots.basins import basin_figure
from rotorsfd.plots.bifurcation_curves import bifurcation_curves_figure
from rotorsfd.plots.campbell import campbell_figure
from rotorsfd.plots.chart import chart_figure
from rotorsfd.plots.dual_spool import plot_dual_spool_response
from rotorsfd.plots.fixed_layout import fixed_layout
from rotorsfd.plots.fold import fold_curve_figure
from rotorsfd.plots.timedomain import bifurcation_figure, simulation_figures
from rotorsfd.plots.torus import plot_torus_components, plot_torus_spectrum
from rotorsfd.plots.transient import envelope_figure, waterfall_figure

LONG = ("A title as long as a user's, naming the rotor, the SFD, the unbalance of 144.02 g mm "
        "and the settings, with the end of a long title")


def _campbell() -> Figure:
    speeds = np.linspace(0.0, 4000.0, 21)
    freq = np.column_stack([800.0 - 0.02 * speeds, 800.0 + 0.02 * speeds,
                            2400.0 - 0.1 * speeds, 2400.0 + 0.1 * speeds])
    whirl = np.tile(["backward", "forward", "backward", "forward"], (21, 1))
    return campbell_figure(speeds, freq, whirl, critical=[811.3, 2784.6], title=LONG)


def _fold() -> Figure:
    v = np.linspace(0.0, 7.7, 40)
    lo, hi = 1.085 + 0.045 * (v / 7.7) ** 2, 1.143 - 0.013 * (v / 7.7) ** 2
    grid = np.linspace(0.0, 10.0, 51)
    return fold_curve_figure(np.r_[v, v[::-1]], np.r_[lo, hi[::-1]], np.zeros(80, int),
                             grid=grid, lo=np.interp(grid, v, lo), hi=np.interp(grid, v, hi),
                             count=np.where(grid < 7.7, 2, 0), cusps=[(7.7, 1.13)],
                             parameter="base.pitching", units="rad/s", H=16, title=LONG)


def _curves() -> Figure:
    s = np.linspace(1.0, 1.2, 30)
    kind = np.array(["fold"] * 30 + ["period-doubling"] * 30)
    return bifurcation_curves_figure(kind, np.r_[np.zeros(30), np.ones(30)], np.r_[s, s],
                                     np.r_[1e-4 * s, 2e-4 * s], turns=[("saddle-node", 1.1,
                                                                        1.1e-4)],
                                     codim2=[("cusp", 1.2, 1.2e-4)],
                                     parameter="unbalance.magnitude", units="kg*m", H=3,
                                     title=LONG)


def _simulation() -> dict[str, Figure]:
    t = np.linspace(0.0, 40 * np.pi, 4000)
    py, pz = 0.7 + 0.01 * np.cos(t[::100]), 0.01 * np.sin(t[::100])
    return simulation_figures(y=0.85 * np.cos(t), z=0.85 * np.sin(t), vy=-np.sin(t), py=py,
                              pz=pz, pvy=0 * py, frequency_ratio=np.linspace(0, 6, 200),
                              amplitude=np.exp(-np.linspace(0, 6, 200)),
                              clearance_circle=True, title=LONG)


def _bifurcation_diagram() -> Figure:
    x = np.repeat(np.linspace(0.9, 1.2, 31), 4)
    n = x.size
    rows = {"speed_ratio": np.r_[x, x], "node": np.r_[np.ones(n), 8 * np.ones(n)],
            "direction": np.tile(np.repeat(["up", "down"], 2), 2 * n // 4),
            "y": np.r_[np.sin(7 * x), 3 * np.cos(5 * x)]}
    return bifurcation_figure(rows, nodes=[1, 8], title=LONG)


def _basins() -> Figure:
    coords = np.random.default_rng(1).uniform(-1, 1, (60, 2))
    attractors = [SimpleNamespace(motion="period-1", points=np.array([[0.1, 0.2]]),
                                  period=1, hb={}),
                  SimpleNamespace(motion="contact", points=np.zeros((0, 2)), period=None,
                                  hb={})]
    census = SimpleNamespace(coords=coords, attractors=attractors, n_starts=60,
                             speed=880.0, speed_ratio=1.085,
                             labels=lambda: (coords[:, 0] > 0).astype(int),
                             fraction=lambda a: (0.5, 0.06))
    return basin_figure(census, ["y of the SFD [C]", "z of the SFD [C]"], title=LONG)


def _lines_result(ratio: float | None = None) -> SimpleNamespace:
    """A torus (or dual-spool) branch of 30 points, 2 nodes, 6 lattice lines."""
    k = np.array([[0, 0], [1, 0], [1, -1], [1, 1], [0, 1], [2, -1]])
    X = np.exp(-np.arange(6))[None, :, None] * (1 + np.linspace(0, 1, 30))[:, None, None]
    X = X * np.ones((1, 1, 8)) * (1 + 1j)
    lyap = {i: SimpleNamespace(per_period=-0.1 + 0.01 * i, uncertainty=0.01, stable=i < 10)
            for i in range(0, 30, 3)}
    branch = SimpleNamespace(X=X, lattice=SimpleNamespace(k=k), omega=np.linspace(700, 900,
                                                                                     30),
                             wb=np.full(30, 120.0), lam=np.linspace(700, 900, 30))
    return SimpleNamespace(branch=branch, nodes=[1, 2], dof=lambda n, d: 4 * (n - 1)
                           + (0 if d == "y" else 1), clearance=1.0, node_names=None,
                           lyapunov=lyap, title=LONG, is_speed=True, reference_speed=811.3,
                           parameter="speed", parameter_units="rad/s", ratio=ratio)


def _chart(stable: bool = False) -> Figure:
    x, y = np.linspace(80.0, 300.0, 23), np.linspace(0.0, 0.3, 16)
    X, Y = np.meshgrid(x, y, indexing="ij")
    m = 1.0 + (0.0 if stable else 0.08) * np.exp(-((X - 190) / 30) ** 2) * Y / 0.3
    return chart_figure(x, y, m, x_path="base.pitching.frequency",
                        y_path="base.pitching.angle_amplitude", x_units="rad/s",
                        y_units="rad", speed=250.0, title=LONG)


def _spectrum() -> Figure:
    result = _lines_result()
    k = np.array([(k1, k2) for k1 in range(4) for k2 in range(-2, 3)])
    result.branch.lattice = SimpleNamespace(H1=3, H2=2, k=k)
    result.branch.X = np.exp(-np.arange(k.shape[0]))[None, :, None] * np.ones((30, 1, 8))
    return plot_torus_spectrum(result, 5)


def _envelope() -> Figure:
    t = np.linspace(0.0, 2.0, 400)
    speed = 300 + 200 * t
    radius = {1: 1e-4 * (1 + np.sin(speed / 50) ** 2), 8: 3e-5 * (1 + t)}
    return envelope_figure(t=t, speed=speed, radius=radius, clearances={1: 1.27e-4},
                           events=[0.7], branch={1: (speed, 1e-4 * np.ones(400),
                                                     np.r_[np.ones(200), np.zeros(200)])},
                           title=LONG)


def _waterfall() -> Figure:
    t = np.linspace(0.0, 2.0, 40)
    f = np.linspace(0.0, 200.0, 100)
    amp = 1e-5 * np.exp(-((f[None, :] - 50 * (1 + t[:, None])) / 10) ** 2) + 1e-9
    speed = 2 * np.pi * 50 * (1 + t)
    return waterfall_figure(time=t, frequency_hz=f, amplitude=amp, node=1, t=t, speed=speed,
                            natural=(np.array([0.0, 1000.0]), np.array([[600.0], [620.0]])),
                            title=LONG)


FIGURES = {"chart": _chart, "chart all stable": lambda: _chart(True),
           "torus spectrum": _spectrum, "envelope": _envelope, "waterfall": _waterfall,
"campbell": _campbell, "fold": _fold, "bifurcation curves": _curves,
           "bifurcation diagram": _bifurcation_diagram, "basins": _basins,
           "torus lines": lambda: plot_torus_components(_lines_result()),
           "dual spool": lambda: plot_dual_spool_response(_lines_result(1.4)),
           **{f"simulation {k}": (lambda k=k: _simulation()[k])
              for k in ("simulation.png", "orbit.png", "phase.png", "poincare.png",
                        "spectrum.png")}}


@pytest.mark.parametrize("name", list(FIGURES))
def test_figure_fixed_layout(name):
    fig = FIGURES[name]()
    assert fig.get_layout_engine() is None
    assert not fixed_layout_faults(fig), fixed_layout_faults(fig)
    if name not in ("torus lines", "dual spool", "envelope", "waterfall"):
        assert not legends_over_panels(fig)     # those keep their legends inside (best)
    assert not labels_under_legends(fig), labels_under_legends(fig)


def test_fixed_layout_gives_the_boxes_their_size_and_room_for_their_labels():
    """Two columns of two panels (3 x 2 in): each box 3 x 2 in, the second column right
    of the first one's right-hand legend, the figure as wide as the title when it is the
    widest."""
    fig = Figure()
    axes = fig.subplots(2, 2)
    for ax in axes.ravel():
        ax.plot([0, 1], [0, 1e4], label="a curve with a long name")
        ax.set_ylabel("amplitude [m]")
        ax.set_title("a panel")
    axes[0, 0].legend(loc="upper left", bbox_to_anchor=(1.02, 1.0))
    fig.suptitle("x" * 200)
    fixed_layout(fig, axes.tolist(), (3.0, 2.0))
    W, H = fig.get_size_inches()
    for ax in axes.ravel():
        p = ax.get_position()
        assert p.width * W == pytest.approx(3.0) and p.height * H == pytest.approx(2.0)
    assert not fixed_layout_faults(fig) and not legends_over_panels(fig)
    title = fig.texts[0].get_window_extent(fig.canvas.get_renderer()).width / fig.dpi
    assert W == pytest.approx(title + 0.24, rel=1e-6)     # the title's width plus 2 PAD


def test_a_clearance_ratio_axis_is_in_per_cent():
    """C/R (a dimensionless ratio) is drawn in per cent, as configs write it ("0.728 %"):
    the values times 100 and the unit named."""
    s = np.linspace(1.0, 1.1, 10)
    fig = bifurcation_curves_figure(np.array(["Neimark-Sacker"] * 10), np.zeros(10), s,
                                    np.linspace(0.0061, 0.00728, 10),
                                    parameter="elements.sfd.clearance_ratio", units="1",
                                    H=8)
    ax = fig.axes[0]
    assert ax.get_ylabel().endswith("[%]")
    assert ax.lines[0].get_ydata() == pytest.approx(np.linspace(0.61, 0.728, 10))
