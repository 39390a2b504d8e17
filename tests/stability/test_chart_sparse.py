"""The LTP stability chart of a rotor above DENSE_MAX_DOF (issue 17 item 2): the system
keeps the band (no dense n x n matrix, no n x n identity basis), the modal basis comes from
the sparse shift-invert eigensolver, and the multipliers equal the dense path of the same
equations (thresholds raised: dense matrices, dense base stack, LAPACK eigh) to 1e-8; the
reduced basis against the complete one (every mode: the full model) is its truncation
error, bounded."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from rotors import forbid_dense_rotor_matrices, uniform_sfd_rotor_raw
from rotorsfd.analyses.stability_chart import run_stability_chart
from rotorsfd.analyses.stability_chart_ltp import rotor_ltp_system
from rotorsfd.analyses.stability_chart_rates import ChartParams
from rotorsfd.io.config import config_from_dict
from rotorsfd.model import base_terms, time_terms
from rotorsfd.model.build import build_system
from rotorsfd.model.lowrank import BandedLowRank
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.stability import chart
from rotorsfd.stability.chart import LARGE_MODES, lowest_modes, stability_chart

FREQ = "base.pitching.frequency"
A0 = "base.pitching.angle_amplitude"
AMPLITUDES = [0.0, 0.1, 0.3]
FREQUENCIES = [90.0, 160.0, 260.0]


def _raw(damping: dict | None = None) -> dict:
    """404 DOFs (100 elements) under harmonic pitching, at 300 rad/s."""
    raw = uniform_sfd_rotor_raw(100, modal_ratio=0.02)
    if damping is not None:
        raw["rotor"]["damping"] = damping
    raw["base"] = {"pitching": {"law": "harmonic", "frequency": 150.0,
                                "angle_amplitude": 0.1}}
    raw["analysis"] = {"stability_chart": {"speed": 300.0}}
    return raw


def _dense_path(monkeypatch) -> None:
    big = 10**9
    monkeypatch.setattr(time_terms, "DENSE_MAX_DOF", big)
    monkeypatch.setattr(base_terms, "DENSE_MAX_DOF", big)
    monkeypatch.setattr(chart, "DENSE_MAX_DOF", big)


def _ltp(raw: dict):
    """The chart's LTP system over (A0, w_b) with its ChartParams."""
    from rotorsfd.analyses.stability_chart_rates import (
        coefficient_target,
        rate_specs_from_config,
    )

    config = config_from_dict(raw)
    system = build_system(config)
    specs = rate_specs_from_config(config)
    params = ChartParams(specs, 300.0, coefficient_target(A0), coefficient_target(FREQ))
    return rotor_ltp_system(system, params, np.array(AMPLITUDES), np.array(FREQUENCIES))


def test_large_ltp_system_keeps_the_band(monkeypatch):
    system = build_system(config_from_dict(_raw()))
    assert system.n_dof == 404 > DENSE_MAX_DOF
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        ltp = _ltp(_raw())
        res = run_stability_chart(config_from_dict(_raw()), x=(A0, AMPLITUDES[:1]),
                                  y=(FREQ, FREQUENCIES[:1]), n_intervals=100)
    assert sp.issparse(ltp.M)
    assert isinstance(ltp.D_terms[0][0], BandedLowRank)        # modal damping of 6 modes
    assert all(sp.issparse(X) for X, _ in ltp.K_terms)
    assert len(ltp.K_terms) > 1                                 # the pitching terms vary
    assert res.chart.info["n_dof"] == 404
    assert 4 <= res.chart.info["n_reduced"] < 40


def test_large_chart_equals_the_dense_path(monkeypatch):
    """The analysis path (CSR, shift-invert modes below the cutoff) against the dense one
    (LAPACK eigh of the dense model): the same span, multipliers to 1e-8."""
    kw = {"x": (A0, AMPLITUDES), "y": (FREQ, FREQUENCIES), "n_intervals": 200}
    res = run_stability_chart(config_from_dict(_raw()), **kw)
    with monkeypatch.context() as m:
        _dense_path(m)
        ref = run_stability_chart(config_from_dict(_raw()), **kw)
    assert res.chart.info["n_reduced"] == ref.chart.info["n_reduced"]
    assert np.ptp(ref.chart.max_abs) > 1e-3          # the grid does change the multipliers
    np.testing.assert_allclose(res.chart.max_abs, ref.chart.max_abs, rtol=0, atol=1e-8)
    np.testing.assert_allclose(res.chart.critical, ref.chart.critical, rtol=0, atol=1e-8)


def test_default_basis_above_dense_max_is_modal_not_the_identity(monkeypatch):
    """Without a basis a large system gets the LARGE_MODES lowest modes (never n x n):
    equal to the chart on LAPACK's modes of the dense model to 1e-8."""
    ltp = _ltp(_raw())
    got = stability_chart(ltp, AMPLITUDES[1:], FREQUENCIES[1:], n_intervals=200)
    assert got.info["n_reduced"] == LARGE_MODES and got.info["basis"].startswith("modal")
    with monkeypatch.context() as m:
        _dense_path(m)
        dense_ltp = _ltp(_raw())
        assert isinstance(dense_ltp.M, np.ndarray)
        ref = stability_chart(dense_ltp, AMPLITUDES[1:], FREQUENCIES[1:], n_intervals=200,
                              n_modes=LARGE_MODES)
    np.testing.assert_allclose(got.max_abs, ref.max_abs, rtol=0, atol=1e-8)
    np.testing.assert_allclose(got.critical, ref.critical, rtol=0, atol=1e-8)


def test_lowest_modes_match_lapack():
    """Shift-invert Lanczos eigenvalues against scipy.linalg.eigh of the dense pencil,
    mass-normalised; a count the solver cannot give is one clear error."""
    import scipy.linalg as sla

    system = build_system(config_from_dict(_raw()))
    r = system.rotor
    lam, V = lowest_modes(r.K_csr, r.M_csr, 10)
    ref = sla.eigh(r.K_csr.toarray(), r.M_csr.toarray(), eigvals_only=True,
                   subset_by_index=(0, 9))
    # LAPACK's own rounding: it splits the first (exactly degenerate) pair by 4e-9
    np.testing.assert_allclose(lam, ref, rtol=1e-8)
    np.testing.assert_allclose(V.T @ (r.M_csr @ V), np.eye(10), atol=1e-10)
    with pytest.raises(ValueError, match="count"):
        lowest_modes(r.K_csr, r.M_csr, 403)


def test_reduced_chart_truncation_against_the_full_model(monkeypatch):
    """The analysis' modal basis (modes below 3 x the top excitation) against every mode
    (the complete basis: the full 404-DOF model), Rayleigh-damped so that the unresolved
    high modes decay: max |mu| differs by the truncation, measured 2e-8 (4 modes); bounded 1e-6."""
    raw = _raw({"kind": "rayleigh", "alpha": 0.0, "beta": 2e-5})
    kw = {"x": (A0, [0.3]), "y": (FREQ, [160.0]), "n_intervals": 200}
    res = run_stability_chart(config_from_dict(raw), **kw)
    with monkeypatch.context() as m:
        _dense_path(m)
        full = run_stability_chart(config_from_dict(raw), n_modes=404, **kw)
    assert full.chart.info["n_reduced"] == 404
    err = abs(res.chart.max_abs[0, 0] - full.chart.max_abs[0, 0])
    print(f"reduced ({res.chart.info['n_reduced']} modes) - full: {err:.2e}")
    assert err <= 1e-6
