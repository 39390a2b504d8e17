"""Benchmark: compiled Newmark integrator vs scipy ``solve_ivp`` (LSODA, Radau).

Problem (mimics the paper's rotor): an 84-DOF chain, 42 nodes with ``y, z`` each,
lumped masses, springs between neighbours and to the ground at both ends, light
Rayleigh damping; a 2-DOF nonlinear radial damper at node 1
(``F = -c0 v / (1 - e^2)^1.5``, ``e = |q|/C``, contact at ``e >= 0.99``) and a rotating
unbalance force at node 15 at 0.9 times the first natural frequency.

1. Ours: 2000 periods x 200 steps (average acceleration), after compilation; the first
   call (compilation or loading of the on-disk cache) is reported separately.
2. Accuracy: from the steady state, ``n_short`` periods by each method; the error of
   the last period's amplitudes (radial at the damper, ``y`` at the unbalance node)
   against our integrator at 4000 steps a period.
3. scipy: for each method the loosest ``rtol`` of a ladder whose error is at most ours,
   timed (CPU time: the machine may be shared) over ``n_short`` periods and
   extrapolated linearly to 2000 periods (stated in the output); analytic Jacobian
   supplied.

All methods run on one core (BLAS threads set to 1 unless set in the environment).
Run: ``python benchmarks/bench_timedomain.py [--short 40] [--json out.json]``.
"""

from __future__ import annotations

import os

for _var in ("OMP_NUM_THREADS", "OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")  # one core for every method (set before numpy)

import argparse  # noqa: E402
import json  # noqa: E402
import math  # noqa: E402
import time  # noqa: E402

import numpy as np  # noqa: E402
from numba import njit  # noqa: E402
from scipy.integrate import solve_ivp  # noqa: E402

from rotorsfd.timedomain import Forcing, HarmonicLoad, integrate  # noqa: E402
from rotorsfd.timedomain import newmark as nm  # noqa: E402

N_NODES = 42
C_CLEAR = 0.127e-3
PARAMS = np.array([2000.0, C_CLEAR, 0.99])


@njit(cache=True)
def radial_damper(q: np.ndarray, v: np.ndarray, p: np.ndarray, F: np.ndarray,
                  dFdq: np.ndarray, dFdv: np.ndarray) -> int:
    """``F = -c0 v / (1 - e^2)^1.5``, ``e^2 = (y^2 + z^2)/C^2``; 1 if ``e >= e_max``."""
    c0, C, emax = p[0], p[1], p[2]
    e2 = (q[0] * q[0] + q[1] * q[1]) / (C * C)
    if not e2 < emax * emax:
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


def chain() -> tuple[np.ndarray, np.ndarray, np.ndarray, Forcing]:
    """Matrices and unbalance forcing of the 84-DOF chain."""
    n = 2 * N_NODES
    M = 0.5 * np.eye(n)
    K = np.zeros((n, n))
    kc = 5e8
    for i in range(N_NODES - 1):
        for d in range(2):
            a, b = 2 * i + d, 2 * (i + 1) + d
            K[a, a] += kc
            K[b, b] += kc
            K[a, b] -= kc
            K[b, a] -= kc
    for d in range(2):
        K[d, d] += 1e7
        K[n - 2 + d, n - 2 + d] += 1e7
    D = 1e-6 * K + 1.0 * M
    w1 = math.sqrt(np.linalg.eigvalsh(K / 0.5)[0])
    omega = 0.9 * w1
    f = 400e-6 * omega**2  # unbalance 400 g mm
    fc, fs = np.zeros(n), np.zeros(n)
    fc[2 * 14], fs[2 * 14 + 1] = f, f
    return M, D, K, Forcing(omega=omega, harmonics=[HarmonicLoad(1.0, fc, fs)])


def amplitudes(q: np.ndarray) -> np.ndarray:
    """Last-period amplitudes: max radial at the damper, half peak-to-peak y at node 15."""
    return np.array([np.max(np.hypot(q[:, 0], q[:, 1])),
                     0.5 * np.ptp(q[:, 2])])


REC = [0, 1, 2 * 14]


def ours(M, D, K, fo, spp: int, n_periods: int, q0, v0):
    t = time.perf_counter()
    c = time.process_time()
    r = integrate(M, D, K, [0, 1], radial_damper, PARAMS, fo, steps_per_period=spp,
                  n_periods=n_periods, q0=q0, v0=v0, record_dofs=REC,
                  record_start=(n_periods - 1) * spp)
    return r, time.perf_counter() - t, time.process_time() - c


def scipy_run(M, D, K, fo, method: str, rtol: float, n_periods: int, q0, v0):
    n = M.shape[0]
    Minv = np.linalg.inv(M)
    A_q, A_v = -Minv @ K, -Minv @ D
    fc, fs = fo.harmonics[0].cos, fo.harmonics[0].sin
    w = fo.omega
    F = np.zeros(2)
    jq, jv = np.zeros((2, 2)), np.zeros((2, 2))
    J = np.zeros((2 * n, 2 * n))
    J[:n, n:] = np.eye(n)

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        if radial_damper(np.ascontiguousarray(q[:2]), np.ascontiguousarray(v[:2]), PARAMS,
                         F, jq, jv):
            raise FloatingPointError("contact")
        g = fc * math.cos(w * t) + fs * math.sin(w * t)
        g[:2] += F
        return np.concatenate([v, A_q @ q + A_v @ v + Minv @ g])

    def jac(t: float, y: np.ndarray) -> np.ndarray:
        q, v = y[:n], y[n:]
        radial_damper(np.ascontiguousarray(q[:2]), np.ascontiguousarray(v[:2]), PARAMS, F,
                      jq, jv)
        J[n:, :n] = A_q
        J[n:, n:] = A_v
        J[n:, :2] += Minv[:, :2] @ jq
        J[n:, n:n + 2] += Minv[:, :2] @ jv
        return J

    T = fo.period
    scale = np.concatenate([np.full(n, 1e-5), np.full(n, 1e-5 * w)])
    t_eval = np.linspace((n_periods - 1) * T, n_periods * T, 401)
    tic, c = time.perf_counter(), time.process_time()
    sol = solve_ivp(rhs, (0.0, n_periods * T), np.concatenate([q0, v0]), method=method,
                    rtol=rtol, atol=rtol * scale, jac=jac, t_eval=t_eval)
    wall, cpu = time.perf_counter() - tic, time.process_time() - c
    return sol, wall, cpu


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--periods", type=int, default=2000)
    ap.add_argument("--spp", type=int, default=200)
    ap.add_argument("--short", type=int, default=40, help="periods for the scipy runs")
    ap.add_argument("--json", default=None)
    a = ap.parse_args()
    M, D, K, fo = chain()
    n = M.shape[0]
    out: dict = {"n_dof": n, "periods": a.periods, "steps_per_period": a.spp,
                 "omega": fo.omega}

    # 1. ours, cold (first call) and warm
    _r0, wall0, _ = ours(M, D, K, fo, a.spp, 2, 1e-6, 0.0)
    out["first_call_s"] = wall0
    out["run_steps_cache_hits"] = int(sum(nm.run_steps.stats.cache_hits.values()))
    r, wall, cpu = ours(M, D, K, fo, a.spp, a.periods, 1e-6, 0.0)
    assert r.success, r.message
    out |= {"ours_wall_s": wall, "ours_cpu_s": cpu, "ours_loop_s": r.elapsed,
            "newton_iterations_mean": r.newton_iterations_mean,
            "eps_max_final_period": float(np.max(np.hypot(r.q[:, 0], r.q[:, 1])) / C_CLEAR)}
    print(f"84-DOF chain, {a.periods} periods x {a.spp} steps: ours {wall:.2f} s wall, "
          f"{cpu:.2f} s CPU (loop {r.elapsed:.2f} s); first call {wall0:.2f} s; "
          f"Newton {r.newton_iterations_mean:.2f} it/step; eps_max "
          f"{out['eps_max_final_period']:.3f}")

    # 2. accuracy from the steady state over n_short periods
    qs, vs = r.q_final.copy(), r.v_final.copy()
    ref, _, _ = ours(M, D, K, fo, 4000, a.short, qs, vs)
    amp_ref = amplitudes(ref.q)
    r_s, _, _ = ours(M, D, K, fo, a.spp, a.short, qs, vs)
    err_ours = float(np.max(np.abs(amplitudes(r_s.q) - amp_ref) / amp_ref))
    out["ours_amplitude_error"] = err_ours
    print(f"amplitude error (vs 4000 steps/period) over {a.short} periods: ours "
          f"{err_ours:.2e}")

    # 3. scipy at matched accuracy, extrapolated
    best = math.inf
    for method in ("LSODA", "Radau"):
        for rtol in (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 1e-5, 1e-6, 1e-7):
            sol, w_sc, c_sc = scipy_run(M, D, K, fo, method, rtol, a.short, qs, vs)
            if not sol.success:
                print(f"  {method} rtol={rtol:g}: failed ({sol.message})")
                continue
            err = float(np.max(np.abs(amplitudes(sol.y[REC].T) - amp_ref) / amp_ref))
            extrap = c_sc * a.periods / a.short
            print(f"  {method} rtol={rtol:g}: error {err:.2e}, {c_sc:.2f} s CPU "
                  f"({w_sc:.2f} s wall) for {a.short} periods ({sol.nfev} f-evals, "
                  f"{sol.njev} jac) -> {extrap:.0f} s CPU extrapolated to {a.periods}")
            if err <= err_ours:
                out[f"scipy_{method}"] = {"rtol": rtol, "error": err, "wall_short_s": w_sc,
                                          "cpu_short_s": c_sc,
                                          "cpu_extrapolated_s": extrap}
                best = min(best, extrap)
                break
    out["speedup_vs_best_scipy_cpu"] = best / cpu
    print(f"speed-up (CPU time) vs the best scipy method at matched accuracy "
          f"(extrapolated from {a.short} periods): {best / cpu:.0f}x")
    if a.json:
        with open(a.json, "w") as fh:
            json.dump(out, fh, indent=1)


if __name__ == "__main__":
    main()
