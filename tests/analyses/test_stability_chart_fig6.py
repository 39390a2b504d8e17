"""`rotorsfd stability-chart` on the Figure 6 example: the files, the numbers of a direct
``stability_chart`` call, one-line errors for bad axes, and the three main zones where
parametric-resonance theory puts them (w_b = omega_bw, (omega_bw + omega_fw) / 2,
omega_fw of the base-frame first mode pair at Omega = 250 rad/s)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.linalg as sla

from rotorsfd.analyses.stability_chart import run_stability_chart
from rotorsfd.cli import main
from rotorsfd.io.config import load_config
from rotorsfd.linear.modal import eigen
from rotorsfd.model.base_terms import base_basis
from rotorsfd.model.build import build_rotor
from rotorsfd.stability.chart import LTPSystem, stability_chart

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "fig6_duchemin_pitching.toml"
FREQ = "base.pitching.frequency"
A0 = "base.pitching.angle_amplitude"
SMALL = ["--set", "analysis.stability_chart.intervals=100",
         "--set", f"analysis.stability_chart.x.parameter={A0}",
         "--set", "analysis.stability_chart.x.start=0.1",
         "--set", "analysis.stability_chart.x.stop=0.5",
         "--set", "analysis.stability_chart.x.n=3",
         "--set", f"analysis.stability_chart.y.parameter={FREQ}",
         "--set", "analysis.stability_chart.y.start=240",
         "--set", "analysis.stability_chart.y.stop=310",
         "--set", "analysis.stability_chart.y.n=36"]


def _intervals(x: np.ndarray, unstable: np.ndarray) -> list[tuple[float, float]]:
    edges = np.diff(np.concatenate([[0], unstable.astype(int), [0]]))
    return [(x[i], x[j - 1]) for i, j in zip(np.flatnonzero(edges == 1),
                                               np.flatnonzero(edges == -1), strict=True)]


def test_cli_chart_equals_direct_stability_chart(tmp_path, capsys):
    """The command's chart.nc = stability_chart on an LTPSystem built here by hand:
    K(t) = K - w_by^2 (T22 + P22 - D22), w_by = A0 w_b sin(w_b t), D = C + Omega G."""
    import xarray as xr

    out = tmp_path / "out"
    assert main(["stability-chart", str(EXAMPLE), "-o", str(out), "--quiet",
                 "--workers", "2", *SMALL]) == 0
    assert capsys.readouterr().err == ""
    ds = xr.load_dataset(out / "chart.nc")
    rotor = build_rotor(load_config(EXAMPLE))
    bb = base_basis(rotor)
    Kp = bb.matrix("T22") + bb.matrix("P22") - bb.matrix("D22")
    ltp = LTPSystem(rotor.M, [(rotor.C + 250.0 * rotor.G, None)],
                    [(rotor.K, None), (Kp, lambda t, a, w: -(a * w * np.sin(w * t))**2)],
                    period=lambda a, w: 2 * np.pi / w + 0.0 * a)
    V = sla.eigh(rotor.K, rotor.M, subset_by_index=(0, 3))[1]
    a0, w_b = ds["base_pitching_angle_amplitude"].values, ds["base_pitching_frequency"].values
    direct = stability_chart(ltp, a0, w_b, n_intervals=100, basis=V)
    np.testing.assert_allclose(ds["max_abs_multiplier"].values, direct.max_abs, atol=1e-9)
    assert np.array_equal(ds["stable"].values.astype(bool), direct.stable)
    assert 0 < (~direct.stable).sum() < direct.stable.size
    assert ds["base_pitching_frequency"].attrs["units"] == "rad/s"
    assert ds["base_pitching_angle_amplitude"].attrs["units"] == "rad"
    np.testing.assert_allclose(ds["natural_frequency"].values[:2], [254.08, 301.65],
                               atol=0.01)


def test_cli_writes_files_with_progress(tmp_path, capsys):
    out = tmp_path / "out"
    assert main(["stability-chart", str(EXAMPLE), "-o", str(out), *SMALL]) == 0
    captured = capsys.readouterr()
    assert "stability chart" in captured.err            # the progress bar
    assert "unstable" in captured.out and "chart.nc" in captured.out
    assert sorted(p.name for p in out.iterdir()) == ["chart.nc", "chart.png", "run.json"]
    assert (out / "chart.png").read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize("override, field", [
    ("analysis.stability_chart.y.parameter=base.rolling.frequency", "base.rolling"),
    ("analysis.stability_chart.y={parameter='base.rolling.frequency', values=[1.0, 2.0]}",
     "base.rolling.frequency: got 1.0; not used with law = 'off'"),
    ("analysis.stability_chart.y.parameter=rotor.nothing", "analysis.stability_chart.y"),
    (f"analysis.stability_chart.y.parameter={FREQ}", "analysis.stability_chart.y"),
    ("analysis.stability_chart.x.start=-5", FREQ),
    ("analysis.stability_chart.x.start=0", "analysis.stability_chart.x"),
])
def test_bad_axes_exit_2_with_one_line(tmp_path, capsys, override, field):
    status = main(["stability-chart", str(EXAMPLE), "-o", str(tmp_path / "o"), "--quiet",
                   "--set", override])
    err = capsys.readouterr().err
    assert status == 2
    assert err.count("\n") == 1 and err.startswith("rotorsfd: error:") and field in err
    assert not (tmp_path / "o").exists()


def test_missing_axis_exits_2(tmp_path, capsys):
    text = EXAMPLE.read_text().split("\nx = {")[0]
    (tmp_path / "c.toml").write_text(text)
    assert main(["stability-chart", str(tmp_path / "c.toml"), "-o", str(tmp_path / "o")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "analysis.stability_chart.x" in err


def test_three_main_zones_where_theory_puts_them():
    """A0 -> 0: the zones start at w_b = omega_bw, (omega_bw + omega_fw) / 2, omega_fw
    (2 w_b = omega_i + omega_j); at A0 = 0.05 their centres are within 0.2 rad/s of these
    (the mean softening A0^2 w_b^2 / 2 moves them by ~ -0.1 rad/s). At A0 = 0.3 there are
    exactly three zones on 230..320 rad/s, each moved to lower w_b."""
    config = load_config(EXAMPLE)
    w_bw, w_fw = eigen(build_rotor(config), 250.0, 2).frequencies
    theory = np.array([w_bw, 0.5 * (w_bw + w_fw), w_fw])
    fine = np.concatenate([np.linspace(c - 1.0, c + 0.5, 76) for c in theory])
    low = run_stability_chart(config, x=(A0, [0.05]), y=(FREQ, fine))
    zones = _intervals(fine, ~low.stable[0])
    assert len(zones) == 3
    centres = np.array([0.5 * (a + b) for a, b in zones])
    assert np.abs(centres - theory).max() < 0.2
    coarse = np.linspace(230.0, 320.0, 361)
    high = run_stability_chart(config, x=(A0, [0.3]), y=(FREQ, coarse))
    zones = _intervals(coarse, ~high.stable[0])
    assert len(zones) == 3
    for (a, b), c in zip(zones, centres, strict=True):
        assert b < c and b - a > 1.0      # moved down, wider (~ w A0^2 / 4)


def test_default_modal_basis_matches_the_full_model():
    """The default basis (modes below 3 x 2 w_b: the first two pairs) gives the full
    52-DOF model's max |mu| to 1e-3 at points in and around the zones."""
    config = load_config(EXAMPLE)
    w_b = np.array([246.0, 252.0, 262.0, 272.0, 298.0])
    kw = {"x": (A0, [0.4]), "y": (FREQ, w_b), "n_intervals": 200}
    red = run_stability_chart(config, **kw)
    full = run_stability_chart(config, n_modes=52, **kw)
    assert red.chart.info["n_reduced"] == 4 and full.chart.info["n_reduced"] == 52
    np.testing.assert_allclose(red.chart.max_abs, full.chart.max_abs, atol=1e-3)
    assert np.array_equal(red.stable, full.stable) and not red.stable.all()
