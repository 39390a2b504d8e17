"""The eccentric-SFD rigid rotor of Zhao, Linnett and McLean (J. Vib. Acoust. 116, 1994,
357-363), compared qualitatively: "for sufficiently large values of the unbalance and the
damper static radial misalignment, the harmonic motion loses its stability and bifurcates
into a stable subharmonic motion ... at speeds above twice the system critical speed".

A rigid rotor (m, centring spring k, critical speed w_n = sqrt(k/m)) on a pi-film SFD whose
housing is offset by eps_0 C (the static misalignment), bearing parameter
B = mu R L^3 / (m w_n C^3) = 0.02 and unbalance U = m_u e / (m C) = 0.2: with eps_0 = 0.8
the synchronous HB branch loses stability through a real multiplier at -1 (period
doubling) above 2 w_n, and time integration there settles on a period-2 orbit; the centred
damper (eps_0 = 0) stays synchronous and stable over the same range.
"""

from __future__ import annotations

import numpy as np

from rotorsfd.elements.sfd import SFDElement
from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.model.sfd import SFD
from rotorsfd.stability.orbit import orbit_floquet
from rotorsfd.timedomain import Forcing, HarmonicLoad, integrate

MASS, STIFFNESS, C = 10.0, 1e6, 1e-4
WN = np.sqrt(STIFFNESS / MASS)
B, U = 0.02, 0.2
RADIUS, LENGTH = 0.05, 0.01


def rotor(eps0: float) -> tuple[PeriodicProblem, SFDElement]:
    mu = B * MASS * WN * C**3 / (RADIUS * LENGTH**3)
    e = SFDElement("sfd", 1, SFD(mu, RADIUS, LENGTH, C, cavitation="pi"), (eps0 * C, 0.0))
    zero = np.zeros((2, 2))
    unb = U * MASS * C * np.array([1.0, -1j])

    def forcing(lam, H):
        F = np.zeros((H + 1, 2), dtype=complex)
        F[1] = unb * lam**2
        return F

    def dforcing(lam, H):
        F = np.zeros((H + 1, 2), dtype=complex)
        F[1] = 2 * unb * lam
        return F

    p = PeriodicProblem(
        2, np.array([0, 1]), lambda lam: (MASS * np.eye(2), zero, STIFFNESS * np.eye(2)),
        lambda lam: (zero, zero, zero), forcing, dforcing, lambda lam: lam, lambda lam: 1.0,
        e.force, lambda q, v: e.force_and_jacobian(q, v)[1:], scaling=C, nl_limit=e.limit,
        nl_force_jacobian=e.force_and_jacobian, nl_kernel=e.kernel,
        nl_kernel_params=e.kernel_params)
    return p, e


def multipliers_along(p: PeriodicProblem, H: int = 6):
    b = continue_periodic(p, 1.5 * WN, 3.2 * WN, H, ds=0.1, ds_max=0.2, harmonics_tol=None)
    assert b.success, b.message
    out = []
    for i in range(b.n_points):
        fl = orbit_floquet(MASS * np.eye(2), np.zeros((2, 2)), STIFFNESS * np.eye(2), b.X[i],
                           b.lam[i], p.nl_dofs, p.law(b.lam[i]).jacobian, method="newmark",
                           n_intervals=400)
        mu = fl.multipliers[np.argmax(np.abs(fl.multipliers))]
        out.append((b.lam[i] / WN, mu))
    return b, out


def test_eccentric_damper_doubles_the_period_above_twice_the_critical_speed():
    _, centred = multipliers_along(rotor(0.0)[0])
    assert max(abs(mu) for _, mu in centred) < 1.0            # synchronous and stable
    p, e = rotor(0.8)
    branch, ecc = multipliers_along(p)
    unstable = [(s, mu) for s, mu in ecc if abs(mu) > 1.0]
    assert unstable, "the misaligned damper's synchronous orbit should lose stability"
    s0, mu0 = unstable[0]
    assert 2.0 < s0 < 2.6 and mu0.real < -1.0 and abs(mu0.imag) < 1e-6   # flip, above 2 w_n
    # time integration at 2.8 w_n from the (unstable) HB orbit: a period-2 orbit (weakly
    # attracting: the Poincare points settle by a factor ~50 per 200 periods)
    speed = 2.8 * WN
    # the HB orbit at exactly 2.8 w_n (re-solved from the nearest branch point: the start
    # does not depend on where the continuation put its points)
    near = branch.X[int(np.argmin(np.abs(branch.lam - speed)))]
    X = solve_periodic(p, speed, branch.H, near).X
    k = np.arange(X.shape[0])
    q0 = np.real(X.sum(axis=0)) + 1e-3 * C
    v0 = np.real((1j * speed * k[:, None] * X).sum(axis=0))
    forcing = Forcing(omega=speed, constant=np.zeros(2),
                      harmonics=[HarmonicLoad(1.0, U * MASS * C * speed**2 * np.array([1, 0.0]),
                                              U * MASS * C * speed**2 * np.array([0.0, 1]))])
    res = integrate(MASS * np.eye(2), np.zeros((2, 2)), STIFFNESS * np.eye(2), p.nl_dofs,
                    e.kernel, e.kernel_params, forcing, q0=q0, v0=v0, steps_per_period=400,
                    n_periods=700, poincare_every=400, poincare_start=600 * 400)
    assert res.success, res.message
    P = res.poincare_q
    assert np.abs(P[2:] - P[:-2]).max() < 1e-6 * C            # period 2 ...
    assert np.linalg.norm(P[1:] - P[:-1], axis=1).min() > 1e-2 * C   # ... not period 1
