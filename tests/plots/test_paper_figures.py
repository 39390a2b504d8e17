"""The paper's figures (rotorsfd.paper.figures) in the reader's terms: legends name the
settings (U, w_by), not case ids; a key for solid/dashed and the markers; symbols in
mathtext; the Poincare panels on the scale of their points; the chart's axes in words and
its title saying what the grid shows (issue 24, item 6)."""

from __future__ import annotations

import numpy as np
from figure_text import fixed_layout_faults, legend_labels, legends_over_panels, texts

from rotorsfd.paper.cases import FIGURES
from rotorsfd.paper.figures import draw
from rotorsfd.paper.run import Outcome


def _response(name: str, unstable: bool = True) -> Outcome:
    s = np.linspace(0.5, 1.6, 40)
    bump = 1.0 / (1.0 + ((s - 1.05) / 0.05) ** 2)
    data = {"speed_ratio": s, "defl_1": bump, "defl_8": 1.5 * bump,
            "stable": (s < 1.02) | (s > 1.08) if unstable else np.ones(40, bool),
            "bifurcations": [{"type": "saddle-node", "speed_ratio": 1.06, "point": 25}]
            if unstable else [], "H": 3, "clearance": 1.0}
    for n in (1, 8):
        data[f"static_{n}_y"] = 0 * s
        for k in (1, 2, 3):
            data[f"amp_{n}_y_h{k}"] = data[f"defl_{n}"] / k ** 2
    return Outcome(name, "ok", "", 1.0, {}, data)


def _words(fig) -> str:
    return " ".join(" ".join(texts(fig)).split())


def test_figure7_legend_names_the_unbalance_and_keys_the_styles():
    outcomes = {c: _response(c, c == "fig7-u144") for c in FIGURES["7"].cases}
    fig = draw(FIGURES["7"], outcomes)
    labels = legend_labels(fig)
    assert {"U = 72.008 g mm", "U = 144.02 g mm", "U = 360.04 g mm"} <= labels
    assert {"stable", "unstable", "saddle-node"} <= labels
    assert not any("u72" in t or "u144" in t for t in labels)
    assert not legends_over_panels(fig)


def test_pitching_figures_name_the_rate():
    from rotorsfd.paper.figures import case_label

    spec = FIGURES["12"]
    assert case_label("fig12-w2", spec) == r"$\omega_{by}$ = 2 rad/s"
    fig = draw(spec, {c: _response(c) for c in spec.cases})
    labels = legend_labels(fig)
    assert r"$\omega_{by}$ = 9 rad/s" in labels and "w9" not in labels
    # the figures of several unbalances and rates name both
    assert case_label("fig17-u252-w6", FIGURES["17"]) == (
        r"U = 252 g mm, $\omega_{by}$ = 6 rad/s")


def test_harmonics_panels_titled_by_setting():
    spec = FIGURES["15"]
    fig = draw(spec, {c: _response(c) for c in spec.cases})
    titles = [ax.get_title() for ax in fig.axes]
    assert r"$\omega_{by}$ = 8 rad/s, node 8 (disk)" in titles
    assert not legends_over_panels(fig)


def _run(ratio: float, motion: str, torus: bool) -> dict:
    t = np.linspace(0.0, 20 * np.pi, 2000)
    n = 100
    th = np.linspace(0.0, 2 * np.pi * 9.7, n)
    py = -0.2 + (0.025 * np.cos(th) if torus else 1e-7 * np.arange(n))
    pvy = 1.0 + (0.025 * np.sin(th) if torus else 1e-7 * np.arange(n))
    return {"y": 0.85 * np.cos(t) - 0.15, "z": 0.85 * np.sin(t) - 0.15,
            "vy": 1.0 + 0.9 * np.sin(t), "py": py, "pz": py, "pvy": pvy,
            "speed_ratio": ratio, "motion": motion, "steps": 200}


def test_time_domain_sections_on_the_scale_of_their_points():
    spec = FIGURES["23t"]
    outcomes = {c: Outcome(c, "ok", "", 1.0, {}, _run(1.07, "quasi-periodic", True))
                for c in spec.cases[:2]}
    fig = draw(spec, outcomes)
    sections = [ax for ax in fig.axes if ax.get_title().startswith("Poincare")]
    assert sections
    for ax in sections:
        lo, hi = ax.get_xlim()
        assert hi - lo < 0.2                 # the 0.05 C torus, not the 1.7 C phase plane
        lo, hi = ax.get_ylim()
        assert hi - lo < 0.2
    words = _words(fig)
    assert "Omega~" not in words and r"$\tilde\Omega$ = 1.070" in " ".join(
        ax.get_title() for ax in fig.axes)


def test_isola_figure_legend_not_over_the_panels():
    iso = _response("fig23-isola")
    iso.data.update(second=_run(1.075, "period-1", False),
                    runs=[_run(1.065, "quasi-periodic", True)],
                    find=_run(1.075, "period-1", False), runs_t200=[])
    fig = draw(FIGURES["23b"], {"fig23-isola": iso,
                                "fig21-cr0.728": _response("fig21-cr0.728")})
    assert not legends_over_panels(fig)
    torus = next(ax for ax in fig.axes if "quasi-periodic" in ax.get_title())
    assert np.diff(torus.get_xlim())[0] < 0.2
    assert "Omega~" not in _words(fig)


def _chart_data() -> dict:
    """Two tongues reaching down to y = 0.3 and 0.2, one single-point island at
    |mu| = 1.0006."""
    x = np.linspace(200.0, 340.0, 29)
    y = np.linspace(0.0, 0.5, 21)
    m = np.ones((x.size, y.size))
    m[5:8, y >= 0.3] = 1.05
    m[15:18, y >= 0.2] = 1.08
    m[25, 10] = 1.0006
    return {"x": x, "y": y, "max_abs": m, "x_label": "base.pitching.frequency [rad/s]",
            "y_label": "base.pitching.angle_amplitude [rad]"}


def test_chart_axes_in_words_and_title_says_what_it_shows():
    fig = draw(FIGURES["6"], {"fig6": Outcome("fig6", "ok", "", 1.0, {}, _chart_data())})
    ax = fig.axes[0]
    assert "base.pitching" not in ax.get_xlabel() + ax.get_ylabel()
    assert ax.get_xlabel().endswith("[rad/s]") and ax.get_ylabel().endswith("[rad]")
    title = " ".join(ax.get_title().split())
    assert "2 unstable zones down to $A_0$ = 0.2-0.3 rad" in title
    assert "1 island of 1 point" in title and "1.0006" in title
    # a colour bar with round ticks (not 1.07361)
    bar = fig.axes[1]
    ticks = [t for t in bar.get_yticks() if bar.get_ylim()[0] <= t <= bar.get_ylim()[1]]
    assert ticks and all(abs(t * 1000 - round(t * 1000)) < 1e-6 for t in ticks)


def _both_readings(number: str) -> dict:
    from rotorsfd.paper.cases import CAL, CASES

    names = [n for c in FIGURES[number].cases for n in (c, CAL + c) if n in CASES]
    return {n: _response(n) for n in names}


def _isola() -> dict:
    iso = _response("fig23-isola")
    iso.data.update(second=_run(1.075, "period-1", False),
                    runs=[_run(1.065, "quasi-periodic", True), _run(1.06, "period-1", False)],
                    find=_run(1.075, "period-1", False),
                    runs_t200=[_run(1.07, "quasi-periodic", True)])
    return {"fig23-isola": iso, "fig21-cr0.728": _response("fig21-cr0.728")}


def _calibrated_alone(number: str) -> dict:
    """The calibrated reading alone: a narrow figure under a three-line title."""
    from rotorsfd.paper.cases import CAL

    return {n: o for n, o in _both_readings(number).items() if n.startswith(CAL)}


LAYOUT_CASES = {
    "7": lambda: _both_readings("7"), "12": lambda: _both_readings("12"),
    "15": lambda: _both_readings("15"), "23b": _isola,
    "23b (calibrated alone)": lambda: _calibrated_alone("23b"),
    "23t": lambda: {c: Outcome(c, "ok", "", 1.0, {}, _run(1.07, "quasi-periodic", True))
                    for c in FIGURES["23t"].cases},
    "6": lambda: {"fig6": Outcome("fig6", "ok", "", 1.0, {}, _chart_data())}}


def test_fixed_layout_keeps_every_text_inside_and_panels_apart():
    for number, outcomes in LAYOUT_CASES.items():
        fig = draw(FIGURES[number.split()[0]], outcomes())
        assert fig.get_layout_engine() is None, number        # no constrained layout
        assert not fixed_layout_faults(fig), (number, fixed_layout_faults(fig))
        assert not legends_over_panels(fig), number
