"""Calibration (rotorsfd.analyses.calibrate): fields recovered from computed targets, the
exact critical-speed derivatives against finite differences, the covariance, bad input."""

import tomllib

import numpy as np
import pytest

from rotors import two_support_rotor_text
from rotorsfd import api
from rotorsfd.analyses.calibrate import (
    check_problem,
    covariance,
    parse_fit,
    parse_target,
    run_calibration,
)
from rotorsfd.analyses.calibrate_model import TargetModel
from rotorsfd.analyses.modal import linear_system
from rotorsfd.errors import ConfigError
from rotorsfd.io.config import config_from_dict
from rotorsfd.linear import critical_speeds

SMALL = two_support_rotor_text(disk_node=2, critical_speed_max="6000 rad/s", n_critical=2)
FIELDS = ("rotor.supports[0].stiffness", "rotor.supports[1].stiffness")
TRUTH = (3.0e7, 2.0e7)


@pytest.fixture()
def small(tmp_path):
    path = tmp_path / "small.toml"
    path.write_text(SMALL)
    return api.load_config(path)


def true_speeds(config, values, n=2):
    """The critical speeds of the rotor with ``values`` by the bracketing search (brentq),
    independent of the Newton tracking and the eigen-derivatives of the fit."""
    from rotorsfd.io.config import with_values

    system = linear_system(with_values(config, dict(zip(FIELDS, values, strict=True))))
    return [c.speed_rad_s for c in critical_speeds(system, n=n, speed_range=(0.0, 6000.0),
                                                   xtol=1e-12)]


def test_recovers_two_support_stiffnesses(small):
    speeds = true_speeds(small, TRUTH)
    targets = [parse_target(f"critical_speed[{i + 1}]={s!r}") for i, s in enumerate(speeds)]
    fields = [parse_fit(small, f) for f in FIELDS]          # start 1e7 each
    result = run_calibration(small, fields, targets)
    assert result.success
    np.testing.assert_allclose(result.values, TRUTH, rtol=1e-6)
    np.testing.assert_allclose(result.computed, speeds, rtol=1e-10)
    assert result.derivative_kinds == ["exact (eigen-derivative)"] * 2
    assert result.covariance is None and "not estimated" in result.covariance_basis
    from rotorsfd.io.config import get_path
    assert get_path(result.config, FIELDS[1]) == pytest.approx(TRUTH[1], rel=1e-6)


def test_exact_jacobian_matches_finite_differences(small):
    fields = [parse_fit(small, f) for f in FIELDS]
    targets = [parse_target("critical_speed[1]=1"), parse_target("critical_speed[2]=1")]
    model = TargetModel(small, fields, targets)
    p = np.array(TRUTH)
    jac = model.jacobian(p)
    fd = np.empty_like(jac)
    for j in range(2):
        h = 1e-4 * p[j]
        hi, lo = p.copy(), p.copy()
        hi[j] += h
        lo[j] -= h
        fd[:, j] = (np.array(true_speeds(small, hi)) - true_speeds(small, lo)) / (2 * h)
    np.testing.assert_allclose(jac, fd, rtol=1e-5)
    assert np.all(jac > 0)      # a stiffer support raises every critical speed


def test_overdetermined_fit_with_tolerances_gives_covariance(small):
    """Three critical speeds (tolerances 1 rad/s) fix two stiffnesses: the fit returns
    the truth and cov = (J_w^T J_w)^-1 scales with the tolerance squared."""
    speeds = true_speeds(small, TRUTH, n=3)
    fields = [parse_fit(small, f) for f in FIELDS]
    targets = [parse_target(f"critical_speed[{i + 1}]={s!r}+-1.0")
               for i, s in enumerate(speeds)]
    result = run_calibration(small, fields, targets)
    np.testing.assert_allclose(result.values, TRUTH, rtol=1e-6)
    assert result.covariance is not None and "tolerances" in result.covariance_basis
    jw = result.jacobian
    np.testing.assert_allclose(result.covariance, np.linalg.inv(jw.T @ jw), rtol=1e-10)
    twice = [parse_target(f"critical_speed[{i + 1}]={s!r}+-2.0") for i, s in enumerate(speeds)]
    cov2, _ = covariance(jw / 2.0, np.zeros(3), twice)
    np.testing.assert_allclose(cov2, 4.0 * result.covariance, rtol=1e-10)
    assert np.all(result.standard_errors > 0)


def test_residual_variance_without_tolerances():
    jac = np.array([[1.0], [1.0], [1.0]])
    r = np.array([1.0, -1.0, 0.0])
    targets = [parse_target(f"critical_speed[{i}]=100") for i in (1, 2, 3)]
    cov, basis = covariance(jac, r, targets)
    # the mean of three measurements: variance s^2 / 3 with s^2 = sum r^2 / (3 - 1) = 1
    assert cov[0, 0] == pytest.approx(1.0 / 3.0)
    assert "residual variance" in basis


def test_more_fields_than_targets_is_refused(small):
    fields = [parse_fit(small, f) for f in FIELDS]
    with pytest.raises(ConfigError, match="more fields than targets"):
        check_problem(fields, [parse_target("critical_speed[1]=800")])


@pytest.mark.parametrize("text, words", [
    ("critical_speed[0]=800", "numbered from 1"),
    ("critical_speed[x]=800", "positive integer"),
    ("mode_speed[1]=800", "kind must be one of"),
    ("critical_speed[1]", "expected KIND"),
    ("critical_speed[1]=3 mm", "expected"),
    ("fold_speed[middle]=1000", "fold_speed[lower]"),
    ("critical_speed[1]=800+-0", "tolerance must be positive"),
])
def test_bad_targets(text, words):
    with pytest.raises(ConfigError) as exc:
        parse_target(text)
    assert words in str(exc.value) and "\n" not in str(exc.value)


def test_target_units_and_fit_bounds(small):
    t = parse_target("critical_speed[2]=7747 rpm +- 10 rpm")
    assert t.value == pytest.approx(7747 * np.pi / 30) and t.tolerance == pytest.approx(
        10 * np.pi / 30)
    f = parse_fit(small, "rotor.supports[1].stiffness=1 MN/m:0.1 GN/m")
    assert (f.lower, f.upper, f.start) == pytest.approx((1e6, 1e8, 1e7))
    with pytest.raises(ConfigError, match="names no config field"):
        parse_fit(small, "rotor.supports[7].stiffness")
    with pytest.raises(ConfigError, match="does not accept a value there"):
        parse_fit(small, "rotor.damping.ratio=0:0.01")    # damping kind 'none'
    assert parse_fit(config_from_dict({**tomllib.loads(SMALL), "rotor": {
        **tomllib.loads(SMALL)["rotor"], "damping": {"kind": "modal", "ratio": 0.0}}}),
        "rotor.damping.ratio=0:0.01").start == 0.0      # its value, on the bound
    with pytest.raises(ConfigError, match="lower bound"):
        parse_fit(small, "rotor.supports[1].stiffness=1e8:1e6")


@pytest.mark.slow
def test_paper_rotor_supports_recovered():
    """The paper rotor with both fitted stiffnesses perturbed (x0.5, x2): the fit to its
    two critical speeds returns them to 1e-6."""
    config = api.load_config("examples/paper_rotor.toml")
    from rotorsfd.io.config import get_path
    paths = ["elements.sfd.centring_stiffness", "rotor.supports[0].stiffness"]
    truth = [get_path(config, p) for p in paths]
    speeds = [c.speed_rad_s for c in critical_speeds(
        linear_system(config), n=2, speed_range=(0.0, 4000.0), xtol=1e-12)]
    moved = api.load_config("examples/paper_rotor.toml", [
        f"{paths[0]}={0.5 * truth[0]}", f"{paths[1]}={2.0 * truth[1]}"])
    result = run_calibration(moved, [parse_fit(moved, p) for p in paths],
                             [parse_target(f"critical_speed[{i + 1}]={s!r}")
                              for i, s in enumerate(speeds)])
    np.testing.assert_allclose(result.values, truth, rtol=1e-6)


@pytest.mark.slow
def test_exact_fold_derivative_matches_finite_differences():
    """dOmega_fold/dU from the fold-augmented system = central differences of the
    located folds of rebuilt branches (paper rotor, U = 144.02 g mm, H = 3)."""
    config = api.load_config("examples/paper_rotor.toml", [
        "unbalance[0].magnitude=144.02 g*mm", "analysis.response.speed_range.start_ratio=1.0",
        "analysis.response.speed_range.stop_ratio=1.1"])
    fields = [parse_fit(config, "unbalance[0].magnitude")]
    targets = [parse_target("fold_speed[lower]=1"), parse_target("fold_speed[upper]=1")]
    model = TargetModel(config, fields, targets)
    assert model.derivative_kinds() == ["exact (fold-augmented system)"] * 2
    p = np.array([144.02e-6])
    exact = model.jacobian(p)
    h = 1e-4 * p[0]
    fd = (model.response_values(p + h) - model.response_values(p - h)) / (2 * h)
    np.testing.assert_allclose(exact[:, 0], fd, rtol=1e-6)
    assert exact[1, 0] > exact[0, 0] > 0      # the bistable range widens with U


@pytest.mark.slow
def test_unbalance_recovered_from_fold_speed_and_peak():
    """Paper rotor, H = 3, Omega~ 0.9..1.2: the unbalance 144.02 g mm recovered from the
    upper saddle-node speed (exact derivative) and the disk's peak amplitude of its own
    branch (finite differences), starting at 130 g mm; the folds are the known 1.0527 / 1.0593."""
    sets = ["analysis.response.speed_range.start_ratio=0.9",
            "analysis.response.speed_range.stop_ratio=1.2"]
    truth = api.load_config("examples/paper_rotor.toml",
                            [*sets, "unbalance[0].magnitude=144.02 g*mm"])
    fields = [parse_fit(truth, "unbalance[0].magnitude=100 g*mm:200 g*mm")]
    model = TargetModel(truth, fields, [parse_target("fold_speed[lower]=1"),
                                        parse_target("fold_speed[upper]=1"),
                                        parse_target("peak_amplitude[8]=1")])
    lower, upper, peak = model.values([144.02e-6])
    np.testing.assert_allclose([lower / 811.3, upper / 811.3], [1.0527, 1.0593], atol=1e-4)
    start = api.load_config("examples/paper_rotor.toml",
                            [*sets, "unbalance[0].magnitude=130 g*mm"])
    result = run_calibration(start, [parse_fit(start, "unbalance[0].magnitude=100 g*mm:"
                                                      "200 g*mm")],
                             [parse_target(f"fold_speed[upper]={float(upper)!r}"),
                              parse_target(f"peak_amplitude[8]={float(peak)!r}")])
    assert result.derivative_kinds == ["exact (fold-augmented system)",
                                       "central finite differences"]
    assert result.values[0] == pytest.approx(144.02e-6, rel=1e-6)
    assert result.jacobian[1, 0] > 0      # more unbalance, larger peak


def test_calibrated_paper_example_meets_the_critical_speeds():
    """examples/paper_rotor_calibrated.toml: the literal rotor plus the fitted modal
    damping; its re-fitted stiffnesses give the paper's 811.3 / 2784.6 rad/s (1e-9)."""
    config = api.load_config("examples/paper_rotor_calibrated.toml")
    assert config.rotor.damping.kind == "modal"
    assert config.rotor.damping.ratio == pytest.approx(0.0021972548, rel=1e-7)
    assert config.unbalance[0].magnitude == pytest.approx(360.04e-6)   # extends the rotor
    speeds = [c.speed_rad_s for c in critical_speeds(
        linear_system(config), n=2, speed_range=(0.0, 4000.0), xtol=1e-12)]
    np.testing.assert_allclose(speeds, [811.3, 2784.6], rtol=1e-9)
