"""Torus branch (two-frequency HB, issue 19 item 6) against what a user does today, time
integration of ``--periods`` rotor periods (2000 in the paper) at every speed, side by side
in one run; plus the cost per continuation point against the periodic HB with the same
total number of harmonics.

Problem: the paper rotor (84 DOF, pi-film SFD) at U = 144.02 g mm under harmonic pitching
angle amplitude A0 = 0.05 rad at w_b = 60 rad/s (rate amplitude A0 w_b = 3 rad/s)
(examples/paper_harmonic_pitching.toml); speeds Omega~ 0.8-1.0; the torus on the box
(3, 2) (18 harmonics, 35 real unknowns per DOF) at a fixed step of ``--step`` (scaled arc
length, 100 points over the range by default); the periodic HB with H = 17 (35 reals per
DOF) of the same rotor under the constant pitching rate of examples/paper_pitching.toml,
same tolerance, step and range; the time integration compiled Newmark at T/200 from the
torus state (as ``rotorsfd simulate`` at the paper's step), timed at the first, middle and
last speed of the branch and summed over its speeds as their mean (every speed costs the
same number of steps).

Times are CPU seconds of this process (``time.process_time``; the machine is shared, wall
times are printed beside them). Every method runs once before it is timed (numba kernels
compiled or loaded from the cache).

Run: ``python -m benchmarks.bench_torus [--quick] [--only torus]`` (quick: 200 periods,
20 speeds; ``--only torus`` the torus branch alone, e.g. to time an older tree).
"""

from __future__ import annotations

import argparse
import time

import benchmarks.common as common  # noqa: F401  (one BLAS thread before numpy loads)
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_system
from rotorsfd.quasiperiodic import TorusLattice, continue_torus, torus_problem

OMEGA_REF = 811.3
EXAMPLE = "examples/paper_harmonic_pitching.toml"


def timed(f):
    """(result, CPU s, wall s) of f()."""
    c0, w0 = time.process_time(), time.perf_counter()
    out = f()
    return out, time.process_time() - c0, time.perf_counter() - w0


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--periods", type=int, default=2000)
    parser.add_argument("--step", type=float, default=None,
                        help="fixed arc-length step (default: 100 points over the range)")
    parser.add_argument("--only", choices=("torus",), default=None)
    args = parser.parse_args()
    periods = 200 if args.quick else args.periods
    stop = 0.84 if args.quick else 1.0
    step = args.step or (0.0147 if not args.quick else 0.04)
    system = build_system(load_config(EXAMPLE))
    lattice = TorusLattice(3, 2)
    problem = torus_problem(system)

    def torus():
        return continue_torus(problem, 0.8 * OMEGA_REF, stop * OMEGA_REF, lattice,
                              ds=step, ds_max=step, max_points=1000)

    continue_torus(problem, 0.8 * OMEGA_REF, 0.802 * OMEGA_REF, lattice, ds=step)  # warm
    branch, c_torus, w_torus = timed(torus)
    n = branch.n_points
    iters = float(branch.iterations.mean())
    print(f"torus branch, box (3, 2): {n} points in {c_torus:.2f} s CPU ({w_torus:.1f} s "
          f"wall), {1e3 * c_torus / n:.1f} ms CPU per point, {iters:.2f} Newton iterations "
          f"per point, grid {branch.grid[0]} x {branch.grid[1]}, Omega~ "
          f"{branch.lam[0] / OMEGA_REF:.3f}-{branch.lam[-1] / OMEGA_REF:.3f} "
          f"({branch.message})")
    if args.only == "torus":
        return
    from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs
    from rotorsfd.harmonic.periodic import continue_periodic
    from rotorsfd.quasiperiodic.torus_stability import torus_state

    def newmark(i: int, count: int):
        q0, v0 = torus_state(lattice, branch.X[i], branch.omega[i], branch.wb[i])
        inputs = time_domain_inputs(system, float(branch.omega[i]))
        return integrate_periods(inputs, q0, v0, steps_per_period=200, periods=count,
                                 record_dofs=system.nl_dofs, record_periods=1,
                                 poincare_periods=1)

    newmark(0, 2)                                                              # warm
    runs = [timed(lambda i=i: newmark(i, periods))[1:] for i in (0, n // 2, n - 1)]
    c_td = sum(c for c, _ in runs) / len(runs)
    w_td = sum(w for _, w in runs) / len(runs)
    print(f"time integration: {periods} periods at T/200, {c_td:.2f} s CPU ({w_td:.1f} s "
          f"wall) per speed (mean of Omega~ {branch.lam[0] / OMEGA_REF:.3f}, "
          f"{branch.lam[n // 2] / OMEGA_REF:.3f}, {branch.lam[-1] / OMEGA_REF:.3f}); "
          f"{n} speeds: {c_td * n:.0f} s CPU; ratio {c_td * n / c_torus:.0f}x CPU "
          f"({w_td * n / w_torus:.0f}x wall)")
    constant = build_system(load_config("examples/paper_pitching.toml"))
    pproblem = constant.periodic_problem("speed")

    def periodic():
        return continue_periodic(pproblem, 0.8 * OMEGA_REF, stop * OMEGA_REF, 17, ds=step,
                                 ds_max=step, harmonics_tol=None, max_points=1000)

    continue_periodic(pproblem, 0.8 * OMEGA_REF, 0.802 * OMEGA_REF, 17, ds=step,
                      harmonics_tol=None)                                      # warm
    pb, c_hb, w_hb = timed(periodic)
    per = c_hb / pb.n_points
    print(f"periodic HB, H = 17 (35 reals per DOF, constant pitching 6 rad/s): "
          f"{pb.n_points} points in {c_hb:.2f} s CPU ({w_hb:.1f} s wall), "
          f"{1e3 * per:.1f} ms CPU per point; torus / periodic per point "
          f"{(c_torus / n) / per:.2f}x")


if __name__ == "__main__":
    main()
