"""The one solver-level record (issue 16 item 1): ``RotorSystem.second_order(speed)`` is the
equation the HB problem describes at that speed, and time stepping and Floquet take it.

Checks: the record's matrices and loads against ``periodic_problem`` at the same speed
(two builders of one equation); its linear part integrated from the analytic steady state
of the unbalance stays on it (``X = (K - W^2 M + i W D)^-1 (F_c - i F_s)``, the Fourier
convention ``q = Re X e^{i W t}``); its Floquet multipliers against ``expm(A T)`` of the
first-order matrix (an independent method); the acceleration-Jacobian hook of a force law.
"""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from rotors import small_rotor_toml
from rotorsfd import api
from rotorsfd.model.system import RotorSystem
from rotorsfd.second_order import ForceLaw, SecondOrderSystem
from rotorsfd.stability.monodromy import MonodromyOptions, system_multipliers
from rotorsfd.timedomain.integrate import StepOptions, integrate_system, prepare_system

SPEED = 700.0


@pytest.fixture(scope="module")
def system(tmp_path_factory) -> RotorSystem:
    path = small_rotor_toml(tmp_path_factory.mktemp("so") / "small.toml")
    config = api.load_config(path, ["rotor.supports[0].damping=800 N*s/m"])
    return api.build_system(config)


def test_the_record_is_the_hb_problem_at_that_speed(system):
    so = system.second_order(SPEED)
    assert isinstance(so, SecondOrderSystem) and isinstance(so.elements, ForceLaw)
    problem = system.periodic_problem()
    M, D, K = (np.asarray(a) for a in problem.matrices(SPEED))
    for a, b in ((so.M, M), (so.D, D), (so.K, K)):
        np.testing.assert_allclose(a, b, rtol=0, atol=1e-12 * np.max(np.abs(b)))
    F = problem.forcing(SPEED, 1)
    (h,) = so.forcing.harmonics
    np.testing.assert_allclose(h.cos - 1j * h.sin, F[1], rtol=1e-14, atol=0)
    np.testing.assert_array_equal(so.nl_dofs, problem.nl_dofs)
    assert so.period == pytest.approx(2 * np.pi / SPEED, rel=1e-15)
    assert so.time_varying is None and not so.has_inertia


def test_linear_record_stays_on_the_analytic_steady_state(system):
    linear = RotorSystem(system.rotor, (), system.unbalances).second_order(SPEED)
    (h,) = linear.forcing.harmonics
    W = SPEED
    X = np.linalg.solve(linear.K - W**2 * linear.M + 1j * W * linear.D, h.cos - 1j * h.sin)
    res = integrate_system(linear, X.real, (1j * W * X).real, steps_per_period=400,
                           n_periods=3, record_dofs="all", options=StepOptions())
    exact = (X[None, :] * np.exp(1j * W * res.t[:, None])).real
    err = np.max(np.abs(res.q - exact)) / np.max(np.abs(X))
    assert 0 < err < 5e-4, err        # measured 1.6e-4: Newmark's phase error


def test_floquet_of_the_linear_record_against_the_matrix_exponential(system):
    linear = RotorSystem(system.rotor, (), system.unbalances).second_order(SPEED)
    res = system_multipliers(linear, options=MonodromyOptions(reduction=None,
                                                              n_intervals=800))
    n = linear.n_dof
    Minv = np.linalg.inv(linear.M)
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-Minv @ linear.K, -Minv @ linear.D]])
    s = np.linalg.eigvals(A)
    low = s[np.abs(s.imag) < 3 * SPEED]                   # resolved: omega h << 1
    assert low.size >= 4
    mu = np.exp(low * linear.period)
    assert np.max(np.abs(mu)) < 0.999                     # damped: a real test of D
    dist = [np.min(np.abs(res.multipliers - m)) for m in mu]
    assert max(dist) < 5e-4, dist                          # measured 5.3e-5
    ref = np.sort(np.abs(np.linalg.eigvals(sla.expm(A * linear.period))))[::-1]
    assert np.max(np.abs(res.multipliers)) == pytest.approx(ref[0], rel=1e-4)


def test_a_force_law_with_an_acceleration_jacobian_is_carried(system):
    so = system.second_order(SPEED)

    class Inertial:
        def __init__(self, law):
            self.law = law

        def __getattr__(self, name):
            return getattr(self.law, name)

        def acceleration_jacobian(self, q, v):
            return -2.0 * np.eye(q.size)

    from dataclasses import replace

    heavy = replace(so, elements=Inertial(so.elements))
    assert heavy.has_inertia
    m = so.n_nl
    np.testing.assert_array_equal(heavy.added_mass(np.zeros(m), np.zeros(m)), 2 * np.eye(m))
    with pytest.raises(NotImplementedError, match="acceleration Jacobian"):
        prepare_system(heavy, so.period / 100, 10)
    assert so.added_mass(np.zeros(m), np.zeros(m)) is None
