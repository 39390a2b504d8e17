"""Stability charts of linear time-periodic systems."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.stability.chart import LTPSystem, stability_chart
from rotorsfd.stability.monodromy import monodromy_newmark


def _mathieu(c: float = 0.0) -> LTPSystem:
    one = np.eye(1)
    return LTPSystem(one, [(c * one, None)],
                     [(one, lambda t, d, e: d + 0.0 * t), (one, lambda t, d, e: e * np.cos(t))],
                     2 * np.pi)


def test_mathieu_chart_matches_transition_curves():
    delta = np.linspace(0.02, 1.45, 40)
    eps = np.linspace(0.05, 0.4, 8)
    ch = stability_chart(_mathieu(), delta, eps, n_intervals=200, names=("delta", "eps"))
    D, E = np.meshgrid(delta, eps, indexing="ij")
    curves = [0.25 - E / 2 - E**2 / 8, 0.25 + E / 2 - E**2 / 8, 1 - E**2 / 12,
              1 + 5 * E**2 / 12, -E**2 / 2]
    unstable = ((D > curves[0]) & (D < curves[1])) | ((D > curves[2]) & (D < curves[3]))
    margin = np.min([np.abs(D - c) for c in curves], axis=0) > 0.01 + E**3
    assert margin.sum() > 250
    assert np.array_equal(~ch.stable[margin], unstable[margin])
    # undamped and stable: the Cayley (trapezoidal) map keeps |mu| = 1
    assert np.all(np.abs(ch.max_abs[ch.stable] - 1.0) < 1e-9)


def test_chart_equals_pointwise_monodromy_and_period_function():
    """Period depending on the parameters, damping term with a coefficient: the batched
    chart equals monodromy_newmark point by point."""
    M = np.diag([1.0, 2.0])
    K0 = np.array([[3.0, -1.0], [-1.0, 2.0]])
    Dg = np.array([[0.0, 0.4], [-0.4, 0.0]])
    Kp = np.array([[1.0, 0.2], [0.2, -0.5]])

    def kc(t, w, a):
        return a * np.cos(w * t)

    def dc(t, w, a):
        return 0.1 + 0.05 * a * np.sin(2 * w * t)

    sys_ = LTPSystem(M, [(np.eye(2), dc), (Dg, None)], [(K0, None), (Kp, kc)],
                     period=lambda w, a: 2 * np.pi / w + 0.0 * a)
    w, a = np.array([1.5, 2.7, 3.3]), np.array([0.0, 0.6, 1.2])
    ch = stability_chart(sys_, w, a, n_intervals=100, workers=2)
    for i, wi in enumerate(w):
        for j, aj in enumerate(a):
            T = 2 * np.pi / wi
            r = monodromy_newmark(
                M, Dg + 0.1 * np.eye(2), K0, T, nl_dofs=[0, 1],
                dFdq=lambda t, wi=wi, aj=aj: -kc(t, wi, aj) * Kp,
                dFdv=lambda t, wi=wi, aj=aj: -0.05 * aj * np.sin(2 * wi * t) * np.eye(2),
                n_intervals=100)
            assert ch.max_abs[i, j] == pytest.approx(r.max_abs, abs=1e-10)


def test_chart_modal_basis_and_netcdf(tmp_path):
    n = 12
    K = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1)
    Kp = np.diag(np.linspace(0.5, 1.0, n))
    sys_ = LTPSystem(np.eye(n), [(0.02 * np.eye(n), None)],
                     [(K, None), (Kp, lambda t, w, a: a * np.cos(w * t))],
                     period=lambda w, a: 2 * np.pi / w)
    w = np.linspace(0.2, 0.6, 6)
    a = np.linspace(0.0, 0.3, 4)
    full = stability_chart(sys_, w, a, n_intervals=150)
    red = stability_chart(sys_, w, a, n_intervals=150, n_modes=6)
    assert red.info["n_reduced"] == 6
    # the low parametric resonances (2 w_1 ~ 0.48) are captured by the lowest modes
    assert np.array_equal(full.stable, red.stable)
    assert np.abs(full.max_abs - red.max_abs).max() < 0.05
    path = tmp_path / "chart.nc"
    red.to_netcdf(str(path))
    import xarray as xr

    ds = xr.load_dataset(path)
    assert np.allclose(ds["max_abs_multiplier"].values, red.max_abs)
    assert ds["stable"].dims == ("p1", "p2")
