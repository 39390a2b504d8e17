"""Benchmark of HB-AFT continuation (run: python benchmarks/bench_hb.py [--quick]).

Generic 84-DOF chain mimicking the paper rotor (21 nodes x 4 DOF Euler-Bernoulli shaft,
disk with gyroscopic coupling at node 8, springs at nodes 1 and 21) with one 2-DOF
nonlinearity: the pi-film SFD of the paper (mu 0.0051 Pa s, C 0.127 mm, C/R 0.485 %,
L/D 0.325) at node 1, unbalance 144.02 g mm at the disk; speed 0.6..1.5 x 811.3 rad/s.

For H = 3 and 8: the whole branch condensed (after a warm-up run), then the same branch
by the full (uncondensed) path (``--quick``: its first 8 points); time per continuation
point (wall and CPU), and the ratio. BLAS runs on one thread (the solvers scope it themselves).
With ``--paper`` the same on the configured paper rotor (examples/paper_rotor.toml).
"""

from __future__ import annotations

import sys
import time

from rotorsfd.harmonic import continue_periodic
from rotorsfd.harmonic.examples import beam_rotor
from rotorsfd.sfd import SFD

W1 = 811.3


def _timed(problem, H, condensed, max_points=2000):
    t0, c0 = time.perf_counter(), time.process_time()
    b = continue_periodic(problem, 0.6 * W1, 1.5 * W1, H, condensed=condensed,
                          max_points=max_points)
    return b, time.perf_counter() - t0, time.process_time() - c0


def run(problem, label: str, quick: bool) -> None:
    print(f"\n{label}: n_dof={problem.n_dof}, nl_dofs={list(problem.nl_dofs)}")
    print(f"{'H':>3} {'path':>10} {'points':>7} {'wall [s]':>9} {'CPU [s]':>8} "
          f"{'ms/point':>9} {'CPU ms/pt':>9} {'N_f':>5} {'folds':>6}")
    for H in (3, 8):
        continue_periodic(problem, 0.6 * W1, 0.65 * W1, H)            # warm-up
        bc, wc, cc = _timed(problem, H, True)
        n_full = 8 if quick else 2000                               # whole branch
        bf, wf, cf = _timed(problem, H, False, max_points=n_full)
        for name, b, w, c in (("condensed", bc, wc, cc), ("full", bf, wf, cf)):
            print(f"{H:>3} {name:>10} {b.n_points:>7} {w:>9.3f} {c:>8.3f} "
                  f"{1e3 * w / b.n_points:>9.2f} {1e3 * c / b.n_points:>9.2f} "
                  f"{b.n_samples:>5} {len(b.folds()):>6}")
        ratio = (wf / bf.n_points) / (wc / bc.n_points)
        ratio_cpu = (cf / bf.n_points) / (cc / bc.n_points)
        print(f"    H={H}: condensed is {ratio:.0f}x faster per point (CPU {ratio_cpu:.0f}x); "
              f"branch ok={bc.success} ({bc.message[:60]})")


def paper_problem():
    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem

    m = build_model(load_config("examples/paper_rotor.toml"))
    return RotorSystem(m.rotor, m.sfd, m.sfd_node, m.unbalances, m.base_motion
                       ).periodic_problem()


if __name__ == "__main__":
    quick = "--quick" in sys.argv
    sfd = SFD.from_ratios(0.0051, 1.27e-4, 0.00485, 0.325, cavitation="pi")
    run(beam_rotor(unbalance=1.4402e-4, sfd=sfd), "generic 84-DOF chain + pi-film SFD", quick)
    if "--paper" in sys.argv:
        run(paper_problem(), "paper rotor (examples/paper_rotor.toml)", quick)
