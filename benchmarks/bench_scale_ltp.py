"""Run-ups and LTP stability charts at scale (issue 17 item 2): the stepped 1.5 m rotor of
:mod:`benchmarks.bench_scale` (1280 elements, 5124 DOF) on a harmonically pitching base,
the banded / reduced path of now against the dense path of before, each workload in a
fresh process (CPU seconds of the process, peak memory ``VmHWM``).

Workloads (:func:`workload`), from the config (build included):

- ``runup``: :func:`~rotorsfd.analyses.runup.run_speed_law` of a ramp from 0.5 to 1.2 x
  the first forward critical speed of the 80-element mesh over ``RUNUP_PERIODS`` periods
  of the top speed at T/``STEPS``, the reduced step (``reduction = "auto"``), from every
  node displaced 1 um. Before: the dense rotor matrices M, C, K, G and the dense (12, n, n)
  stack of the base patterns in the inputs (the reduced step then converted them to CSR);
  now: CSR throughout (``keeps_band``).
- ``chart``: :func:`~rotorsfd.analyses.stability_chart.run_stability_chart` over
  ``GRID`` x ``GRID`` points of (pitching amplitude, pitching frequency) at 0.8 x that
  critical speed, ``INTERVALS`` Newmark intervals per period. Before, a model above 400
  DOFs failed (``rotor_ltp_system`` took ``np.asarray`` of the CSR record); the baseline
  is the dense path of a small model forced at this size (dense record and base stack,
  LAPACK ``eigh`` of the whole pencil for the modal basis). Now: CSR, shift-invert modes.

The "before" runs raise the module thresholds (``DENSE_MAX_DOF`` of
:mod:`rotorsfd.model.time_terms`, :mod:`rotorsfd.model.base_terms` and, for the chart,
:mod:`rotorsfd.stability.chart`) so that the code takes the dense path it takes at <= 400
DOFs; the equations are the same (the tests compare both paths at 404 DOFs).

``--quick``: 112 elements (452 DOF), 5 periods, a 2 x 2 chart of 100 intervals, the
banded path only, in this process (no baseline, no peak memory asserted).
Run: ``python -m benchmarks --only scale-ltp`` or ``python benchmarks/bench_scale_ltp.py``.
"""

from __future__ import annotations

import json
import subprocess
import sys
import time
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import Row

ROOT = Path(__file__).resolve().parents[1]
SIZE = 1280
QUICK_SIZE = 112
STEPS = 100
RUNUP_PERIODS = 30
GRID = 4
INTERVALS = 200
PITCH = {"law": "harmonic", "frequency": 60.0, "angle_amplitude": 2e-3}
FREQ = "base.pitching.frequency"
A0 = "base.pitching.angle_amplitude"


def raw_config(n_elements: int) -> dict[str, Any]:
    """The stepped rotor on the pitching base (raw config table)."""
    from benchmarks.bench_scale import stepped_rotor_config

    raw = stepped_rotor_config(n_elements)
    raw["base"] = {"pitching": dict(PITCH)}
    return raw


def critical_speed() -> float:
    """First forward critical speed of the 80-element mesh [rad/s] (fixed base)."""
    from benchmarks.bench_scale import config, first_critical
    from rotorsfd.model.build import build_system

    return first_critical(build_system(config(80)), config(80))


def dense_path(chart: bool) -> None:
    """Raise the thresholds: the dense path of a <= 400 DOF model (module docstring)."""
    from rotorsfd.model import base_terms, time_terms
    from rotorsfd.stability import chart as ltp_chart

    big = 10**9
    time_terms.DENSE_MAX_DOF = big
    base_terms.DENSE_MAX_DOF = big
    if chart:
        ltp_chart.DENSE_MAX_DOF = big


def runup(n_elements: int, w_c: float, periods: int = RUNUP_PERIODS) -> dict[str, Any]:
    from rotorsfd.analyses.runup import run_speed_law
    from rotorsfd.io.config import config_from_dict
    from rotorsfd.model.build import build_system
    from rotorsfd.timedomain.speed_law import RampSpeed

    system = build_system(config_from_dict(raw_config(n_elements)))
    w1 = 1.2 * w_c
    t_end = periods * 2.0 * np.pi / w1
    law = RampSpeed(0.5 * w_c, w1, t_end)
    q0 = np.zeros(system.n_dof)
    q0[0::4] = q0[1::4] = 1e-6
    run = run_speed_law(system, law, t_end, steps_per_period=STEPS,
                        record_dofs=[int(d) for d in system.nl_dofs[:2]], q0=q0,
                        reduction="auto")
    r = np.hypot(run.q[:, 0], run.q[:, 1])
    return {"n_dof": system.n_dof, "steps": int(run.t.size - 1),
            "peak_radius_C": float(r.max() / system.length_scale)}


def chart(n_elements: int, w_c: float, grid: int = GRID, intervals: int = INTERVALS
          ) -> dict[str, Any]:
    from rotorsfd.analyses.stability_chart import run_stability_chart
    from rotorsfd.io.config import config_from_dict

    raw = raw_config(n_elements)
    raw["analysis"] = {"stability_chart": {"speed": 0.8 * w_c}}
    res = run_stability_chart(config_from_dict(raw), x=(A0, np.linspace(0.0, 0.2, grid)),
                              y=(FREQ, np.linspace(0.2, 1.6, grid) * w_c),
                              n_intervals=intervals)
    return {"n_dof": int(res.chart.info["n_dof"]),
            "n_reduced": int(res.chart.info["n_reduced"]),
            "max_abs": res.chart.max_abs.tolist()}


def peak_memory_gib() -> float:
    """``VmHWM`` of this process [GiB]."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM"):
            return int(line.split()[1]) / 2**20
    return float("nan")


def workload(name: str, n_elements: int, w_c: float, before: bool,
             quick: bool = False) -> dict[str, Any]:
    """Run one workload in this process: its result, CPU seconds and VmHWM."""
    if before:
        dense_path(chart=name == "chart")
    c0, t0 = time.process_time(), time.perf_counter()
    if name == "runup":
        out = runup(n_elements, w_c, 5 if quick else RUNUP_PERIODS)
    else:
        out = chart(n_elements, w_c, 2 if quick else GRID, 100 if quick else INTERVALS)
    out.update(cpu_s=time.process_time() - c0, wall_s=time.perf_counter() - t0,
               peak_gib=peak_memory_gib())
    return out


def fresh(name: str, n_elements: int, w_c: float, before: bool) -> dict[str, Any]:
    """:func:`workload` in a fresh Python process."""
    cmd = [sys.executable, "-m", "benchmarks.bench_scale_ltp", "--workload", name,
           str(n_elements), repr(w_c), "before" if before else "now"]
    out = subprocess.run(cmd, cwd=ROOT, capture_output=True, text=True, check=True)
    return json.loads(out.stdout.strip().splitlines()[-1])


def run(quick: bool = False, repeat: int = 1) -> list[Row]:
    """Rows of the module docstring (one fresh process per workload and path)."""
    n_el = QUICK_SIZE if quick else SIZE
    w_c = critical_speed()
    rows: list[Row] = []
    for name in ("runup", "chart"):
        now = workload(name, n_el, w_c, False, quick=True) if quick else \
            fresh(name, n_el, w_c, before=False)
        what = (f"run-up 0.5-1.2 x w_c, {RUNUP_PERIODS} periods x T/{STEPS}, reduced step"
                if name == "runup" else
                f"LTP chart {GRID}x{GRID} (A0, w_b), {INTERVALS} intervals")
        if quick:
            what = f"{name}, quick settings"
        case = f"stepped rotor {n_el} el. ({now['n_dof']} DOF), pitching base: {what}"
        note = (f"peak SFD radius {now['peak_radius_C']:.3f} C" if name == "runup" else
                f"basis {now['n_reduced']} modes (shift-invert)")
        rows.append(Row("scale-ltp", case, "banded / reduced (now)", now["cpu_s"],
                        ratio=1.0, ref="now",
                        note=f"CPU s; peak {now['peak_gib']:.2f} GiB; {note}", extra=now))
        if quick:
            continue
        old = fresh(name, n_el, w_c, before=True)
        if name == "chart":
            diff = float(np.max(np.abs(np.subtract(now["max_abs"], old["max_abs"]))))
            note = f"basis {old['n_reduced']} modes (dense eigh); max |mu| differs {diff:.1e}"
        else:
            note = (f"peak SFD radius {old['peak_radius_C']:.3f} C "
                    f"(now {now['peak_radius_C']:.3f} C)")
        rows.append(Row("scale-ltp", case, "dense path (before)", old["cpu_s"],
                        ratio=old["cpu_s"] / now["cpu_s"], ref="now",
                        note=f"CPU s; peak {old['peak_gib']:.2f} GiB; {note}", extra=old))
    return rows


if __name__ == "__main__":
    if len(sys.argv) >= 6 and sys.argv[1] == "--workload":
        res = workload(sys.argv[2], int(sys.argv[3]), float(sys.argv[4]),
                       sys.argv[5] == "before")
        print(json.dumps(res))
        sys.exit(0)
    from benchmarks.__main__ import main

    sys.exit(main(["--only", "scale-ltp", *sys.argv[1:]]))
