"""The dense condensation of a branch on a full modal damping matrix: one
eigendecomposition per harmonic (:mod:`rotorsfd.harmonic.pencil_condensation`, ours since
2026-12-04) against a complex LU of every harmonic's Zt_k at every point (the LAPACK path
before, what a user would write with scipy: ``lu_factor`` / ``lu_solve``).

Compared in one run on the calibrated paper rotor (84 DOFs, modal damping on every
mode: the dense path): (a) one condensation with lam-derivatives at H = 3 and 12, CPU per
call, and the build of one harmonic's pencil; (b) the paper case ``cal-fig24-u360``
(C/R = 0.728 %, U = 360.04 g mm: 2800 condensations at H = 8-12, Floquet stability and
the bifurcations located) end to end, with the largest difference of
its bifurcations' speeds between the two paths (relative).

Run: ``python -m benchmarks.bench_pencil [--quick] --json benchmarks/results-pencil.json``.
"""

from __future__ import annotations

import contextlib
import statistics
import sys
import time
from collections.abc import Iterator

import numpy as np

from benchmarks.common import ROOT, W1, Row, one_blas_thread

CASE = "cal-fig24-u360"


@contextlib.contextmanager
def lu_only() -> Iterator[None]:
    """The LU at every point (the pencils never reached)."""
    from rotorsfd.harmonic import pencil_condensation as pcm

    saved = pcm.PENCIL_AFTER
    pcm.PENCIL_AFTER = 1 << 60
    try:
        yield
    finally:
        pcm.PENCIL_AFTER = saved


def _system():
    from rotorsfd.api import build_system, load_config

    config = load_config(ROOT / "examples" / "paper_rotor_calibrated.toml")
    return config, build_system(config, ROOT / "examples")


def per_call(H: int, lu: bool, n: int) -> float:
    """CPU ms per condensation (with lam-derivatives) along n speeds of a fresh problem
    (the pencils from the first call: the count set to zero)."""
    from rotorsfd.harmonic import pencil_condensation as pcm
    from rotorsfd.harmonic.condensation import CondensedHB

    _, system = _system()
    problem = system.periodic_problem("speed")
    hb = CondensedHB(problem, H, 4 * H + 4)
    hb.set_shift(np.zeros((2 * H + 1, problem.m)), W1)
    saved = pcm.PENCIL_AFTER
    pcm.PENCIL_AFTER = 1 << 60 if lu else 0
    try:
        hb.condense(1.1 * W1)                       # builds the pencils
        t0 = time.process_time()
        for lam in np.linspace(1.0, 1.3, n) * W1:
            hb.condense(float(lam))
        return (time.process_time() - t0) / n * 1e3
    finally:
        pcm.PENCIL_AFTER = saved


def build_ms(k: int = 5) -> float:
    """CPU ms of one harmonic's pencil (companion matrix, eig, Q)."""
    from rotorsfd.harmonic import pencil_condensation as pcm

    _, system = _system()
    M, D, K = system.periodic_problem("speed").matrices.polynomial()
    t0 = time.process_time()
    pcm.decompose(pcm.coefficients(M, D, K, 0.0, 1.0, k), W1, M.shape[0])
    return (time.process_time() - t0) * 1e3


def branch(lu: bool) -> tuple[float, list[float]]:
    """CPU seconds of the paper case ``cal-fig24-u360`` (the calibrated rotor at C/R =
    0.728 %, U = 360.04 g mm: its branch with stability and bifurcations, H 8-12) and
    its bifurcations' speeds."""
    from rotorsfd.paper.cases import CASES
    from rotorsfd.paper.run import run_case

    with lu_only() if lu else contextlib.nullcontext():
        t0 = time.process_time()
        o = run_case(CASES[CASE])
        cpu = time.process_time() - t0
    return cpu, [float(b[1]) for b in o.numbers["bifurcations"]]


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    rows: list[Row] = []
    Hs = (3,) if quick else (3, 12)
    n = 20 if quick else 200
    with one_blas_thread():
        for H in Hs:
            t: dict[str, list[float]] = {"lu": [], "pencil": []}
            for _ in range(max(1, repeat)):     # interleaved
                t["lu"].append(per_call(H, True, n))
                t["pencil"].append(per_call(H, False, n))
            lu, pen = (statistics.median(t[k]) for k in ("lu", "pencil"))
            case = f"calibrated paper rotor, one condensation, H = {H}"
            rows.append(Row("pencil", case, "LU of every Zt_k (before)", lu,
                            unit="ms CPU / call", repeat=repeat))
            rows.append(Row("pencil", case, "pencils (ours)", pen, unit="ms CPU / call",
                            repeat=repeat, ratio=pen / lu, ref="before"))
        rows.append(Row("pencil", "calibrated paper rotor, one harmonic's pencil",
                        "eigendecomposition (once per branch and harmonic)",
                        statistics.median(build_ms() for _ in range(max(1, repeat))),
                        unit="ms CPU", repeat=repeat))
        if not quick:
            runs = {key: [branch(key == "lu") for _ in range(max(1, repeat))]
                    for key in ("lu", "pencil")}
            cpu = {k: statistics.median(c for c, _ in v) for k, v in runs.items()}
            folds = {k: np.array(v[0][1]) for k, v in runs.items()}
            diff = (float(np.max(np.abs(folds["pencil"] - folds["lu"]) / folds["lu"]))
                    if folds["lu"].size == folds["pencil"].size else float("nan"))
            case = f"paper case {CASE} (branch, stability, bifurcations)"
            rows.append(Row("pencil", case, "LU of every Zt_k (before)", cpu["lu"],
                            unit="s CPU", repeat=repeat))
            rows.append(Row("pencil", case, "pencils (ours)", cpu["pencil"], unit="s CPU",
                            repeat=repeat, ratio=cpu["pencil"] / cpu["lu"], ref="before",
                            note=f"{folds['lu'].size} bifurcation speeds, differ by "
                                 f"{diff:.1e} (relative)"))
    return rows


if __name__ == "__main__":
    from benchmarks.__main__ import main

    sys.exit(main(["--only", "pencil", *sys.argv[1:]]))
