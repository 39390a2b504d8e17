"""Compiled loop against the numpy reference; chunked runs; contact; kernels."""

from __future__ import annotations

import math

import numpy as np
import pytest
from numba import njit

from rotorsfd.errors import JournalContactError
from rotorsfd.timedomain import (
    Forcing,
    HarmonicLoad,
    TimeVaryingMatrices,
    as_cfunc,
    cubic_spring_kernel,
    integrate,
)
from rotorsfd.timedomain.integrate import initial_state, prepare, run
from rotorsfd.timedomain.reference import integrate_reference


@njit(cache=True)
def coupled_damper_kernel(q: np.ndarray, v: np.ndarray, params: np.ndarray, F: np.ndarray,
                          dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """Radial damper ``F = -c0 v / (1 - e^2)^1.5``, ``e = |q|/C``; contact at ``e >= 1``."""
    c0, C = params[0], params[1]
    e2 = (q[0] * q[0] + q[1] * q[1]) / (C * C)
    if not e2 < 1.0:
        return 1
    s = 1.0 - e2
    c = c0 / (s * math.sqrt(s))
    dc = 3.0 * c0 / (s * s * math.sqrt(s) * C * C)
    for i in range(2):
        F[i] = -c * v[i]
        for j in range(2):
            dFdv[i, j] = -c if i == j else 0.0
            dFdq[i, j] = -v[i] * dc * q[j]
    return 0


def _problem(n: int = 6, seed: int = 0) -> dict:
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(n, n))
    M = A @ A.T + n * np.eye(n)
    B = rng.normal(size=(n, n))
    K = B @ B.T + n * np.eye(n)
    G = rng.normal(size=(n, n))
    D = 0.05 * K + 0.3 * (G - G.T)
    fo = Forcing(omega=1.1, constant=0.1 * rng.normal(size=n),
                 harmonics=[HarmonicLoad(1.0, rng.normal(size=n), rng.normal(size=n)),
                            HarmonicLoad(2.0, rng.normal(size=n))],
                 series=[(lambda t: np.sin(0.3 * t), rng.normal(size=n))])
    tv = TimeVaryingMatrices(
        damping=[(lambda t: 0.1 * np.cos(0.7 * t), rng.normal(size=(n, n)))],
        stiffness=[(lambda t: 0.2 * np.sin(0.5 * t), rng.normal(size=(n, n)))])
    return dict(M=M, D=D, K=K, forcing=fo, time_varying=tv)


@pytest.mark.parametrize("method", ["newmark", "hht", "generalized-alpha"])
def test_compiled_equals_numpy_reference(method: str) -> None:
    """Same run (cubic springs on 2 DOFs, harmonic + constant + series forcing,
    time-varying D and K) by the compiled loop and the plain-numpy full-Newton stepper:
    equal to 1e-10 relative over 2000 steps."""
    p = _problem()
    dt, N = 2 * np.pi / 1.1 / 100, 2000
    args = (p["M"], p["D"], p["K"], [1, 3], cubic_spring_kernel, [0.5, 2.0], p["forcing"])
    r = integrate(*args, dt, N, 0.01, 0.0, time_varying=p["time_varying"], method=method,
                  record_dofs="all", newton_rtol=1e-13, tv_rtol=1e-14)
    _, q, v = integrate_reference(*args, dt, N, 0.01, 0.0, time_varying=p["time_varying"],
                                  method=method)
    assert np.max(np.abs(r.q - q)) <= 1e-10 * np.max(np.abs(q))
    assert np.max(np.abs(r.v - v)) <= 1e-10 * np.max(np.abs(v))


def test_hht_alpha_zero_is_newmark() -> None:
    """The generalized-alpha form with ``am = af = 0`` reproduces the trapezoidal form."""
    p = _problem(4, seed=5)
    args = (p["M"], p["D"], p["K"], [0, 2], coupled_damper_kernel, [0.5, 5.0], p["forcing"])
    kw = dict(steps_per_period=50, n_periods=20, q0=0.1, record_dofs="all")
    r0 = integrate(*args, method="newmark", **kw)
    r1 = integrate(*args, method="hht", alpha=0.0, **kw)
    assert np.max(np.abs(r0.q - r1.q)) < 1e-10 * np.max(np.abs(r0.q))


def test_chunked_run_continues_exactly() -> None:
    """Two calls of ``run`` continue bit for bit where one call of ``n`` steps goes."""
    p = _problem(5, seed=2)
    ps = prepare(p["M"], p["D"], p["K"], [0, 4], coupled_damper_kernel, [1.0, 3.0],
                 p["forcing"], 0.05, 600, time_varying=p["time_varying"])
    a = initial_state(ps, 0.1, 0.0)
    b = initial_state(ps, 0.1, 0.0)
    run(ps, a, 600)
    run(ps, b, 250)
    run(ps, b, 350)
    np.testing.assert_array_equal(a.X, b.X)


def test_contact_raises_with_time_and_state() -> None:
    """Kernel status 1 stops the run: ``JournalContactError`` with step, time, state."""
    M, D, K = np.eye(2), 0.01 * np.eye(2), np.eye(2)
    fo = Forcing(omega=1.0, harmonics=[HarmonicLoad(1.0, np.array([1.0, 0.0]),
                                                    np.array([0.0, 1.0]))])
    with pytest.raises(JournalContactError) as info:
        integrate(M, D, K, [0, 1], coupled_damper_kernel, [0.01, 1.0], fo,
                  steps_per_period=100, n_periods=50)
    err = info.value
    assert 0 < err.step < 5000 and err.time == pytest.approx((err.step + 1) * 2 * np.pi / 100)
    assert np.hypot(*err.q_nl) >= 1.0 - 1e-6
    assert err.result is not None and not err.result.success
    r = integrate(M, D, K, [0, 1], coupled_damper_kernel, [0.01, 1.0], fo,
                  steps_per_period=100, n_periods=50, on_failure="return")
    assert not r.success and r.status == 1 and r.steps_done == err.step
    assert np.all(np.hypot(r.q[:, 0], r.q[:, 1]) < 1.0)


def test_initial_state_in_contact_raises() -> None:
    with pytest.raises(JournalContactError):
        integrate(np.eye(2), np.eye(2), np.eye(2), [0, 1], coupled_damper_kernel,
                  [1.0, 1.0], None, 0.1, 10, q0=1.0)


def test_kernel_compiled_once_and_input_checks() -> None:
    assert as_cfunc(cubic_spring_kernel) is as_cfunc(cubic_spring_kernel)
    with pytest.raises(ValueError):
        integrate(np.eye(2), np.eye(2), np.eye(2), [2], cubic_spring_kernel, [1.0, 0.0],
                  None, 0.1, 10)
    with pytest.raises(ValueError):
        integrate(np.eye(2), np.eye(2), np.eye(2), [0], cubic_spring_kernel, [1.0, 0.0],
                  None, 0.1, 10, q0=[np.nan, 0.0])


def test_cubic_kernel_duffing_free_vibration_energy() -> None:
    """Undamped Duffing ``x'' + x + x^3 = 0``: the energy ``v^2/2 + x^2/2 + x^4/4`` stays
    within the step's accuracy (average acceleration), the Newton converges in few
    iterations."""
    r = integrate(np.eye(1), np.zeros((1, 1)), np.eye(1), [0], cubic_spring_kernel,
                  [0.0, 1.0], None, 0.01, 20000, q0=1.0)
    E = 0.5 * r.v[:, 0] ** 2 + 0.5 * r.q[:, 0] ** 2 + 0.25 * r.q[:, 0] ** 4
    assert np.max(np.abs(E - E[0])) < 1e-4 * E[0]
    assert r.newton_iterations_max <= 5


def test_read_only_inputs_accepted() -> None:
    """Read-only parameter, DOF and matrix arrays (e.g. cached model data) are copied."""
    arrays = [np.eye(2), 0.1 * np.eye(2), np.eye(2), np.array([0, 1]), np.array([1.0, 1.0])]
    for a in arrays:
        a.flags.writeable = False
    M, D, K, nl, prm = arrays
    r = integrate(M, D, K, nl, cubic_spring_kernel, prm, None, 0.1, 10, q0=0.1,
                  record_dofs=nl)
    assert r.success
