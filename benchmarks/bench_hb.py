"""HB continuation of the paper rotor: exact condensation onto the SFD DOFs vs the
full-model HB (the paper's method as written), H = 3 and H = 8.

Problem: examples/paper_rotor.toml (84 DOF, pi-film SFD at node 1, C/R 0.485 %) at the
paper's Table 1 unbalance U = 144.02 g mm, fixed base, Omega~ = 0.5 .. 1.6 through the
saddle-node pair, with the continuation options of ``[analysis.response]`` (tolerance
1e-6 on the scaled residual, the same for both paths: same accuracy). After a warm-up,
both paths run in turn (condensed, full, condensed, full, ...); the table gives the
median branch time, the time per continuation point and the full/condensed ratio, and
the largest difference of the Fourier coefficients between the two branches (relative
to the largest coefficient). At the response tolerance 1e-6 on the scaled residual the
full path may accept its linearised start at nearly linear points (0 iterations) while
the condensed path iterates on, so the branches differ by ~1e-4 there and the ratio
favours the full path. Over the whole branch the two paths adapt their arc-length
steps differently, so their points are not at the same parameter values and no
difference is printed. The single-point rows solve both from the linearised guess at tol
1e-10 and time one Newton solve each, printing the coefficient difference (1e-7 or
better in our runs).
``--quick``: Omega~ 0.5 .. 0.6, the full path's first 3 points.

Run: ``python -m benchmarks --only hb`` (or ``python benchmarks/bench_hb.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import (
    W1,
    Row,
    interleaved,
    paper_config,
    paper_system,
    response_options,
)


def branch_difference(a, b) -> float:
    """Max |X_a - X_b| / max |X_a| over the points both branches share (same arc-length
    steps: same lam); NaN if the parameter values differ."""
    n = min(a.n_points, b.n_points)
    if n == 0 or not np.allclose(a.lam[:n], b.lam[:n], rtol=1e-6):
        return float("nan")
    return float(np.max(np.abs(a.X[:n] - b.X[:n])) / np.max(np.abs(a.X[:n])))


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.harmonic.periodic import continue_periodic

    problem = paper_system().periodic_problem()
    opts = response_options(paper_config())
    stop = (0.6 if quick else 1.6) * W1
    rows: list[Row] = []
    for H in (3, 8):
        for condensed in (True, False):  # warm-up (caches, first-call costs)
            continue_periodic(problem, 0.5 * W1, stop, H, condensed=condensed,
                              **{**opts, "max_points": 2})
        n_full = 3 if quick else opts["max_points"]
        res = interleaved({
            "condensed": lambda H=H: continue_periodic(problem, 0.5 * W1, stop, H,
                                                       condensed=True, **opts),
            "full": lambda H=H, n=n_full: continue_periodic(
                problem, 0.5 * W1, stop, H, condensed=False, **{**opts, "max_points": n}),
        }, repeat)
        (tc, _, bc), (tf, _, bf) = res["condensed"], res["full"]
        diff = branch_difference(bc, bf)
        pc, pf = tc / bc.n_points, tf / bf.n_points
        case = f"H={H}, Omega~ 0.5-{stop / W1:.1f}, {problem.n_dof} DOF, N_f={bc.n_samples}"
        common = {"repeat": repeat, "ref": "condensed"}
        rows += [
            Row("hb", case, "condensed: per point", pc, ratio=1.0, **common,
                note=f"{bc.n_points} points, {len(bc.folds())} folds",
                extra={"points": bc.n_points, "branch_s": tc, "success": bc.success}),
            Row("hb", case, "full HB (paper): per point", pf, ratio=pf / pc, **common,
                note=f"{bf.n_points} points; " + (
                    f"max |dX|/|X| = {diff:.1e}" if np.isfinite(diff)
                    else "steps differ from the condensed ones"),
                extra={"points": bf.n_points, "branch_s": tf, "max_rel_diff": diff}),
            Row("hb", case, "condensed: whole branch", tc, ratio=1.0, **common,
                note=bc.message[:60]),
        ]
        if bf.n_points == bc.n_points:
            rows.append(Row("hb", case, "full HB (paper): whole branch", tf, ratio=tf / tc,
                            **common, note=bf.message[:60]))
        else:
            est = pf * bc.n_points
            rows.append(Row("hb", case, "full HB (paper): whole branch (est.)", est,
                            ratio=est / tc, **common,
                            note=f"per point x {bc.n_points} points"))
        rows += point_rows(problem, H, repeat, quick)
    return rows


def point_rows(problem, H: int, repeat: int, quick: bool) -> list[Row]:
    """One periodic solution from the linearised guess, both paths at tol 1e-10: the same
    accuracy in the coefficients (their difference is printed), time per solve."""
    from rotorsfd.errors import ConvergenceError
    from rotorsfd.harmonic.periodic import solve_periodic

    rows = []
    for ratio in (0.8,) if quick else (0.8, 1.4):
        def solve(condensed: bool, lam=ratio * W1):
            return solve_periodic(problem, lam, H, tol=1e-10, condensed=condensed)

        try:
            solve(True), solve(False)
        except ConvergenceError as exc:
            print(f"   skipped the point Omega~={ratio}: {exc}")
            continue
        res = interleaved({"condensed": lambda: solve(True), "full": lambda: solve(False)},
                          repeat)
        (tc, _, a), (tf, _, b) = res["condensed"], res["full"]
        diff = float(np.max(np.abs(a.X - b.X)) / np.max(np.abs(a.X)))
        case = f"H={H}, one point Omega~={ratio}, tol 1e-10"
        rows += [Row("hb", case, "condensed: Newton solve", tc, ratio=1.0, ref="condensed",
                     repeat=repeat, note=f"{a.iterations} iterations"),
                 Row("hb", case, "full HB (paper): Newton solve", tf, ratio=tf / tc,
                     ref="condensed", repeat=repeat,
                     note=f"{b.iterations} iterations; max |dX|/|X| = {diff:.1e}",
                     extra={"max_rel_diff": diff})]
    return rows


if __name__ == "__main__":
    from benchmarks.__main__ import main

    # --paper (the old flag) is accepted and ignored: the paper rotor is the case now
    sys.exit(main(["--only", "hb", *(a for a in sys.argv[1:] if a != "--paper")]))
