"""The paper rotor (84 DOF) with an SFD Jacobian on a synthetic orbit: the SFD-coupled
leading multipliers by full Newmark (paper), full generalized-alpha, Craig-Bampton
Newmark and Hill agree with the full-model Magnus-4 reference."""

from __future__ import annotations

import os
import sys
from pathlib import Path

import numpy as np
import pytest

pytestmark = pytest.mark.slow

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def problem():
    if not (ROOT / "examples" / "paper_rotor.toml").exists():
        pytest.skip("paper rotor example not available")
    sys.path.insert(0, str(ROOT / "benchmarks"))
    cwd = os.getcwd()
    try:
        os.chdir(ROOT)
        from bench_stability import paper_rotor_problem

        return paper_rotor_problem()
    finally:
        os.chdir(cwd)
        sys.path.remove(str(ROOT / "benchmarks"))


def test_paper_rotor_methods_agree(problem):
    from rotorsfd.stability import (
        craig_bampton,
        floquet_multipliers,
        fourier_coefficients,
        hill_floquet,
        monodromy_magnus4,
    )
    from rotorsfd.stability.monodromy import monodromy_generalized_alpha, monodromy_newmark

    M, D, K, T, nl, Jq, Jv, fq, fv = problem
    kw = dict(nl_dofs=nl, dFdq=Jq, dFdv=Jv)
    ref = monodromy_magnus4(M, D, K, T, nl_dofs=nl, dFdq=fq, dFdv=fv, n_intervals=200)
    cb_nm = floquet_multipliers(M, D, K, T, **kw)
    lead = cb_nm.multipliers[:4]  # the two SFD-coupled pairs (|mu| ~ 0.94, 0.92)

    def nearest(r):
        return np.array([r.multipliers[np.argmin(np.abs(r.multipliers - m))] for m in lead])

    full_nm = monodromy_newmark(M, D, K, T, **kw)
    full_ga = monodromy_generalized_alpha(M, D, K, T, **kw)
    cb = craig_bampton(M, D, K, nl, omega_max=0.25 * 400 / T)
    hill = hill_floquet(cb.M, cb.D, cb.K, 2 * np.pi / T, nl_dofs=cb.nl_dofs,
                        dFdq_hat=fourier_coefficients(Jq[:-1], 16),
                        dFdv_hat=fourier_coefficients(Jv[:-1], 16), n_harmonics=8)
    r_ref = np.abs(nearest(ref))
    for r in (full_nm, full_ga, cb_nm, hill):
        assert np.abs(np.abs(nearest(r)) - r_ref).max() < 3e-4
    # the trap: the undamped structural modes sit at |mu| = 1 in the full models
    assert abs(full_nm.max_abs - 1) < 1e-7 and abs(ref.max_abs - 1) < 1e-7
    # generalized-alpha (rho_inf 0.6) and the reduced models expose the SFD-coupled one
    for r in (full_ga, cb_nm, hill):
        assert abs(r.max_abs - r_ref[0]) < 3e-4
