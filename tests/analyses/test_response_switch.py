"""``rotorsfd response --switch-at N``: the period-2 branch from the N-th period doubling
(issue 21 item 2).

Fast: the bad inputs (N < 1; no Floquet stability, before the work; a branch with no
period doubling, after the main branch is written), and the period-2 branch's start on
the period doubling of the quadratic-cubic oscillator (its points extrapolated to zero
odd amplitude, lam = lam_pd + c a^2 + ...: 1e-6; measured 1.4e-8).
Slow: the paper case C/R = 0.728 % at H = 12 through the CLI: the same start check on
the written branch_period2.csv and its orbit at Omega~ = 1.04 against the time domain's
period-2 Poincare points (as tests/analyses/test_branch_switching_paper.py, 2e-3 C).
"""

from __future__ import annotations

import csv
from pathlib import Path

import numpy as np
import pytest
from test_branch_stability_switching import oscillator

from rotorsfd import cli
from rotorsfd.harmonic.branch_switching import switch_period_doubling
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.stability.branch_stability import StabilityOptions, branch_stability

ROOT = Path(__file__).parents[2]
PAPER = ROOT / "examples" / "paper_rotor.toml"
CLEARANCE = ROOT / "examples" / "paper_clearance.toml"


def one_error_line(capsys: pytest.CaptureFixture[str]) -> str:
    err = capsys.readouterr().err
    lines = [line for line in err.strip().splitlines() if line.startswith("rotorsfd: error")]
    assert len(lines) == 1 and "Traceback" not in err, err
    return lines[0]


def test_switch_at_must_be_a_positive_integer(tmp_path, capsys):
    status = cli.main(["response", str(PAPER), "-o", str(tmp_path / "o"), "--switch-at",
                       "0"])
    line = one_error_line(capsys)
    assert status == 2 and "--switch-at" in line and "must be >= 1" in line


def test_switch_at_without_stability_stops_before_the_work(tmp_path, capsys, monkeypatch):
    def reached(*a, **k):
        raise AssertionError("the response started")

    monkeypatch.setattr("rotorsfd.api.run_response", reached)
    status = cli.main(["response", str(PAPER), "-o", str(tmp_path / "o"), "--switch-at",
                       "1", "--set", "analysis.stability.enabled=false"])
    line = one_error_line(capsys)
    assert status == 2
    assert "--switch-at" in line and "analysis.stability.enabled" in line


def test_switch_at_on_a_branch_without_period_doubling(tmp_path, capsys):
    out = tmp_path / "o"
    status = cli.main(["response", str(PAPER), "-o", str(out), "-q", "--switch-at", "1",
                       "--set", "analysis.response.speed_range={start_ratio=0.5, "
                       "stop_ratio=0.56}"])
    line = one_error_line(capsys)
    assert status == 2
    assert "--switch-at" in line and "no period-doubling point" in line
    assert (out / "branch.csv").exists() and not (out / "branch_period2.csv").exists()


def extrapolated_start(lam: np.ndarray, odd: np.ndarray, n: int = 3) -> float:
    """lam at zero odd amplitude from the first n points (lam polynomial in odd^2)."""
    return float(np.polyfit(odd[:n] ** 2, lam[:n], n - 1)[-1])


def test_period_two_branch_starts_on_the_period_doubling():
    p = oscillator()
    branch = continue_periodic(p, 1.6, 2.4, 7, ds=0.05, ds_max=0.1)
    pd = branch_stability(branch, p, StabilityOptions(n_intervals=800)).bifurcations[0]
    pt = branch.point_at(pd.s)
    sw = switch_period_doubling(p, pt.lam, pt.X, (1.9, 2.1), delta=0.01, ds_max=0.05)
    assert sw.legs[0].H == 28                                  # 4H harmonics of w/2
    lam0 = extrapolated_start(sw.legs[0].lam, sw.odd_amplitude())
    assert lam0 == pytest.approx(sw.lam_bifurcation, rel=1e-6)    # measured 1.4e-8
    # = the period doubling the monodromy locates on the period-1 branch up to the Newmark
    # step's error (H = 7 orbit: 5.8e-6 at the default 200 intervals, 1.5e-6 at 800)
    assert lam0 == pytest.approx(pd.lam, rel=2e-6)


def read_csv(path: Path) -> dict[str, np.ndarray]:
    with path.open() as f:
        rows = list(csv.DictReader(f))
    return {k: np.array([float(r[k]) if r[k] not in ("True", "False") else r[k] == "True"
                         for r in rows]) for k in rows[0]}


@pytest.mark.slow
def test_cli_period_two_branch_of_the_paper_case(tmp_path, capsys):
    import xarray as xr

    from rotorsfd import api
    from rotorsfd.analyses.simulate import run_simulation

    out = tmp_path / "o"
    status = cli.main(["response", str(CLEARANCE), "-o", str(out), "-q", "--switch-at", "1",
                       "--set", "analysis.response.harmonics=12", "--set",
                       "analysis.response.speed_range={start_ratio=0.98, stop_ratio=1.06}"])
    assert status == 0, capsys.readouterr().err
    for name in ("branch_period2.nc", "branch_period2.csv", "response_deflection.png"):
        assert (out / name).exists()
    tab = read_csv(out / "branch_period2.csv")
    with xr.open_dataset(out / "branch_period2.nc") as ds:
        lam_hb = float(ds.attrs["pd_parameter_hb"])
        H2 = ds.sizes["harmonic"] - 1
        ref = float(ds["speed_rad_s"][0] / ds["speed_ratio"][0])
        X = ds["X_real"].values + 1j * ds["X_imag"].values
    assert H2 == 48                                             # 4 H
    # the branch starts on the period doubling of the period-2 HB equations
    assert extrapolated_start(tab["speed_rad_s"], tab["sub_1"]) == pytest.approx(lam_hb,
                                                                                 rel=1e-6)
    assert abs(lam_hb / ref - 1.0356) < 5e-4                    # the paper test's value
    # a point on it against the time domain's period-2 Poincare points (journal, node 1)
    cfg = api.load_config(str(CLEARANCE), [])
    td = run_simulation(cfg, speed_ratio=1.04, steps_per_period=1600, poincare_periods=20,
                        record_periods=20, lyapunov_periods=0, progress=False)
    assert td.motion_name == "period-2"
    i = int(np.argmin(np.abs(tab["speed_rad_s"] - td.speed)))
    assert abs(tab["speed_rad_s"][i] / td.speed - 1) < 2e-3
    j = td.column(td.element_node)
    pq = td.poincare_q[-2:, j, :]
    C = 0.127e-3
    k = np.arange(H2 + 1)
    w = tab["speed_rad_s"][i]
    t = np.array([0.0, 2 * np.pi / w])
    node1 = X[i][:, :2]                                         # y, z of node 1
    hb = (np.exp(0.5j * w * np.outer(t, k)) @ node1).real
    for q in pq:
        assert np.min(np.linalg.norm(hb - q, axis=1)) / C < 5e-3
