"""What the branch-point test adds to the stability of a branch.

``branch_stability`` takes the sign of the bordered HB determinant ``det [J; t^T]`` at
every computed point (:func:`rotorsfd.stability.branch_typing.branch_point_scan`) to find
and type branch points. Since 2026-12-04 the sign is the one the continuation took at each
accepted point with the Jacobian it holds (``Branch.info["bordered_sign"]``: one LU of
the (nu+1)-square bordered matrix per point); before, the scan re-evaluated the condensed
residual and Jacobian at every point. Compared here on the paper rotor's branch (0.5 to
1.6 Omega~, U = 144.02 g mm, H = 3 and H = 12): ``branch_stability`` with the scan on the
stored signs (ours), with the re-evaluating scan (the signs removed from the branch's
info: the code before) and without a scan, interleaved, CPU time.

Measured 2026-12-02 (load 4.7 on 2 cores, median CPU of 3): H = 3, 71 points: 0.597 s
before, 0.625 s with the scan (1.05x; the scan alone 0.019 s); H = 12: 0.573 s, 0.633 s
(1.11x; 0.045 s). The test's sign needs no SVD (``sign_only``): the cost is the
condensation of the residual at each point's speed.

Measured 2026-12-04 (2-core AMD EPYC, load 1, median of 3): see the README's speed table
(the scan alone 0.019 -> 0.000x s at H = 3).

Run: ``python -m benchmarks.bench_branch_points [--quick]``.
"""

from __future__ import annotations

import contextlib
import statistics
import sys
import time
from collections.abc import Iterator

from benchmarks.common import ROOT, Row, one_blas_thread, paper_config


def without_stored_signs(branch):
    """The branch with the continuation's signs removed: the scan re-evaluates every
    point (the code before 2026-12-04)."""
    import dataclasses

    from rotorsfd.harmonic.periodic import BORDERED

    return dataclasses.replace(branch, info={k: v for k, v in branch.info.items()
                                             if k not in BORDERED})


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
            bare = without_stored_signs(branch)
            variants = {"stored": branch, "re-evaluated": bare, "none": branch}
            times: dict[str, list[float]] = {k: [] for k in variants}
            for _ in range(max(1, repeat)):   # interleaved
                for key, b in variants.items():
                    with (without_scan() if key == "none" else contextlib.nullcontext()):
                        t0 = time.process_time()
                        branch_stability(b, problem)
                        times[key].append(time.process_time() - t0)
            scans = {}
            for key in ("stored", "re-evaluated"):
                t0 = time.process_time()
                scan = branch_point_scan(variants[key], problem)
                scans[key] = (time.process_time() - t0, scan)
            assert scans["stored"][1].intervals == scans["re-evaluated"][1].intervals
            t = {k: statistics.median(v) for k, v in times.items()}
            n_bp = len(scan.intervals) if scan else 0
            rows.append(Row("branch-points", case, "branch_stability without a scan",
                            t["none"], unit="s CPU", repeat=repeat))
            rows.append(Row("branch-points", case, "with the scan re-evaluating every "
                            "point (before)", t["re-evaluated"], unit="s CPU", repeat=repeat,
                            note=f"the scan alone {scans['re-evaluated'][0]:.3f} s CPU"))
            rows.append(Row("branch-points", case, "with the scan on the continuation's "
                            "signs (ours)", t["stored"], unit="s CPU", repeat=repeat,
                            ratio=t["stored"] / t["re-evaluated"], ref="before",
                            note=f"{branch.n_points} points; the scan alone "
                            f"{scans['stored'][0]:.4f} s CPU; {n_bp} branch points (the "
                            "same intervals both ways)"))
    return rows


if __name__ == "__main__":
    from benchmarks.__main__ import main

    sys.exit(main(["--only", "branch-points", *sys.argv[1:]]))
