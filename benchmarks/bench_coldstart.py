"""Cold start: ``rotorsfd --help`` and the first call of each compiled kernel, each in a
fresh interpreter (so that import and JIT compilation or cache loading are measured).

- ``rotorsfd --help`` and ``rotorsfd config check examples/paper_rotor.toml``: wall time
  of the console script (subprocess), median of 5.
- ``import rotorsfd.io.config`` (what loading a config costs) and ``import rotorsfd.api``:
  wall and CPU time of the import in a fresh interpreter, median of 5, with the number of
  modules loaded and whether numba, matplotlib, xarray, dask or pint are among them (the
  element kinds keep their kernels in ``elements/<kind>_kernel.py``, imported on first use).
- First calls, each in a fresh subprocess, with numba's on-disk cache on (``cache=True``,
  the project's default; the cache was filled by an earlier call): import of the module,
  model set-up, then the first call (cache load + run) and a second call (run only):
  the SFD kernel (one sample of force and Jacobian), the Newmark loop (one rotor period of
  the paper rotor, 200 steps) and the first HB solve (one point, H = 3).
- The same with an empty cache directory (``NUMBA_CACHE_DIR`` = a new temporary
  directory each time): the JIT compilation cost a user pays once after installing.
  Not in ``--quick``.
"""

from __future__ import annotations

import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from benchmarks.common import ROOT, Row, run_python

PRELUDE = r"""
import json, time
t0 = time.perf_counter()
"""

KERNELS = {
    "SFD kernel (1 sample)": PRELUDE + r"""
import numpy as np
from rotorsfd.sfd import SFD
sfd = SFD.from_ratios(0.0051, 1.27e-4, 0.00485, 0.325, cavitation="pi")
k, p = sfd.numba_kernel, sfd.kernel_params
q, v = np.array([3e-5, -2e-5]), np.array([0.01, 0.02])
F, dq, dv = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
t1 = time.perf_counter()
k(q, v, p, F, dq, dv)
t2 = time.perf_counter()
k(q, v, p, F, dq, dv)
t3 = time.perf_counter()
""",
    "Newmark loop (1 period)": PRELUDE + r"""
from benchmarks.bench_timedomain import ours, paper_inputs
from rotorsfd.analyses.simulate import displaced_state
system, inp = paper_inputs()
q0 = displaced_state(inp.M.shape[0], 1e-6)
t1 = time.perf_counter()
ours(inp, 200, 1, q0, 0.0)
t2 = time.perf_counter()
ours(inp, 200, 1, q0, 0.0)
t3 = time.perf_counter()
""",
    "HB solve (1 point, H=3)": PRELUDE + r"""
from benchmarks.common import W1, paper_system
from rotorsfd.harmonic.periodic import solve_periodic
problem = paper_system().periodic_problem()
t1 = time.perf_counter()
solve_periodic(problem, 0.8 * W1, 3)
t2 = time.perf_counter()
solve_periodic(problem, 0.8 * W1, 3)
t3 = time.perf_counter()
""",
}
POSTLUDE = r"""
print(json.dumps({"setup_s": t1 - t0, "first_s": t2 - t1, "second_s": t3 - t2}))
"""


def cli_help(n: int, *args: str) -> list[float]:
    """Wall times of ``n`` runs of ``rotorsfd ARGS`` (default ``--help``)."""
    exe = shutil.which("rotorsfd") or str(Path(sys.executable).parent / "rotorsfd")
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        subprocess.run([exe, *(args or ("--help",))], cwd=ROOT, capture_output=True,
                       check=True, timeout=120)
        times.append(time.perf_counter() - t0)
    return times


IMPORT_PROBE = r"""
import json, sys, time
t0, c0 = time.perf_counter(), time.process_time()
import {module}
t1, c1 = time.perf_counter(), time.process_time()
heavy = [m for m in ("numba", "matplotlib", "xarray", "dask", "pint") if m in sys.modules]
print(json.dumps({{"wall_s": t1 - t0, "cpu_s": c1 - c0, "modules": len(sys.modules),
                  "heavy": " ".join(heavy) or "none"}}))
"""

#: modules whose import is timed: the config loader and the API
IMPORTS = ("rotorsfd.io.config", "rotorsfd.api")


def import_rows(n: int, bare: float) -> list[Row]:
    """``import <module>`` in fresh interpreters: median wall and CPU time of ``n``."""
    rows = []
    for module in IMPORTS:
        res = [run_python(IMPORT_PROBE.format(module=module)) for _ in range(n)]
        wall = statistics.median(r["wall_s"] for r in res)
        cpu = statistics.median(r["cpu_s"] for r in res)
        rows.append(Row("coldstart", "import (fresh interpreter)", f"import {module}", wall,
                        repeat=n, ratio=wall / bare, ref="bare python",
                        note=(f"CPU {cpu:.2f} s, {res[0]['modules']} modules, heavy: "
                              f"{res[0]['heavy']}"),
                        extra={"cpu_s": cpu, "modules": res[0]["modules"]}))
    return rows


def python_startup(n: int) -> list[float]:
    times = []
    for _ in range(n):
        t0 = time.perf_counter()
        subprocess.run([sys.executable, "-c", "pass"], capture_output=True, check=True)
        times.append(time.perf_counter() - t0)
    return times


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    n = 1 if quick else 5
    bare = statistics.median(python_startup(n))
    t_help = statistics.median(cli_help(n))
    rows = [Row("coldstart", "CLI (subprocess wall time)", "rotorsfd --help", t_help,
                repeat=n, ratio=t_help / bare, ref="bare python",
                note=f"bare 'python -c pass' {bare * 1e3:.0f} ms")]
    t_check = statistics.median(cli_help(n, "config", "check", "examples/paper_rotor.toml"))
    rows.append(Row("coldstart", "CLI (subprocess wall time)",
                    "rotorsfd config check examples/paper_rotor.toml", t_check, repeat=n,
                    ratio=t_check / bare, ref="bare python",
                    note="loads the config and builds the model (numba for the SFD film)"))
    rows += import_rows(n, bare)
    variants = [("cache on", False)] + ([] if quick else [("empty cache: compile", True)])
    for name, code in KERNELS.items():
        for label, fresh in variants:
            res = []
            for _ in range(n if not fresh else max(1, min(repeat, 3))):
                env = {"NUMBA_CACHE_DIR": tempfile.mkdtemp(prefix="bench_numba_")} \
                    if fresh else None
                try:
                    res.append(run_python(code + POSTLUDE, env=env))
                finally:
                    if env:
                        shutil.rmtree(env["NUMBA_CACHE_DIR"], ignore_errors=True)
            med = {k: statistics.median(r[k] for r in res) for k in res[0]}
            rows.append(Row(
                "coldstart", f"first call, {label}", name, med["first_s"], repeat=len(res),
                ratio=med["first_s"] / med["second_s"], ref="second call",
                note=(f"import + set-up {med['setup_s']:.2f} s; second call "
                      f"{med['second_s'] * 1e3:.2f} ms"), extra=med))
    return rows
