"""``python -m benchmarks [--quick] [--only NAME ...] [--repeat N] [--json PATH]``.

Runs the benchmarks side by side, prints one table and writes ``benchmarks/results.json``
(``--quick``: ``benchmarks/results-quick.json``) with the machine, the load average at
start and end, versions and every row. ``--quick`` is the ~30 s smoke run of CI: every
benchmark on a tiny size, one repeat, no time is asserted.
"""

from __future__ import annotations

import argparse
import importlib
import json
import os
import sys
import time
import traceback
from collections.abc import Callable
from pathlib import Path

import benchmarks.common as common  # sets one BLAS thread before numpy loads

HERE = Path(__file__).resolve().parent


REGISTRY: dict[str, tuple[str, str]] = {
    "hb": ("HB continuation: condensed vs full", "bench_hb:run"),
    "stability": ("Floquet per point: CB Newmark vs full Newmark vs Hill",
                  "bench_stability:run_points"),
    "monodromy": ("Floquet monodromy per point: compiled loop vs numpy loop",
                  "bench_stability:run_monodromy"),
    "timedomain": ("2000 periods x 200 steps: ours vs scipy vs ROSS", "bench_timedomain:run"),
    "step-control": ('simulate on paper cases: steps_per_period = "auto" vs the fixed T/200',
                     "bench_timedomain:step_rows"),
    "chart": ("stability chart: serial vs threads vs process pool vs Dask",
              "bench_stability:run_chart"),
    "coldstart": ("cold start: CLI and first calls of the compiled kernels",
                  "bench_coldstart:run"),
    "memory": ("peak resident memory", "bench_memory:run"),
    "scaling": ("cost per continuation point against H and shaft elements",
                "bench_scaling:run"),
    "branch-stability": ("stability of every branch point + bifurcation location",
                         "bench_branch_stability:run"),
    "branch-points": ("branch_stability: the branch-point scan on the continuation's "
                      "signs vs re-evaluating every point vs none", "bench_branch_points:run"),
    "two-parameter": ("HB problems of a two-parameter family (fold curves): stored terms vs "
                      "built from scratch", "bench_two_parameter:run"),
    "pencil": ("dense condensation of a branch (full modal damping): one eigendecomposition "
               "per harmonic vs an LU per harmonic and point", "bench_pencil:run"),
    "nf": ("AFT samples N_f along a pitching branch: adaptive vs the old grow-only rule",
           "bench_nf:run"),
    "linear": ("linear part of the HB problem on a moving base: assembled once vs per call",
               "bench_linear:run"),
    "convergence": ("rotorsfd response: convergence defaults (auto H, Floquet step control, "
                    "checked bifurcations) vs fixed H = 3, M = 400", "bench_convergence:run"),
    "scale": ("first critical speed and modal of a stepped rotor, 80-2560 elements: sparse "
              "shift-invert vs the dense eig path", "bench_scale:run"),
    "scale-modal": ("modal damping of a few modes on the stepped rotor: banded + low-rank "
                    "vs the full damping matrix (linear, Floquet, time step)",
                    "bench_scale_modal:run"),
    "scale-timedomain": ("500 periods x 200 steps of the stepped rotor, 80-1280 elements: "
                         "reduced (Craig-Bampton) step vs the full dense step",
                         "bench_scale_timedomain:run"),
    "scale-ltp": ("run-up and LTP stability chart of the stepped rotor at 1280 elements on "
                  "a pitching base: banded / reduced vs the dense path of before (fresh "
                  "processes, CPU s and VmHWM; --quick: 112 elements, banded only)",
                  "bench_scale_ltp:run"),
    "elements": ("nonlinear elements: one SFD through the element interface vs the previous "
                 "path; cost against 1, 2, 4, 8 elements", "bench_elements:run"),
    "film": ("squeeze film models: force + Jacobian per sample, short vs finite-length film; "
             "the paper rotor's branch with each", "bench_film:run"),
    "attractors": ("attractor census: 256 starts at one speed on 2 workers, stopped once "
                   "settled, vs 2000 periods each", "bench_attractors:run"),
    "ns-curve": ("Neimark-Sacker curve: one evaluation of the augmented system, batched "
                 "shifted Hill operator vs the previous loops", "bench_ns_curve:run"),
    "paper": ("rotorsfd paper: the full reproduction and --quick, wall and CPU (not in "
              "--quick)", "bench_paper:run"),
}


def _function(name: str) -> Callable[..., list[common.Row]]:
    module, func = REGISTRY[name][1].split(":")
    return getattr(importlib.import_module(f"benchmarks.{module}"), func)


def fmt_value(r: common.Row) -> str:
    if r.unit == "s":
        v = r.value
        return f"{v * 1e3:.2f} ms" if v < 1.0 else f"{v:.2f} s"
    return f"{r.value:.4g} {r.unit}"


def table(rows: list[common.Row]) -> str:
    """Markdown table of the rows."""
    lines = ["| bench | case | method | median | ratio | n | note |",
             "|---|---|---|---:|---:|---:|---|"]
    for r in rows:
        ratio = "" if r.ratio is None else f"{r.ratio:.3g}x"
        lines.append(f"| {r.bench} | {r.case} | {r.method} | {fmt_value(r)} | {ratio} | "
                     f"{r.repeat} | {r.note} |")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    reg = REGISTRY
    ap = argparse.ArgumentParser(prog="python -m benchmarks", description=__doc__.split("\n")[2])
    ap.add_argument("--quick", action="store_true", help="~30 s smoke run (tiny sizes)")
    ap.add_argument("--only", action="append", choices=sorted(reg), metavar="NAME",
                    help=f"run only this benchmark (repeatable): {', '.join(reg)}")
    ap.add_argument("--repeat", type=int, default=None,
                    help="repeats per figure (median); default 3, --quick 1")
    ap.add_argument("--json", type=Path, default=None, help="results file")
    a = ap.parse_args(argv)
    repeat = a.repeat or (1 if a.quick else 3)
    names = a.only or list(reg)
    out = a.json or HERE / ("results-quick.json" if a.quick else "results.json")
    info = common.machine_info()
    load0 = os.getloadavg()
    print(f"# {info['cpu']}, {info['usable_cores']}/{info['cores']} cores, "
          f"load {load0[0]:.2f} {load0[1]:.2f} {load0[2]:.2f}; Python {info['python']}, "
          f"numpy {info['numpy']}; BLAS 1 thread; {'quick' if a.quick else 'full'} run, "
          f"median of {repeat}", flush=True)
    rows: list[common.Row] = []
    timings: dict[str, float] = {}
    failed: dict[str, str] = {}
    t_all = time.perf_counter()
    with common.one_blas_thread():
        for name in names:
            title, fun = reg[name][0], _function(name)
            print(f"## {name}: {title} ...", flush=True)
            t0 = time.perf_counter()
            try:
                new = fun(quick=a.quick, repeat=repeat)
            except Exception as exc:  # report, keep going: the other benchmarks still run
                traceback.print_exc()
                failed[name] = f"{type(exc).__name__}: {exc}"
                new = []
            timings[name] = time.perf_counter() - t0
            rows += new
            for r in new:
                ratio = "" if r.ratio is None else f" ({r.ratio:.3g}x {r.ref})"
                print(f"   {r.case} | {r.method}: {fmt_value(r)}{ratio}  {r.note}", flush=True)
            print(f"   [{name}: {timings[name]:.1f} s]", flush=True)
    load1 = os.getloadavg()
    total = time.perf_counter() - t_all
    print()
    print(table(rows))
    print(f"\n{info['cpu']}, {info['usable_cores']} cores, load average at start "
          f"{load0[0]:.2f}, at end {load1[0]:.2f}; total {total:.0f} s")
    data = {"machine": info, "load_average_start": load0, "load_average_end": load1,
            "git": common.git_revision(), "quick": a.quick, "repeat": repeat,
            "total_s": total, "bench_s": timings, "failed": failed,
            "rows": common.rows_to_json(rows)}
    tmp = out.with_suffix(".json.tmp")
    tmp.write_text(json.dumps(data, indent=1, default=str))
    tmp.replace(out)
    print(f"wrote {out}")
    for name, msg in failed.items():
        print(f"FAILED {name}: {msg}", file=sys.stderr)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
