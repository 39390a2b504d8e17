"""Plain-numpy reference stepper (slow, textbook form) to check the compiled loop.

Generalized-alpha with force averaging and a full Newton on all DOFs every step::

    R(q1) = (1-am) M a1 + am M a0 + (1-af) [D(t1) v1 + K(t1) q1 - f(t1) - F_nl(q1, v1)]
            + af [D(t0) v0 + K(t0) q0 - f(t0) - F_nl(q0, v0)] = 0
    a1 = (q1 - q0 - h v0 - h^2 (1/2 - b) a0) / (b h^2),   v1 = v0 + h ((1-c) a0 + c a1)

Newmark average acceleration is ``am = af = 0, b = 1/4, c = 1/2``.
The kernel is called from Python (an ``@njit`` dispatcher or a plain function).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

from rotorsfd.timedomain.forcing import Forcing, TimeVaryingMatrices, sample_coefficient
from rotorsfd.timedomain.newmark import Scheme


def integrate_reference(M: np.ndarray, D: np.ndarray, K: np.ndarray, nl_dofs: Any,
                        kernel: Callable | None, params: Any, forcing: Forcing | None,
                        dt: float, n_steps: int, q0: Any = 0.0, v0: Any = 0.0, *,
                        t0: float = 0.0, time_varying: TimeVaryingMatrices | None = None,
                        method: str = "newmark", alpha: float = 0.05, rho_inf: float = 0.9,
                        tol: float = 1e-13, max_iter: int = 50,
                        ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Return ``t (n_steps+1,)``, ``q, v (n_steps+1, n)`` of every step."""
    M, D, K = (np.asarray(x, dtype=float) for x in (M, D, K))
    n = M.shape[0]
    nl = np.asarray(nl_dofs, dtype=np.int64).reshape(-1)
    m = nl.size
    prm = np.asarray(params if params is not None else [0.0], dtype=float)
    forcing = forcing if forcing is not None else Forcing()
    tv = time_varying if time_varying is not None else TimeVaryingMatrices()
    sc = Scheme.from_method(method, alpha=alpha, rho_inf=rho_inf)
    am, af, b, c = sc.alpha_m, sc.alpha_f, sc.beta, sc.gamma
    h = dt
    t = t0 + h * np.arange(n_steps + 1)
    series = [(sample_coefficient(cf, t0, dt, n_steps), np.asarray(vec, float))
              for cf, vec in forcing.series]
    dterms = [(sample_coefficient(cf, t0, dt, n_steps), np.asarray(X, float))
              for cf, X in tv.damping]
    kterms = [(sample_coefficient(cf, t0, dt, n_steps), np.asarray(X, float))
              for cf, X in tv.stiffness]

    def f_at(k: int) -> np.ndarray:
        f = np.zeros(n) if forcing.constant is None else np.array(forcing.constant, float)
        for hl in forcing.harmonics:
            ph = hl.multiple * forcing.omega * t[k]
            f = f + np.cos(ph) * np.asarray(hl.cos, float)
            if hl.sin is not None:
                f = f + np.sin(ph) * np.asarray(hl.sin, float)
        for cf, vec in series:
            f = f + cf[k] * vec
        return f

    def mats(k: int) -> tuple[np.ndarray, np.ndarray]:
        Dk = D + sum((cf[k] * X for cf, X in dterms), np.zeros((n, n)))
        Kk = K + sum((cf[k] * X for cf, X in kterms), np.zeros((n, n)))
        return Dk, Kk

    def fnl(q: np.ndarray, v: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        F, Jq, Jv = np.zeros(n), np.zeros((n, n)), np.zeros((n, n))
        if m:
            f, dq, dv = np.zeros(m), np.zeros((m, m)), np.zeros((m, m))
            st = kernel(np.ascontiguousarray(q[nl]), np.ascontiguousarray(v[nl]), prm, f,
                        dq, dv)
            if st != 0:
                raise FloatingPointError("contact")
            F[nl] = f
            Jq[np.ix_(nl, nl)] = dq
            Jv[np.ix_(nl, nl)] = dv
        return F, Jq, Jv

    q = np.zeros((n_steps + 1, n))
    v = np.zeros((n_steps + 1, n))
    q[0] = np.broadcast_to(np.asarray(q0, float), (n,))
    v[0] = np.broadcast_to(np.asarray(v0, float), (n,))
    D0, K0 = mats(0)
    F0 = fnl(q[0], v[0])[0]
    a = np.linalg.solve(M, f_at(0) + F0 - D0 @ v[0] - K0 @ q[0])
    old = D0 @ v[0] + K0 @ q[0] - f_at(0) - F0
    c0 = 1.0 / (b * h * h)
    for k in range(n_steps):
        qt = q[k] + h * v[k] + h * h * (0.5 - b) * a
        vt = v[k] + h * (1.0 - c) * a
        D1, K1 = mats(k + 1)
        f1 = f_at(k + 1)
        q1 = q[k] + h * v[k]
        for _ in range(max_iter):
            a1 = c0 * (q1 - qt)
            v1 = vt + c * h * a1
            F1, Jq, Jv = fnl(q1, v1)
            new = D1 @ v1 + K1 @ q1 - f1 - F1
            R = (1.0 - am) * M @ a1 + am * M @ a + (1.0 - af) * new + af * old
            Jac = (1.0 - am) * c0 * M + (1.0 - af) * (c * h * c0 * (D1 - Jv) + K1 - Jq)
            dq = np.linalg.solve(Jac, -R)
            q1 = q1 + dq
            if np.max(np.abs(dq)) <= tol * max(np.max(np.abs(q1)), 1e-300):
                break
        a1 = c0 * (q1 - qt)
        v1 = vt + c * h * a1
        F1 = fnl(q1, v1)[0]
        old = D1 @ v1 + K1 @ q1 - f1 - F1
        q[k + 1], v[k + 1], a = q1, v1, a1
    return t, q, v
