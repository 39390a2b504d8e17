"""The torus (two-frequency HB) of the stepped rotor under harmonic pitching at 320 and 1280
elements (1284 / 5124 DOF), before / after the banded torus linear part (issue 17 item 2):
CPU seconds and peak memory of each workload in a fresh process.

Problem: the stepped rotor of :mod:`benchmarks.bench_scale` (SFD at node 1) on a base
pitching as in ``examples/paper_harmonic_pitching.toml`` at w_b = 60 rad/s, zero mean rate,
with the angle amplitude 0.005 rad instead of 0.05 (at 0.05 the journal of this heavier,
longer rotor reaches contact at 0.8 w1; at 0.005 its orbit is about 0.5 C), the torus on
the box lattice (3, 2).

Workloads (``python -m benchmarks.bench_torus_scale --one NAME N`` in its own interpreter,
the peak memory its ``VmHWM``, the build included):

- ``point``: one torus at 0.8 w1 (w1 the first critical speed), Newton to tol 1e-10, the
  median of 3 after a warm-up;
- ``branch``: a short branch from 0.8 w1 towards 0.9 w1 (``continue_torus`` defaults,
  at most :data:`BRANCH_POINTS` points), after a warm-up point.

"Before" is the code of a given tree (``--before DIR``: its ``src``, e.g. ``git archive``
of the commit before the change), "after" this tree; each run with ``PYTHONPATH`` set to
the tree. The dense path of before forms the (b + 1, n, n) complex base-term stacks, so
its runs have an address-space limit (:data:`AS_LIMIT_GIB`) and a time limit
(:data:`TIMEOUT_S`). The CPU is ``time.process_time`` of the workload alone (build
apart). ``python -m benchmarks.bench_torus_scale [--before DIR] [--out FILE]`` prints one
JSON line per run and the load average.

``--small``: below DENSE_MAX_DOF, the dense stacks (``torus_problem(banded=False)``)
against the band (the default there too) in one process, in turn (A B A B): a point
(median of 5 after a warm-up) and a 10-point branch from it, on the paper rotor
(examples/paper_harmonic_pitching.toml, 0.9 x 811.3 rad/s) and the stepped rotor at 16,
48, 96 elements (68, 196, 388 DOF; 0.8 w1), with the largest difference of the points.
"""

from __future__ import annotations

import json
import os
import sys
import time
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import (
    child_record,
    cpu_timed,
    fresh_process_record,
    pop_option,
    write_jsonl,
)

ROOT = Path(__file__).resolve().parents[1]
SIZES = (320, 1280)
WORKLOADS = ("point", "branch")
BRANCH_POINTS = 8
AS_LIMIT_GIB = 14.0
TIMEOUT_S = 900.0
PITCHING = {"pitching": {"law": "harmonic", "value": 0.0, "frequency": 60.0,
                         "angle_amplitude": 0.005}}


def build(n_elements: int) -> tuple[Any, Any, float]:
    """(system, torus problem in the speed, first critical speed [rad/s])."""
    from benchmarks.bench_scale import stepped_rotor_config
    from rotorsfd import api
    from rotorsfd.io.config import config_from_dict
    from rotorsfd.linear import critical_speeds
    from rotorsfd.quasiperiodic import torus_problem

    d = stepped_rotor_config(n_elements)
    plain = config_from_dict(d)
    w1 = critical_speeds(api.build_system(plain), n=1, speed_range=(
        0.0, plain.analysis.modal.critical_speed_max))[0].speed_rad_s
    d["base"] = PITCHING
    system = api.build_system(config_from_dict(d))
    return system, torus_problem(system), w1


def one(name: str, n_elements: int) -> dict[str, Any]:
    """Run workload ``name`` at ``n_elements`` in this process (module docstring)."""
    from rotorsfd.quasiperiodic import TorusLattice, continue_torus, solve_torus

    c0 = time.process_time()
    system, problem, w1 = build(n_elements)
    out: dict[str, Any] = {"build_cpu": time.process_time() - c0, "n_dof": system.n_dof,
                           "banded": getattr(problem, "bands", None) is not None}
    lat = TorusLattice(3, 2)

    def point() -> Any:
        return solve_torus(problem, 0.8 * w1, lat, tol=1e-10)

    first = point()                                          # warm-up (kernels, caches)
    if name == "point":
        cpu, wall, res = cpu_timed(point, 3)
        s = system.nl_dofs
        out.update(cpu=cpu, wall=wall, iterations=res.iterations,
                   result=float(np.abs(res.X[:, s]).max() / system.length_scale))
        return out
    cpu, wall, br = cpu_timed(lambda: continue_torus(problem, 0.8 * w1, 0.9 * w1, lat,
                                                     X0=first.X, max_points=BRANCH_POINTS))
    s = system.nl_dofs
    out.update(cpu=cpu, wall=wall, points=br.n_points, lam_end=float(br.lam[-1] / w1),
               result=float(np.abs(br.X[-1][:, s]).max() / system.length_scale))
    return out


def small() -> list[dict[str, Any]]:
    """The ``--small`` comparison (module docstring)."""
    from rotorsfd import api
    from rotorsfd.io.config import load_config
    from rotorsfd.quasiperiodic import TorusLattice, continue_torus, solve_torus, torus_problem

    lat = TorusLattice(3, 2)
    cases = [("paper rotor", api.build_system(load_config(
        ROOT / "examples" / "paper_harmonic_pitching.toml")), 0.9 * 811.3)]
    for ne in (16, 48, 96):
        sysm, _, w1 = build(ne)
        cases.append((f"stepped {ne} el.", sysm, 0.8 * w1))
    out = []
    for label, system, om in cases:
        res: dict[bool, list[tuple[float, float, Any]]] = {False: [], True: []}
        for banded in (False, True, False, True):
            problem = torus_problem(system, banded=banded)
            solve_torus(problem, om, lat, tol=1e-10)                 # warm-up
            cpu, _, pt = cpu_timed(lambda p=problem, w=om: solve_torus(p, w, lat, tol=1e-10),
                                   5)
            cb, _, _ = cpu_timed(lambda p=problem, x=pt.X, w=om: continue_torus(
                p, w, 1.1 * w, lat, X0=x, max_points=10))
            res[banded].append((cpu, cb, pt.X))
        ref = res[False][0][2]
        out.append({"case": label, "n_dof": system.n_dof, "load": os.getloadavg()[0],
                    "dense_point": [r[0] for r in res[False]],
                    "banded_point": [r[0] for r in res[True]],
                    "dense_branch": [r[1] for r in res[False]],
                    "banded_branch": [r[1] for r in res[True]],
                    "difference": float(np.abs(res[True][0][2] - ref).max()
                                        / np.abs(ref).max())})
    return out


def run_one(name: str, n_elements: int, src: Path, label: str) -> dict[str, Any]:
    """Workload ``name`` in a fresh process on the tree ``src``: its JSON record (or the
    reason it failed)."""
    env = {**os.environ, "PYTHONPATH": str(src), "OPENBLAS_NUM_THREADS": "1"}
    return {"code": label, "workload": name, "n_elements": n_elements,
            **fresh_process_record("benchmarks.bench_torus_scale", [name, str(n_elements)],
                                   TIMEOUT_S, env)}


def main(argv: list[str]) -> None:
    if len(argv) >= 3 and argv[0] == "--one":
        child_record(lambda: one(argv[1], int(argv[2])), AS_LIMIT_GIB)
        return
    if argv[:1] == ["--small"]:
        for rec in small():
            print(json.dumps(rec), flush=True)
        return
    dest, argv = pop_option(argv, "--out")
    before, argv = pop_option(argv, "--before")
    sizes = [int(a) for a in argv] or list(SIZES)
    trees = [("after", ROOT / "src")] + ([("before", Path(before) / "src")] if before else [])
    write_jsonl((run_one(name, n, src, label) for n in sizes for name in WORKLOADS
                 for label, src in trees), None if dest is None else Path(dest))


if __name__ == "__main__":
    main(sys.argv[1:])
