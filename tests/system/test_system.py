"""The assembled rotor-SFD system: exact parameter derivatives and the linear limit."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.elements.sfd import SFDElement
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.base_motion import BaseMotion
from rotorsfd.model.system import PARAMETERS, RotorSystem
from rotorsfd.model.unbalance import Unbalance
from rotorsfd.sfd import SFD

STEEL = Material(7810.0, 211e9, 81.783e9)


def small_system(base: BaseMotion | None = None, magnitude: float = 5e-6) -> RotorSystem:
    shaft = uniform_shaft(0.6, 6, 0.02, 0.03, STEEL)
    rotor = Rotor(shaft, disks=[Disk.from_geometry(3, 7810.0, 0.03, 0.1, 0.05)],
                  supports=[LinearSupport.isotropic(1, 5e6), LinearSupport.isotropic(7, 1e7)])
    sfd = SFD(viscosity=0.0051, radius=0.127e-3 / 0.00485, length=0.325 * 2 * 0.127e-3 / 0.00485,
              clearance=0.127e-3)
    return RotorSystem(rotor, [SFDElement("sfd", 1, sfd)], [Unbalance(3, magnitude, 0.3)],
                       base or BaseMotion())


@pytest.mark.parametrize("parameter", list(PARAMETERS))
def test_parameter_derivatives_match_finite_differences(parameter: str) -> None:
    base = BaseMotion(wx=3.0, wy=-4.0, wz=2.5)
    problem = small_system(base).periodic_problem(parameter, speed=600.0)
    lam = {"speed": 600.0, "base.rolling": 3.0, "base.pitching": -4.0, "base.yawing": 2.5,
           "unbalance.magnitude": 5e-6}[parameter]
    h = 1e-6 * max(abs(lam), 1.0)
    for exact, f in ((problem.dmatrices(lam), problem.matrices),):
        for d, a, b in zip(exact, f(lam + h), f(lam - h), strict=True):
            fd = (a - b) / (2 * h)
            assert np.allclose(d, fd, rtol=1e-6, atol=1e-9 * (np.abs(a).max() + 1e-30))
    dF = problem.dforcing(lam, 3)
    fd = (problem.forcing(lam + h, 3) - problem.forcing(lam - h, 3)) / (2 * h)
    assert np.allclose(dF, fd, rtol=1e-6, atol=1e-9 * np.abs(fd).max() + 1e-300)
    dw = (problem.frequency(lam + h) - problem.frequency(lam - h)) / (2 * h)
    assert problem.dfrequency(lam) == pytest.approx(dw, abs=1e-9)


def test_small_unbalance_gives_the_linear_response_with_the_film_as_a_damper() -> None:
    """eps -> 0: the pi film is the linear damper c = pi mu R L^3 / (2 C^3) (issue 4), so a
    tiny unbalance gives the linear rotor's response with that damper at the SFD node."""
    system = small_system(magnitude=1e-9)
    speed = 700.0
    sol = solve_periodic(system.periodic_problem(), speed, H=3)
    M, D, K = system.matrices(speed)
    iy, iz = system.nl_dofs
    D = D.copy()
    D[iy, iy] += system.elements[0].film.linear_damping
    D[iz, iz] += system.elements[0].film.linear_damping
    Fc, Fs = system.unbalance_harmonics(speed)
    X1 = np.linalg.solve(K - speed**2 * M + 1j * speed * D, Fc - 1j * Fs)
    # The film's linear damping holds to O(eps^2); eps here is ~1e-4.
    assert np.allclose(sol.X[1], X1, rtol=1e-4, atol=1e-6 * np.abs(X1).max())
    assert np.abs(sol.X[2:]).max() < 1e-3 * np.abs(X1).max()


def test_constant_base_rates_enter_the_linear_matrices() -> None:
    fixed = small_system()
    pitching = small_system(BaseMotion(wy=6.0))
    M0, D0, K0 = fixed.matrices(500.0)
    M1, D1, K1 = pitching.matrices(500.0)
    assert np.array_equal(M0, M1)
    assert np.array_equal(D0, D1)  # C_base is proportional to w_bx only
    # -m w_by^2 on z at the disk (centrifugal softening of the pitching base)
    iz = 4 * 2 + 1
    disk = pitching.rotor.disks[0]
    shaft_mass_near = pitching.rotor.total_mass - disk.mass
    assert -(disk.mass + shaft_mass_near) * 36.0 < (K1 - K0)[iz, iz] < -disk.mass * 36.0
    # gyroscopic moment Ip Omega w_by at the disk (tz DOF of node 3), issue 3 item 7
    F = pitching.static_force(500.0)
    shaft_part = F[4 * 2 + 3] - disk.polar_inertia * 500.0 * 6.0
    assert abs(shaft_part) < 0.2 * abs(F[4 * 2 + 3])
    assert np.all(fixed.static_force(500.0) == 0.0)
