"""Stability of every point of a branch and the location of its bifurcations.

The paper rotor's branches from 0.5 to 1.6 Omega~ (``[analysis.response]`` of
examples/paper_rotor.toml, fixed base, U = 144.02 g mm, H = 3 and H = 8; and the pitching
example, w_by = 4 rad/s, H = 8, whose orbits are not circular): the branch itself, then
:func:`rotorsfd.stability.branch_stability.branch_stability` with ``newmark-cb`` (ours,
the default: Craig-Bampton basis once per (M, K), compiled monodromy loop), the same with
the numpy monodromy loop it replaced (``compiled=False``, the code before; H = 3 only),
Hill (H = 8, same reduction) and the paper's literal full-model Newmark; and the whole
``run_response`` (branch + stability, what ``rotorsfd response`` computes). Reported:
the branch's time, the stability's total (points + location of every bifurcation to
1e-6), per point, the one-off basis, the number of bases computed. One process, one
BLAS thread (the machine has 2 cores; the per-point loop is serial).

Run: ``python -m benchmarks.bench_branch_stability [--quick]``.
"""

from __future__ import annotations

import contextlib
import functools
import sys
import time
from collections.abc import Iterator

import numpy as np

from benchmarks.common import ROOT, Row, median_time, one_blas_thread, paper_config

PITCHING = ROOT / "examples" / "paper_pitching.toml"


def _branch(config):
    from rotorsfd.analyses.response import run_response

    return run_response(config, search_path=ROOT / "examples", progress=False,
                        stability_options=False)


def _response(config):
    from rotorsfd.analyses.response import run_response

    return run_response(config, search_path=ROOT / "examples", progress=False)


@contextlib.contextmanager
def numpy_monodromy() -> Iterator[None]:
    """``branch_stability`` with the numpy monodromy loop (``compiled=False``): the
    evaluator module's ``floquet_multipliers`` replaced for the duration."""
    import rotorsfd.stability.floquet_evaluator as bs

    original = bs.floquet_multipliers
    bs.floquet_multipliers = functools.partial(original, compiled=False)
    try:
        yield
    finally:
        bs.floquet_multipliers = original


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.io.config import load_config
    from rotorsfd.stability.branch_stability import (
        FloquetEvaluator,
        StabilityOptions,
        branch_stability,
    )

    cases = {"paper U=144.02 H=3": paper_config(["analysis.response.harmonics=3"]),
             "paper U=144.02 H=8": paper_config(["analysis.response.harmonics=8"])}
    if PITCHING.exists():
        cases["pitching w_by=4 H=8"] = load_config(PITCHING, [
            "analysis.response.harmonics=8"])
    if quick:
        cases = dict(list(cases.items())[:1])
    methods = {"newmark-cb": "ours: Newmark-CB (M=400)",
               "newmark-cb-numpy": "Newmark-CB, numpy monodromy loop (before)",
               "hill": "Hill (H=8, CB)", "newmark": "paper: full Newmark (M=400)"}
    rows: list[Row] = []
    with one_blas_thread():
        for case, config in cases.items():
            t_branch, _, result = median_time(lambda c=config: _branch(c), repeat)
            branch, system = result.branch, result.system
            problem = system.periodic_problem("speed")
            n = branch.n_points
            rows.append(Row("branch-stability", case, "branch (HB continuation)", t_branch,
                            repeat=repeat, note=f"{n} points"))
            ref = None
            for meth, label in methods.items():
                if quick and meth != "newmark-cb":
                    continue
                if meth in ("newmark", "newmark-cb-numpy") and "H=3" not in case:
                    continue  # same orbits as H=3 for the fixed base; costly
                opts = StabilityOptions(method=meth.removesuffix("-numpy"))
                reps = 1 if meth == "newmark" else repeat
                with (numpy_monodromy() if meth.endswith("-numpy")
                      else contextlib.nullcontext()):
                    t, _, st = median_time(
                        lambda o=opts, b=branch, p=problem: branch_stability(b, p, o), reps)
                ref = ref or t
                kinds = ", ".join(f"{b.kind} {b.lam / 811.3:.6f}"
                                  for b in st.bifurcations) or "none"
                rows.append(Row("branch-stability", case, label, t, repeat=reps,
                                ratio=t / ref, ref="newmark-cb", note=(
                                    f"+{100 * t / t_branch:.0f}% of the branch; "
                                    f"{1e3 * st.elapsed_points / n:.1f} ms/point; locate "
                                    f"{st.elapsed - st.elapsed_points:.2f} s; bases "
                                    f"{st.n_bases}; {kinds}"),
                                extra={"per_point_s": st.elapsed_points / n,
                                       "locate_s": st.elapsed - st.elapsed_points,
                                       "n_points": n, "n_bases": st.n_bases}))
            if "H=3" in case and "paper" in case and not quick:
                t_resp, _, resp = median_time(lambda c=config: _response(c), repeat)
                rows.append(Row("branch-stability", case,
                                "run_response: branch + stability (rotorsfd response)",
                                t_resp, repeat=repeat, note=(
                                    f"{resp.branch.n_points} points; "
                                    f"{len(resp.bifurcations or [])} bifurcations "
                                    "located; no files written")))
            ev = FloquetEvaluator(problem)
            t_basis, _, _ = median_time(
                lambda e=ev, lam=branch.lam[0]: (setattr(e, "_basis", None), e.reduced(lam, 1.0)),
                repeat)
            rows.append(Row("branch-stability", case, "Craig-Bampton basis (once)", t_basis,
                            repeat=repeat))
    return rows


def main(argv: list[str]) -> int:
    quick = "--quick" in argv
    t0 = time.perf_counter()
    rows = run(quick=quick, repeat=1 if quick else 3)
    print("| case | method | median | ratio | note |\n|---|---|---:|---:|---|")
    for r in rows:
        v = f"{r.value * 1e3:.2f} ms" if r.value < 1 else f"{r.value:.2f} s"
        ratio = "" if r.ratio is None else f"{r.ratio:.3g}x"
        print(f"| {r.case} | {r.method} | {v} | {ratio} | {r.note} |")
    print(f"total {time.perf_counter() - t0:.1f} s", file=sys.stderr)
    return 0


if __name__ == "__main__":
    np.seterr(all="ignore")
    raise SystemExit(main(sys.argv[1:]))
