"""``rotorsfd paper``: the full reproduction (76 cases, both readings) and ``--quick``,
wall and CPU time (the command in a fresh interpreter, 2 workers, BLAS one thread).

Before / after (issue 17 item 5): the code before is any other source tree, run the same
way in turn with this one (A B A B ..., ``--before SRC``: a folder holding the package,
e.g. ``git archive b25da63 src examples | tar -x -C /tmp/base`` then ``--before
/tmp/base/src``); without it the rows carry the figures recorded below as the reference.

Recorded 2026-12-03, first on the shared 2-core machine at load 5-8 (wall about 1.6 x
CPU): before (862686d) full 1107 s wall / 682 s CPU, ``--quick`` 21.2 s / 33.5 s; the
changes then: no ``max_multiplier_outside`` eigenproblem per branch point, every case
ordered by its measured cost, each figure drawn as soon as its cases end. Then on a
2-core AMD EPYC (issue 17 item 5, before = b25da63): idle, the full run took 137 s wall,
254 s CPU; run in turn with ours at load 4-7 (``--before /tmp/base/src --keep DIR``, two
rounds): before 253.7 / 282.1 s wall, 249.5 / 260.3 s CPU, ours 438.7 / 386.8 s wall,
256.9 / 276.9 s CPU (the runs' CPU differs by more than the change between them at this
load), ``--quick`` 19.2-20.7 s wall, 12-14 s CPU both; every number of ``results.json``
the same in all four runs (1e-9, none moved). The changes: the dense modal-damping
condensation's truncation estimate copies the point's harmonics, dense D(p), K(p) from
the terms' dense forms (no scipy.sparse per call), the linear part's band scan stops at a
dense term, the unbalance derivative of the continuation parameter alone (the second
round also with the new CASE_COST order); counted: 9-10 % fewer complex LUs in the
calibrated branches, 10853 -> 38 scipy.sparse constructions in one; per case in one
process, base and ours in turn (the README's "Speed" row): calibrated branches 0-15 %
less CPU, the literal ones unchanged. Issue 17's 90 s (idle, 2 cores) is not reached:
the dense LAPACK condensation of the calibrated reading (modal damping on all modes, 84
DOF x 9-17 harmonics, at its flop rate) is about half of the run's CPU, the compiled
Newmark steps of the time-domain cases a quarter.

Not in ``python -m benchmarks --quick`` (the suite's smoke run stays under 75 s): the
quick row needs ~10-15 s, the full one minutes. Run: ``python -m benchmarks --only paper``
(full and quick) or ``python -m benchmarks.bench_paper [--quick] [--before SRC]
[--repeat N] [--keep DIR]`` (``--keep``: each run's ``results.json`` into DIR).
"""

from __future__ import annotations

import os
import resource
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.common import ROOT, Row

#: The code before (b25da63), recorded as above: mode -> (wall s, CPU s, load).
RECORDED_BEFORE = {"full": (137.0, 254.0, "0 (idle)"), "quick": (19.2, 12.1, "5.8")}


def paper_time(src: Path, quick: bool, keep: Path | None = None) -> tuple[float, float]:
    """(wall, CPU of the command and its workers) [s] of ``rotorsfd paper`` run from the
    package in ``src`` into a scratch folder (its ``results.json`` copied to the file
    ``keep`` if given, to compare the runs' numbers)."""
    out = Path(tempfile.mkdtemp(prefix="bench_paper_"))
    env = {**os.environ, "PYTHONPATH": str(src), "OPENBLAS_NUM_THREADS": "1"}
    cmd = [sys.executable, "-m", "rotorsfd", "paper", "-o", str(out / "paper"), "--quiet",
           "--workers", "2", *(["--quick"] if quick else [])]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    try:
        subprocess.run(cmd, cwd=ROOT, env=env, check=True, capture_output=True, text=True,
                       timeout=3600)
        if keep is not None:
            keep.parent.mkdir(parents=True, exist_ok=True)
            shutil.copyfile(out / "paper" / "results.json", keep)
    finally:
        shutil.rmtree(out, ignore_errors=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu


def run(quick: bool = False, repeat: int = 1, before: Path | None = None,
        keep: Path | None = None) -> list[Row]:
    """Rows of ``rotorsfd paper --quick`` and of the full run, ours and (``before``) the
    other source tree's in turn; none in the suite's smoke run (``quick``: module
    docstring). ``keep``: a folder for each run's ``results.json``
    (``<ours|before>-<quick|full>-<round>.json``)."""
    if quick:              # the benchmark suite's smoke run: too long for it
        print("   paper: skipped in --quick (see benchmarks/bench_paper.py)", flush=True)
        return []
    rows: list[Row] = []
    ours = ROOT / "src"
    load = os.getloadavg()[0]
    for mode in ("quick", "full"):
        runs: dict[str, list[tuple[float, float]]] = {"ours": [], "before": []}
        for i in range(max(1, repeat)):        # interleaved: load hits both alike
            for label, src in (("ours", ours), ("before", before)):
                if src is not None:
                    at = os.getloadavg()[0]
                    runs[label].append(paper_time(
                        src, mode == "quick",
                        None if keep is None else keep / f"{label}-{mode}-{i}.json"))
                    w, c = runs[label][-1]
                    print(f"   paper {mode} {label} round {i + 1}: {w:.1f} s wall, "
                          f"{c:.1f} s CPU (load {at:.1f} at start)", flush=True)
        wall, cpu = (sorted(x[i] for x in runs["ours"])[len(runs["ours"]) // 2]
                     for i in (0, 1))
        case = f"rotorsfd paper{' --quick' if mode == 'quick' else ''}, 2 workers"
        ref, ref_note = None, ""
        if runs["before"]:
            bw, bc = (sorted(x[i] for x in runs["before"])[len(runs["before"]) // 2]
                      for i in (0, 1))
            rows.append(Row("paper", case, "before (wall)", bw, unit="s", repeat=repeat,
                            note=f"CPU {bc:.0f} s; {before}"))
            ref = bw
        elif mode in RECORDED_BEFORE:
            bw, bc, bload = RECORDED_BEFORE[mode]
            ref, ref_note = bw, f"; before recorded at load {bload}: {bw:.0f} s wall, " \
                                f"{bc:.0f} s CPU"
        rows.append(Row("paper", case, "ours (wall)", wall, unit="s", repeat=repeat,
                        ratio=None if ref is None else wall / ref, ref="before",
                        note=f"CPU {cpu:.0f} s, load {load:.1f} at start{ref_note}",
                        extra={"cpu_s": cpu}))
    return rows


def main(argv: list[str]) -> int:
    quick_only = "--quick" in argv
    before = Path(argv[argv.index("--before") + 1]) if "--before" in argv else None
    repeat = int(argv[argv.index("--repeat") + 1]) if "--repeat" in argv else 1
    keep = Path(argv[argv.index("--keep") + 1]) if "--keep" in argv else None
    if quick_only:
        rows = []
        wall, cpu = paper_time(ROOT / "src", True)
        rows.append(Row("paper", "rotorsfd paper --quick, 2 workers", "ours (wall)", wall,
                        note=f"CPU {cpu:.0f} s"))
    else:
        rows = run(False, repeat, before, keep)
    print("| case | method | wall | ratio | note |\n|---|---|---:|---:|---|")
    for r in rows:
        ratio = "" if r.ratio is None else f"{r.ratio:.3g}x"
        print(f"| {r.case} | {r.method} | {r.value:.1f} s | {ratio} | {r.note} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
