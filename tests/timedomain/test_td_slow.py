"""Heavier checks: the paper-sized run (2000 periods x 200 steps, 84 DOFs)."""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.timedomain import classify_result, integrate, largest_lyapunov

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "benchmarks"))
from bench_timedomain import PARAMS, chain, radial_damper


@pytest.mark.slow
def test_chain_2000_periods_under_5_s_and_period_1() -> None:
    """84-DOF chain with the radial damper: 400000 steps in under 5 s of CPU time (after
    compilation), period-1 steady state with a negative Lyapunov exponent."""
    M, D, K, fo = chain()
    integrate(M, D, K, [0, 1], radial_damper, PARAMS, fo, steps_per_period=200,
              n_periods=1, q0=1e-6)  # compile / load the cache
    cpu = time.process_time()
    r = integrate(M, D, K, [0, 1], radial_damper, PARAMS, fo, steps_per_period=200,
                  n_periods=2000, q0=1e-6, record_start=1900 * 200)
    cpu = time.process_time() - cpu
    assert r.success and cpu < 5.0
    assert classify_result(r).motion == "period-1"
    ly = largest_lyapunov(M, D, K, [0, 1], radial_damper, PARAMS, fo, steps_per_period=200,
                          n_periods=50, q0=r.q_final, v0=r.v_final, t0=r.t_final)
    assert ly.exponent < 0.0
    assert np.max(np.hypot(r.q[:, 0], r.q[:, 1])) < PARAMS[1]
