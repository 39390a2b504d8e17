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

import numpy as np

from benchmarks.common import ROOT, Row, interleaved

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


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd import api

    rows: list[Row] = []
    cases = dict(list(CASES.items())[:1]) if quick else CASES
    for case, (path, sets) in cases.items():
        configs = {name: api.load_config(path, [*sets, *extra]) for name, extra in
                   (("H = 3, M = 400, no check", BEFORE), ("defaults (auto H, "
                    "step-controlled M, checked bifurcations)", DEFAULTS))}
        api.run_response(configs["H = 3, M = 400, no check"], progress=False)  # compile
        res = interleaved({k: (lambda c=c: api.run_response(c, progress=False))
                           for k, c in configs.items()}, repeat=1 if quick else repeat)
        ref = "H = 3, M = 400, no check"
        for name, (t, times, out) in res.items():
            rows.append(Row("convergence", case, name, t, repeat=len(times),
                            ratio=t / res[ref][0], ref=ref, note=_note(out)))
    return rows


if __name__ == "__main__":
    for r in run(quick="--quick" in sys.argv):
        print(f"{r.case:45s} {r.method:60s} {r.value:7.2f} s  x{r.ratio:.2f}  {r.note}")
