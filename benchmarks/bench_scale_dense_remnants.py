"""The last dense n x n remnants on the 1280-element stepped rotor (5124 DOF; issue 17
item 2), before / after, each workload in a fresh process (CPU seconds, peak memory
``VmHWM`` with the build):

- ``ns-blocks``: the receptance blocks of the Neimark-Sacker test function
  (``harmonic.ns_curve.receptance_blocks``, K = 6 pairs: 12 shifted frequencies, as
  ``bifurcation-curves`` runs it at H = 3) at 0.8 w1, theta = 0.3: now one banded LU per
  frequency (median of 3 after a warm-up);
- ``ns-blocks-dense``: the same by the code of before (the dense batched solve of the 12
  ``Z(W) = K - W^2 M + i W D``) under an address-space limit of
  :data:`~benchmarks.bench_scale_1280.AS_LIMIT_GIB`;
- ``ns-blocks-dense-2``: the code of before with K = 1 (2 frequencies), once: its time
  x 6 is the 12-frequency cost when memory allows it;
- ``full-step-dense``: ``reduction = "none"`` as before: the full step's ``prepare`` (LU
  of K_eff, ``A = K_eff^-1 [-2K, 4/h M]``) and one period of 200 steps, timed apart;
- ``full-step``: ``run_simulation(reduction = "none")`` now: the time to its ConfigError.

``python -m benchmarks.bench_scale_dense_remnants [NAME ...] [--out FILE]``: one JSON
line per workload and the load average.
"""

from __future__ import annotations

import dataclasses
import sys
import time
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

from benchmarks.bench_scale_1280 import AS_LIMIT_GIB, N_ELEMENTS
from benchmarks.common import (
    child_record,
    cpu_timed,
    fresh_process_record,
    pop_option,
    write_jsonl,
)

ROOT = Path(__file__).resolve().parents[1]
WORKLOADS = ("ns-blocks", "ns-blocks-dense", "ns-blocks-dense-2", "full-step",
             "full-step-dense")
K_PAIRS = 6
THETA = 0.3
STEPS = 200
TIMEOUT_S = 900.0


def _dense(problem: Any) -> Any:
    """The problem with its linear part as plain dense matrices: the dense path."""
    part = problem.matrices
    return dataclasses.replace(problem, matrices=lambda lam: part(lam),
                               dmatrices=part.derivatives)


def one(name: str) -> dict[str, Any]:
    """Run workload ``name`` in this process (module docstring)."""
    from benchmarks import scale_hb as S

    c0 = time.process_time()
    system, problem, w1, _ = S.build(N_ELEMENTS)
    out: dict[str, Any] = {"build_cpu": time.process_time() - c0, "n_dof": system.n_dof}
    lam = 0.8 * w1
    if name.startswith("ns-blocks"):
        from rotorsfd.harmonic.ns_curve import receptance_blocks

        if name == "ns-blocks":
            receptance_blocks(problem, lam, THETA, K_PAIRS)          # warm-up (JIT cache)
            cpu, wall, b = cpu_timed(lambda: receptance_blocks(problem, lam, THETA,
                                                               K_PAIRS), 3)
        else:
            K = 1 if name.endswith("-2") else K_PAIRS
            dense = _dense(problem)
            dense.matrices(lam)                                    # dense M, D, K apart
            cpu, wall, b = cpu_timed(lambda: receptance_blocks(dense, lam, THETA, K))
        out.update(cpu=cpu, wall=wall, frequencies=int(b.shape[0]),
                   result=float(abs(b).max()))
        return out
    from rotorsfd.analyses.td_integration import integrate_periods, time_domain_inputs

    speed = 0.8 * w1
    if name == "full-step":
        from rotorsfd.analyses.simulate import run_simulation
        from rotorsfd.errors import ConfigError

        c1, t1 = time.process_time(), time.perf_counter()
        try:
            run_simulation(system, speed, reduction="none", progress=False)
            out["result"] = "ran"
        except ConfigError as exc:
            out["result"] = str(exc)
        out.update(cpu=time.process_time() - c1, wall=time.perf_counter() - t1)
        return out
    from rotorsfd.timedomain.integrate import prepare

    inputs = dataclasses.replace(time_domain_inputs(system, speed), reduction=None)
    dt = inputs.period / STEPS
    cpu_p, wall_p, _ = cpu_timed(lambda: prepare(
        inputs.M, inputs.D, inputs.K, inputs.nl_dofs, inputs.kernel, inputs.params,
        inputs.forcing, dt, STEPS))
    rd = [int(d) for d in system.nl_dofs]
    cpu, wall, _ = cpu_timed(lambda: integrate_periods(
        inputs, 1e-6, 0.0, steps_per_period=STEPS, periods=1, record_dofs=rd,
        record_periods=1, poincare_periods=1))
    out.update(cpu_prepare=cpu_p, wall_prepare=wall_p, cpu_period=max(0.0, cpu - cpu_p),
               cpu=cpu, wall=wall)
    return out


def run_one(name: str) -> dict[str, Any]:
    """Workload ``name`` in a fresh process: its JSON record (or why it failed)."""
    return {"workload": name, **fresh_process_record(
        "benchmarks.bench_scale_dense_remnants", [name], TIMEOUT_S)}


def main(argv: list[str]) -> None:
    if len(argv) >= 2 and argv[0] == "--one":
        # the batched dense solve can exhaust memory
        child_record(lambda: one(argv[1]),
                     AS_LIMIT_GIB if argv[1] == "ns-blocks-dense" else None)
        return
    dest, argv = pop_option(argv, "--out")
    write_jsonl((run_one(name) for name in argv or list(WORKLOADS)),
                None if dest is None else Path(dest))


if __name__ == "__main__":
    main(sys.argv[1:])
