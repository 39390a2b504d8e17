"""The report generator: rows beside the paper's, report.md and a self-contained
report.html from a small set of outcomes (no computation)."""

from __future__ import annotations

import base64
import io
import json

import numpy as np
from matplotlib.figure import Figure

from rotorsfd.cli import main
from rotorsfd.paper.cases import FIGURES
from rotorsfd.paper.figures import draw
from rotorsfd.paper.report import comparison_rows, write_report
from rotorsfd.paper.run import Outcome


def _response(name, bifs, success=True):
    s = np.linspace(0.5, 1.6, 50)
    data = {"speed_ratio": s, "defl_1": np.exp(-(s - 1.05) ** 2 * 40),
            "defl_8": np.exp(-(s - 1.05) ** 2 * 40) * 1.5, "stable": np.ones(50, bool),
            "bifurcations": [{"type": t, "speed_ratio": x, "max_multiplier": m}
                             for t, x, m, *_ in bifs], "H": 3, "clearance": 1.27e-4,
            "nodes": [1, 8], "orbits": []}
    for n in (1, 8):
        data[f"static_{n}_y"] = np.zeros(50)
        for k in (1, 2, 3):
            data[f"amp_{n}_y_h{k}"] = data[f"defl_{n}"] * 1.27e-4 / k ** 3
    numbers = {"bifurcations": bifs, "success": success, "end": "reached Omega~ = 1.6000",
               "peak_ratio": 1.05, "dominant": "1X"}
    sn = sorted(b[1] for b in bifs if b[0] == "saddle-node")
    if sn:
        numbers.update(sn_hi=sn[-1], sn_lo=sn[0], sn_hi_mu=1.013, sn_lo_mu=1.0145)
    return Outcome(name, "ok", "", 1.0, numbers, data)


def _outcomes():
    return {"modal": Outcome("modal", "ok", "", 1.0, {"crit1": 811.3, "crit2": 2784.6}),
            "fig7-u72": _response("fig7-u72", []),
            "fig7-u144": _response("fig7-u144", [
                ("saddle-node", 1.0593460, 1.01304, 1.01304, 0.0),
                ("saddle-node", 1.0526554, 1.01453, 1.01453, 0.0)]),
            "fig7-u360": _response("fig7-u360", [
                ("secondary-hopf", 1.2881, 1.00004, 0.988, 0.155)], success=False)}


def test_rows_beside_the_paper():
    rows = {r.quantity: r for r in comparison_rows(_outcomes())}
    r = rows["U = 144.02: upper saddle-node Omega~"]
    assert (r.paper, r.ours, r.verdict) == ("1.0565", "1.0593", "agrees")
    assert r.difference.startswith("+0.002846")
    assert rows["U = 72.008: bifurcations"].verdict == "agrees"
    assert rows["U = 360.04: upper saddle-node Omega~"].verdict == "differs"
    assert rows["1st forward critical speed [rad/s]"].verdict == "fitted"
    # the calibrated reading did not run: its columns say so
    assert (r.calibrated, r.cal_verdict) == ("not run", "not run")


def _calibrated(outcomes):
    """The outcomes of both readings: the calibrated U = 360.04 case folds."""
    out = dict(outcomes)
    out["cal-fig7-u360"] = _response("cal-fig7-u360", [
        ("saddle-node", 1.28218, 1.0072, 1.0072, 0.0),
        ("saddle-node", 1.11505, 1.0709, 1.0709, 0.0)])
    out["cal-fig7-u144"] = _response("cal-fig7-u144", [
        ("saddle-node", 1.0542, 1.0088, 1.0088, 0.0),
        ("saddle-node", 1.0513, 1.0068, 1.0068, 0.0)])
    return out


def test_rows_of_both_readings_fitted_and_predicted():
    rows = {r.quantity: r for r in comparison_rows(_calibrated(_outcomes()))}
    up = rows["U = 360.04: upper saddle-node Omega~"]
    assert (up.verdict, up.calibrated, up.cal_verdict) == ("differs", "1.2822", "fitted")
    lo = rows["U = 360.04: lower saddle-node Omega~"]       # a prediction: -0.84 %
    assert (lo.calibrated, lo.cal_verdict) == ("1.1151", "differs")
    assert lo.cal_difference.startswith("-0.00945")
    u144 = rows["U = 144.02: upper saddle-node Omega~"]
    assert (u144.ours, u144.calibrated, u144.cal_verdict) == ("1.0593", "1.0542", "agrees")
    pair = rows["U = 360.04: bifurcations of our branch"]
    assert (pair.verdict, pair.cal_verdict) == ("differs", "agrees")
    # the critical speeds: the calibrated modal case did not run
    assert rows["1st forward critical speed [rad/s]"].cal_verdict == "not run"


def test_report_of_both_readings(tmp_path):
    write_report(tmp_path, _calibrated(_outcomes()), {}, elapsed=1.0)
    md = (tmp_path / "report.md").read_text()
    assert "| paper | literal | difference | verdict | calibrated | difference | verdict |" in md
    assert "Calibrated reading:" in md and "**Calibrated**" in md
    assert ("| Table 1 | U = 360.04: lower saddle-node Omega~ | 1.1245 | none [reached "
            "Omega~ = 1.6000] | no such point | differs | 1.1151 | -0.00945" in md)
    # literal only: no calibrated columns
    write_report(tmp_path, _outcomes(), {}, elapsed=1.0)
    md = (tmp_path / "report.md").read_text()
    assert "| paper | literal | difference | verdict |\n" in md and "**Calibrated**" not in md


def test_write_report(tmp_path):
    outcomes = _outcomes()
    fig = draw(FIGURES["7"], outcomes)
    assert isinstance(fig, Figure)
    buf = io.BytesIO()
    fig.savefig(buf, format="png", dpi=50)
    paths = write_report(tmp_path, outcomes, {"7": buf.getvalue()}, elapsed=1.0)
    md = (tmp_path / "report.md").read_text()
    assert "| Table 1 | U = 144.02: upper saddle-node Omega~ | 1.0565 | 1.0593 |" in md
    assert "## Where we differ from the paper" in md and "![Figure 7](fig7.png)" in md
    page = (tmp_path / "report.html").read_text()
    assert "<table>" in page and "<td>1.0565</td>" in page
    b64 = base64.b64encode(buf.getvalue()).decode()
    assert f"data:image/png;base64,{b64}" in page and "fig7.png" not in page.split("<img")[1]
    data = json.loads((tmp_path / "results.json").read_text())
    assert data["cases"]["fig7-u144"]["numbers"]["sn_hi"] == 1.059346
    assert {"fig7.png", "report.md", "report.html", "results.json"} <= set(paths)
    assert not list(tmp_path.glob("*.tmp*"))


def test_cli_unknown_figure(tmp_path, capsys):
    assert main(["paper", "-o", str(tmp_path), "--figure", "99", "-q"]) == 2
    assert "no figure 99" in capsys.readouterr().err


def test_missing_width_says_why_not_nan():
    why = "no fold pair, stopped at Omega~ = 1.3121, eps = 0.995"
    outcomes = {"fig19-u360": Outcome("fig19-u360", "ok", "", 1.0,
                                      {"width0": None, "width10": 0.1, "width0_why": why,
                                       "end_rate": None, "notes": []})}
    rows = {r.quantity: r for r in comparison_rows(outcomes)}
    r0 = rows["U = 360.04: unstable width at w_by = 0"]
    assert r0.ours == f"none [{why}]" and r0.verdict == "differs"
    r10 = rows["U = 360.04: unstable width at w_by = 10"]
    assert r10.ours == "0.1" and "nan" not in r10.difference


def test_cusp_above_the_paper_rate_differs():
    """The paper has no fold pair from 4 rad/s on (U = 144.02 g mm): a cusp above 4 rad/s
    means our model is still bistable there, which is a difference, not a grid effect."""
    def rows(end, width4):
        o = Outcome("fig19-u144", "ok", "", 1.0,
                    {"end_rate": end, "width0": 0.0067, "width10": 0.0, "width4": width4})
        return {r.quantity: r for r in comparison_rows({"fig19-u144": o})}

    r = rows(4.379, 7e-4)
    end = r["U = 144.02: no unstable range from w_by [rad/s]"]
    assert (end.ours, end.difference, end.verdict) == ("4.3790", "+0.379 rad/s", "differs")
    w4 = r["U = 144.02: unstable width at w_by = 4"]
    assert (w4.ours, w4.verdict) == ("0.0007", "differs")
    r = rows(3.2, 0.0)
    assert r["U = 144.02: no unstable range from w_by [rad/s]"].verdict == "agrees"
    assert r["U = 144.02: unstable width at w_by = 4"].verdict == "agrees"


def test_time_domain_rows_name_the_step_and_the_eccentricities():
    numbers = {"motion": "period-1", "steps_per_period": 800, "poincare_y": 0.29491,
               "poincare_z": -0.81721, "eps_poincare": 0.86880, "eps_max": 0.98834,
               "step_check": 0.0022}
    iso = {"find_motion": "period-1", "second_motion": "period-1",
           "motion_1.062": "period-3", "motion_1.07_T200": "quasi-periodic",
           "lyapunov_1.07_T200": -0.0038, "second_steps_per_period": 800,
           "second_poincare_y": -0.2262, "second_poincare_z": -0.9022,
           "second_eps_poincare": 0.9301, "second_eps_max": 0.9930, "bifurcations": []}
    outcomes = {"fig23-s1.075": Outcome("fig23-s1.075", "ok", "", 1.0, numbers),
                "fig23-isola": Outcome("fig23-isola", "ok", "", 1.0, iso)}
    rows = {(r.section, r.quantity): r for r in comparison_rows(outcomes)}
    r = rows[("Figure 23 (T/800)", "Omega~ = 1.075")]
    assert (r.paper, r.ours, r.verdict) == ("quasi-periodic", "period-1", "differs")
    r = rows[("Figure 23 (T/800)", "Omega~ = 1.075: journal at the Poincare point "
              "(main branch)")]
    assert r.ours == ("(+0.2949, -0.8172) C at T/800; eps there 0.8688, max over the orbit "
                      "0.9883; halving the step moves the orbit 0.0022 C")
    r = rows[("Figure 23 (T/800)", "the second attractor: journal at the Poincare point")]
    assert r.ours.startswith("(-0.2262, -0.9022) C at T/800; eps there 0.9301")
    assert rows[("Figure 23 (T/800)", "isola: Omega~ = 1.062 (from the previous state)")
                ].ours == "period-3"
    r = rows[("Figure 23 (T/200)", "isola: Omega~ = 1.07 (from the previous state)")]
    assert (r.ours, r.verdict) == ("quasi-periodic (Lyapunov -0.0038/period)", "agrees")
    assert rows[("Figure 23 (T/800)", "Omega~ = 1.075 started on the isola's HB orbit")
                ].ours == "period-1"
