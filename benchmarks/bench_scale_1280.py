"""The 1280-element stepped rotor (5124 DOF) before / after (issue 17 item 2, HB side):
every workload of the issue's targets in a fresh process, CPU seconds and peak memory.

Workloads (:data:`WORKLOADS`), each ``python -m benchmarks.bench_scale_1280 --one NAME``
in its own interpreter (so that the peak memory is the workload's: ``VmHWM`` of
/proc/self/status, the build included):

- ``point``: one condensed HB point at 0.8 w1, tol 1e-10 (median of 3 after a warm-up);
- ``branch``: the 56-point branch (``[analysis.response]`` options, adaptive H);
- ``stability``: that branch and the Floquet multipliers of every point (M = 400; the
  Floquet kernels warmed up on the first point before, like the HB kernels by a point);
- ``modal-point`` / ``modal-stability``: the same with modal damping 0.2 % of 6 modes;
- ``full-point`` / ``full-point-modal``: one full-model HB point (every DOF an unknown,
  CSR Jacobian + SuperLU) at 0.97 w1, tol 1e-13; the modal one under an address-space
  limit (:data:`AS_LIMIT_GIB`) and a time limit (:data:`TIMEOUT_S`);
- ``critical``: the first forward critical speed (median of 3);
- ``modal-cli``: the whole ``rotorsfd modal`` command on the config of the modal-damping
  rotor (``/usr/bin/time``: user + sys CPU, maximum resident set), second of two runs.

The CPU is ``time.process_time`` of the workload alone (build apart); wall times move with
the load of the shared machine, CPU much less. ``python -m benchmarks.bench_scale_1280
[NAME ...] [--out FILE]`` prints one JSON line per workload and the load average.
"""

from __future__ import annotations

import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path
from types import SimpleNamespace
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
N_ELEMENTS = 1280
WORKLOADS = ("point", "branch", "stability", "modal-point", "modal-stability", "full-point",
             "full-point-modal", "critical", "modal-cli")
AS_LIMIT_GIB = 8.0
TIMEOUT_S = 300.0


def one(name: str) -> dict[str, Any]:
    """Run workload ``name`` in this process (module docstring)."""
    from benchmarks import scale_hb as S
    from rotorsfd.harmonic.periodic import solve_periodic

    modal = name.startswith("modal") or name.endswith("modal")
    c0 = time.process_time()
    if name == "critical":
        from benchmarks.bench_scale import config, first_critical

        cfg = config(N_ELEMENTS)
        from rotorsfd import api

        system = api.build_system(cfg)
        build = time.process_time() - c0
        cpu, wall, w1 = cpu_timed(lambda: first_critical(system, cfg), 3)
        return {"build_cpu": build, "cpu": cpu, "wall": wall, "result": w1}
    system, problem, w1, opts = S.build(N_ELEMENTS, S.MODAL_MODES if modal else None)
    build = time.process_time() - c0
    out: dict[str, Any] = {"build_cpu": build, "n_dof": system.n_dof}
    if name.startswith("full"):
        cpu, wall, res = cpu_timed(lambda: solve_periodic(problem, 0.97 * w1, S.H, tol=1e-13,
                                                          condensed=False))
        out.update(cpu=cpu, wall=wall, iterations=res.iterations,
                   result=float(np.abs(res.X).max()))
        return out
    S.point(problem, w1)                                     # warm-up (kernels, caches)
    if name.endswith("point"):
        cpu, wall, res = cpu_timed(lambda: S.point(problem, w1), 3)
        out.update(cpu=cpu, wall=wall, result=float(np.abs(res.X).max()))
        return out
    cpu, wall, br = cpu_timed(lambda: S.branch(problem, w1, opts))
    out.update(cpu=cpu, wall=wall, points=br.n_points, lam_end=float(br.lam[-1] / w1))
    if name.endswith("stability"):
        # warm-up on the first point: the monodromy kernel's JIT (a fresh process)
        S.stability(problem, SimpleNamespace(lam=br.lam[:1], X=br.X[:1], n_points=1))
        cs, ws, mu = cpu_timed(lambda: S.stability(problem, br))
        out.update(cpu_branch=cpu, cpu_stability=cs, cpu=cpu + cs, wall=wall + ws,
                   result=float(mu.max()))
    return out


def modal_cli() -> dict[str, Any]:
    """``rotorsfd modal`` of the modal-damping rotor under /usr/bin/time (second run)."""
    from benchmarks.bench_scale import stepped_rotor_config
    from rotorsfd.io.config import to_toml

    d = stepped_rotor_config(N_ELEMENTS)
    d["rotor"]["damping"] = {"kind": "modal", "ratio": 0.002, "modes": 6}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "rotor1280.toml"
        path.write_text(to_toml(d))
        res: dict[str, Any] = {}
        for _ in range(2):
            t0 = time.perf_counter()
            proc = subprocess.run(["/usr/bin/time", "-f", "%U %S %M", sys.executable, "-m",
                                   "rotorsfd", "modal", "-q", str(path), "-o",
                                   str(Path(tmp) / "out")], capture_output=True, text=True,
                                  check=True)
            wall = time.perf_counter() - t0
            user, sys_, kib = proc.stderr.strip().splitlines()[-1].split()
            res = {"cpu": float(user) + float(sys_), "wall": wall,
                   "peak_gib": int(kib) / 2**20}
            crit = (Path(tmp) / "out" / "critical_speeds.csv").read_text().splitlines()
            res["result"] = crit[1] if len(crit) > 1 else ""
    return res


def run_one(name: str) -> dict[str, Any]:
    """Workload ``name`` in a fresh process: its JSON record (or the reason it failed)."""
    if name == "modal-cli":
        return {"workload": name, "load": os.getloadavg()[0], **modal_cli()}
    return {"workload": name,
            **fresh_process_record("benchmarks.bench_scale_1280", [name], TIMEOUT_S)}


def main(argv: list[str]) -> None:
    if len(argv) >= 2 and argv[0] == "--one":
        # the dense path of before can exhaust memory
        child_record(lambda: one(argv[1]),
                     AS_LIMIT_GIB if argv[1] == "full-point-modal" else None)
        return
    dest, argv = pop_option(argv, "--out")
    write_jsonl((run_one(name) for name in argv or list(WORKLOADS)),
                None if dest is None else Path(dest))


if __name__ == "__main__":
    main(sys.argv[1:])
