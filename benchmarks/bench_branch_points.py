"""What the branch-point test adds to the stability of a branch.

``branch_stability`` now evaluates the bordered HB determinant ``det [J; t^T]`` at every
computed point (:func:`rotorsfd.stability.branch_typing.branch_point_scan`: one residual
and Jacobian evaluation and one SVD of the condensed (nu+1) x (nu+1) matrix per point) to
find and type branch points. Compared here on the paper rotor's branch (0.5 to 1.6
Omega~, U = 144.02 g mm, H = 3 and H = 12): ``branch_stability`` with the scan (ours) and
without it (the scan replaced by ``None``, the code before), interleaved, CPU time.

Measured 2026-12-02 (load 4.7 on 2 cores, median CPU of 3): H = 3, 71 points: 0.597 s
before, 0.625 s with the scan (1.05x; the scan alone 0.019 s); H = 12: 0.573 s, 0.633 s
(1.11x; 0.045 s). The test's sign needs no SVD (``sign_only``): the cost is the
condensation of the residual at each point's speed.

Run: ``python -m benchmarks.bench_branch_points [--quick]``.
"""

from __future__ import annotations

import contextlib
import statistics
import sys
import time
from collections.abc import Iterator

from benchmarks.common import ROOT, Row, one_blas_thread, paper_config


@contextlib.contextmanager
def without_scan() -> Iterator[None]:
    """``branch_stability`` without the branch-point scan (the code before)."""
    import rotorsfd.stability.branch_stability as bs

    original = bs.branch_point_scan
    bs.branch_point_scan = lambda branch, problem: None
    try:
        yield
    finally:
        bs.branch_point_scan = original


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.analyses.response import run_response
    from rotorsfd.stability.branch_stability import branch_stability
    from rotorsfd.stability.branch_typing import branch_point_scan

    rows: list[Row] = []
    Hs = (3,) if quick else (3, 12)
    with one_blas_thread():
        for H in Hs:
            config = paper_config([f"analysis.response.harmonics={H}"])
            result = run_response(config, search_path=ROOT / "examples", progress=False,
                                  stability_options=False)
            branch = result.branch
            problem = result.system.periodic_problem("speed")
            case = f"paper U=144.02 H={H}"
            times: dict[str, list[float]] = {"with": [], "without": []}
            for _ in range(max(1, repeat)):   # interleaved
                for key in times:
                    with (without_scan() if key == "without" else contextlib.nullcontext()):
                        t0 = time.process_time()
                        branch_stability(branch, problem)
                        times[key].append(time.process_time() - t0)
            t0 = time.process_time()
            scan = branch_point_scan(branch, problem)
            t_scan = time.process_time() - t0
            t_with, t_without = (statistics.median(times[k]) for k in ("with", "without"))
            note = (f"{branch.n_points} points; the scan alone {t_scan:.3f} s CPU; "
                    f"{len(scan.intervals) if scan else 0} branch points")
            rows.append(Row("branch-points", case, "branch_stability without the scan "
                            "(before)", t_without, unit="s CPU", repeat=repeat))
            rows.append(Row("branch-points", case, "branch_stability with the scan (ours)",
                            t_with, unit="s CPU", repeat=repeat, ratio=t_with / t_without,
                            ref="before", note=note))
    return rows


def main(argv: list[str]) -> int:
    quick = "--quick" in argv
    rows = run(quick=quick, repeat=1 if quick else 3)
    print("| case | method | median CPU | ratio | note |\n|---|---|---:|---:|---|")
    for r in rows:
        ratio = "" if r.ratio is None else f"{r.ratio:.3g}x"
        print(f"| {r.case} | {r.method} | {r.value:.3f} s | {ratio} | {r.note} |")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
