"""Benchmark: the paper's Figure 19 study as one sweep (run: python benchmarks/bench_sweep.py
[--quick] [--workers N] [--harmonics H] [-o DIR]).

Paper rotor under constant pitching, C/R = 0.485 %: 11 pitching rates w_by = 0..10 rad/s
x 3 unbalances U = 144.02, 252, 360.04 g mm, each point a response branch over
Omega~ = 0.5..1.6 with stability; prints the wall time and the total unstable width in
Omega~ per (U, w_by) next to the paper's values (NOTES.md: U = 144.02 small at 0 and none
from 4 rad/s; U = 252 0.041 at 0, none from 7; U = 360.04 0.195 at 0, 0.119 at 10).
``--quick``: 3 x 2 points, H = 3.
"""

from __future__ import annotations

import argparse
import os
import shutil
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

ROOT = Path(__file__).resolve().parents[1]
PAPER = {144.02: {0: "small", 4: 0.0}, 252.0: {0: 0.041, 7: 0.0},
         360.04: {0: 0.195, 10: 0.119}}


def main() -> int:
    from rotorsfd.io.config import load_config
    from rotorsfd.studies import available_cpus, load_sweep, run_sweep

    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--quick", action="store_true")
    p.add_argument("--workers", type=int, default=available_cpus())
    p.add_argument("--harmonics", type=int, default=None)
    p.add_argument("-o", "--output", type=Path, default=None)
    args = p.parse_args()
    rates = [0, 5, 10] if args.quick else list(range(11))
    unbalances = [144.02, 360.04] if args.quick else [144.02, 252.0, 360.04]
    H = args.harmonics or (3 if args.quick else 8)
    config = load_config(ROOT / "examples" / "paper_pitching.toml",
                         ["elements.sfd.clearance_ratio=0.485 %",
                          f"analysis.response.harmonics={H}"])
    axes = {"unbalance[0].magnitude": [f"{u} g*mm" for u in unbalances],
            "base.pitching.value": [f"{w} rad/s" for w in rates]}
    out = args.output or Path(tempfile.mkdtemp(prefix="bench_sweep_"))
    if args.output is not None and out.exists():
        shutil.rmtree(out)
    t0 = time.perf_counter()
    result = run_sweep(config, axes, "response", directory=out, workers=args.workers,
                       progress=True)
    elapsed = time.perf_counter() - t0
    print(f"Figure 19 study: {len(unbalances)} x {len(rates)} points, H = {H}, "
          f"{args.workers} workers: {elapsed:.1f} s")
    print(result.summary())
    ds = load_sweep(out)
    width = ds.get("unstable_width_speed_ratio")
    print("U [g mm]  w_by [rad/s]  unstable width (Omega~)  paper   status")
    for i, u in enumerate(unbalances):
        for j, w in enumerate(rates):
            value = "n/a" if width is None else f"{float(width.values[i, j]):.4f}"
            ref = PAPER.get(u, {}).get(w, "")
            print(f"{u:8.2f}  {w:12d}  {value:>23}  {ref!s:>6}   "
                  f"{str(ds['message'].values[i, j]) or 'ok'}")
    if args.output is None:
        shutil.rmtree(out)
    return 0


if __name__ == "__main__":
    sys.exit(main())
