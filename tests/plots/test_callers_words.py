"""The callers of the shared figure helpers (issue 24, item 6): the Campbell diagram of
``rotorsfd modal``, the stability chart and the fold curve are drawn through
rotorsfd.plots, so their titles are wrapped (never cut with "..."), their axes are words
with units and their symbols mathtext (no config paths, no ASCII ``Omega~``); the modal
summary says how the Campbell modes were computed; the paper's cases are titled by their
own settings."""

from __future__ import annotations

from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from figure_text import legends_over_panels, texts

PAPER = Path(__file__).parents[2] / "examples" / "paper_rotor.toml"
LONG = ("Fig. 6: stability chart, linear single-disk rotor, harmonic base pitching at "
        "Omega = 250 rad/s (Zhang et al. 2025), the end of a long title")
ASCII = ("Omega~", "|mu|", "w_b", "A0 ")


def _words(fig) -> str:
    return " ".join(" ".join(texts(fig)).split())


def _no_ascii_symbols(words: str) -> None:
    assert "..." not in words
    for a in ASCII:
        assert a not in words, a
    assert "Omega" not in words.replace(r"\Omega", "")


@pytest.fixture(scope="module")
def modal():
    from rotorsfd import api

    cfg = api.load_config(PAPER, ["analysis.modal.speeds=[0, 500, 1000, 1500]",
                                  "analysis.modal.n_critical=2"])
    return api.run_modal(cfg.model_copy(update={"title": LONG}))


def test_modal_campbell_title_whole_and_axes_in_words(modal):
    fig = modal.plot()["campbell.png"]
    ax = fig.axes[0]
    words = _words(fig)
    assert "the end of a long title" in words
    _no_ascii_symbols(words)
    assert ax.get_xlabel() == r"spin speed $\Omega$ [rad/s]"
    assert ax.get_ylabel() == r"damped natural frequency $\omega$ [rad/s]"
    assert not legends_over_panels(fig)
    # the critical speeds are marked on the 1X line at the values computed
    marks = [ln for ln in ax.lines if ln.get_marker() == "o"]
    crit = [c.speed_rad_s for c in modal.critical_speeds]
    assert [float(m.get_xdata()[0]) for m in marks] == pytest.approx(crit, rel=1e-12)
    assert any(f"{crit[0]:.1f} rad/s" == t for t in texts(fig))


def test_modal_write_draws_the_same_figure(modal, tmp_path):
    paths = modal.write(tmp_path)
    assert paths["campbell.png"].read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


def test_modal_summary_says_the_campbell_method(modal):
    text = modal.summary()
    assert f"Campbell diagram: 4 speeds, {modal.campbell.info['method']} eigensolver" in text
    reduced = replace(modal, campbell=replace(modal.campbell, info={
        "method": "reduced", "reduced_error": 3.2e-12, "snapshots_rad_s": [0.0, 750.0, 1500.0],
        "basis_size": 36}))
    line = next(ln for ln in reduced.summary().splitlines() if ln.startswith("Campbell"))
    assert "reduced model on exact modes at 3 speeds (basis 36)" in line
    assert "measured relative eigenvalue error 3.2e-12" in line
    missed = replace(modal, campbell=replace(modal.campbell, info={
        "method": "sparse", "reduced_error": 4.0e-7}))
    assert "error 4.0e-07 was above its tolerance" in missed.summary()


def _chart_result(title: str = LONG):
    from rotorsfd.analyses.stability_chart import ChartAxis, ChartResult
    from rotorsfd.stability.chart import StabilityChart

    x = np.linspace(200.0, 340.0, 29)
    y = np.linspace(0.0, 0.5, 21)
    m = np.ones((29, 21))
    m[5:8, 12:] = 1.0736
    m[15:18, 8:] = 1.0982
    m[25, 10] = 1.0006
    xa = ChartAxis("base.pitching.frequency", x, "rad/s")
    ya = ChartAxis("base.pitching.angle_amplitude", y, "rad")
    chart = StabilityChart(x, y, m, np.ones_like(m, complex), tol=1e-5,
                           names=(xa.name, ya.name))
    return ChartResult(chart, xa, ya, 250.0, title=title)


def test_stability_chart_through_chart_axes(tmp_path):
    from matplotlib.figure import Figure

    r = _chart_result()
    fig = Figure(figsize=(7.4, 5.6), layout="constrained")
    ax = r.plot_on(fig.add_subplot())
    assert ax.get_xlabel() == r"pitching frequency $\omega_b$ [rad/s]"
    assert ax.get_ylabel() == r"pitching amplitude $A_0$ [rad]"
    title = " ".join(ax.get_title().split())
    assert "the end of a long title" in title
    # counted from the grid above: 3*9 + 3*13 + 1 = 67 unstable points, 2 zones, 1 island
    assert "67 of 609 points unstable" in title
    assert r"$\Omega$ = 250 rad/s" in title
    assert "2 unstable zones down to $A_0$ = 0.2-0.3 rad" in title
    assert "1 island of 1 point" in title
    _no_ascii_symbols(_words(fig))
    assert r.write(tmp_path)["chart.png"].read_bytes()[:4] == b"\x89PNG"


def _fold_curve():
    from rotorsfd.analyses.fold_curve import CuspPoint, FoldCurve

    v = np.linspace(0.0, 7.7, 40)
    lo = 1.085 + 0.045 * (v / 7.7) ** 2
    hi = 1.143 - 0.013 * (v / 7.7) ** 2
    f = FoldCurve("base.pitching", (0.0, 10.0), 811.3, 16, 64, (1,), [1.085 * 811.3],
                  [], None, {}, [CuspPoint(1.13 * 811.3, 1.13, 7.7, 0.6)], True, "ok")
    f.table = {"curve": np.zeros(80, int), "segment": np.r_[np.zeros(40, int),
                                                             np.ones(40, int)],
               f.value_column: np.r_[v, v[::-1]], "speed_ratio": np.r_[lo, hi[::-1]]}
    return f


def test_fold_curve_plot_through_fold_curve_figure():
    f = _fold_curve()
    f.title = LONG
    fig = f.plot()["fold_curve.png"]
    ax, ax2 = fig.axes
    assert ax2.get_xlabel() == r"pitching rate $\omega_{by}$ [rad/s]"
    assert ax.get_ylabel() == r"$\tilde\Omega$ of the saddle-nodes"
    assert ax2.get_ylabel() == r"unstable width in $\tilde\Omega$"
    words = _words(fig)
    assert "the end of a long title" in words and "H = 16" in words
    assert "cusp at 7.7 rad/s" in words
    _no_ascii_symbols(words)
    assert not legends_over_panels(fig)
    # the width drawn is hi - lo of the two segments: 1.143 - 1.085 = 0.058 at rate 0
    width = ax2.lines[0].get_ydata()
    assert width[0] == pytest.approx(0.058, abs=1e-12)


def test_paper_case_titled_by_its_own_settings():
    from rotorsfd.paper.cases import CASES
    from rotorsfd.paper.run import case_title

    fig7 = ("Figs. 7 and Table 1: fixed base, C/R = 0.485 %, H = 3, U = 72.008 / 144.02 / "
            "360.04 g mm (Zhang et al. 2025)")
    t = case_title(CASES["fig7-u144"], fig7)
    assert t == ("Figs. 7 and Table 1: fixed base, C/R = 0.485 %, H = 3, U = 144.02 g mm "
                 "(Zhang et al. 2025)")
    fig21 = ("Figs. 21-22 and Table 3: C/R = 0.485 / 0.61 / 0.728 %, U = 252 g mm, "
             "w_by = 10 rad/s, H = 8 (Zhang et al. 2025)")
    t = case_title(CASES["fig21-cr0.61"], fig21)
    assert " / " not in t and t.endswith("H = 8, C/R = 0.61 % (Zhang et al. 2025)")
    t = case_title(CASES["fig12-w4"], "Figs. 12-15: constant base pitching w_by, "
                   "w_by = 0 rad/s, U = 144.02 g mm")
    assert "w_by = 0" not in t and t.endswith(r"$\omega_{by}$ = 4 rad/s")
    assert case_title(CASES["modal"], "Paper rotor") == "Paper rotor"


def test_paper_case_config_carries_its_title():
    from rotorsfd.paper.cases import CASES
    from rotorsfd.paper.run import load_case_config

    cfg = load_case_config(CASES["fig7-u144"])
    assert "U = 144.02 g mm" in cfg.title and "72.008" not in cfg.title


def test_paper_chart_case_passes_tol_and_speed():
    """A 3 x 2 grid of the Figure 6 case: the figure data carry the chart's tol and speed
    (figures.py would otherwise fall back to 1e-5 and 250 rad/s)."""
    from rotorsfd.paper.cases import CASES, FigureSpec
    from rotorsfd.paper.figures import draw
    from rotorsfd.paper.run import run_case
    from rotorsfd.stability.chart import STABILITY_TOL

    case = replace(CASES["fig6"], quick=("analysis.stability_chart.x.n=3",
                                         "analysis.stability_chart.y.n=2",
                                         "analysis.stability_chart.speed=240 rad/s"))
    o = run_case(case, quick=True)
    assert o.status == "ok", o.message
    assert o.data["tol"] == STABILITY_TOL and o.data["speed"] == pytest.approx(240.0, rel=1e-12)
    fig = draw(FigureSpec("6", "stability chart", ("fig6",), "chart"), {"fig6": o})
    title = " ".join(fig.axes[0].get_title().split())
    assert r"$\Omega$ = 240 rad/s" in title and f"1 + {STABILITY_TOL:g}" in title
    _no_ascii_symbols(_words(fig))


def test_paper_fold_curve_case_figure_titled(tmp_path, monkeypatch):
    """The fold-curve case's own figure carries the case's title (a short range at H = 3)."""
    from rotorsfd.io import atomic
    from rotorsfd.paper.cases import CASES
    from rotorsfd.paper.run import run_case

    saved = {}
    save = atomic.save_figure

    def keep(fig, path, **kw):
        saved[Path(path).name] = fig
        return save(fig, path, **kw)

    monkeypatch.setattr(atomic, "save_figure", keep)
    c = CASES["fig19-u144"]
    o = run_case(replace(c, options={**c.options, "range": [0.0, 2.0], "harmonics": 3}),
                 out=tmp_path, plots=True)
    assert o.status == "ok", o.message
    assert (tmp_path / "fig19-u144" / "fold_curve.png").exists()
    words = _words(saved["fold_curve.png"])
    assert "Fig. 19: unstable speed range against the pitching rate, U = 144.02 g mm" in words
    assert "252 /" not in words
    _no_ascii_symbols(words)
