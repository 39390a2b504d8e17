"""report.html reads as a page: paragraphs joined across the source's line breaks, inline
code as code, the symbols as symbols; a quick or single-figure report explains only the
figures that ran; the "second peak" row takes the second peak (issue 24, item 7)."""

from __future__ import annotations

import re

import numpy as np

from rotorsfd.paper.report import DIAGNOSES, comparison_rows, write_report
from rotorsfd.paper.run import Outcome


def _fig7() -> dict[str, Outcome]:
    s = np.linspace(0.5, 1.6, 30)
    data = {"speed_ratio": s, "defl_1": s, "defl_8": s, "stable": np.ones(30, bool),
            "bifurcations": [], "H": 3, "clearance": 1.0}
    numbers = {"bifurcations": [], "success": False,
               "end": "stopped at Omega~ = 1.3121, eps = 0.995"}
    return {"modal": Outcome("modal", "ok", "", 1.0, {"crit1": 811.3, "crit2": 2784.6}),
            **{c: Outcome(c, "ok", "", 1.0, numbers, data)
               for c in ("fig7-u72", "fig7-u144", "fig7-u360")}}


def _page(tmp_path, outcomes) -> tuple[str, str]:
    write_report(tmp_path, outcomes, {}, elapsed=1.0, diagnoses=DIAGNOSES)
    return (tmp_path / "report.md").read_text(), (tmp_path / "report.html").read_text()


def _text(page: str) -> str:
    """The page without its code spans."""
    return re.sub(r"<code>.*?</code>", "", page, flags=re.S)


def test_paragraphs_are_not_broken_per_source_line(tmp_path):
    md, page = _page(tmp_path, _fig7())
    assert "fitted so that the first two forward critical speeds of the\nlinear" in md
    paragraphs = re.findall(r"<p>(.*?)</p>", page, flags=re.S)
    stiff = [p for p in paragraphs if "Support stiffnesses" in p]
    assert len(stiff) == 1 and "changed by" in stiff[0]       # one paragraph, not five
    assert not any(p.startswith("right support") for p in paragraphs)


def test_inline_code_rendered_as_code(tmp_path):
    _, page = _page(tmp_path, _fig7())
    assert "<code>nearest_multiplier_abs</code>" in page
    assert "`" not in page


def test_symbols_rendered(tmp_path):
    _, page = _page(tmp_path, _fig7())
    text = _text(page)
    assert "\u03a9\u0303" in text                                 # Omega~ -> Ω̃
    assert "|\u03bc|<sub>max</sub>" in text
    for ascii_ in ("Omega~", "|mu|max", "w_by"):
        assert ascii_ not in text, ascii_


def test_quick_report_lists_only_the_diagnoses_of_what_ran(tmp_path):
    md, _ = _page(tmp_path, _fig7())
    assert "Journal contact instead of a fold" in md               # U = 360.04 ran
    for other in ("Figure 15, second disk peak", "Table 3 and Figure 23",
                  "Figure 21, C/R = 0.485 %", "Figure 19 widths"):
        assert other not in md, other
    assert "Figure 6 rotor" not in md                              # its chart did not run


def test_single_figure_report_explains_its_figure(tmp_path):
    x = np.linspace(200.0, 340.0, 15)
    y = np.linspace(0.0, 0.5, 11)
    m = np.ones((15, 11))
    m[4:7, 6:] = 1.05                                              # from y[6] = 0.3 up
    chart = Outcome("fig6", "ok", "", 1.0, {"unstable_fraction": 0.1},
                    {"x": x, "y": y, "max_abs": m, "x_label": "base.pitching.frequency "
                     "[rad/s]", "y_label": "base.pitching.angle_amplitude [rad]"})
    md, _ = _page(tmp_path, {"fig6": chart})
    assert "Journal contact instead of a fold" not in md
    assert "Figure 6 rotor" in md
    assert "1 unstable zone down to A0 = 0.3 rad" in md


def _peak_row(peaks):
    o = Outcome("fig12-w9", "partial", "", 1.0,
                {"disk_peaks": peaks, "success": True, "bifurcations": []})
    rows = [r for r in comparison_rows({"fig12-w9": o}) if "second peak" in r.quantity]
    assert len(rows) == 1
    return rows[0]


def test_second_peak_row_takes_the_second_peak():
    r = _peak_row([1.385, 1.43])           # the first peak is nearer 1.40
    assert r.ours == "1.385, 1.430" and r.difference.startswith("+0.03")   # 1.43 - 1.40
    r = _peak_row([1.39])                  # one peak only: no second peak
    assert (r.difference, r.verdict) == ("no second peak", "differs")


def test_local_peaks_finds_a_shoulder_peak_not_a_wiggle():
    """Figure 15 at 9 rad/s: the second disk peak stands 3 % of the main peak above its
    trough (found); a ripple of 1 % crest to trough is not a peak."""
    from rotorsfd.paper.run import local_peaks

    x = np.linspace(0.5, 1.6, 1101)
    main = 0.7 / (1 + ((x - 1.09) / 0.04) ** 2)
    second = 0.035 * np.exp(-((x - 1.39) / 0.05) ** 2)
    peaks = local_peaks(x, main + 0.25 + second - 0.05 * x)
    assert len(peaks) == 2 and abs(peaks[1] - 1.39) < 0.01
    ripple = 0.004 * np.sin(40 * x)              # 0.8 % of the peak, crest to trough
    assert len(local_peaks(x, main + 0.25 + ripple * (x > 1.3))) == 1
