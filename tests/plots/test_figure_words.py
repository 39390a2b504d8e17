"""The figures speak the user's language: titles wrapped, never cut; symbols in mathtext;
config paths as words; legends beside the panels, not over the curves; each panel on the
scale of what it shows (issue 24, item 6)."""

from __future__ import annotations

import numpy as np
import pytest
from figure_text import legend_labels, legends_over_panels, texts

from rotorsfd.plots.response import plot_multipliers, response_figures
from rotorsfd.plots.timedomain import bifurcation_figure, simulation_figures

LONG = ("Figs. 7 and Table 1: fixed base, C/R = 0.485 %, H = 3, U = 72.008 / 144.02 / 360.04 "
        "g mm (Zhang et al. 2025), with the end of a long title")


def _table(n: int = 60, scale8: float = 7.0) -> dict[str, np.ndarray]:
    s = np.linspace(0.5, 1.3, n)
    bump = 1.0 / (1.0 + ((s - 1.0) / 0.08) ** 2)
    t = {"speed_ratio": s, "stable": s < 1.1, "defl_1": bump, "defl_8": scale8 * bump}
    for node in (1, 8):
        for d in ("y", "z"):
            t[f"static_{node}_{d}"] = 0 * s
            t[f"amp_{node}_{d}_h1"] = t[f"defl_{node}"]
    return t


def _figs(title: str = LONG, x_label: str = r"$\tilde\Omega$", scale8: float = 7.0):
    folds = [{"type": "saddle-node", "speed_ratio": 1.1, "point": 45}]
    return response_figures(_table(scale8=scale8), x_name="speed_ratio", x_label=x_label,
                            nodes=[1, 8], directions=["y", "z"], H=1, clearance=1.0,
                            bifurcations=folds, title=title)


def _whole(fig) -> str:
    return " ".join(" ".join(texts(fig)).split())


def test_response_titles_are_wrapped_not_cut():
    figs = _figs()
    for fig in (figs["response_deflection.png"], figs["response_node8.png"]):
        words = _whole(fig)
        assert "..." not in words
        assert "with the end of a long title" in words


def test_nodes_of_very_different_amplitude_get_their_own_panels():
    fig = _figs(scale8=7.0)["response_deflection.png"]
    panels = [ax for ax in fig.axes if ax.lines]
    assert len(panels) == 2
    tops = sorted(ax.get_ylim()[1] for ax in panels)
    assert tops[0] < 1.5 and tops[1] > 6.0          # each on its own scale
    assert len(_figs(scale8=1.5)["response_deflection.png"].axes) == 1


def test_response_legends_beside_the_curves_with_the_style_key():
    figs = _figs()
    for name in ("response_deflection.png", "response_node1.png"):
        assert not legends_over_panels(figs[name]), name
    assert {"node 1", "node 8", "stable", "unstable", "saddle-node"} <= legend_labels(
        figs["response_deflection.png"])


def test_config_path_axis_label_in_words():
    fig = _figs(x_label="base.pitching.value [rad/s]")["response_deflection.png"]
    label = fig.axes[-1].get_xlabel()
    assert "base.pitching" not in label and "[rad/s]" in label
    assert r"\omega_{by}" in label


def test_multipliers_title_in_mathtext():
    fig = plot_multipliers([0.5, 1.02, 0.3j], where="Omega~ = 1.05 (point 3)", title=LONG)
    title = fig.axes[0].get_title()
    assert "Omega~" not in title and r"$\tilde\Omega$ = 1.05" in title
    assert "..." not in title
    assert not legends_over_panels(fig)


def _torus(n: int = 100, centre=(-0.2, -0.6), r: float = 0.025):
    th = np.linspace(0.0, 2 * np.pi * 0.97 * n / 10, n)
    return centre[0] + r * np.cos(th), centre[1] + r * np.sin(th)


def _simulation(py, pz, title: str = LONG):
    t = np.linspace(0.0, 40 * np.pi, 4000)
    y = 0.85 * np.cos(t) - 0.15
    z = 0.85 * np.sin(t) - 0.15                      # an orbit from -1 to 0.7 C
    return simulation_figures(y=y, z=z, vy=-np.sin(t), py=py, pz=pz, pvy=0 * py,
                              frequency_ratio=np.linspace(0, 6, 200),
                              amplitude=np.exp(-np.linspace(0, 6, 200)),
                              clearance_circle=True, title="node 1, Omega~ = 1.07: " + title)


def test_poincare_panel_on_the_scale_of_its_points():
    py, pz = _torus()
    for name in ("simulation.png", "poincare.png"):
        fig = _simulation(py, pz)[name]
        ax = next(a for a in fig.axes if a.get_title().startswith("Poincare"))
        lo, hi = ax.get_xlim()
        assert py.min() >= lo and py.max() <= hi
        assert hi - lo < 4 * (py.max() - py.min())   # the torus fills the panel
        lo, hi = ax.get_ylim()
        assert pz.min() >= lo and pz.max() <= hi and hi - lo < 4 * (pz.max() - pz.min())


def test_period_one_point_is_not_blown_up_to_its_scatter():
    py = -0.2 + 1e-7 * np.arange(5)
    pz = -0.6 + 1e-7 * np.arange(5)
    ax = next(a for a in _simulation(py, pz)["poincare.png"].axes
              if a.get_title().startswith("Poincare"))
    lo, hi = ax.get_xlim()
    assert hi - lo > 0.01                            # a few % of the 1.7 C orbit


def test_simulation_titles_wrapped_and_in_mathtext():
    py, pz = _torus()
    figs = _simulation(py, pz)
    for fig in (figs["simulation.png"], figs["orbit.png"]):
        words = _whole(fig)
        assert "..." not in words and "end of a long title" in words
        assert "Omega~" not in words


def test_bifurcation_diagram_up_dots_drawn_over_down_crosses():
    x = np.repeat(np.linspace(1.0, 1.1, 11), 2)
    rows = {"speed_ratio": np.r_[x, x], "node": np.r_[np.ones(44, int)],
            "direction": np.array(["up"] * 22 + ["down"] * 22),
            "y": np.r_[np.sin(x), np.sin(x)]}
    fig = bifurcation_figure(rows, nodes=[1], title=LONG)
    ax = fig.axes[0]
    up = next(ln for ln in ax.lines if ln.get_gid() == "sweep-up")
    down = next(ln for ln in ax.lines if ln.get_gid() == "sweep-down")
    assert up.get_zorder() > down.get_zorder()
    assert up.get_markersize() < down.get_markersize()   # a dot inside its cross
    assert not legends_over_panels(fig)
    assert "..." not in _whole(fig)


@pytest.mark.parametrize("text, want", [
    ("Omega~ = 1.05", r"$\tilde\Omega$ = 1.05"),
    ("|mu|max = 1.2", r"$|\mu|_{max}$ = 1.2"),
    ("w_by = 2 rad/s", r"$\omega_{by}$ = 2 rad/s"),
    (r"kept $\tilde\Omega$, Omega_ref", r"kept $\tilde\Omega$, $\Omega_{ref}$"),
    ("Omegas stay", "Omegas stay"),
])
def test_mathtext_of_the_ascii_symbols(text, want):
    from rotorsfd.plots.labels import mathtext

    assert mathtext(text) == want


@pytest.mark.parametrize("override, want", [
    ("unbalance[0].magnitude=72.008 g*mm", "U = 72.008 g mm"),
    ("base.pitching.value=2 rad/s", r"$\omega_{by}$ = 2 rad/s"),
    ("base.rolling.value=10 rad/s", r"$\omega_{bx}$ = 10 rad/s"),
    ("sfd.clearance_ratio=0.485 %", "C/R = 0.485 %"),
    ("elements.sfd.clearance_ratio=0.61 %", "C/R = 0.61 %"),
    ("elements[0].clearance_ratio=0.728 %", "C/R = 0.728 %"),
    ("analysis.simulate.steps_per_period=200", "T/200"),
    ("rotor.damping.ratio=0.002", "0.2 % modal damping"),
    ("rotor.damping.kind=modal", ""),
])
def test_settings_in_words(override, want):
    from rotorsfd.plots.labels import setting

    assert setting(override) == want
