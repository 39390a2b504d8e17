"""Dual-spool torus branch (issue 20 item 3): the condensation per harmonic
(:class:`~rotorsfd.quasiperiodic.dual_frequency.HarmonicCondenser`, the linear part is
time-invariant) against the generic one LU per k1 block
(:class:`~rotorsfd.quasiperiodic.torus_linear.TorusCondenser` with its banded columns, the
honest baseline: what the torus code does for any problem), side by side on the same
branch. Measured (2 loaded cores): 29 points 5.14 s -> 1.11 s CPU (4.6x), the same branch
to 7e-13; and the branch against time
integration at every one of its speeds.

Problem: examples/dual_spool_unbalance.toml (72 DOF, two SFDs, LP 150 g mm and HP
400 g mm), box (3, 3), Omega_LP = 150 ... 160 rad/s.

Run: ``python -m benchmarks.bench_dual_spool`` (CPU seconds, time.process_time).
"""

from __future__ import annotations

import time

import numpy as np

import benchmarks.common as common  # noqa: F401  (one BLAS thread before numpy loads)
from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_system
from rotorsfd.quasiperiodic import TorusLattice, continue_torus
from rotorsfd.quasiperiodic.dual_frequency import dual_spool_problem
from rotorsfd.quasiperiodic.torus_linear import TorusCondenser


def main() -> None:
    system = build_system(load_config("examples/dual_spool_unbalance.toml"))
    lattice = TorusLattice(3, 3)
    out = {}
    for label, cls in (("one LU per k1 block (TorusCondenser)", TorusCondenser),
                       ("one LU per harmonic (HarmonicCondenser)", None)):
        problem = dual_spool_problem(system)
        if cls is not None:
            problem.info["condenser"] = cls
        continue_torus(problem, 150.0, 150.5, lattice, tol=1e-8)          # warm up
        t0 = time.process_time()
        branch = continue_torus(problem, 150.0, 160.0, lattice, tol=1e-8, ds_max=0.05)
        out[label] = (time.process_time() - t0, branch)
        print(f"{label}: {branch.n_points} points in {out[label][0]:.2f} s CPU")
    (ta, a), (tb, b) = out.values()
    diff = np.abs(a.X[-1] - b.X[-1]).max() / np.abs(a.X[-1]).max()
    print(f"speed-up {ta / tb:.1f}x; last points differ by {diff:.1e} (relative)")
    inputs = time_domain_inputs(system, 150.0)
    t0 = time.process_time()
    integrate_periods(inputs, 0.0, 0.0, steps_per_period=400, periods=300,
                      record_dofs=system.nl_dofs, record_periods=1, poincare_periods=1)
    t_td = time.process_time() - t0
    print(f"time integration, 300 LP periods at T/400: {t_td:.2f} s CPU per speed, "
          f"{b.n_points} speeds {t_td * b.n_points:.1f} s")


if __name__ == "__main__":
    main()
