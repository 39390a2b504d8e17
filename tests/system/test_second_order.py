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
from rotorsfd.timedomain.integrate import integrate_system, prepare_system
from rotorsfd.timedomain.step_records import StepOptions

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


def test_a_force_law_with_fluid_inertia_is_carried(tmp_path):
    """An SFD with fluid inertia: the record is inertial and hands its compiled inertial
    kernel to the time step, whose run equals integrate() given that kernel directly
    (bit for bit); without inertia the record has no inertial kernel."""
    from rotorsfd.timedomain.integrate import integrate

    path = small_rotor_toml(tmp_path / "r.toml", unbalance="100 g*mm")
    inertial = api.build_system(api.load_config(path, [
        "elements.sfd.density=850 kg/m^3", "elements.sfd.fluid_inertia=true"]))
    so = inertial.second_order(SPEED)
    assert so.has_inertia and so.inertial_kernel is not None
    plain = api.build_system(api.load_config(path)).second_order(SPEED)
    assert not plain.has_inertia and plain.inertial_kernel is None
    kw = dict(steps_per_period=64, n_periods=3, record_dofs=[0, 1])
    a = integrate_system(so, 0.0, 0.0, options=StepOptions(), **kw)
    b = integrate(so.M, so.D, so.K, so.nl_dofs, so.kernel, so.params, so.forcing,
                  time_varying=so.time_varying, inertial_kernel=so.inertial_kernel,
                  **StepOptions().scheme, **StepOptions().iteration, **kw)
    np.testing.assert_array_equal(a.q, b.q)
    c = integrate_system(plain, 0.0, 0.0, options=StepOptions(), **kw)
    assert np.max(np.abs(a.q - c.q)) > 0.0          # the added mass acts
    assert prepare_system(so, so.period / 100, 10).n_dof == so.n_dof
