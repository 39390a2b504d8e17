"""The cost of converged results: ``rotorsfd response`` with the convergence defaults
(``harmonics = "auto"``, the Floquet step control, every bifurcation checked at about
1.5 H and 2M) against the settings before them (H = 3, M = 400 fixed, no check), side by
side in one run (interleaved, median of ``repeat``).

Cases: the paper's Table 1 (paper rotor, fixed base, U = 144.02 g mm: a circular whirl,
exact at one harmonic), the paper rotor pitching at w_by = 4.3 rad/s (the Figure 19
family: a narrow fold pair near the cusp, where H = 3 gets the stability between the
folds wrong) and the two-element anisotropic rotor of issue 14 (tests/data: H = 3
reports a fold pair that the converged branch does not have). Notes: H range, the M
range, the bifurcations and their check status.

Run: ``python -m benchmarks --only convergence`` (or ``python benchmarks/bench_convergence.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import statistics
import time

import numpy as np

from benchmarks.common import ROOT, Row

CASES = {
    "Table 1, fixed base, U = 144.02 g mm": (
        ROOT / "examples" / "paper_rotor.toml", ["unbalance[0].magnitude=144.02 g*mm"]),
    "pitching w_by = 4.3 rad/s, U = 144.02 g mm": (
        ROOT / "examples" / "paper" / "fig19_unstable_range.toml",
        ["unbalance[0].magnitude=144.02 g*mm", "base.pitching.value=4.3 rad/s"]),
    "issue 14 anisotropic two-element rotor": (
        ROOT / "tests" / "data" / "issue14_anisotropic.toml", []),
}
BEFORE = ["analysis.response.harmonics=3", "analysis.stability.intervals=400",
          "analysis.stability.adaptive_intervals=false",
          "analysis.stability.check_bifurcations=false"]
DEFAULTS = ["analysis.response.harmonics=auto", "analysis.stability.adaptive_intervals=true",
            "analysis.stability.check_bifurcations=true"]


def _note(result) -> str:
    b = result.branch
    st = result.info.get("stability")
    Hs = b.info.get("harmonics", np.array([b.H]))
    M = st.n_intervals if st is not None and st.n_intervals is not None else [0]
    bifs = "; ".join(f"{r['type']} {r['speed_ratio']:.5f} {r.get('status', '')}"
                     for r in result.bifurcations or [])
    return (f"{b.n_points} points, H {int(np.min(Hs))}..{int(np.max(Hs))}, M "
            f"{int(np.min(M))}..{int(np.max(M))}, unstable {int(np.sum(~result.stable))}; "
            f"{bifs or 'no bifurcation'}")


def _interleaved_cpu(funs: dict, repeat: int) -> dict:
    """Median wall and CPU (``time.process_time``: this process alone, which the other
    jobs of a shared machine inflate far less than the wall time) of the methods run in
    turn (A B A B ...), with the per-pair CPU ratios and the last result of each."""
    wall: dict[str, list[float]] = {k: [] for k in funs}
    cpu: dict[str, list[float]] = {k: [] for k in funs}
    outs: dict = {}
    for _ in range(max(1, repeat)):
        for k, f in funs.items():
            t0, c0 = time.perf_counter(), time.process_time()
            outs[k] = f()
            cpu[k].append(time.process_time() - c0)
            wall[k].append(time.perf_counter() - t0)
    return {k: (statistics.median(wall[k]), statistics.median(cpu[k]), wall[k], cpu[k],
                outs[k]) for k in funs}


def run(quick: bool = False, repeat: int = 5) -> list[Row]:
    from rotorsfd import api

    rows: list[Row] = []
    cases = dict(list(CASES.items())[:1]) if quick else CASES
    ref = "H = 3, M = 400, no check"
    for case, (path, sets) in cases.items():
        configs = {name: api.load_config(path, [*sets, *extra]) for name, extra in
                   ((ref, BEFORE), ("defaults (auto H, step-controlled M, checked "
                                    "bifurcations)", DEFAULTS))}
        for c in configs.values():          # compile (and load the numba caches) first
            api.run_response(c, progress=False)
        res = _interleaved_cpu({k: (lambda c=c: api.run_response(c, progress=False))
                                for k, c in configs.items()}, 1 if quick else repeat)
        w0, c0, _, cpu0, _ = res[ref]
        for name, (w, c, walls, cpus, out) in res.items():
            pairs = [a / b for a, b in zip(cpus, cpu0, strict=True)]
            rows.append(Row("convergence", case, name, w, repeat=len(walls),
                            ratio=w / w0, ref=ref,
                            note=f"CPU {c:.2f} s (x{c / c0:.2f}, pairs x{min(pairs):.2f}"
                                 f"-{max(pairs):.2f}); {_note(out)}",
                            extra={"cpu": c, "cpu_ratio": c / c0, "cpu_times": cpus,
                                   "wall_times": walls}))
    return rows


if __name__ == "__main__":
    for r in run(quick="--quick" in sys.argv):
        print(f"{r.case:42s} {r.method[:24]:24s} wall {r.value:6.2f} s x{r.ratio:.2f}  "
              f"{r.note}")
