"""Run-ups of a rotor above DENSE_MAX_DOF (issue 17 item 2): the integrator inputs keep the
band (CSR, the modal damping of a few modes as banded + low-rank, the CSR base patterns)
with no dense n x n array, and the run equals the dense path of the same equations (the
thresholds raised so that every matrix, the Craig-Bampton modes and the base patterns are
dense, as at <= 400 DOFs) to 1e-10 of the largest orbit; the reduced step against the full
step is the reduction's truncation error, bounded."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from rotors import forbid_dense_rotor_matrices, uniform_sfd_rotor_raw
from rotorsfd.analyses.runup import run_speed_law, speed_law_inputs
from rotorsfd.analyses.td_integration import with_reduction
from rotorsfd.io.config import config_from_dict
from rotorsfd.model import base_terms, time_terms
from rotorsfd.model.lowrank import BandedLowRank, dense
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.timedomain import reduced
from rotorsfd.timedomain.speed_law import RampSpeed

LAW = RampSpeed(250.0, 450.0, 0.03)
T_END = 0.03
STEPS = 80


def _system():
    """404 DOFs (100 elements), modal damping of 6 modes, harmonic pitching of the base."""
    from rotorsfd.model.build import build_system

    raw = uniform_sfd_rotor_raw(100, modal_ratio=0.02)
    raw["base"] = {"pitching": {"law": "harmonic", "frequency": 120.0,
                                "angle_amplitude": 2e-3}}
    system = build_system(config_from_dict(raw))
    assert system.n_dof == 404 > DENSE_MAX_DOF
    return system


def _dense_path(monkeypatch) -> None:
    """Every threshold above the model: dense matrices, dense base stack, dense CB."""
    big = 10**9
    monkeypatch.setattr(time_terms, "DENSE_MAX_DOF", big)
    monkeypatch.setattr(base_terms, "DENSE_MAX_DOF", big)
    monkeypatch.setattr(reduced, "DENSE_MAX", big)


def _run(inputs, reduction: str):
    q0 = np.zeros(inputs.n_dof)
    q0[0::4] = q0[1::4] = 1e-6
    rec = [0, 1, 4 * 50, 4 * 50 + 1]          # SFD node 1 and the disk (node 51)
    return run_speed_law(None, LAW, T_END, steps_per_period=STEPS, record_dofs=rec,
                         q0=q0, inputs=inputs, reduction=reduction)


def test_large_runup_inputs_keep_the_band_and_equal_the_dense_assembly(monkeypatch):
    system = _system()
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        inputs = speed_law_inputs(system, LAW, T_END)
        red = with_reduction(inputs, "auto")          # the projection stays sparse too
    assert red.reduction is not None and red.reduction.n_dof < 60
    assert sp.issparse(inputs.M) and sp.issparse(inputs.K)
    assert isinstance(inputs.D, BandedLowRank)
    tv = inputs.time_varying
    assert len(tv.damping) >= 1 and len(tv.stiffness) >= 3    # Omega G; P21, base terms
    assert all(sp.issparse(X) for _, X in (*tv.damping, *tv.stiffness))
    with monkeypatch.context() as m:
        _dense_path(m)
        ref = speed_law_inputs(_system(), LAW, T_END)
    assert isinstance(ref.M, np.ndarray) and isinstance(ref.D, np.ndarray)
    t = np.linspace(0.0, T_END, 7)
    for a, b in ((inputs.M, ref.M), (inputs.D, ref.D), (inputs.K, ref.K)):
        assert np.max(np.abs(dense(a) - b)) <= 1e-12 * np.max(np.abs(b))
    for kind in ("damping", "stiffness"):
        pairs, ref_pairs = getattr(tv, kind), getattr(ref.time_varying, kind)
        assert len(pairs) == len(ref_pairs)
        for (c, X), (c_r, X_r) in zip(pairs, ref_pairs, strict=True):
            np.testing.assert_array_equal(c(t), c_r(t))
            assert np.max(np.abs(dense(X) - X_r)) <= 1e-12 * np.max(np.abs(X_r))


@pytest.mark.parametrize("reduction", ["auto", "none"])
def test_large_runup_orbit_equals_the_dense_path(monkeypatch, reduction):
    """The same equations on both paths: the orbit to 1e-10 of its largest value
    ("auto": the sparse Craig-Bampton (shift-invert modes) against the dense one, the
    same span; "none": the full step of the CSR inputs against the dense inputs)."""
    run = _run(speed_law_inputs(_system(), LAW, T_END), reduction)
    with monkeypatch.context() as m:
        _dense_path(m)
        ref = _run(speed_law_inputs(_system(), LAW, T_END), reduction)
    scale = np.max(np.abs(ref.q))
    assert scale > 1e-7
    dq = np.max(np.abs(run.q - ref.q)) / scale
    dv = np.max(np.abs(run.v - ref.v)) / np.max(np.abs(ref.v))
    print(f"{reduction}: orbit {dq:.1e}, velocity {dv:.1e} of the largest value")
    assert dq <= 1e-10
    # the velocity carries the highest kept modes' eigenvector error (ARPACK against
    # LAPACK, ~1e-9 here) with reduction; none without
    assert dv <= (1e-8 if reduction == "auto" else 1e-10)


def test_large_reduced_runup_truncation_error_is_bounded():
    """Reduced (Craig-Bampton to 40 x the top speed) against the full step of the same
    inputs: the truncation of the dropped fixed-interface modes, measured 1.5e-4 of the
    largest orbit here; bounded by 1e-3 (and nonzero: the two are different equations)."""
    inputs = speed_law_inputs(_system(), LAW, T_END)
    a, b = _run(inputs, "auto"), _run(inputs, "none")
    err = np.max(np.abs(a.q - b.q)) / np.max(np.abs(b.q))
    assert 1e-9 < err <= 1e-3


def test_large_runup_simulation_forms_no_dense_matrix(monkeypatch):
    """``simulate`` under a speed law (the CLI's path: the reduced step, the step check,
    the Campbell lines of the waterfall) on the 404-DOF rotor without a dense matrix."""
    from rotorsfd.analyses.runup_simulation import run_speed_law_simulation
    from rotorsfd.model.build import build_system

    raw = uniform_sfd_rotor_raw(100, modal_ratio=0.02)
    raw["base"] = {"pitching": {"law": "harmonic", "frequency": 120.0,
                                "angle_amplitude": 2e-3}}
    config = config_from_dict(raw)
    system = build_system(config)
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        res = run_speed_law_simulation(system, LAW, sim=config.analysis.simulate,
                                       nodes=[1, 51], steps_per_period=STEPS,
                                       natural_modes=2)
    assert res.settings["reduction"] == "auto"
    assert res.natural is not None and np.all(res.natural[1] > 0.0)
    assert np.max(res.radius(1)) > 0.0
