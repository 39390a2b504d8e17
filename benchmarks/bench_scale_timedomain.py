"""Time integration at scale (issue 17 item 4): 500 periods x 200 steps of the stepped
1.5 m rotor of :mod:`benchmarks.bench_scale` (80 to 1280 elements, SFD at node 1), the
reduced step (``analysis.simulate.reduction = "auto"``, Craig-Bampton on the SFD DOFs plus
the fixed-interface modes up to 40 Omega and the load residuals) against the full dense
step of before (``reduction = "none"``: an n x 2n step operator).

Speed: 0.8 x the first forward critical speed of the 80-element mesh (the same speed for
every mesh; computed once, not timed). Start: every node displaced 1 um, as ``rotorsfd
simulate``; the last 10 periods recorded at the SFD and the unbalanced disk, 50 Poincare
points, as :func:`~rotorsfd.analyses.td_integration.integrate_periods` runs them.

Rows per mesh, from the built integrator inputs (``time_domain_inputs``, timed apart: it
reads the dense model matrices):

- reduced: ``with_reduction`` (the Craig-Bampton model: at > 400 DOF the CSR path) plus
  the 500-period run; the kept coordinates and the highest kept mode in the note;
- full (dense) step: measured directly over ``FULL_PERIODS`` periods (its ``prepare``, the
  LU of ``K_eff`` and ``A = K_eff^-1 [..]``, timed apart) up to ``FULL_MAX`` elements and
  extrapolated linearly in periods to 500; above ``FULL_MAX`` extrapolated from the
  largest measured mesh as n^2 per step and n^3 for ``prepare`` (stated in the row);
- accuracy: the reduced and the full run over ``ACC_PERIODS`` periods from the linear
  steady state (:func:`linear_start`), largest difference of the SFD and disk orbits and
  Poincare points in C (up to ``ACC_MAX`` elements).

``--quick``: 80 and 160 elements, 20 periods, the full step over 2 periods, no times
asserted.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import Row, median_time

SIZES = (80, 160, 320, 640, 1280)
QUICK_SIZES = (80, 160)
PERIODS = 500
STEPS = 200
FULL_MAX = 640          # largest mesh whose full step is run (its prepare is n^3)
FULL_PERIODS = 4
ACC_MAX = 320
ACC_PERIODS = 60
SPEED_RATIO = 0.8


def build(n_elements: int):
    from benchmarks.bench_scale import config
    from rotorsfd.model.build import build_system

    return build_system(config(n_elements))


def reference_speed() -> float:
    from benchmarks.bench_scale import config, first_critical

    return first_critical(build(80), config(80))


def record_dofs(system) -> list[int]:
    disk = system.unbalances[0].node
    return [*map(int, system.nl_dofs[:2]), system.rotor.dof_index(disk, "y"),
            system.rotor.dof_index(disk, "z")]


def run_periods(inputs, q0, periods: int, rd: list[int], v0=0.0):
    from rotorsfd.analyses.td_integration import integrate_periods

    return integrate_periods(inputs, q0, v0, steps_per_period=STEPS, periods=periods,
                             record_dofs=rd, record_periods=min(10, periods),
                             poincare_periods=min(50, periods))


def linear_start(inputs) -> tuple[np.ndarray, np.ndarray]:
    """``(q, v)`` at t = 0 of the linear steady state (film off, its centring spring
    kept): ``K q_s = f_0`` plus ``Re X``, ``(K - w^2 M + i w D) X = F_c - i F_s``. From
    there the nonlinear runs start without a transient of the undamped high modes (which
    the full step would keep forever and the reduced one does not have)."""
    from rotorsfd.model.lowrank import dense

    h = inputs.forcing.harmonics[0]
    w = inputs.speed
    M, D, K = (dense(a) for a in (inputs.M, inputs.D, inputs.K))   # CSR above 400 DOFs
    X = np.linalg.solve(K - w**2 * M + 1j * w * D, h.cos - 1j * h.sin)
    f0 = inputs.forcing.constant
    qs = np.zeros(inputs.n_dof) if f0 is None else np.linalg.solve(K, f0)
    return qs + X.real, (1j * w * X).real


def full_step_time(inputs, q0, periods: int, rd: list[int]) -> tuple[float, float]:
    """(prepare [s], stepping per period [s]) of the full dense step."""
    from rotorsfd.timedomain.integrate import prepare

    dt = inputs.period / STEPS
    t0 = time.perf_counter()
    prepare(inputs.M, inputs.D, inputs.K, inputs.nl_dofs, inputs.kernel, inputs.params,
            inputs.forcing, dt, STEPS * periods)
    t_prep = time.perf_counter() - t0
    t0 = time.perf_counter()
    run_periods(inputs, q0, periods, rd)
    total = time.perf_counter() - t0
    return t_prep, max(0.0, total - t_prep) / periods


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.analyses.simulate import displaced_state
    from rotorsfd.analyses.td_integration import time_domain_inputs, with_reduction

    sizes = QUICK_SIZES if quick else SIZES
    periods = 20 if quick else PERIODS
    full_periods = 2 if quick else FULL_PERIODS
    speed = SPEED_RATIO * reference_speed()
    rows: list[Row] = []
    measured: dict[int, tuple[int, float, float]] = {}
    series: dict[str, list[tuple[int, float]]] = {"reduced": [], "full": []}
    for n_el in sizes:
        system = build(n_el)
        t0 = time.perf_counter()
        inputs = time_domain_inputs(system, speed)
        t_inputs = time.perf_counter() - t0
        n = inputs.n_dof
        rd = record_dofs(system)
        q0 = displaced_state(n, 1e-6)
        case = f"stepped rotor {n_el} el. ({n} DOF), {periods} periods x {STEPS} steps"
        run_periods(with_reduction(inputs), q0, 1, rd)          # compiled / cache loaded

        def reduced(inputs=inputs, q0=q0, rd=rd):
            t = time.perf_counter()
            ri = with_reduction(inputs)
            t_red = time.perf_counter() - t
            return ri, t_red, run_periods(ri, q0, periods, rd)

        t_red_total, _, (ri, t_reduce, _) = median_time(reduced, repeat)
        red = ri.reduction
        top = float(red.model.omegas.max()) / speed if red.n_modes else 0.0
        series["reduced"].append((n, t_red_total))
        # the full dense step: measured, or extrapolated from the largest measured mesh
        if n_el <= FULL_MAX:
            t_prep, per_period = full_step_time(inputs, q0, full_periods, rd)
            measured[n_el] = (n, t_prep, per_period)
            how = (f"measured over {full_periods} periods (prepare {t_prep:.2f} s + "
                   f"{per_period:.3f} s/period) x {periods}")
        else:
            n0, p0, s0 = measured[max(measured)]
            t_prep, per_period = p0 * (n / n0) ** 3, s0 * (n / n0) ** 2
            how = (f"extrapolated from {n0} DOF: prepare x (n/n0)^3 = {t_prep:.0f} s, "
                   f"stepping x (n/n0)^2 = {per_period:.2f} s/period")
        t_full = t_prep + per_period * periods
        series["full"].append((n, t_full))
        acc = ""
        extra = {"n_dof": n, "reduced_dof": red.n_dof, "modes": red.n_modes,
                 "residuals": red.n_residuals, "highest_mode_over_speed": top,
                 "reduce_s": t_reduce, "inputs_s": t_inputs}
        if n_el <= ACC_MAX:
            C = system.length_scale
            qa, va = linear_start(inputs)
            a = run_periods(ri, qa, min(ACC_PERIODS, periods), rd, va)
            b = run_periods(inputs, qa, min(ACC_PERIODS, periods), rd, va)
            diff = float(max(np.max(np.abs(a.q - b.q)), np.max(np.abs(a.poincare_q
                                                                     - b.poincare_q))) / C)
            amp = float(np.max(np.abs(b.q))) / C
            acc = (f"; reduced - full over {min(ACC_PERIODS, periods)} periods from the "
                   f"linear steady state: {diff:.1e} C (largest orbit {amp:.3f} C)")
            extra["difference_C"] = diff
        rows.append(Row("scale-timedomain", case, "reduced step (CB, cutoff 40 Omega)",
                        t_red_total, ratio=1.0, ref="reduced", repeat=repeat,
                        note=(f"{red.n_dof} coordinates ({red.n_modes} modes up to "
                              f"{top:.1f} Omega, {red.n_residuals} load residuals); "
                              f"reduction {t_reduce:.2f} s; inputs (dense model matrices) "
                              f"{t_inputs:.2f} s apart" + acc), extra=extra))
        rows.append(Row("scale-timedomain", case, "full dense step (n x 2n operator)",
                        t_full, ratio=t_full / t_red_total, ref="reduced", note=how,
                        extra={"prepare_s": t_prep, "per_period_s": per_period,
                               "measured": n_el <= FULL_MAX}))
        print(f"   {n_el:5d} el. {n:5d} DOF: reduced {t_red_total:.2f} s "
              f"(reduction {t_reduce:.2f} s), full {t_full:.1f} s", flush=True)
    if len(sizes) > 2:
        from benchmarks.bench_scale import exponent

        for label, pts in series.items():
            x, y = zip(*pts, strict=True)
            rows.append(Row("scale-timedomain", f"{label} step, {sizes[0]}-{sizes[-1]} "
                            "elements", "exponent p of time ~ DOF^p", exponent(x, y),
                            unit="", note="least-squares slope in log-log"))
    return rows


if __name__ == "__main__":
    from benchmarks.__main__ import main

    sys.exit(main(["--only", "scale-timedomain", *sys.argv[1:]]))
