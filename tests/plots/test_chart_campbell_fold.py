"""The figures the analyses are to draw through rotorsfd.plots: the stability chart (round
colour-bar ticks, axes in words, a title that says what the grid shows), the Campbell
diagram (legend beside, title wrapped) and the fold curve (the parameter in words, Omega~
in mathtext) (issue 24, item 6)."""

from __future__ import annotations

import numpy as np
from figure_text import legends_over_panels, texts

LONG = ("Fig. 6: stability chart, linear single-disk rotor, harmonic base pitching at "
        "Omega = 250 rad/s (Zhang et al. 2025), the end of a long title")


def _grid():
    x = np.linspace(200.0, 340.0, 29)
    y = np.linspace(0.0, 0.5, 21)
    m = np.ones((29, 21))
    m[5:8, 12:] = 1.0736
    m[15:18, 8:] = 1.0982
    m[25, 10] = 1.0006
    m[2, 17] = 1.0001
    return x, y, m


def test_regions_counted_from_the_grid():
    from rotorsfd.plots.chart import describe, unstable_regions

    x, y, m = _grid()
    regions = unstable_regions(x, y, m)
    assert [r.n_points for r in regions] == [39, 27, 1, 1]
    assert regions[0].y_range == (y[8], 0.5) and regions[1].y_range == (y[12], 0.5)
    words = describe(regions, "A0", "rad", mu="|mu|", ringed=False)
    assert words == ("2 unstable zones down to A0 = 0.2-0.3 rad; 2 islands of 1 point "
                     "(max |mu| 1.0001-1.0006)")


def test_chart_figure_ticks_labels_and_title():
    from rotorsfd.plots.chart import chart_figure

    x, y, m = _grid()
    fig = chart_figure(x, y, m, x_path="base.pitching.frequency",
                       y_path="base.pitching.angle_amplitude", x_units="rad/s",
                       y_units="rad", speed=250.0, title=LONG)
    ax, bar = fig.axes
    assert ax.get_xlabel() == r"pitching frequency $\omega_b$ [rad/s]"
    assert ax.get_ylabel() == r"pitching amplitude $A_0$ [rad]"
    title = " ".join(ax.get_title().split())
    assert "the end of a long title" in title and "..." not in title
    assert "2 islands of 1 point (ringed; max" in title
    lo, hi = bar.get_ylim()
    ticks = [t for t in bar.get_yticks() if lo <= t <= hi]
    assert len(ticks) >= 3
    assert all(abs(t * 1000 - round(t * 1000)) < 1e-6 for t in ticks)  # 1.025, not 1.07361
    ringed = [ln for ln in ax.lines if ln.get_gid() == "islands"]
    assert ringed and len(ringed[0].get_xdata()) == 2


def test_campbell_legend_beside_and_title_wrapped():
    from rotorsfd.plots.campbell import campbell_figure

    speeds = np.linspace(0.0, 4000.0, 21)
    freq = np.column_stack([800.0 - 0.02 * speeds, 800.0 + 0.02 * speeds,
                            2400.0 - 0.1 * speeds, 2400.0 + 0.1 * speeds])
    whirl = np.tile(["backward", "forward", "backward", "forward"], (21, 1))
    fig = campbell_figure(speeds, freq, whirl, critical=[811.3, 2784.6], title=LONG)
    assert not legends_over_panels(fig)
    words = " ".join(" ".join(texts(fig)).split())
    assert "the end of a long title" in words and "..." not in words
    assert "Omega" not in words.replace(r"\Omega", "")


def test_fold_curve_parameter_in_words():
    from rotorsfd.plots.fold import fold_curve_figure

    v = np.linspace(0.0, 7.7, 40)
    lo = 1.085 + 0.045 * (v / 7.7) ** 2
    hi = 1.143 - 0.013 * (v / 7.7) ** 2
    grid = np.linspace(0.0, 10.0, 51)
    fig = fold_curve_figure(np.r_[v, v[::-1]], np.r_[lo, hi[::-1]], np.zeros(80, int),
                            grid=grid, lo=np.interp(grid, v, lo), hi=np.interp(grid, v, hi),
                            count=np.where(grid < 7.7, 2, 0), cusps=[(7.7, 1.13)],
                            parameter="base.pitching", units="rad/s", H=16)
    ax, ax2 = fig.axes
    assert ax2.get_xlabel() == r"pitching rate $\omega_{by}$ [rad/s]"
    assert "Omega~" not in ax.get_ylabel() + ax2.get_ylabel() + ax.get_title()
    assert not legends_over_panels(fig)


def test_island_threshold_scales_with_the_grid():
    """A 5-point unstable patch is a zone on a coarse 29 x 21 grid (it would be called an
    island with a fixed 10-point threshold) and an island on a 100 x 100 grid."""
    from rotorsfd.plots.chart import unstable_regions

    for shape, island in (((29, 21), False), ((100, 100), True)):
        m = np.full(shape, 0.9)
        m[3:8, 4] = 1.2                      # 5 unstable points in a row
        (region,) = unstable_regions(np.arange(shape[0]), np.arange(shape[1]), m)
        assert region.n_points == 5 and region.is_island is island
