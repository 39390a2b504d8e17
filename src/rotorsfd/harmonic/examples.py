"""Small periodic problems for tests, benchmarks and demonstrations of the HB solvers.

- :func:`duffing`: ``x'' + c x' + k x + k3 x^3 = F cos(w t)``, lam = w.
- :func:`jeffcott_damper`: 2-DOF Jeffcott rotor (y, z) with unbalance ``m e Omega^2``,
  a centring spring and a rational radial damper ``F = -c0 v / (1 - r^2/C^2)^{3/2}``
  (a stand-in for a squeeze film: unbounded at r = C), lam = Omega.
- :func:`beam_rotor`: 21-node, 4-DOF-per-node Euler-Bernoulli rotor (84 DOF) with a disk at
  node 8, a centring spring + radial damper at node 1, a spring at node 21 (mimics the
  paper's rotor), lam = Omega.
- :func:`generic_chain`: n-DOF chain where everything depends on lam (matrices, forcing,
  frequency) and a polynomial two-DOF nonlinearity in q and v (for Jacobian checks).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rotorsfd.errors import JournalContactError
from rotorsfd.harmonic.problem import PeriodicProblem

FloatArray = NDArray[np.float64]


def _const(*arrays: FloatArray):
    return lambda lam: arrays


def duffing(c: float = 0.05, k: float = 1.0, k3: float = 0.1, F: float = 0.1
            ) -> PeriodicProblem:
    """Duffing oscillator, lam = w; ``F_nl = -k3 x^3``."""
    M, D, K = np.eye(1), np.array([[c]]), np.array([[k]])
    Z = np.zeros((1, 1))

    def forcing(lam: float, H: int) -> np.ndarray:
        f = np.zeros((H + 1, 1), dtype=complex)
        f[1, 0] = F
        return f

    return PeriodicProblem(
        n_dof=1, nl_dofs=np.array([0]), matrices=_const(M, D, K), dmatrices=_const(Z, Z, Z),
        forcing=forcing, dforcing=lambda lam, H: np.zeros((H + 1, 1), dtype=complex),
        frequency=lambda lam: lam, dfrequency=lambda lam: 1.0,
        nl_force=lambda q, v: -k3 * q**3,
        nl_jacobian=lambda q, v: ((-3 * k3 * q**2)[..., None], np.zeros((*q.shape, 1))),
        scaling=1.0, name="duffing")


def radial_damper(c0: float, clearance: float):
    """``F = -c0 v / s^{3/2}``, ``s = 1 - |q|^2/C^2``: force, Jacobian, limit |q|/C, None
    (no combined force-and-Jacobian)."""

    def _s(q: FloatArray, v: FloatArray) -> FloatArray:
        s = 1.0 - np.sum(q**2, axis=-1) / clearance**2
        if np.any(s <= 0.0):
            i = np.unravel_index(np.argmin(s), s.shape)
            raise JournalContactError(float(np.sqrt(1 - s[i])), *q[i], *v[i],
                                      where="radial_damper")
        return s

    def force(q: FloatArray, v: FloatArray) -> FloatArray:
        return -c0 * v * _s(q, v)[..., None] ** -1.5

    def jacobian(q: FloatArray, v: FloatArray) -> tuple[FloatArray, FloatArray]:
        s = _s(q, v)
        dv = -c0 * s[..., None, None] ** -1.5 * np.eye(2)
        dq = -3.0 * c0 / clearance**2 * (s**-2.5)[..., None, None] * v[..., :, None] \
            * q[..., None, :]
        return dq, np.broadcast_to(dv, dq.shape).copy()

    def limit(q: FloatArray) -> float:
        return float(np.sqrt(np.max(np.sum(q**2, axis=-1)))) / clearance

    return force, jacobian, limit, None


def sfd_nonlinearity(sfd):
    """Force, Jacobian, limit (max eccentricity ratio) and force-and-Jacobian of a
    ``rotorsfd.sfd.SFD`` in the vectorised form of :class:`PeriodicProblem` (q, v (..., 2))."""

    def force(q: FloatArray, v: FloatArray) -> FloatArray:
        Fy, Fz = sfd.force(q[..., 0], q[..., 1], v[..., 0], v[..., 1])
        return np.stack([Fy, Fz], axis=-1)

    def jacobian(q: FloatArray, v: FloatArray) -> tuple[FloatArray, FloatArray]:
        return sfd.jacobian(q[..., 0], q[..., 1], v[..., 0], v[..., 1])

    def limit(q: FloatArray) -> float:
        return float(np.sqrt(np.max(np.sum(q**2, axis=-1)))) / sfd.clearance

    def force_jacobian(q: FloatArray, v: FloatArray):
        return sfd.force_and_jacobian(q[..., 0], q[..., 1], v[..., 0], v[..., 1])

    return force, jacobian, limit, force_jacobian


def _kernel_of(sfd) -> dict:
    """The SFD's compiled kernel for :class:`PeriodicProblem` (none for the radial damper)."""
    if sfd is None:
        return {}
    return {"nl_kernel": sfd.numba_kernel, "nl_kernel_params": sfd.kernel_params}


def unbalance_forcing(direction: NDArray[np.complex128], unbalance: float,
                      static: ArrayLike = 0.0):
    """``(forcing, dforcing)`` of an unbalance turning at lam = Omega: ``F_1 = U lam^2 d``
    (``d`` the complex direction per DOF, e.g. ``(1, -i)`` for ``(cos, sin)`` on (y, z)),
    ``F_0 = static``; ``dF_1/dlam = 2 U lam d``."""
    direction = np.asarray(direction, dtype=complex)

    def forcing(lam: float, H: int) -> np.ndarray:
        f = np.zeros((H + 1, direction.size), dtype=complex)
        f[0] = static
        f[1] = unbalance * lam**2 * direction
        return f

    def dforcing(lam: float, H: int) -> np.ndarray:
        f = np.zeros((H + 1, direction.size), dtype=complex)
        f[1] = 2 * unbalance * lam * direction
        return f

    return forcing, dforcing


def jeffcott_damper(mass: float = 10.0, stiffness: float = 1e6, damping: float = 20.0,
                    unbalance: float = 1e-4, c0: float = 400.0, clearance: float = 2e-4,
                    static: tuple[float, float] = (0.0, 0.0), sfd=None) -> PeriodicProblem:
    """Jeffcott rotor ``m q'' + c q' + k q = U Omega^2 (cos, sin) + static + F_nl``; the
    damper is :func:`radial_damper` (c0, clearance) or, if given, an SFD object."""
    M, D, K = mass * np.eye(2), damping * np.eye(2), stiffness * np.eye(2)
    Z = np.zeros((2, 2))
    forcing, dforcing = unbalance_forcing(np.array([1.0, -1.0j]), unbalance, static)

    force, jac, limit, both = (radial_damper(c0, clearance) if sfd is None
                               else sfd_nonlinearity(sfd))
    clearance = clearance if sfd is None else sfd.clearance
    return PeriodicProblem(
        n_dof=2, nl_dofs=np.array([0, 1]), matrices=_const(M, D, K), dmatrices=_const(Z, Z, Z),
        forcing=forcing, dforcing=dforcing, frequency=lambda lam: lam,
        dfrequency=lambda lam: 1.0, nl_force=force, nl_jacobian=jac, scaling=clearance,
        nl_limit=limit, name="jeffcott_damper", nl_force_jacobian=both,
        **_kernel_of(sfd))


def _beam_element(L: float, EI: float, rhoA: float) -> tuple[FloatArray, FloatArray]:
    """8x8 EB element [y1, z1, ty1, tz1, y2, z2, ty2, tz2] (tz = dy/dx, ty = -dz/dx)."""
    k = EI / L**3 * np.array([[12, 6 * L, -12, 6 * L], [6 * L, 4 * L**2, -6 * L, 2 * L**2],
                              [-12, -6 * L, 12, -6 * L], [6 * L, 2 * L**2, -6 * L, 4 * L**2]])
    m = rhoA * L / 420 * np.array([[156, 22 * L, 54, -13 * L],
                                   [22 * L, 4 * L**2, 13 * L, -3 * L**2],
                                   [54, 13 * L, 156, -22 * L],
                                   [-13 * L, -3 * L**2, -22 * L, 4 * L**2]])
    Ke, Me = np.zeros((8, 8)), np.zeros((8, 8))
    iy = [0, 3, 4, 7]
    iz = [1, 2, 5, 6]
    T = np.diag([1.0, -1.0, 1.0, -1.0])
    for idx, t in ((iy, np.eye(4)), (iz, T)):
        Ke[np.ix_(idx, idx)] = t @ k @ t
        Me[np.ix_(idx, idx)] = t @ m @ t
    return Ke, Me


def beam_rotor(n_nodes: int = 21, unbalance: float = 1.44e-4, c0: float = 500.0,
               clearance: float = 1.27e-4, support: float = 1e7,
               rayleigh_beta: float = 0.0, sfd=None) -> PeriodicProblem:
    """84-DOF rotor mimicking the paper's (section 4): hollow steel shaft 0.5994 m,
    radii 20.65/30.15 mm, disk (11.7 kg) at node 8 with gyroscopic coupling, springs
    ``support`` at nodes 1 and 21, radial damper (c0, clearance) or the SFD object ``sfd``
    at node 1; lam = Omega."""
    n = 4 * n_nodes
    Ls, ri, ro, rho, E = 0.5994, 0.02065, 0.03015, 7810.0, 211e9
    A, Iz = np.pi * (ro**2 - ri**2), np.pi / 4 * (ro**4 - ri**4)
    Le = Ls / (n_nodes - 1)
    Ke, Me = _beam_element(Le, E * Iz, rho * A)
    M, K, G = np.zeros((n, n)), np.zeros((n, n)), np.zeros((n, n))
    for e in range(n_nodes - 1):
        sl = slice(4 * e, 4 * e + 8)
        M[sl, sl] += Me
        K[sl, sl] += Ke
    dn = 4 * 7  # node 8
    Ro, t = 0.1016, 0.0508
    md = rho * np.pi * (Ro**2 - ro**2) * t
    Ip = 0.5 * md * (Ro**2 + ro**2)
    Id = 0.25 * md * (Ro**2 + ro**2) + md * t**2 / 12
    M[dn, dn] += md
    M[dn + 1, dn + 1] += md
    M[dn + 2, dn + 2] += Id
    M[dn + 3, dn + 3] += Id
    G[dn + 2, dn + 3], G[dn + 3, dn + 2] = Ip, -Ip
    for node0 in (0, n_nodes - 1):
        K[4 * node0, 4 * node0] += support
        K[4 * node0 + 1, 4 * node0 + 1] += support
    Cs = rayleigh_beta * K
    Z = np.zeros((n, n))
    dirn = np.zeros(n, dtype=complex)
    dirn[dn], dirn[dn + 1] = 1.0, -1.0j
    forcing, dforcing = unbalance_forcing(dirn, unbalance)

    force, jac, limit, both = (radial_damper(c0, clearance) if sfd is None
                               else sfd_nonlinearity(sfd))
    clearance = clearance if sfd is None else sfd.clearance
    return PeriodicProblem(
        n_dof=n, nl_dofs=np.array([0, 1]), matrices=lambda lam: (M, Cs + lam * G, K),
        dmatrices=lambda lam: (Z, G, Z), forcing=forcing, dforcing=dforcing,
        frequency=lambda lam: lam, dfrequency=lambda lam: 1.0, nl_force=force,
        nl_jacobian=jac, scaling=clearance, nl_limit=limit, name="beam_rotor",
        nl_force_jacobian=both, **_kernel_of(sfd))


def generic_chain(n: int = 6, nl: tuple[int, int] = (2, 3), seed: int = 0
                  ) -> PeriodicProblem:
    """Chain of n masses where M, D, K, forcing and w all depend on lam; nonlinear force
    ``F = -k3 |q|^2 q - c3 (q.q) v - b (q x v-like coupling)`` on two DOFs; w = 2 lam."""
    rng = np.random.default_rng(seed)
    K0 = 2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1) + 0.5 * np.eye(n)
    K1 = np.diag(rng.uniform(0.1, 0.3, n))
    M0 = np.diag(rng.uniform(0.8, 1.2, n))
    C0 = 0.05 * K0 + 0.02 * np.eye(n)
    Gs = np.zeros((n, n))
    Gs[0, 1], Gs[1, 0] = 0.3, -0.3
    f1 = rng.uniform(-1, 1, n) + 1j * rng.uniform(-1, 1, n)
    f2 = 0.1 * (rng.uniform(-1, 1, n) + 1j * rng.uniform(-1, 1, n))
    f0 = 0.2 * rng.uniform(-1, 1, n)

    def matrices(lam):
        return M0 * (1 + 0.1 * lam), C0 + lam * Gs, K0 + lam**2 * K1

    def dmatrices(lam):
        return 0.1 * M0, Gs, 2 * lam * K1

    def forcing(lam, H):
        f = np.zeros((H + 1, n), dtype=complex)
        f[0] = f0 * lam
        f[1] = f1 * lam**2
        if H >= 2:
            f[2] = f2 * lam
        return f

    def dforcing(lam, H):
        f = np.zeros((H + 1, n), dtype=complex)
        f[0] = f0
        f[1] = 2 * f1 * lam
        if H >= 2:
            f[2] = f2
        return f

    k3, c3, b = 0.5, 0.2, 0.3

    def force(q, v):
        r2 = np.sum(q**2, axis=-1)[..., None]
        cross = np.stack([q[..., 1] * v[..., 0], -q[..., 0] * v[..., 1]], axis=-1)
        return -k3 * r2 * q - c3 * r2 * v - b * cross

    def jacobian(q, v):
        eye = np.eye(2)
        r2 = np.sum(q**2, axis=-1)[..., None, None]
        dq = -k3 * (r2 * eye + 2 * q[..., :, None] * q[..., None, :]) \
            - 2 * c3 * v[..., :, None] * q[..., None, :]
        dv = np.broadcast_to(-c3 * r2 * eye, dq.shape).copy()
        dq[..., 0, 1] -= b * v[..., 0]
        dq[..., 1, 0] += b * v[..., 1]
        dv[..., 0, 0] -= b * q[..., 1]
        dv[..., 1, 1] += b * q[..., 0]
        return dq, dv

    return PeriodicProblem(
        n_dof=n, nl_dofs=np.array(nl), matrices=matrices, dmatrices=dmatrices, forcing=forcing,
        dforcing=dforcing, frequency=lambda lam: 2 * lam, dfrequency=lambda lam: 2.0,
        nl_force=force, nl_jacobian=jacobian, scaling=0.5, name="generic_chain")
