"""Modal damping of a few modes at scale (issue 17 item 2, its modal-damping part): the
stepped rotor of :mod:`benchmarks.bench_scale` with ``damping.kind = "modal"``,
``ratio = 0.2 %``, ``modes = 6`` (``C_s = U diag(c) U^T``, U = M Phi n x 6), meshed in 80,
320 and 1280 elements. The damping stays banded + low-rank
(:class:`rotorsfd.model.lowrank.BandedLowRank`) through the linear analyses (shift-invert
with a Woodbury correction), the Floquet basis and the time step (Craig-Bampton
projections from the factors), against the path of before, run in the same process on
the same built model: the damping handed over as one matrix with the low-rank term
formed (a full n x n: 26 M entries at 1280 elements), i.e.

- linear: the system seen through ``matrices`` / ``sparse_matrices`` only
  (:class:`FullDamping`, what ``sparse_modes`` read before ``split_matrices``);
- Floquet: ``FloquetEvaluator.linear_part = problem.matrices.sparse`` (the full CSR D);
- time step: the integrator's inputs as dense M, D, K (``time_terms.DENSE_MAX_DOF`` raised:
  the ``system.matrices(speed)`` of before), reduced from them.

Workloads, CPU seconds of this process (``time.process_time``) and wall: the first
forward critical speed (``reference.speed = "first_critical"``), ``run_modal``'s work
(critical speeds, reference, 81-speed Campbell diagram of 8 modes), the multipliers of
every point of the 56-point HB branch (``FloquetEvaluator``, M = 400; 1280 elements only),
and 500 periods x 200 steps at 0.8 w1 from every node displaced 1 um (the reduced step,
``reduction = "auto"``, cutoff 40 Omega; 1280 elements only). Peak memory: a fresh process
per workload (build + workload). The results of the two paths are compared in each row's
note (relative). ``--quick``: 80 elements, first critical speed and modal, one repeat.
"""

from __future__ import annotations

import contextlib
import json
import resource
import subprocess
import sys
import time
from collections.abc import Iterator
from functools import partial
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import Row

ROOT = Path(__file__).resolve().parents[1]
SIZES = (80, 320, 1280)
QUICK_SIZES = (80,)
TARGET = 1280
RATIO, MODES = 0.002, 6
PERIODS, STEPS = 500, 200


def build(n_elements: int) -> tuple[Any, Any]:
    """(system, config) of the stepped rotor with modal damping of MODES modes."""
    from benchmarks.bench_scale import stepped_rotor_config
    from rotorsfd import api
    from rotorsfd.io.config import config_from_dict

    d = stepped_rotor_config(n_elements)
    d["rotor"]["damping"] = {"kind": "modal", "ratio": RATIO, "modes": MODES}
    cfg = config_from_dict(d)
    return api.build_system(cfg), cfg


class FullDamping:
    """``system`` as the linear solvers saw it before: ``matrices`` and
    ``sparse_matrices`` (the damping with its low-rank term formed: a full matrix)."""

    def __init__(self, system: Any) -> None:
        self.system, self.n_dof = system, system.n_dof

    def matrices(self, speed: float):
        return self.system.matrices(speed)

    def sparse_matrices(self, speed: float):
        return self.system.sparse_matrices(speed)


@contextlib.contextmanager
def dense_inputs() -> Iterator[None]:
    """The integrator's inputs dense inside the block (``system.matrices``: before)."""
    from rotorsfd.model import time_terms

    old = time_terms.DENSE_MAX_DOF
    time_terms.DENSE_MAX_DOF = 10**9
    try:
        yield
    finally:
        time_terms.DENSE_MAX_DOF = old


def timed(fun: Any) -> tuple[float, float, Any]:
    t0, c0 = time.perf_counter(), time.process_time()
    out = fun()
    return time.perf_counter() - t0, time.process_time() - c0, out


def first(system: Any, cfg: Any) -> float:
    from rotorsfd.analyses.modal import first_critical

    return first_critical(system, cfg.analysis.modal.critical_speed_max)


def modal(system: Any, cfg: Any) -> np.ndarray:
    """run_modal's work; the critical speeds and the Campbell eigenvalues."""
    from benchmarks.bench_scale import modal_from

    crit, camp, ref = modal_from(system, cfg)
    return np.concatenate([[c.speed_rad_s for c in crit], [ref],
                           np.abs(camp.eigenvalues).ravel()])


def hb_branch(system: Any, w1: float, cfg: Any) -> tuple[Any, Any]:
    from benchmarks import scale_hb as S
    from benchmarks.common import response_options

    problem = system.periodic_problem()
    return problem, S.branch(problem, w1, response_options(cfg))


def stability(problem: Any, br: Any, before: bool = False) -> np.ndarray:
    from benchmarks import scale_hb as S
    from rotorsfd.stability.branch_options import StabilityOptions
    from rotorsfd.stability.floquet_evaluator import FloquetEvaluator

    ev = FloquetEvaluator(problem, StabilityOptions(n_intervals=S.N_INTERVALS))
    if before:
        ev.linear_part = problem.matrices.sparse          # the full CSR damping
    return np.array([ev(float(br.lam[j]), br.X[j]).max_abs for j in range(br.n_points)])


def simulate(system: Any, speed: float, before: bool = False) -> tuple[np.ndarray, int]:
    """500 x 200 steps of the reduced step (inputs, reduction and run); the SFD orbit of
    the last 10 periods and the reduced coordinates."""
    from benchmarks.bench_scale_timedomain import record_dofs
    from rotorsfd.analyses.simulate import displaced_state
    from rotorsfd.analyses.td_integration import (
        integrate_periods,
        time_domain_inputs,
        with_reduction,
    )

    with dense_inputs() if before else contextlib.nullcontext():
        inputs = with_reduction(time_domain_inputs(system, speed))
    run = integrate_periods(inputs, displaced_state(inputs.n_dof, 1e-6), 0.0,
                            steps_per_period=STEPS, periods=PERIODS,
                            record_dofs=record_dofs(system), record_periods=10,
                            poincare_periods=50)
    return run.q, inputs.reduction.n_dof


def rel(a: Any, b: Any) -> float:
    a, b = np.asarray(a), np.asarray(b)
    return float(np.abs(a - b).max() / max(np.abs(b).max(), 1e-300))


def peak_memory(n: int, workload: str, before: bool) -> float:
    """Peak RSS [GiB] of a fresh process: build + ``workload`` (before or after)."""
    out = subprocess.run([sys.executable, "-m", "benchmarks.bench_scale_modal", "--memory",
                          str(n), workload, "before" if before else "after"], cwd=ROOT,
                         capture_output=True, text=True, check=True)
    return float(json.loads(out.stdout.strip().splitlines()[-1])["peak_gib"])


def _memory_main(n: int, workload: str, which: str) -> None:
    system, cfg = build(n)
    before = which == "before"
    lin = FullDamping(system) if before else system
    if workload == "first":
        first(lin, cfg)
    elif workload == "modal":
        modal(lin, cfg)
    elif workload == "stability":
        problem, br = hb_branch(system, first(system, cfg), cfg)
        stability(problem, br, before)
    elif workload == "simulate":
        simulate(system, 0.8 * first(system, cfg), before)
    print(json.dumps({"peak_gib": peak_rss_gib()}))


def peak_rss_gib() -> float:
    """Peak resident memory of this process [GiB]: ``VmHWM`` of /proc/self/status (its
    own address space; ``ru_maxrss`` would carry the parent's size at the fork across
    the exec), else ``ru_maxrss``."""
    try:
        for line in Path("/proc/self/status").read_text().splitlines():
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) / 2**20
    except OSError:
        pass
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20


def pair(rows: list[Row], case: str, label: str, new: tuple, old: tuple, note: str) -> None:
    """Rows of one workload: after (the reference) and before, CPU in the notes."""
    rows += [Row("scale-modal", case, f"{label}: banded + low-rank", new[0], ratio=1.0,
                 ref="low-rank", note=f"CPU {new[1]:.3g} s; {note}"),
             Row("scale-modal", case, f"{label}: full damping matrix (before)", old[0],
                 ratio=old[0] / new[0], ref="low-rank",
                 note=f"CPU {old[1]:.3g} s (CPU ratio {old[1] / new[1]:.3g}x)")]


def run(quick: bool = False, repeat: int = 1) -> list[Row]:
    sizes = QUICK_SIZES if quick else SIZES
    rows: list[Row] = []
    for n in sizes:
        system, cfg = build(n)
        case = f"{n} elements ({system.n_dof} DOF), modal damping {RATIO:g} on {MODES} modes"
        first(system, cfg)                      # warm-up (imports, ARPACK)
        old = FullDamping(system)
        a, b = timed(partial(first, system, cfg)), timed(partial(first, old, cfg))
        pair(rows, case, "first critical speed", a, b,
             f"w1 = {a[2]:.6f} rad/s, relative difference {rel(a[2], b[2]):.1e}")
        a, b = timed(partial(modal, system, cfg)), timed(partial(modal, old, cfg))
        pair(rows, case, "modal (critical speeds + Campbell)", a, b,
             f"largest relative difference {rel(a[2], b[2]):.1e}")
        if n != TARGET:
            continue
        w1 = first(system, cfg)
        problem, br = hb_branch(system, w1, cfg)
        a = timed(partial(stability, problem, br))
        b = timed(partial(stability, problem, br, before=True))
        pair(rows, case, f"stability of the {br.n_points}-point branch", a, b,
             f"M = 400; max |mu| {a[2].max():.6f}, largest difference {rel(a[2], b[2]):.1e}")
        a = timed(partial(simulate, system, 0.8 * w1))
        b = timed(partial(simulate, system, 0.8 * w1, before=True))
        pair(rows, case, f"simulate {PERIODS} x {STEPS} (inputs + reduction + run)", a, b,
             f"{a[2][1]} coordinates; SFD / disk orbit difference {rel(a[2][0], b[2][0]):.1e}")
        rows += memory_rows(n, case)
    return rows


def memory_rows(n: int, case: str) -> list[Row]:
    """Peak memory of build + each workload in a fresh process, after and before."""
    rows = []
    for workload in ("first", "modal", "stability", "simulate"):
        for before in (False, True):
            rows.append(Row("scale-modal", case, f"peak memory: {workload}"
                            + (" (before)" if before else ""),
                            peak_memory(n, workload, before), unit="GiB",
                            note="fresh process: build + workload"))
    return rows


if __name__ == "__main__":
    if len(sys.argv) >= 5 and sys.argv[1] == "--memory":
        _memory_main(int(sys.argv[2]), sys.argv[3], sys.argv[4])
    else:
        from benchmarks.__main__ import fmt_value

        rows = (memory_rows(TARGET, f"{TARGET} elements") if "--memory-rows" in sys.argv
                else run(quick="--quick" in sys.argv))
        for r in rows:
            print(f"{r.case} | {r.method}: {fmt_value(r)}  {r.note}")
