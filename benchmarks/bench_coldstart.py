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
- The first CLI run after an install (not in ``--quick``): ``rotorsfd response
  examples/paper_rotor.toml`` and ``rotorsfd paper --quick``, each with an empty cache
  directory, by the code before the compile-once change (:data:`BEFORE`, extracted with
  ``git archive``) and by this checkout, then this checkout again with the cache it
  filled: wall and CPU time (the process and its children) and the load average, since
  the 2 cores may be shared. And where the compile time goes: every numba compile of the
  first ``rotorsfd response`` (empty cache, in-process, ``numba:compile`` events), its
  exclusive time summed per kernel module.
"""

from __future__ import annotations

import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from collections import defaultdict
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


#: the code before the kernels were compiled once up front in 2 processes (issue 17 item 5)
BEFORE = "b25da63"
#: first runs timed cold and warm: label -> CLI arguments (each gets ``-o DIR``)
FIRST_RUNS = {"rotorsfd response examples/paper_rotor.toml":
              ("response", "examples/paper_rotor.toml"),
              "rotorsfd paper --quick": ("paper", "--quick")}


def checkout_src(commit: str, into: Path) -> Path:
    """``src/`` (and ``examples/``, which ``rotorsfd paper`` finds above the package) of
    ``commit`` extracted under ``into`` (``git archive``)."""
    archive = subprocess.run(["git", "archive", commit, "src", "examples"], cwd=ROOT,
                             check=True, capture_output=True).stdout
    subprocess.run(["tar", "-x", "-C", str(into)], input=archive, check=True)
    return into / "src"


def cli_run(src: Path, args: tuple[str, ...], cache: Path, out: Path) -> dict[str, object]:
    """``python -m rotorsfd ARGS -o OUT`` with ``src`` first on the path and numba's cache
    in ``cache``: wall and CPU time (with its children), load average before, the
    progress line about compiling."""
    env = {**os.environ, "PYTHONPATH": str(src), "NUMBA_CACHE_DIR": str(cache)}
    load = os.getloadavg()[0]
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = subprocess.run([sys.executable, "-m", "rotorsfd", *args, "-o", str(out)], cwd=ROOT,
                       env=env, capture_output=True, text=True, timeout=900)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise RuntimeError(f"{args} failed ({p.returncode}): {p.stderr.strip()[-800:]}")
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    line = next((x.strip() for x in p.stderr.replace("\r", "\n").splitlines()
                 if x.startswith("compiling")), "")
    return {"wall_s": wall, "cpu_s": cpu, "load": load, "line": line}


def first_run_rows() -> list[Row]:
    """Cold (empty cache) first runs, :data:`BEFORE` against this checkout, and this
    checkout's warm second run."""
    rows = []
    with tempfile.TemporaryDirectory(prefix="bench_first_") as tmp:
        srcs = {f"before ({BEFORE})": checkout_src(BEFORE, Path(tmp)),
                "this checkout": ROOT / "src"}
        for label, args in FIRST_RUNS.items():
            res = {}
            for name, src in srcs.items():
                cache = Path(tempfile.mkdtemp(prefix="cache_", dir=tmp))
                res[name] = cli_run(src, args, cache, Path(tmp) / "out")
                if name == "this checkout":
                    res["this checkout, cache filled"] = cli_run(src, args, cache,
                                                                 Path(tmp) / "out")
            ref = res["this checkout"]["wall_s"]
            for name, r in res.items():
                rows.append(Row("coldstart", f"first run, empty numba cache: {label}", name,
                                r["wall_s"], ratio=r["wall_s"] / ref, ref="this checkout",
                                note=(f"CPU {r['cpu_s']:.1f} s, load {r['load']:.1f}"
                                      + (f"; '{r['line']}'" if r["line"] else "")),
                                extra=r))
    return rows


#: every numba compile of a CLI run in-process (``numba:compile`` events; a cfunc's
#: compile timed around ``CFunc._compile_uncached``): exclusive time per function
PROFILE = r"""
import json, sys, time
from numba.core import ccallback, event
stack, recs = [], []
def _done(name):
    t0, child = stack.pop()
    dt = time.perf_counter() - t0
    if stack:
        stack[-1][1] += dt
    recs.append({"name": name, "excl": dt - child, "incl": dt})
class Listener(event.Listener):
    def on_start(self, ev):
        stack.append([time.perf_counter(), 0.0])
    def on_end(self, ev):
        f = ev.data["dispatcher"].py_func
        _done(f.__module__ + "." + f.__qualname__)
event.register("numba:compile", Listener())
_orig = ccallback.CFunc._compile_uncached
def _cfunc(self):
    stack.append([time.perf_counter(), 0.0])
    try:
        return _orig(self)
    finally:
        _done("cfunc " + self._pyfunc.__module__ + "." + self._pyfunc.__qualname__)
ccallback.CFunc._compile_uncached = _cfunc
from rotorsfd.cli.app import main
t0 = time.perf_counter()
main(ARGS)
print(json.dumps({"wall_s": time.perf_counter() - t0, "recs": recs}))
"""


def compile_profile(args: tuple[str, ...], src: Path) -> dict[str, object]:
    """:data:`PROFILE` of ``rotorsfd ARGS -o TMP -q`` with an empty cache."""
    with tempfile.TemporaryDirectory(prefix="bench_profile_") as tmp:
        argv = [*args, "-o", str(Path(tmp) / "out"), "-q"]
        return run_python(PROFILE.replace("ARGS", repr(argv)),
                          env={"PYTHONPATH": str(src), "NUMBA_CACHE_DIR": tmp})


def profile_rows(args: tuple[str, ...] = FIRST_RUNS[next(iter(FIRST_RUNS))]) -> list[Row]:
    """Exclusive compile time of the first ``rotorsfd ARGS`` per kernel module (numba's
    own helpers, e.g. ``np.empty``, under ``numba``), with its largest functions."""
    prof = compile_profile(args, ROOT / "src")
    per: dict[str, list[tuple[float, str]]] = defaultdict(list)
    for r in prof["recs"]:
        name = r["name"].removeprefix("cfunc ")
        module = "numba" if name.startswith("numba.") else ".".join(
            name.split(".")[:-1] if "<locals>" not in name else name.split(".")[:2])
        per[module].append((r["excl"], name.rsplit(".", 1)[-1]))
    total = sum(t for v in per.values() for t, _ in v)
    rows = []
    for module, items in sorted(per.items(), key=lambda kv: -sum(t for t, _ in kv[1])):
        sec = sum(t for t, _ in items)
        top = ", ".join(f"{n} {t:.2f}" for t, n in sorted(items, reverse=True)[:3])
        rows.append(Row("coldstart", f"compile time per module, first rotorsfd {args[0]}",
                        module, sec, ratio=sec / total, ref="all compiles",
                        note=f"{len(items)} compiles; largest: {top}; load "
                             f"{os.getloadavg()[0]:.1f}"))
    return rows


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
    if not quick:
        rows += first_run_rows() + profile_rows()
    return rows
