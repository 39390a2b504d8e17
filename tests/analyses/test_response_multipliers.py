"""The Floquet multipliers of one response point against the unit circle (issue 6 item 4):
the figure has the unit circle and one marker per stored multiplier of that point (the
zero padding left out), the critical one highlighted; ``write`` puts ``multipliers.png``
at the point of largest |mu|max or the one nearest ``--multipliers-at``."""

from __future__ import annotations

import numpy as np
import pytest

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.cli import main

PNG = b"\x89PNG\r\n\x1a\n"


@pytest.fixture(scope="module")
def result(tmp_path_factory):
    tmp = tmp_path_factory.mktemp("multipliers")
    config = api.load_config(small_rotor_toml(tmp / "small.toml"),
                             ["analysis.response.speed_range.stop_ratio=1.2"])
    return api.run_response(config, progress=False)


def _markers(fig):
    """(unit circle line, [multiplier marker lines], critical marker line)."""
    lines = {ln.get_gid(): ln for ln in fig.axes[0].get_lines() if ln.get_gid()}
    return lines["unit-circle"], lines["multipliers"], lines["critical"]


def test_stored_with_counts(result):
    assert result.multipliers is not None and result.max_multiplier is not None
    counts = result.multiplier_counts
    assert counts.shape == (result.branch.n_points,)
    assert (counts >= 1).all() and counts.max() <= result.multipliers.shape[1]
    i = int(np.argmax(counts))
    mu = result.point_multipliers(i)
    assert mu.size == counts[i]
    assert np.abs(mu).max() == pytest.approx(result.max_multiplier[i], rel=1e-12)


def test_figure_circle_and_one_marker_per_multiplier(result):
    i = result.branch.n_points // 2
    fig = result.plot_multipliers(index=i)
    circle, others, critical = _markers(fig)
    x, y = circle.get_xdata(), circle.get_ydata()
    np.testing.assert_allclose(np.hypot(x, y), 1.0, rtol=1e-12)
    assert x.size > 100
    n = int(result.multiplier_counts[i])
    assert len(others.get_xdata()) + len(critical.get_xdata()) == n
    mu = result.point_multipliers(i)
    crit = complex(critical.get_xdata()[0], critical.get_ydata()[0])
    assert abs(crit) == pytest.approx(np.abs(mu).max(), rel=1e-12)
    assert f"{result.max_multiplier[i]:.5f}" in fig.axes[0].get_title()
    ratio = result.speeds[i] / result.reference_speed
    assert rf"$\tilde\Omega$ = {ratio:.5g}" in fig.axes[0].get_title()


def test_default_point_is_largest_and_speed_ratio_picks_nearest(result):
    assert result.point_index() == int(np.argmax(result.max_multiplier))
    ratios = result.speeds / result.reference_speed
    for target in (0.6, 0.87, 1.05, 1.2, 3.0):
        j = result.point_index(speed_ratio=target)
        assert abs(ratios[j] - target) == pytest.approx(np.abs(ratios - target).min())
    j = result.point_index(speed_ratio=1.05)
    assert f"(point {j})" in result.plot_multipliers(speed_ratio=1.05).axes[0].get_title()
    with pytest.raises(ValueError, match="not"):
        result.plot_multipliers(index=0, speed_ratio=1.0)


def test_padding_left_out():
    """Rows zero-padded to the widest: the markers of a point are its count only."""
    from rotorsfd.plots.response import plot_multipliers

    mu = np.array([0.9 + 0.3j, 0.9 - 0.3j, 1.02, -0.4, 0.0, 0.0])
    fig = plot_multipliers(mu[:4], where="Omega~ = 1")
    _, others, critical = _markers(fig)
    assert len(others.get_xdata()) == 3
    assert (critical.get_xdata()[0], critical.get_ydata()[0]) == (1.02, 0.0)
    assert r"= 1.02000" in fig.axes[0].get_title()


def test_counts_from_branch_stability_drop_padding(result):
    n = result.branch.n_points
    mu = np.zeros((n, 4), complex)
    mu[:, :2] = [0.5, 0.2j]
    mu[0, 2] = 1.1
    padded = result.with_stability(np.ones(n, bool), np.abs(mu).max(1), mu)
    padded.info = {"n_multipliers": np.r_[3, np.full(n - 1, 2)]}
    assert padded.point_multipliers(0).size == 3
    assert padded.point_multipliers(1).size == 2
    _, others, critical = _markers(padded.plot_multipliers())
    assert len(others.get_xdata()) == 2 and critical.get_xdata()[0] == 1.1


def test_write_puts_multipliers_png(result, tmp_path):
    paths = result.write(tmp_path / "out")
    assert paths["multipliers.png"].read_bytes()[:8] == PNG
    none = result.with_stability(result.stable, result.max_multiplier)
    none.multipliers = None
    assert "multipliers.png" not in none.write(tmp_path / "none")


def test_cli_multipliers_at(tmp_path):
    config = small_rotor_toml(tmp_path / "small.toml")
    out = tmp_path / "cli"
    status = main(["response", str(config), "-o", str(out), "--quiet",
                   "--set", "analysis.response.speed_range.stop_ratio=0.8",
                   "--multipliers-at", "0.7"])
    assert status == 0
    assert (out / "multipliers.png").read_bytes()[:8] == PNG
