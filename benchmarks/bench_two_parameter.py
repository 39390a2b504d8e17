"""Building the HB problems of a two-parameter family (fold, period-doubling and
Neimark-Sacker curves): the fold-curve Newton builds ``first(value)`` and
``second(speed)`` at every evaluation.

Since 2026-12-04 :meth:`RotorSystem.two_parameter_problem
<rotorsfd.model.system.RotorSystem.two_parameter_problem>` stores the rotor's matrices
and base patterns once (``StoredTerms``: band storage, dense for a full modal damping)
and the base state once; each problem is a few scaled adds of the stored arrays. Before,
each was built from scratch: the base patterns summed as sparse matrices, their band read
and converted at every build, the base state recomputed. Compared in one run on the
paper rotor pitching at 10 rad/s (Figure 19's second parameter, ``base.pitching.value``),
literal (banded) and calibrated (full modal damping: dense), at 20 (speed, rate) pairs:
the family's builds (ours) against ``with_parameter(...).periodic_problem("speed")`` and
``periodic_problem(rate, speed)`` from scratch (the code before; the numbers equal bit for
bit, tests/system/test_two_parameter_bands.py), CPU time per build pair.

Run: ``python -m benchmarks.bench_two_parameter [--quick]``.
"""

from __future__ import annotations

import statistics
import sys
import time

import numpy as np

from benchmarks.common import ROOT, W1, Row, one_blas_thread

RATE = "base.pitching.value"
CONFIGS = {"literal": "paper/fig19_unstable_range.toml"}


def build_pairs(system, rates, speeds, fam=None) -> float:
    """CPU seconds per (first(rate), second(speed)) pair."""
    t0 = time.process_time()
    for w, om in zip(rates, speeds, strict=True):
        if fam is None:
            system.with_parameter(RATE, w).periodic_problem("speed")
            system.periodic_problem(RATE, om)
        else:
            fam.first(w)
            fam.second(om)
    return (time.process_time() - t0) / len(rates)


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.api import build_system, load_config, with_values
    from rotorsfd.paper.cases import calibration_overrides

    rows: list[Row] = []
    n = 5 if quick else 20
    rates = np.linspace(0.0, 10.0, n)
    speeds = W1 * np.linspace(0.9, 1.2, n)
    readings = {"literal": {}, "calibrated": dict(o.split("=", 1)
                                                 for o in calibration_overrides())}
    with one_blas_thread():
        for reading, sets in readings.items():
            config = load_config(ROOT / "examples" / CONFIGS["literal"], [f"{RATE}=10 rad/s"])
            if sets:
                config = with_values(config, sets)
            system = build_system(config, ROOT / "examples")
            fam = system.two_parameter_problem(RATE)
            times: dict[str, list[float]] = {"before": [], "ours": []}
            for _ in range(max(1, repeat)):     # interleaved
                times["before"].append(build_pairs(system, rates, speeds))
                times["ours"].append(build_pairs(system, rates, speeds, fam))
            before, ours = (statistics.median(times[k]) for k in ("before", "ours"))
            case = f"paper rotor {reading}, {RATE}, {n} (speed, rate) pairs"
            rows.append(Row("two-parameter", case, "built from scratch (before)",
                            before * 1e3, unit="ms CPU / pair", repeat=repeat))
            rows.append(Row("two-parameter", case, "family's stored terms (ours)",
                            ours * 1e3, unit="ms CPU / pair", repeat=repeat,
                            ratio=ours / before, ref="before"))
    return rows


if __name__ == "__main__":
    from benchmarks.__main__ import main

    sys.exit(main(["--only", "two-parameter", *sys.argv[1:]]))
