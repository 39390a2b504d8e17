"""A rotor with an SFD and a rub (the composite of two elements through ``RotorSystem``):
its HB branch against time integration of the same system (issue 15 item 4).

Rotor: a 0.6 m hollow shaft in 6 elements, a disk at node 3 (with the unbalance), an SFD
with a centring spring at node 1, a spring at node 7. The rub (clearance 0.3 C, stator
offset 0.1 C in y, so a partial rub once per revolution) sits at the SFD node or at the
disk; both are in contact at the checked speeds, below the first critical speed's jump.
"""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.elements.rub import RubElement
from rotorsfd.elements.sfd import SFDElement
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance
from rotorsfd.sfd import SFD
from rotorsfd.timedomain import Forcing, HarmonicLoad, integrate

STEEL = Material(7810.0, 211e9, 81.783e9)
C = 0.127e-3
H = 16
SPEEDS = (650.0, 680.0)


def sfd_rub_rotor(rub_node: int) -> RotorSystem:
    shaft = uniform_shaft(0.6, 6, 0.02, 0.03, STEEL)
    rotor = Rotor(shaft, disks=[Disk.from_geometry(3, 7810.0, 0.03, 0.1, 0.05)],
                  supports=[LinearSupport.isotropic(1, 5e6), LinearSupport.isotropic(7, 1e7)])
    film = SFD(viscosity=0.0051, radius=C / 0.00485, length=0.325 * 2 * C / 0.00485,
               clearance=C)
    delta = 0.3 * C
    rub = RubElement("rub", rub_node, delta, 1e7, 0.1, 0.05 * delta, (0.1 * C, 0.0))
    return RotorSystem(rotor, [SFDElement("sfd", 1, film), rub], [Unbalance(3, 5e-5, 0.3)])


def time_domain_orbit(system: RotorSystem, speed: float, steps_per_period: int = 1000,
                      n_periods: int = 150):
    """The last period of a run from rest (generalized-alpha, rho_inf = 0.6: the shaft's
    undamped high modes die out instead of ringing on)."""
    M, D, K = system.matrices(speed)
    Fc, Fs = system.unbalance_harmonics(speed)
    forcing = Forcing(omega=speed, constant=system.static_force(speed),
                      harmonics=[HarmonicLoad(1.0, Fc, Fs)])
    el = system.elements
    res = integrate(M, D, K, system.nl_dofs, el.kernel, el.kernel_params, forcing,
                    steps_per_period=steps_per_period, n_periods=n_periods,
                    record_start=(n_periods - 1) * steps_per_period, record_dofs="all",
                    method="generalized-alpha", rho_inf=0.6)
    assert res.success, res.message
    return res


@pytest.mark.slow
@pytest.mark.parametrize("rub_node", [1, 3], ids=["rub-at-sfd-node", "rub-at-disk"])
def test_hb_branch_matches_time_integration(rub_node: int) -> None:
    system = sfd_rub_rotor(rub_node)
    assert [e.kind for e in system.elements] == ["sfd", "rub"]
    assert system.nl_dofs.size == (2 if rub_node == 1 else 4)
    problem = system.periodic_problem()
    branch = continue_periodic(problem, 500.0, max(SPEEDS), H, ds=0.05, ds_max=0.2,
                               harmonics_tol=None)
    assert branch.success, branch.message
    assert np.all(np.diff(branch.lam) > 0)                 # no fold: one orbit per speed
    lateral = np.sort(np.r_[0:system.n_dof:4, 1:system.n_dof:4])
    k = np.arange(H + 1)
    for speed in SPEEDS:
        X = solve_periodic(problem, speed, H, branch.X[np.argmin(np.abs(branch.lam - speed))],
                           tol=1e-9).X
        res = time_domain_orbit(system, speed)
        drift = np.abs(res.poincare_q[-1] - res.poincare_q[-2])[lateral].max()
        assert drift < 1e-4 * C                            # settled
        q_hb = np.real(np.exp(1j * speed * np.outer(res.t, k)) @ X)
        assert np.abs(q_hb[:, lateral] - res.q[:, lateral]).max() < 1e-3 * C
        d = system.elements.diagnostics(q_hb[:, system.nl_dofs], q_hb[:, system.nl_dofs])
        assert 0.1 < d["contact_fraction_rub"] < 0.9 and d["force_max_rub"] > 0
        assert 0.1 < d["eps_max_sfd"] < 1
