"""Benchmark of the Floquet tools (run: python benchmarks/bench_stability.py [--quick]).

1. Per-point monodromy cost on the paper rotor (84 DOF, 2-DOF SFD Jacobian sampled on a
   synthetic period-1 orbit at the SFD node, Omega = 850 rad/s):
   full Newmark N = 400 (the paper's literal method), Craig-Bampton reduced Newmark,
   full generalized-alpha (rho_inf = 0.6), Hill (symmetric and Koopman, on the reduced
   model) and, as the reference, Magnus-4 on the full model (exact for the constant stiff
   part). Reports time, max |mu| and the SFD-coupled leading multipliers.
2. A 100 x 100 stability chart of a linear rotor under harmonic base pitching
   ``w_by = A0 w_b sin(w_b t)`` (K(t) = K + w_by^2 (-T22 - P22 + D22), the base terms of
   ``rotorsfd.model.base_terms``), Omega = 250 rad/s, on a 12-mode basis.
"""

from __future__ import annotations

import contextlib
import sys
import time

import numpy as np

from rotorsfd.stability.chart import LTPSystem, stability_chart
from rotorsfd.stability.hill import fourier_coefficients, hill_floquet
from rotorsfd.stability.monodromy import (
    floquet_multipliers,
    monodromy_generalized_alpha,
    monodromy_magnus4,
    monodromy_newmark,
)
from rotorsfd.stability.reduction import craig_bampton


def paper_rotor_problem(speed: float = 850.0, n_intervals: int = 400):
    """M, D, K of the paper rotor and SFD Jacobian samples on a synthetic orbit."""
    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_rotor, build_sfd

    cfg = load_config("examples/paper_rotor.toml")
    rotor, sfd = build_rotor(cfg), build_sfd(cfg)
    M, D, K = rotor.matrices(speed)
    nl = [rotor.dof_index(1, "y"), rotor.dof_index(1, "z")]
    C = cfg.sfd.resolved_clearance
    T = 2 * np.pi / speed
    t = np.arange(n_intervals + 1) * T / n_intervals
    wt = speed * t
    e = 0.4
    y = C * (e * np.cos(wt) + 0.05 * np.cos(2 * wt))
    z = C * (e * np.sin(wt) - 0.1)
    vy = -C * speed * (e * np.sin(wt) + 0.1 * np.sin(2 * wt))
    vz = C * speed * e * np.cos(wt)
    Jq, Jv = sfd.jacobian(y, z, vy, vz)

    def interp(J):
        def f(tt: float) -> np.ndarray:
            return np.array([[np.interp(tt, t, J[:, i, j]) for j in range(2)]
                             for i in range(2)])
        return f

    # exact Jacobian at any t for the Magnus reference
    def exact(kind: int):
        def f(tt: float) -> np.ndarray:
            w = speed * tt
            yy = C * (e * np.cos(w) + 0.05 * np.cos(2 * w))
            zz = C * (e * np.sin(w) - 0.1)
            vyy = -C * speed * (e * np.sin(w) + 0.1 * np.sin(2 * w))
            vzz = C * speed * e * np.cos(w)
            return sfd.jacobian(yy, zz, vyy, vzz)[kind]
        return f

    return M, D, K, T, nl, Jq, Jv, exact(0), exact(1)


def _timeit(fun, repeat: int = 3):
    best = np.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fun()
        best = min(best, time.perf_counter() - t0)
    return out, best


def bench_monodromy(quick: bool = False) -> None:
    M, D, K, T, nl, Jq, Jv, fq, fv = paper_rotor_problem()
    print(f"paper rotor: n = {M.shape[0]} DOF, T = {T:.4e} s, SFD |dF/dq|max = "
          f"{np.abs(Jq).max():.3e} N/m, |dF/dv|max = {np.abs(Jv).max():.3e} N s/m")
    kw = dict(nl_dofs=nl, dFdq=Jq, dFdv=Jv)
    rows = []
    full, tf = _timeit(lambda: monodromy_newmark(M, D, K, T, n_intervals=400, **kw))
    rows.append(("full Newmark N=400 (paper)", tf, full))
    ga, tg = _timeit(lambda: monodromy_generalized_alpha(M, D, K, T, n_intervals=400, **kw))
    rows.append(("full gen-alpha N=400 rho=0.6", tg, ga))
    for n_modes in (None, 12):
        red, tr = _timeit(lambda n=n_modes: floquet_multipliers(M, D, K, T, n_modes=n,
                                                                **kw))
        rows.append((f"CB Newmark N=400, {red.info['n_modes']} modes", tr, red))
    cb = craig_bampton(M, D, K, nl, omega_max=0.25 * 400 / T)
    H = 8
    Jq_hat = fourier_coefficients(Jq[:-1], 2 * H)
    Jv_hat = fourier_coefficients(Jv[:-1], 2 * H)
    for method in ("symmetric", "koopman"):
        hr, th = _timeit(lambda m=method: hill_floquet(
            cb.M, cb.D, cb.K, 2 * np.pi / T, nl_dofs=cb.nl_dofs, dFdq_hat=Jq_hat,
            dFdv_hat=Jv_hat, n_harmonics=H, method=m), repeat=1)
        rows.append((f"Hill {method} H={H} on CB model", th, hr))
    if not quick:
        ref, tm = _timeit(lambda: monodromy_magnus4(M, D, K, T, nl_dofs=nl, dFdq=fq,
                                                    dFdv=fv, n_intervals=200), repeat=1)
        rows.append(("full Magnus-4 N=200 (reference)", tm, ref))
        refcb, tm = _timeit(lambda: monodromy_magnus4(cb.M, cb.D, cb.K, T,
                                                      nl_dofs=cb.nl_dofs, dFdq=fq,
                                                      dFdv=fv, n_intervals=200), repeat=1)
        rows.append(("CB Magnus-4 N=200", tm, refcb))
    print(f"{'method':38s} {'time [s]':>9s} {'|mu|max':>11s}  critical mu"
          f"            Liouville err")
    for name, tt, r in rows:
        c = r.critical
        print(f"{name:38s} {tt:9.4f} {r.max_abs:11.8f}  {c.real:+.6f}{c.imag:+.6f}j"
              f"  {r.liouville_error:.2e}")
    # the SFD-coupled multipliers: the largest ones of the reduced model, matched in
    # the other results
    lead = rows[2][2].multipliers[:4]
    print("leading multipliers of the CB model and the nearest in each result:")
    for name, _, r in rows:
        near = [r.multipliers[np.argmin(np.abs(r.multipliers - m))] for m in lead]
        print(f"  {name:38s} " + " ".join(f"{abs(x):.6f}" for x in near))


def pitching_chart_system(speed: float = 250.0):
    """36-DOF shaft-disk rotor on a pitching base: LTP family over (w_b, A0)."""
    from rotorsfd.model import Disk, LinearSupport, Material, RayleighDamping, Rotor, uniform_shaft
    from rotorsfd.model.base_terms import base_basis

    steel = Material(7800.0, 2.0e11, 7.7e10)
    rotor = Rotor(uniform_shaft(0.4, 8, 0.0, 0.01, steel),
                  disks=[Disk.from_geometry(4, 7800.0, 0.01, 0.075, 0.03)],
                  supports=[LinearSupport.isotropic(1, 5e5), LinearSupport.isotropic(9, 5e5)],
                  damping=RayleighDamping(0.0, 1e-5))
    M, D, K = rotor.matrices(speed)
    b = base_basis(rotor)
    Kp = -b.matrix("T22") - b.matrix("P22") + b.matrix("D22")

    def wy2(t, wb, a0):
        return (a0 * wb * np.sin(wb * t)) ** 2

    sys_ = LTPSystem(M, [(D, None)], [(K, None), (Kp, wy2)],
                     period=lambda wb, a0: 2 * np.pi / wb)
    return sys_, rotor


def bench_chart(n: int = 100, workers: int = 2) -> None:
    sys_, rotor = pitching_chart_system()
    wb = np.linspace(20.0, 400.0, n)
    a0 = np.linspace(0.0, 1.0, n)
    t0 = time.perf_counter()
    ch = stability_chart(sys_, wb, a0, n_intervals=200, n_modes=12, workers=workers,
                         names=("w_b", "A0"))
    dt = time.perf_counter() - t0
    print(f"chart {n}x{n}, {rotor.n_dof} DOF -> 12 modes, N=200, workers={workers}: "
          f"{dt:.1f} s; unstable fraction {np.mean(~ch.stable):.3f}, "
          f"max |mu| {ch.max_abs.max():.4f}")


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    try:  # small matrices: BLAS threads only add overhead
        from threadpoolctl import threadpool_limits
        limit = threadpool_limits(limits=1, user_api="blas")
    except ImportError:
        limit = contextlib.nullcontext()
    with limit:
        bench_monodromy(quick)
        bench_chart(30 if quick else 100)
