"""The linear part of the HB problem under a constant base motion: assembled once as a
polynomial in the parameter (``RotorSystem.periodic_problem(assembly="polynomial")``, the
default) vs recombined from the 12 base-motion matrices at every residual/Jacobian
evaluation (``assembly="direct"``, the baseline: what the code did before).

Problem: the paper rotor, ``examples/paper_pitching.toml`` (U = 144.02 g mm) at
w_by = 6 rad/s and ``examples/paper_rolling.toml`` at w_bx = 6 rad/s, H = 3,
Omega~ 0.5 .. 1.6, the options of ``[analysis.response]`` with N_f fixed at 32 (so that
only the linear part differs) and, for the pitching case, the adaptive N_f too; the
fixed-base branch (w_by = 0, N_f = 32) is timed alongside for scale. The two assemblies
run in turn (direct, polynomial, fixed base, direct, ...). Notes: points, and the largest
difference between the two branches (points' parameter values relative, coefficients
relative to the largest). Plus the linear part alone: one ``matrices + dmatrices +
forcing + dforcing`` call at a new speed (median of 2000).

Run: ``python -m benchmarks --only linear`` (or ``python -m benchmarks.bench_linear
[--quick]``); ``--quick``: Omega~ 0.95 .. 1.0, pitching only.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import ROOT, W1, Row, interleaved, response_options

CASES = {
    "pitching w_by=6": (ROOT / "examples" / "paper_pitching.toml", "base.pitching.value=6 rad/s"),
    "rolling w_bx=6": (ROOT / "examples" / "paper_rolling.toml", "base.rolling.value=6 rad/s"),
    "fixed base": (ROOT / "examples" / "paper_pitching.toml", "base.pitching.value=0 rad/s"),
}


def system_and_options(case: str) -> tuple:
    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem

    path, override = CASES[case]
    config = load_config(path, [override])
    m = build_model(config)
    system = RotorSystem(m.rotor, m.elements, m.unbalances, m.base_motion)
    return system, response_options(config), config.analysis.response.harmonics


def branch_difference(a, b) -> str:
    if a.n_points != b.n_points:
        return f"points differ: {a.n_points} vs {b.n_points}"
    dlam = float(np.max(np.abs(a.lam - b.lam) / np.abs(b.lam)))
    dX = float(np.max(np.abs(np.asarray(a.X) - np.asarray(b.X))) / np.max(np.abs(b.X)))
    return f"vs direct: lam {dlam:.1e}, X {dX:.1e} (rel.)"


def per_call(problem, lam0: float, n: int = 2000) -> float:
    """Median time of matrices + dmatrices + forcing + dforcing at a new lam (H = 3)."""
    times = []
    for i in range(n):
        lam = lam0 * (1.0 + 1e-6 * i)
        t0 = time.perf_counter()
        problem.matrices(lam)
        problem.dmatrices(lam)
        problem.forcing(lam, 3)
        problem.dforcing(lam, 3)
        times.append(time.perf_counter() - t0)
    return float(np.median(times))


def both_changes(repeat: int) -> list[Row]:
    """The pitching branch (w_by = 6 rad/s, adaptive N_f) as the code had it before both
    changes (grow-only N_f rule, base terms recombined per call) and as it is now."""
    from rotorsfd.harmonic.periodic import continue_periodic

    rows = []
    system, opts, _ = system_and_options("pitching w_by=6")
    old = system.periodic_problem("speed", assembly="direct")
    new = system.periodic_problem("speed")
    for H in (3, 8):
        funs = {
            "before": lambda H=H: continue_periodic(old, 0.5 * W1, 1.6 * W1, H,
                                                    **{**opts, "n_samples_rule": "grow"}),
            "after": lambda H=H: continue_periodic(new, 0.5 * W1, 1.6 * W1, H, **opts),
        }
        funs["after"]()  # warm-up (compiled kernels)
        res = interleaved(funs, repeat)
        for key, method in (("before", "grow-only N_f + base terms per call (before)"),
                            ("after", "adaptive N_f + polynomial base terms (after)")):
            t, times, b = res[key]
            rows.append(Row("linear", case=f"pitching w_by=6, H={H}, Omega~ 0.5-1.6: both "
                            "changes", method=method, value=t, repeat=repeat,
                            ratio=t / res["before"][0], ref="before",
                            note=f"{b.n_points} points", extra={"times": times}))
    return rows


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.harmonic.periodic import continue_periodic

    rows: list[Row] = []
    lo, hi = (0.95, 1.0) if quick else (0.5, 1.6)
    runs = [("pitching w_by=6", 32)] if quick else [
        ("pitching w_by=6", 32), ("pitching w_by=6", None), ("rolling w_bx=6", 32)]
    base, base_opts, _ = system_and_options("fixed base")
    base_problem = base.periodic_problem("speed")
    for case, n_f in runs:
        system, opts, H = system_and_options(case)
        kw = {**opts, "n_samples": n_f} if n_f else opts
        problems = {a: system.periodic_problem("speed", assembly=a)
                    for a in ("direct", "polynomial")}

        def branch(problem, kw=kw, H=H):
            return continue_periodic(problem, lo * W1, hi * W1, H, **kw)

        branch(problems["polynomial"])  # warm-up (compiled kernels)
        funs = {a: (lambda p=p: branch(p)) for a, p in problems.items()}
        if n_f == 32 and case.startswith("pitching"):
            funs["fixed_base"] = lambda H=H: continue_periodic(
                base_problem, lo * W1, hi * W1, H, **{**base_opts, "n_samples": 32})
        res = interleaved(funs, repeat)
        label = f"{case}, H={H}, N_f={'adaptive' if n_f is None else n_f}, Omega~ {lo}-{hi}"
        t_ref = res["direct"][0]
        for key, method in (("direct", "direct: base terms recombined per call (before)"),
                            ("polynomial", "polynomial in Omega, assembled once (after)"),
                            ("fixed_base", "fixed base (w = 0), for scale")):
            if key not in res:
                continue
            t, times, b = res[key]
            note = f"{b.n_points} points"
            if key == "polynomial":
                note += "; " + branch_difference(b, res["direct"][2])
            rows.append(Row("linear", case=label, method=method, value=t, repeat=repeat,
                            ratio=t / t_ref, ref="direct", note=note,
                            extra={"times": times, "points": b.n_points}))
    if not quick:
        rows += both_changes(repeat)
    # the linear part alone, per evaluation
    system, _, _ = system_and_options("pitching w_by=6")
    n = 200 if quick else 2000
    calls = {a: system.periodic_problem("speed", assembly=a) for a in ("direct", "polynomial")}
    calls["fixed_base"] = base_problem
    t = {k: per_call(p, 0.9 * W1, n) for k, p in calls.items()}
    for key, method in (("direct", "direct (before)"), ("polynomial", "polynomial (after)"),
                        ("fixed_base", "fixed base")):
        rows.append(Row("linear", "pitching w_by=6: matrices+dmatrices+forcing+dforcing",
                        method, t[key], repeat=n, ratio=t[key] / t["direct"], ref="direct",
                        note="one call each at a new speed, median"))
    return rows


if __name__ == "__main__":
    from benchmarks.__main__ import table

    print(table(run(quick="--quick" in sys.argv)))
