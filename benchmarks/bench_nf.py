"""AFT sample count N_f along a branch: the adaptive rule (up and down, on the sampling
error in the units of the Newton test) vs the old "grow" rule (relative change of the
force coefficients, re-chosen at alias_tol/100, never down).

Problem: examples/paper_pitching.toml (the paper rotor under constant base pitching,
U = 144.02 g mm), w_by = 6 rad/s and 4 rad/s at H = 3, w_by = 6 rad/s at H = 8,
Omega~ 0.5 .. 1.6, the options of
``[analysis.response]`` (tolerance 1e-6). Near resonance the SFD orbit passes close to
the bearing centre, where the pi film's arc turns abruptly, and N_f must rise there; the
old rule then stays at the cap (2048) for the rest of the branch. The two rules run in
turn (grow, adaptive, fixed, grow, ...); the "fixed N_f" row (the floor
``default_min_samples(H)``: 32 at H = 3, 128 at H = 8; not accurate near
resonance) shows what the branch costs without any sampling work, and the fixed-base
branch (w_by = 0, same options) is timed alongside for scale. Notes: points, N_f
history ("N@Omega~" at each change), and the largest distance of a branch point from the
same point re-solved with 4096 samples (scaled unknowns, units of the clearance).
``--quick``: Omega~ 0.95 .. 1.0 at w_by = 6 rad/s only, no 4096 check.

Run: ``python -m benchmarks --only nf`` (or ``python benchmarks/bench_nf.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import ROOT, W1, Row, interleaved, response_options

PITCHING = ROOT / "examples" / "paper_pitching.toml"


def pitching_problem(rate: str) -> tuple:
    """(PeriodicProblem in speed, continue_periodic options) at pitching rate ``rate``."""
    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem

    config = load_config(PITCHING, [f"base.pitching.value={rate}"])
    m = build_model(config)
    system = RotorSystem(m.rotor, m.elements, m.unbalances, m.base_motion)
    opts = response_options(config)
    return system.periodic_problem("speed"), opts, config.analysis.response.harmonics


def history(branch) -> str:
    """N_f at the first point and at every change: ``32@0.500 64@0.952 ...``."""
    N = branch.info["n_samples"]
    idx = [0, *(np.flatnonzero(np.diff(N)) + 1)]
    return " ".join(f"{N[i]}@{branch.lam[i] / W1:.3f}" for i in idx)


def distance_to_4096(problem, branch, n_ref: int = 4096) -> float:
    """Largest |z - z_ref| over the points (scaled unknowns), z_ref re-solved with n_ref
    samples on the plane through z normal to the branch tangent (tol 1e-10)."""
    from rotorsfd.continuation.newton import newton_extended
    from rotorsfd.harmonic.fourier import to_real
    from rotorsfd.harmonic.hb_system import HBSystem

    worst = 0.0
    for i in range(branch.n_points):
        ref = HBSystem(problem, branch.H, n_ref, True, branch.lam[i], branch.lam_scale)
        xs = to_real(branch.X[i][:, problem.nl_dofs])
        ref.hb.set_shift(xs, branch.lam[i])
        z = ref.to_z(xs, branch.lam[i])
        a = ref.weights * branch.tangents[i]
        res = newton_extended(ref, z, a, float(a @ z), 1e-10, 30)
        worst = max(worst, float(np.linalg.norm(res.z - z)) if res.converged else np.inf)
    return worst


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.harmonic.fourier import default_min_samples
    from rotorsfd.harmonic.periodic import continue_periodic

    rows: list[Row] = []
    lo, hi = (0.95, 1.0) if quick else (0.5, 1.6)
    cases = [("6 rad/s", 3)] if quick else [("6 rad/s", 3), ("4 rad/s", 3), ("6 rad/s", 8)]
    for rate, H in cases:
        problem, opts, _ = pitching_problem(rate)
        floor = default_min_samples(H)

        def branch(rule: str | None, problem=problem, opts=opts, H=H, floor=floor):
            kw = {"n_samples_rule": rule} if rule else {"n_samples": floor}
            return continue_periodic(problem, lo * W1, hi * W1, H, **{**opts, **kw})

        branch("adaptive")  # warm-up (compiled kernels, caches)
        funs = {"grow": lambda: branch("grow"), "adaptive": lambda: branch("adaptive"),
                "fixed32": lambda: branch(None)}
        if (rate, H) == ("6 rad/s", 3) and not quick:   # the fixed base, for scale
            base, base_opts, _ = pitching_problem("0 rad/s")
            funs["fixed_base"] = lambda base=base, o=base_opts, H=H: continue_periodic(
                base, lo * W1, hi * W1, H, **o)
        res = interleaved(funs, repeat)
        case = f"pitching w_by={rate.split()[0]}, H={H}, Omega~ {lo}-{hi}"
        t_old = res["grow"][0]
        for key, method in (("grow", "old rule: grow only (relative test)"),
                            ("adaptive", "adaptive: up and down (residual test)"),
                            ("fixed32", f"fixed N_f = {floor} (floor, not accurate)"),
                            ("fixed_base", "fixed base (w_by = 0), adaptive")):
            if key not in res:
                continue
            t, times, b = res[key]
            N = b.info["n_samples"]
            extra = {"points": b.n_points, "n_samples": N.tolist(), "times": times,
                     "n_max": int(N.max()), "success": b.success,
                     "aliasing_max": float(b.aliasing.max())}
            note = f"{b.n_points} points, N_f {history(b)}"
            if not quick and key in ("grow", "adaptive"):
                d = distance_to_4096(problem, b)
                extra["distance_to_4096"] = d
                note += f"; max |z - z(4096)| = {d:.1e} C"
            rows.append(Row("nf", case, method, t, repeat=repeat, ratio=t / t_old,
                            ref="old rule", note=note, extra=extra))
    return rows


if __name__ == "__main__":
    from benchmarks.__main__ import main

    sys.exit(main(["--only", "nf", *sys.argv[1:]]))
