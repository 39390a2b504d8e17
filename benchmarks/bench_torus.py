"""Torus branch (two-frequency HB, issue 19 item 6) against what a user does today, time
integration of ``--periods`` rotor periods (2000 in the paper) at every speed, side by side
in one run; plus the cost per continuation point against the periodic HB with the same
total number of harmonics.

Problem: the paper rotor (84 DOF, pi-film SFD) at U = 144.02 g mm under harmonic pitching
``w_by = A0 w_b sin(w_b t)``, A0 = 0.05 rad, w_b = 60 rad/s; speeds Omega~ 0.8-1.0; the
torus on the box (3, 2) (35 real unknowns per DOF); the periodic HB (H = 17, 35 reals per
DOF) of the same rotor under the constant pitching rate of examples/paper_pitching.toml;
the time integration compiled Newmark at T/200 from the torus state.

Run: ``python -m benchmarks.bench_torus [--quick]`` (quick: 200 periods, a short branch).
The time integration is timed at one speed and multiplied by the branch's number of
speeds (every speed costs the same number of steps).
"""

from __future__ import annotations

import argparse
import time

import benchmarks.common as common  # noqa: F401  (one BLAS thread before numpy loads)
from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_system
from rotorsfd.quasiperiodic import TorusLattice, continue_torus, torus_problem
from rotorsfd.quasiperiodic.torus_stability import torus_state

PITCHING = ["base.pitching.law=harmonic", "base.pitching.value=0 rad/s",
            "base.pitching.frequency=60 rad/s", "base.pitching.angle_amplitude=0.05 rad"]
OMEGA_REF = 811.3


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--periods", type=int, default=2000)
    args = parser.parse_args()
    periods = 200 if args.quick else args.periods
    stop = 0.85 if args.quick else 1.0
    system = build_system(load_config("examples/paper_pitching.toml", PITCHING))
    lattice = TorusLattice(3, 2)
    t0 = time.perf_counter()
    branch = continue_torus(torus_problem(system), 0.8 * OMEGA_REF, stop * OMEGA_REF,
                            lattice, ds=0.02, ds_max=0.05)
    t_torus = time.perf_counter() - t0
    n = branch.n_points
    q0, v0 = torus_state(lattice, branch.X[0], branch.omega[0], branch.wb[0])
    inputs = time_domain_inputs(system, float(branch.omega[0]))
    t0 = time.perf_counter()
    integrate_periods(inputs, q0, v0, steps_per_period=200, periods=periods,
                      record_dofs=system.nl_dofs, record_periods=1, poincare_periods=1)
    t_td = time.perf_counter() - t0
    constant = build_system(load_config("examples/paper_pitching.toml"))
    t0 = time.perf_counter()
    periodic = continue_periodic(constant.periodic_problem("speed"), 0.8 * OMEGA_REF,
                                 stop * OMEGA_REF, 17, ds=0.02, ds_max=0.05,
                                 harmonics_tol=None)
    t_hb = time.perf_counter() - t0
    print(f"torus branch, box (3, 2): {n} points in {t_torus:.1f} s, "
          f"{t_torus / n:.2f} s per point, grid {branch.grid[0]} x {branch.grid[1]}, "
          f"Omega~ {branch.lam[0] / OMEGA_REF:.3f}-{branch.lam[-1] / OMEGA_REF:.3f} "
          f"({branch.message})")
    print(f"time integration: {periods} periods at T/200 in {t_td:.1f} s per speed, "
          f"{n} speeds: {t_td * n:.1f} s; ratio {t_td * n / t_torus:.1f}x")
    print(f"periodic HB, H = 17: {periodic.n_points} points in {t_hb:.1f} s, "
          f"{t_hb / periodic.n_points:.3f} s per point; torus / periodic per point "
          f"{(t_torus / n) / (t_hb / periodic.n_points):.1f}x")


if __name__ == "__main__":
    main()
