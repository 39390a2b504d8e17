"""The linear part assembled once as a polynomial in the parameter (the fast path of
``RotorSystem.matrices``/``static_force`` and of every ``periodic_problem``) equals the
straightforward combination of the base-motion basis at every call, to round-off."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.elements.sfd import SFDElement
from rotorsfd.errors import ConfigError
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.base_motion import BaseMotion, BaseState, UniformAcceleration
from rotorsfd.model.base_polynomial import POLYNOMIAL_VARIABLES, coefficient_polynomial
from rotorsfd.model.base_terms import base_coefficients
from rotorsfd.model.gravity import Gravity
from rotorsfd.model.system import PARAMETERS, RotorSystem
from rotorsfd.model.unbalance import Unbalance
from rotorsfd.sfd import SFD

STEEL = Material(7810.0, 211e9, 81.783e9)
RTOL = 1e-12

BASES = {
    "fixed": BaseMotion(),
    "pitching": BaseMotion(wy=6.0),
    "rolling": BaseMotion(wx=6.0),
    "yawing": BaseMotion(wz=-6.0),
    "all rates, gravity": BaseMotion(wx=3.0, wy=-4.0, wz=2.5, gravity=Gravity(frame="base")),
    "acceleration, gravity": BaseMotion(y0=UniformAcceleration(2.0),
                                        z0=UniformAcceleration(-1.5), gravity=Gravity()),
}


def small_system(base: BaseMotion) -> RotorSystem:
    shaft = uniform_shaft(0.6, 6, 0.02, 0.03, STEEL)
    rotor = Rotor(shaft, disks=[Disk.from_geometry(3, 7810.0, 0.03, 0.1, 0.05)],
                  supports=[LinearSupport.isotropic(1, 5e6), LinearSupport.isotropic(7, 1e7)])
    sfd = SFD(viscosity=0.0051, radius=0.0262, length=0.017, clearance=0.127e-3)
    return RotorSystem(rotor, [SFDElement("sfd", 1, sfd)], [Unbalance(3, 5e-6, 0.3)], base)


def close(a: np.ndarray, b: np.ndarray) -> bool:
    """|a - b| <= RTOL max|b| (entrywise, relative to the array's scale)."""
    scale = float(np.abs(b).max())
    return float(np.abs(np.asarray(a) - b).max()) <= RTOL * scale


def reference(system: RotorSystem, state: BaseState, speed: float) -> tuple:
    """(D, K, F) by the direct combination: C + speed G + sum c_C B, K + sum c_K B, sum c_F f."""
    r = system.rotor
    C_b, K_b, F_b = system.basis.combine(base_coefficients(state, speed))
    return r.C + speed * r.G + C_b, r.K + K_b, F_b


@pytest.mark.parametrize("variable", POLYNOMIAL_VARIABLES)
def test_coefficient_polynomial_is_exact(variable: str) -> None:
    state = BaseState.constant(w=(3.0, -4.0, 2.5), a0=(0.0, 1.0, -2.0), g=(0.0, 0.0, -9.81))
    speed = 700.0
    c0, c1, c2 = coefficient_polynomial(state, speed, variable)
    for p in (-9.0, 0.0, 0.7, 6.0, 1200.0):
        if variable == "speed":
            st, om = state, p
        else:
            w = np.array(state.w)
            w["wx wy wz".split().index(variable)] = p
            st, om = BaseState(w, state.dw, state.a0, state.v0, state.g), speed
        ref = base_coefficients(st, om)
        for a in ("c_C", "c_K", "c_F"):
            poly = getattr(c0, a) + p * getattr(c1, a) + p * p * getattr(c2, a)
            assert np.allclose(poly, getattr(ref, a), rtol=1e-14,
                               atol=1e-14 * (np.abs(getattr(ref, a)).max() + 1.0))


@pytest.mark.parametrize("name", list(BASES))
def test_matrices_and_static_force_equal_the_direct_combination(name: str) -> None:
    system = small_system(BASES[name])
    state = system.constant_base_state()
    for speed in (0.0, 150.0, 612.5, 1900.0, 150.0):    # the last one from the cache
        M, D, K = system.matrices(speed)
        D_ref, K_ref, F_ref = reference(system, state, speed)
        assert M is system.rotor.M
        assert close(D, D_ref) and close(K, K_ref)
        F = system.static_force(speed)
        assert (not F.any()) if not F_ref.any() else close(F, F_ref)


def test_the_cache_follows_a_changed_base() -> None:
    system = small_system(BaseMotion(wy=6.0))
    system.matrices(500.0)
    system.base = BaseMotion(wx=6.0)
    D_ref, K_ref, _ = reference(system, system.constant_base_state(), 500.0)
    _, D, K = system.matrices(500.0)
    assert close(D, D_ref) and close(K, K_ref)


@pytest.mark.parametrize("name", list(BASES))
@pytest.mark.parametrize("parameter", list(PARAMETERS))
def test_periodic_problem_equals_the_direct_assembly(name: str, parameter: str) -> None:
    system = small_system(BASES[name])
    if PARAMETERS[parameter].kind == "base_rate" and name == "acceleration, gravity":
        # a rate would make this base vary in time (inertial gravity off the axis, or
        # a0 = v0' + w x v0 growing): refused (tests/system/test_base_rate_translation.py)
        with pytest.raises(ConfigError, match="no periodic response"):
            system.periodic_problem(parameter, speed=600.0)
        return
    fast = system.periodic_problem(parameter, speed=600.0)
    ref = system.periodic_problem(parameter, speed=600.0, assembly="direct")
    values = {"speed": (80.0, 600.0, 1500.0), "unbalance.magnitude": (1e-6, 7e-6)}.get(
        parameter, (-8.0, 0.0, 3.0, 6.0))
    for lam in values:
        for f in ("matrices", "dmatrices"):
            for a, b in zip(getattr(fast, f)(lam), getattr(ref, f)(lam), strict=True):
                assert (not a.any()) if not b.any() else close(a, b), (f, lam)
        for f in ("forcing", "dforcing"):
            a, b = getattr(fast, f)(lam, 3), getattr(ref, f)(lam, 3)
            assert (not a.any()) if not b.any() else close(a, b), (f, lam)


def test_parameter_free_matrices_are_the_same_objects() -> None:
    """Constant M, K (pitching: K_base is free of the speed) and the derivatives' zeros
    come back as the same arrays, so the condensation scans their band only once."""
    problem = small_system(BaseMotion(wy=6.0)).periodic_problem("speed")
    (M1, _, K1), (M2, _, K2) = problem.matrices(500.0), problem.matrices(501.0)
    (dM1, dD1, dK1), (dM2, dD2, dK2) = problem.dmatrices(500.0), problem.dmatrices(501.0)
    assert M1 is M2 and K1 is K2
    assert dM1 is dM2 and dD1 is dD2 and dK1 is dK2
    assert problem.matrices(501.0) is problem.matrices(501.0)   # same lam: cached


def test_unknown_assembly_is_refused() -> None:
    from rotorsfd.errors import ConfigError

    with pytest.raises(ConfigError):
        small_system(BaseMotion()).periodic_problem("speed", assembly="dense")


def test_moving_base_rotor_equals_the_direct_combination() -> None:
    from rotorsfd.model.base_polynomial import MovingBaseRotor
    from rotorsfd.model.base_terms import assemble_base

    system = small_system(BaseMotion())
    state = BaseState.constant(w=(3.0, -4.0, 2.5), a0=(0.0, 1.0, -2.0))
    view = MovingBaseRotor(system.rotor, state)
    r = system.rotor
    for speed in (0.0, 420.0, 1700.0):
        C_b, K_b, F_b = assemble_base(r, state, speed)
        M, D, K = view.matrices(speed)
        assert M is r.M
        assert close(D, r.C + speed * r.G + C_b) and close(K, r.K + K_b)
        assert close(view.force(speed), F_b)
