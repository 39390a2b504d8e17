"""Attractor census (issue 21 item 4): 256 starts at one speed on the paper rotor, on the
process pool of the sweeps (2 workers), each start stopped once its Poincare points
repeat or once captured by an orbit an earlier start of its batch settled on (the first
row: without capture, the code before), against the same starts run for the paper's
fixed 2000 periods (estimated from the measured cost per period: every period costs the
same number of steps).

Case: examples/paper/fig23_time_domain.toml (C/R = 0.728 %, U = 252 g mm, w_by = 10
rad/s) at Omega~ = 1.075, where the main branch and the isola coexist; starts around the
HB orbit (``around = "orbit"``); the file's converged step T/800 and the paper's T/200.

CPU: of this process and of the pool's processes (the forkserver and the workers, read
with psutil before the pool shuts down; without psutil only the starts' own CPU), with the
load average: on the shared machine the wall time moves with the load, ``CPU / 2`` is what
2 idle cores would take.

Run: ``python -m benchmarks --only attractors`` (quick: 8 starts at T/200).
"""

from __future__ import annotations

import os
import time
from pathlib import Path

import benchmarks.common as common  # noqa: F401  (one BLAS thread before numpy loads)
from benchmarks.common import Row

CONFIG = Path(__file__).resolve().parents[1] / "examples/paper/fig23_time_domain.toml"
FIXED_PERIODS = 2000


def process_cpu() -> tuple[float, float | None]:
    """CPU seconds [user + system] of this process and of its live descendants (None
    without psutil)."""
    try:
        import psutil
    except ImportError:
        return time.process_time(), None
    me = psutil.Process()
    own = sum(me.cpu_times()[:2])
    kids = 0.0
    for p in me.children(recursive=True):
        try:
            kids += sum(p.cpu_times()[:2])
        except psutil.Error:           # exited meanwhile
            pass
    return own, kids


def census_row(n_starts: int, steps: int, workers: int = 2, capture_tol: float = 5e-3
               ) -> Row:
    from rotorsfd.analyses.attractors import CensusOptions
    from rotorsfd.analyses.attractors_config import run_census
    from rotorsfd.io.config import load_config
    from rotorsfd.studies.executors import make_executor

    config = load_config(CONFIG)
    opts = CensusOptions(n_starts=n_starts, steps_per_period=steps, around="orbit",
                         harmonics=16, capture_tol=capture_tol)
    load = os.getloadavg()[0]
    tic = time.perf_counter()
    own0, _ = process_cpu()
    with make_executor(workers) as ex:
        (c,) = run_census(config, speed_ratios=[1.075], search_path=CONFIG.parent,
                          options=opts, executor=ex)
        own1, pool = process_cpu()          # the pool's processes start after tic
    wall = time.perf_counter() - tic
    load = max(load, os.getloadavg()[0])
    periods = sum(r.periods_run for r in c.outcomes)
    cpu = sum(r.cpu for r in c.outcomes)
    total = own1 - own0 + (pool if pool is not None else cpu)
    captured = sum(r.note.startswith("captured") for r in c.outcomes)
    fixed = c.elapsed_integration * FIXED_PERIODS * c.n_starts / max(periods, 1)
    kinds = ", ".join(f"{a.motion} {len(a.members)}"
                      + (" at ({:.3f}, {:.3f}) C".format(*a.points[0][:2])
                         if a.period is not None else "") for a in c.attractors)
    how = "stopped once settled" + (f" or captured ({capture_tol:g} C)" if capture_tol
                                    else "")
    return Row("attractors", f"{n_starts} starts, Omega~ 1.075, T/{steps}, {workers} workers",
               how, wall, ratio=fixed / c.elapsed_integration,
               ref=f"{FIXED_PERIODS} periods each (estimated)",
               note=f"{periods / c.n_starts:.0f} periods per start ({captured} captured); "
                    f"CPU {total:.1f} s (this process {own1 - own0:.1f} s, the pool "
                    f"{'?' if pool is None else f'{pool:.1f}'} s, the starts {cpu:.1f} s): "
                    f"{total / workers:.1f} s on {workers} idle cores; load {load:.1f}; "
                    f"integration {c.elapsed_integration:.1f} s wall; HB + Floquet "
                    f"{c.elapsed_hb:.1f} s; {kinds}",
               extra={"periods_run": periods, "elapsed_integration_s": c.elapsed_integration,
                      "integration_cpu_s": cpu, "captured": captured, "cpu_total_s": total,
                      "cpu_process_s": own1 - own0, "cpu_pool_s": pool,
                      "cpu_per_core_s": total / workers, "load_1min": load,
                      "elapsed_hb_s": c.elapsed_hb, "attractors": kinds})


def run(quick: bool = False, repeat: int = 1) -> list[Row]:
    if quick:
        return [census_row(8, 200)]
    return [census_row(256, 800, capture_tol=0.0), census_row(256, 800),
            census_row(256, 200)]


if __name__ == "__main__":
    for r in run():
        print(r)
