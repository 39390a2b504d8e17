"""Shared helpers of the benchmarks: one BLAS thread, medians, fresh subprocesses, rows.

Every figure is a median of repeated runs, and every comparison a ratio measured in the
same run (the machine is shared). BLAS is limited to one thread for every method alike
(environment before numpy is imported, and threadpoolctl for the running process).
"""

from __future__ import annotations

import os

for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ[_var] = "1"

import datetime  # noqa: E402
import json  # noqa: E402
import platform  # noqa: E402
import resource  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import time  # noqa: E402
from collections.abc import Callable  # noqa: E402
from dataclasses import asdict, dataclass, field  # noqa: E402
from pathlib import Path  # noqa: E402
from typing import Any  # noqa: E402

import numpy as np  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
PAPER_ROTOR = ROOT / "examples" / "paper_rotor.toml"
W1 = 811.3  # first critical speed of the paper rotor [rad/s] (Omega~ = Omega / W1)
U_TABLE1 = "144.02 g*mm"  # the paper's Table 1 case: branch with the saddle-node pair
ROSS_DIR = Path(__file__).resolve().parent / ".ross"



def vmhwm_gib() -> float:
    """Peak resident memory of this process [GiB] (``VmHWM``)."""
    for line in Path("/proc/self/status").read_text().splitlines():
        if line.startswith("VmHWM:"):
            return int(line.split()[1]) / 2**20
    return float("nan")


def cpu_timed(fun: Callable[[], Any], repeat: int = 1) -> tuple[float, float, Any]:
    """Median CPU and wall seconds of ``fun()`` over ``repeat`` calls, the last result."""
    cpus, walls, out = [], [], None
    for _ in range(repeat):
        c0, t0 = time.process_time(), time.perf_counter()
        out = fun()
        cpus.append(time.process_time() - c0)
        walls.append(time.perf_counter() - t0)
    return float(np.median(cpus)), float(np.median(walls)), out


def write_jsonl(records: Any, dest: Path | None = None) -> None:
    """Print (and write to ``dest``) one JSON line per record of the iterable
    ``records``, between a start and an end line with the UTC time and the load."""
    def stamp(key: str) -> str:
        return json.dumps({key: time.strftime("%H:%M:%S", time.gmtime()),
                           "load": os.getloadavg()})

    lines = [stamp("start_utc")]
    print(lines[0], flush=True)
    for record in records:
        lines.append(json.dumps(record))
        print(lines[-1], flush=True)
    lines.append(stamp("end_utc"))
    print(lines[-1], flush=True)
    if dest is not None:
        dest.write_text("\n".join(lines) + "\n")


def pop_option(argv: list[str], flag: str) -> tuple[str | None, list[str]]:
    """(the value after ``flag``, argv without the two) or (None, argv)."""
    if flag not in argv:
        return None, argv
    i = argv.index(flag)
    return argv[i + 1], argv[:i] + argv[i + 2:]


def child_record(fun: Callable[[], dict[str, Any]], limit_gib: float | None = None) -> None:
    """The ``--one`` side of a fresh-process workload: ``fun()``'s record with the
    process' peak memory (``peak_gib``) printed as the last line of JSON; the address
    space capped at ``limit_gib`` first when given (a dense path that can exhaust memory
    fails there instead of swapping)."""
    if limit_gib is not None:
        lim = int(limit_gib * 2**30)
        resource.setrlimit(resource.RLIMIT_AS, (lim, lim))
    out = fun()
    out["peak_gib"] = vmhwm_gib()
    print(json.dumps(out))


def fresh_process_record(module: str, args: list[str], timeout: float,
                         env: dict[str, str] | None = None) -> dict[str, Any]:
    """``python -m module --one *args`` in a fresh process (from the repository): the
    load and its record (:func:`child_record`), or ``failed`` with why."""
    try:
        proc = subprocess.run([sys.executable, "-m", module, "--one", *args], cwd=ROOT,
                              capture_output=True, text=True, timeout=timeout, env=env)
    except subprocess.TimeoutExpired:
        return {"failed": f"more than {timeout:.0f} s"}
    if proc.returncode != 0:
        return {"failed": proc.stderr.strip().splitlines()[-1:]}
    return {"load": os.getloadavg()[0], **json.loads(proc.stdout.strip().splitlines()[-1])}

def one_blas_thread() -> Any:
    """Limit BLAS to one thread in this process (threadpoolctl), for every method alike."""
    from threadpoolctl import threadpool_limits

    return threadpool_limits(limits=1)


@dataclass
class Row:
    """One line of the table: ``seconds`` is a median over ``repeat`` runs; ``ratio`` is
    this method's time over the reference method's (``ref``) in the same run."""

    bench: str
    case: str
    method: str
    value: float
    unit: str = "s"
    repeat: int = 1
    ratio: float | None = None
    ref: str = ""
    note: str = ""
    extra: dict[str, Any] = field(default_factory=dict)


def median_time(fun: Callable[[], Any], repeat: int = 3) -> tuple[float, list[float], Any]:
    """Median wall time of ``repeat`` calls, all times, and the last result."""
    times, out = [], None
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        out = fun()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), times, out


def interleaved(funs: dict[str, Callable[[], Any]], repeat: int = 3
                ) -> dict[str, tuple[float, list[float], Any]]:
    """Median times of several methods run in turn (A B C A B C ...): load changes on a
    shared machine hit all of them alike."""
    times: dict[str, list[float]] = {k: [] for k in funs}
    outs: dict[str, Any] = {}
    for _ in range(max(1, repeat)):
        for k, f in funs.items():
            t0 = time.perf_counter()
            outs[k] = f()
            times[k].append(time.perf_counter() - t0)
    return {k: (statistics.median(v), v, outs[k]) for k, v in times.items()}


def run_python(code: str, env: dict[str, str] | None = None, timeout: float = 600.0
               ) -> dict[str, Any]:
    """Run ``code`` in a fresh interpreter (cwd = repository root); the code prints one
    JSON object on its last stdout line, which is returned."""
    e = {**os.environ, **(env or {})}
    p = subprocess.run([sys.executable, "-c", code], cwd=ROOT, env=e, capture_output=True,
                       text=True, timeout=timeout)
    if p.returncode != 0:
        raise RuntimeError(f"subprocess failed ({p.returncode}): {p.stderr.strip()[-800:]}")
    return json.loads(p.stdout.strip().splitlines()[-1])


def paper_config(overrides: list[str] | None = None, unbalance: str = U_TABLE1) -> Any:
    """The paper rotor's config (examples/paper_rotor.toml) at ``unbalance``."""
    from rotorsfd.io.config import load_config

    return load_config(PAPER_ROTOR, [f"unbalance[0].magnitude={unbalance}",
                                     *(overrides or [])])


def paper_system(overrides: list[str] | None = None, unbalance: str = U_TABLE1) -> Any:
    """:class:`RotorSystem` of the paper rotor (fixed base) at ``unbalance``."""
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem

    m = build_model(paper_config(overrides, unbalance))
    return RotorSystem(m.rotor, m.elements, m.unbalances, m.base_motion)


def response_options(config: Any) -> dict[str, Any]:
    """``continue_periodic`` keywords of the config's ``[analysis.response]`` (what
    ``rotorsfd response`` uses), without ``condensed``."""
    from rotorsfd.analyses.response_inputs import continuation_options

    opts = dict(continuation_options(config.analysis.response))
    opts.pop("condensed")
    return opts


def elements_overrides(n_elements: int) -> list[str]:
    """Config overrides for the paper rotor with ``n_elements`` shaft elements (a multiple
    of 20): the disk and the unbalance stay at L/3 (node 8 of 21), the support at the end."""
    if n_elements % 20:
        raise ValueError("n_elements must be a multiple of 20")
    disk = 1 + 7 * n_elements // 20
    return [f"rotor.shaft[0].n_elements={n_elements}", f"rotor.disks[0].node={disk}",
            f"unbalance[0].node={disk}", f"rotor.supports[0].node={n_elements + 1}"]


def cpu_model() -> str:
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                return line.split(":", 1)[1].strip()
    except OSError:
        pass
    return platform.processor() or platform.machine()


def machine_info() -> dict[str, Any]:
    """CPU model, cores (total and usable), memory, load, Python/numpy/scipy/numba."""
    import numba
    import scipy

    try:
        usable = len(os.sched_getaffinity(0))
    except AttributeError:
        usable = os.cpu_count()
    try:
        mem = os.sysconf("SC_PAGE_SIZE") * os.sysconf("SC_PHYS_PAGES") / 2**30
    except (ValueError, OSError):
        mem = float("nan")
    return {"cpu": cpu_model(), "cores": os.cpu_count(), "usable_cores": usable,
            "memory_GiB": round(mem, 1), "platform": platform.platform(),
            "python": platform.python_version(), "numpy": np.__version__,
            "scipy": scipy.__version__, "numba": numba.__version__,
            "blas_threads": 1,
            "date": datetime.datetime.now(datetime.UTC).isoformat(timespec="seconds")}


def git_revision() -> str:
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                             capture_output=True, text=True, timeout=10)
        dirty = subprocess.run(["git", "status", "--porcelain", "--", "src"], cwd=ROOT,
                               capture_output=True, text=True, timeout=10).stdout.strip()
        return out.stdout.strip() + ("+dirty(src)" if dirty else "")
    except (OSError, subprocess.SubprocessError):
        return ""


def rows_to_json(rows: list[Row]) -> list[dict[str, Any]]:
    return [asdict(r) for r in rows]
