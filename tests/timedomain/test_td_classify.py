"""Motion classification on systems with known answers; spectra; Poincare tools."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.timedomain import (
    Forcing,
    HarmonicLoad,
    amplitude_spectrum,
    classify_motion,
    classify_result,
    closed_curve_test,
    correlation_dimension,
    cubic_spring_kernel,
    integrate,
    largest_lyapunov,
    poincare_period,
    spectral_lines,
)

SPP = 200  # steps per forcing period


def _duffing(c: float, k1: float, k3: float, F: float, w: float, q0: float,
             n_periods: int = 600, keep: int = 200):
    """``x'' + c x' + k1 x + k3 x^3 = F cos(w t)`` (``k1, k3`` in the cubic kernel)."""
    fo = Forcing(omega=w, harmonics=[HarmonicLoad(1.0, np.array([F]))])
    sys_ = (np.eye(1), np.array([[c]]), np.zeros((1, 1)), [0], cubic_spring_kernel,
            [k1, k3], fo)
    r = integrate(*sys_, steps_per_period=SPP, n_periods=n_periods, q0=q0,
                  record_start=(n_periods - keep) * SPP)
    return sys_, r


def _lyapunov(sys_, q0: float):
    return largest_lyapunov(*sys_, steps_per_period=SPP, n_periods=300, q0=q0,
                            transient_steps=100 * SPP)


def test_ueda_oscillator_is_chaotic() -> None:
    """Ueda: ``x'' + 0.05 x' + x^3 = 7.5 cos t``, chaotic (lambda about 0.1 1/s)."""
    sys_, r = _duffing(0.05, 0.0, 1.0, 7.5, 1.0, 0.1)
    ly = _lyapunov(sys_, 0.1)
    assert 0.05 < ly.exponent < 0.2
    mc = classify_result(r, ly)
    assert mc.motion == "chaotic"
    assert mc.evidence["lyapunov_exponent"] == ly.exponent
    assert mc.evidence["n_distinct_poincare"] > 100
    assert classify_result(r).motion == "chaotic"  # spectrum alone agrees


@pytest.mark.parametrize(("F", "expected"), [(0.20, "period-1"), (0.28, "period-2"),
                                             (0.29, "period-4"), (0.35, "period-5")])
def test_double_well_duffing_periodic_windows(F: float, expected: str) -> None:
    """``x'' + 0.3 x' - x + x^3 = F cos(1.2 t)`` from ``x0 = 1``: the period-doubling
    route (period 1, 2, 4) and the period-5 window (Guckenheimer & Holmes)."""
    _, r = _duffing(0.3, -1.0, 1.0, F, 1.2, 1.0)
    mc = classify_result(r)
    assert mc.motion == expected
    n = mc.period
    assert mc.evidence["n_distinct_poincare"] == n
    ratios = np.array(mc.evidence["frequency_ratios"])
    assert np.all(np.abs(ratios * n - np.round(ratios * n)) < 1e-3)  # lines at k/n
    assert np.min(ratios) == pytest.approx(1.0 / n, abs=1e-3)


def test_double_well_duffing_chaotic() -> None:
    """F = 0.5: the Poincare section folds into a thin curve, the Lyapunov exponent is
    positive and decides."""
    sys_, r = _duffing(0.3, -1.0, 1.0, 0.5, 1.2, 1.0)
    ly = _lyapunov(sys_, 1.0)
    assert ly.per_period > 0.2
    assert classify_result(r, ly).motion == "chaotic"


def test_two_frequency_linear_is_quasi_periodic() -> None:
    """Linear 2-DOF forced at ``w`` and ``sqrt(2) w``: a closed curve in the section,
    incommensurate line at ratio sqrt(2), negative Lyapunov exponent."""
    M = np.diag([1.0, 2.0])
    K = np.array([[3.0, -1.0], [-1.0, 2.0]])
    D = 0.05 * K
    fo = Forcing(omega=1.0, harmonics=[HarmonicLoad(1.0, np.array([1.0, 0.0])),
                                       HarmonicLoad(np.sqrt(2.0), np.array([0.0, 1.0]))])
    r = integrate(M, D, K, [], None, None, fo, steps_per_period=SPP, n_periods=600,
                  record_start=400 * SPP, record_dofs=[0, 1])
    mc = classify_result(r)
    assert mc.motion == "quasi-periodic"
    assert mc.evidence["closed_curve"]["passed"]
    assert any(abs(x - np.sqrt(2.0)) < 1e-3 for x in mc.evidence["incommensurate_ratios"])
    assert 0.8 < mc.evidence["correlation_dimension"] < 1.2
    ly = largest_lyapunov(M, D, K, [], None, None, fo, steps_per_period=SPP, n_periods=50)
    assert ly.exponent < 0.0
    mc = classify_result(r, ly)
    assert mc.motion == "quasi-periodic"
    assert mc.evidence["basis"].startswith("non-periodic")


def test_amplitude_spectrum_line_amplitudes_and_ratios() -> None:
    """``0.3 + 2 cos(w t) + 0.5 sin(2.5 w t + 1)``: amplitudes (half peak-to-peak) and
    ratios 1 and 5/2 to ``w``; the DC term excluded after detrending."""
    w, dt = 3.0, 2 * np.pi / 3.0 / 64
    t = dt * np.arange(64 * 100)
    x = 0.3 + 2.0 * np.cos(w * t) + 0.5 * np.sin(2.5 * w * t + 1.0)
    freq, amp = amplitude_spectrum(x, dt)
    k = np.argmin(np.abs(freq - w))
    assert amp[k] == pytest.approx(2.0, rel=1e-6)
    assert amp[0] == pytest.approx(0.3, rel=1e-6)
    spec = spectral_lines(x, dt, w)
    assert [round(ln.ratio, 6) for ln in spec.lines] == [1.0, 2.5]
    assert spec.lines[1].amplitude == pytest.approx(0.5, rel=1e-6)
    assert not spec.incommensurate and spec.broadband_fraction < 1e-6
    # off-bin line: frequency and amplitude refined from the three bins around the peak
    x2 = np.cos(1.2345 * w * t)
    ln = spectral_lines(x2, dt, w).lines[0]
    assert ln.ratio == pytest.approx(1.2345, abs=1e-4)
    assert ln.amplitude == pytest.approx(1.0, rel=2e-2)


def test_poincare_tools() -> None:
    rng = np.random.default_rng(0)
    pts = np.tile(np.array([[0.0, 1.0], [1.0, 0.0], [0.5, 0.5]]), (10, 1))
    assert poincare_period(pts + 1e-6 * rng.normal(size=pts.shape)) == 3
    assert poincare_period(rng.normal(size=(50, 2))) is None
    th = 2 * np.pi * np.sqrt(2) * np.arange(300)
    circle = np.column_stack([np.cos(th), 0.5 * np.sin(th)])
    assert closed_curve_test(circle)["passed"]
    assert not closed_curve_test(rng.normal(size=(300, 2)))["passed"]
    assert correlation_dimension(circle) == pytest.approx(1.0, abs=0.15)
    assert correlation_dimension(rng.uniform(size=(600, 2))) > 1.6
    with pytest.raises(ValueError):
        classify_motion(np.zeros((3, 2)))


@pytest.mark.parametrize(("k1", "k3", "F"), [(1.0, 0.0, 1.0), (-1.0, 1.0, 0.2)])
def test_lyapunov_exponent_of_a_damped_focus_is_minus_half_damping(k1: float, k3: float,
                                                                    F: float) -> None:
    """Linear oscillator and the period-1 double-well Duffing (complex Floquet pair,
    ``|mu|^2 = exp(-c T)``): both exponents are ``-c/2``."""
    c = 0.3
    fo = Forcing(omega=1.2, harmonics=[HarmonicLoad(1.0, np.array([F]))])
    ly = largest_lyapunov(np.eye(1), np.array([[c]]), np.zeros((1, 1)), [0],
                          cubic_spring_kernel, [k1, k3], fo, steps_per_period=SPP,
                          n_periods=200, q0=1.0, transient_steps=100 * SPP)
    assert ly.exponent == pytest.approx(-c / 2, rel=2e-2)


def test_spiral_into_a_point_is_period_1_not_period_3() -> None:
    """Poincare points spiralling into a fixed point, ``P_k = P* + a rho^k e^{i k theta}``
    with theta = 2 pi 0.32 (near 1/3) and rho = 0.99 (a slowly damped complex multiplier):
    over 100 points ``|P[k+3] - P[k]| = a rho^k |rho^3 e^{3 i theta} - 1|`` passes the
    period-3 test at rtol 1e-3, but the differences shrink by rho per period: period-1,
    converging, with the shrink factor measured."""
    k = np.arange(100)
    theta, rho, a = 2 * np.pi * 0.32, 0.99, 2e-3
    z = a * rho ** k * np.exp(1j * theta * k)
    P = np.column_stack([0.5 + z.real, -0.3 + z.imag])
    mc = classify_motion(P, scale=1.0)
    assert mc.motion == "period-1"
    conv = mc.evidence["converging"]
    assert conv["from_period"] == 3 and conv["to_period"] == 1
    assert conv["shrink_per_period"] == pytest.approx(rho, abs=0.01)
    assert "spiralling" in mc.evidence["note"]


def test_true_period_3_cycle_is_not_converging() -> None:
    """Three fixed points 0.05 apart with 1e-6 noise: period-3, no convergence flag."""
    rng = np.random.default_rng(1)
    cycle = np.array([[0.04, -0.90], [0.01, -0.91], [0.009, -0.95]])
    P = np.tile(cycle, (34, 1))[:100] + 1e-6 * rng.normal(size=(100, 2))
    mc = classify_motion(P, scale=1.0)
    assert mc.motion == "period-3" and "converging" not in mc.evidence


def test_torus_near_a_1_7_resonance_is_not_period_7() -> None:
    """Points on a circle turning by 2 pi (1/7 + 1e-5) per period: after 7 periods they
    come back within 1e-3 (of the normalised section) but move on steadily, 100 points
    spreading over 7 arcs: not periodic; with a zero Lyapunov exponent, quasi-periodic."""
    k = np.arange(100)
    ang = 2 * np.pi * (1 / 7 + 1e-5) * k
    P = np.column_stack([np.cos(ang), np.sin(ang)])
    assert poincare_period(P / 2.0) == 7
    mc = classify_motion(P, lyapunov=0.0)
    assert mc.motion == "quasi-periodic"
    assert mc.evidence["near_period"] == 7 and mc.evidence["poincare_period"] is None
    assert "drift on steadily" in mc.evidence["note"]
