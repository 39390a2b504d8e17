"""Every analysis takes a dual-spool config (issue 20 items 3 and 5): modal against either
spool, the two-frequency response, simulate, bifurcation-diagram and sweep with each
shaft's unbalance at its own speed; bad input exits 2 with one line; no NaN in results."""

from __future__ import annotations

import csv
import math
from pathlib import Path

import numpy as np
import pytest

from rotorsfd import cli

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "dual_spool_unbalance.toml"


#: a short branch through 150 ... 152 rad/s in 4 points (about 2 s CPU)
SHORT = ("analysis.response.speed_range.start=150 rad/s",
         "analysis.response.speed_range.stop=152 rad/s",
         "analysis.response.step_initial=0.3", "analysis.response.step_max=0.5")


def _rows(path: Path) -> list[dict[str, str]]:
    with path.open() as fh:
        return list(csv.DictReader(fh))


def _no_nan(rows: list[dict[str, str]]) -> None:
    for row in rows:
        for key, value in row.items():
            assert value.lower() not in ("nan", "inf", "-inf"), (key, value)


def test_modal_against_either_spool(tmp_path: Path) -> None:
    """The critical speeds of each spool's unbalance; against the HP spool the same
    criticals at 1.8 times the speed (the view's own check is the closed form in
    test_dual_spool_linear)."""
    assert cli.main(["modal", str(EXAMPLE), "-o", str(tmp_path / "lp"), "-q"]) == 0
    assert cli.main(["modal", str(EXAMPLE), "-o", str(tmp_path / "hp"), "-q",
                     "--set", "analysis.modal.spool=hp"]) == 0
    lp, hp = (_rows(tmp_path / k / "critical_speeds.csv") for k in ("lp", "hp"))
    assert [r["line"] for r in lp] == ["hp", "lp", "hp", "lp"]   # n_critical = 2 per line
    assert float(lp[0]["speed_rad_s"]) == pytest.approx(157.67, abs=0.01)
    assert float(lp[1]["speed_rad_s"]) == pytest.approx(297.81, abs=0.01)
    for a, b in zip(lp, hp, strict=True):
        assert a["line"] == b["line"]
        assert float(b["speed_rad_s"]) == pytest.approx(float(a["speed_rad_s"]), rel=1e-7)
        assert float(b["spool_speed_rad_s"]) == pytest.approx(1.8 * float(a["speed_rad_s"]),
                                                              rel=1e-7)
    camp = _rows(tmp_path / "hp" / "campbell.csv")
    _no_nan(camp)
    assert (tmp_path / "hp" / "campbell.png").stat().st_size > 10_000


def test_response_is_the_two_frequency_branch() -> None:
    from rotorsfd.analyses.dual_spool_response import DualSpoolResponseResult
    from rotorsfd.api import run_response
    from rotorsfd.io.config import load_config

    config = load_config(EXAMPLE, overrides=SHORT)
    result = run_response(config, progress=False)
    assert isinstance(result, DualSpoolResponseResult)
    b = result.branch
    assert b.n_points == 4 and result.success and result.ratio == 1.8
    np.testing.assert_allclose(b.wb, 1.8 * b.omega, rtol=1e-14)
    table = result.table()
    for key, col in table.items():
        if key not in ("lyapunov_per_period", "lyapunov_uncertainty", "stable"):
            assert np.all(np.isfinite(np.asarray(col, dtype=float))), key
    assert "Omega_HP = 1.8 Omega_LP" in result.summary()
    assert result.lyapunov and all(ly.stable for ly in result.lyapunov.values())


@pytest.mark.slow    # about 10 s CPU: the response and simulate commands end to end
def test_commands_write_finite_results(tmp_path: Path) -> None:
    short = [a for item in SHORT for a in ("--set", item)]
    assert cli.main(["response", str(EXAMPLE), "-o", str(tmp_path / "r"), "-q", *short]) == 0
    rows = _rows(tmp_path / "r" / "torus.csv")
    assert len(rows) == 4
    _no_nan(rows)
    assert float(rows[0]["hp_speed_rad_s"]) == pytest.approx(1.8 * float(rows[0]["speed_rad_s"]))
    assert (tmp_path / "r" / "dual_spool_response.png").exists()
    sim = ["--set", "analysis.simulate.speed=160 rad/s", "--set", "analysis.simulate.periods=300",
           "--set", "analysis.simulate.poincare_periods=100",
           "--set", "analysis.simulate.steps_per_period=200"]
    assert cli.main(["simulate", str(EXAMPLE), "-o", str(tmp_path / "s"), "-q", *sim]) == 0
    import json

    summary = json.loads((tmp_path / "s" / "summary.json").read_text())
    ratios = summary["evidence"]["frequency_ratios"]      # the HP line 1.8 X is there
    assert any(abs(v - 1.8) < 1e-6 for v in ratios) and any(abs(v - 1.0) < 1e-6 for v in ratios)
    assert summary["motion"] == "period-5"                 # r = 9/5: periodic over 5 T_LP
    for v in summary["evidence"].values():
        assert not (isinstance(v, float) and not math.isfinite(v))


@pytest.mark.parametrize(("args", "match"), [
    (["modal", "--set", "analysis.modal.spool=ip"], "analysis.modal.spool: got 'ip'"),
    (["response", "--set", "analysis.response.parameter=unbalance.0.magnitude",
      "--set", "analysis.response.speed=150 rad/s"], "analysis.response.parameter"),
    (["response", "--set", 'base.z={law = "harmonic", frequency = "50 rad/s", '
      'amplitude = "1 mm"}'], "base: got 'harmonic'"),
    (["response", "--set", "unbalance.1.node=3"], None),   # both on the LP: periodic HB
])
def test_bad_input_exits_2_with_one_line(args, match, tmp_path: Path, capsys) -> None:
    argv = [args[0], str(EXAMPLE), "-o", str(tmp_path / "out"), "-q", *args[1:]]
    if match is None:                         # not bad: a single-frequency response
        argv += ["--set", "analysis.response.speed_range.start=150 rad/s",
                 "--set", "analysis.response.speed_range.stop=151 rad/s",
                 "--set", "analysis.response.max_points=3", "--set", "analysis.stability."
                 "enabled=false", "--set", "analysis.response.harmonics=3"]
        assert cli.main(argv) in (0, 1)        # 1: the branch stopped at max_points
        assert (tmp_path / "out" / "branch.csv").exists()
        return
    assert cli.main(argv) == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert len(err) == 1 and match in err[0], err


def test_three_speeds_are_refused(tmp_path: Path) -> None:
    from rotorsfd.errors import ConfigError
    from rotorsfd.io.config import config_from_dict, read_config

    raw = read_config(EXAMPLE)
    third = dict(name="ip", speed_ratio=1.3, x_start="0.45 m",
                 sections=raw["rotor"]["shafts"][1]["sections"])
    raw["rotor"]["shafts"].append(third)
    raw["unbalance"].append(dict(node=20, magnitude="10 g*mm"))
    with pytest.raises(ConfigError, match="two speeds"):
        config_from_dict(raw)
