"""Is numba's on-disk cache of an analysis' compiled kernels warm? If not, fill it before
the analysis starts, on two cores, and say so in one progress line.

The compiled loops (``@njit(cache=True)``) are compiled on their first call and their
machine code is stored in numba's cache (``__pycache__`` beside the sources, or under
``NUMBA_CACHE_DIR``). The first run after an install or an update pays the compilation
once; later runs load the code in a fraction of a second. :func:`cold_modules` reads each
kernel module's cache index the way numba does (an index whose source stamp does not
match the file is stale, as after an edit) without compiling anything.

Numba compiles one function at a time under a process-wide lock, and a caller's compile
re-optimises the code of every kernel it calls, so the entry points of an analysis
(:data:`ENTRY_POINTS`: the kernels Python calls, with the argument types the solvers pass)
are split into :data:`GROUPS` whose call trees share no function, and
:func:`compile_kernels` compiles the groups side by side: the first in this process, the
others in ``python -m rotorsfd.kernel_cache ANALYSIS GROUP`` subprocesses that write the
cache this process then loads. :func:`compile_notice` prints ``compiling the numerical
kernels once (...) ...`` on stderr, compiles, and ends the line with the measured wall
and CPU times. A kernel missing from the table (another force law, another solver
option) is compiled on its first call as before.
"""

from __future__ import annotations

import importlib
import os
import subprocess
import sys
import time
from collections.abc import Sequence
from typing import Any, TextIO

from numba import types

from rotorsfd.kernels import as_cfunc, as_inertial_cfunc

try:
    import resource
except ImportError:  # not on Unix: the subprocesses' CPU time is not reported
    resource = None  # type: ignore[assignment]

__all__ = ["COMPILE_SECONDS", "ENTRY_POINTS", "GROUPS", "KERNEL_MODULES", "cold_modules",
           "compile_group", "compile_kernels", "compile_notice", "module_cached"]

#: analysis -> the modules of the compiled loops it runs
KERNEL_MODULES: dict[str, tuple[str, ...]] = {
    "response": ("rotorsfd.harmonic.aft_kernels", "rotorsfd.harmonic.banded",
                 "rotorsfd.model.sfd_kernels", "rotorsfd.stability.monodromy_kernels"),
    "simulate": ("rotorsfd.timedomain.newmark", "rotorsfd.model.sfd_kernels"),
}
KERNEL_MODULES["bifurcation_diagram"] = KERNEL_MODULES["simulate"]
KERNEL_MODULES["paper"] = tuple(dict.fromkeys(KERNEL_MODULES["response"]
                                              + KERNEL_MODULES["simulate"]))

#: wall time of :func:`compile_kernels` with an empty cache on 2 cores [s] (rounded up;
#: benchmarks/README.md "Compiling the kernels")
COMPILE_SECONDS: dict[str, int] = {"response": 15, "simulate": 10, "bifurcation_diagram": 10,
                                   "paper": 20}

_F8, _I8, _B1 = types.float64, types.int64, types.boolean
_F1, _F2, _F3, _F4 = (types.float64[::1], types.float64[:, ::1], types.float64[:, :, ::1],
                      types.float64[:, :, :, ::1])
_C2, _C3, _I1 = types.complex128[:, ::1], types.complex128[:, :, ::1], types.int64[::1]
_KERNEL = types.FunctionType(types.int64(_F1, _F1, _F1, _F1, _F2, _F2))
_INERTIAL = types.FunctionType(types.int64(_F1, _F1, _F1, _F1, _F1, _F2, _F2, _F2))

#: an entry point: (module, function, argument types); the types ``"cfunc"`` /
#: ``"inertial cfunc"`` mean the first-class version of a force kernel
#: (:func:`rotorsfd.kernels.as_cfunc` / :func:`~rotorsfd.kernels.as_inertial_cfunc`)
Entry = tuple[str, str, Any]

#: name -> entry point, with the argument types the solvers pass (C-contiguous float64 /
#: complex128 arrays, int64 indices; tests/test_kernel_cache.py checks that a run after
#: :func:`compile_kernels` compiles nothing)
ENTRY_POINTS: dict[str, Entry] = {
    "condense_bands": ("rotorsfd.harmonic.banded", "condense_bands",
                       (_F2,) * 6 + (_F8, _F8, _I8, _I8, _I1, _C2, _C2, _C2, _B1, _C3, _C3,
                                     _C3, _C2, _C3, _C2, types.none, _I8)),
    "condensed_residual": ("rotorsfd.harmonic.aft_kernels", "condensed_residual",
                           (_KERNEL, _F1, _F2, _F8, _F8, _F2, _F2, _F2, _C3, _F2, _C3, _C2,
                            _C3, _C2, _B1, _F2, _F2, _F2, _F2, _F3, _F3, _F2, _F4, _F2, _F2,
                            _F2, _F2)),
    "force_coefficients": ("rotorsfd.harmonic.aft_kernels", "force_coefficients",
                           (_KERNEL, _F1, _F2, _F8) + (_F2,) * 7 + (_F3, _F3, _F2)),
    "monodromy": ("rotorsfd.stability.monodromy_kernels", "newmark_loop",
                  (_F2, _F2, _F2, _F2, _I1, _F3, _F3, _F8)),
    "sfd_batch": ("rotorsfd.model.sfd_kernels", "sfd_batch",
                  (_F1,) * 5 + (_F2, _F3, _F3, _B1)),
    "sfd_element": ("rotorsfd.elements.sfd_kernel", "sfd_element_kernel", "cfunc"),
    "null_inertial": ("rotorsfd.timedomain.kernels", "null_inertial_kernel",
                      "inertial cfunc"),
    "eval_kernel": ("rotorsfd.timedomain.newmark", "eval_kernel",
                    (_KERNEL, _F1, _F1, _F1, _F1, _F2, _F2)),
    "run_steps": ("rotorsfd.timedomain.newmark", "run_steps",
                  (_KERNEL, _F1, _I8, _F1, _F2, _F2, _F2, _I1, _F8, _F8, _F1, _F1, _F2, _F2,
                   _F2, _F2, _F2, _I1, _F3, _F1, _F1, _F1, _F1, _I8, _I8, _I1, _I8, _I8, _F1,
                   _F2, _F2, _I8, _I8, _F1, _F2, _F2, _F8, _F8, _I8, _F8, _I8, _I1, _F1,
                   _INERTIAL, _B1, _F1)),
}

_AFT = ("condensed_residual", "force_coefficients", "monodromy")
_SFD = ("sfd_batch", "sfd_element")
#: analysis -> groups of entry points compiled side by side (one process each), balanced
#: by their measured compile time; no function is compiled by two groups (numba's cache
#: index of a function is rewritten whole by the process that adds to it)
GROUPS: dict[str, tuple[tuple[str, ...], ...]] = {
    "response": (("condense_bands", *_SFD), _AFT),
    "simulate": (("run_steps", "eval_kernel"), ("sfd_element", "null_inertial")),
    "paper": (("condense_bands", "run_steps", "eval_kernel"), _AFT + _SFD + ("null_inertial",)),
}
GROUPS["bifurcation_diagram"] = GROUPS["simulate"]


def _dispatchers(module: Any) -> list[Any]:
    """The cached numba dispatchers defined in ``module``."""
    out = []
    for value in vars(module).values():
        cache = getattr(value, "_cache", None)
        func = getattr(value, "py_func", None)
        if cache is not None and func is not None and func.__module__ == module.__name__:
            out.append(value)
    return out


def module_cached(name: str) -> bool | None:
    """True when numba's cache holds fresh code of at least one kernel of module
    ``name`` (the module has been run since its last change), False when none; None when
    the cache cannot be read (another numba layout: then nothing is announced)."""
    module = importlib.import_module(name)
    try:
        files = [d._cache._cache_file for d in _dispatchers(module)]
        return any(bool(f._load_index()) for f in files) if files else None
    except (AttributeError, OSError, EOFError, ValueError):
        return None


def cold_modules(analysis: str) -> list[str]:
    """The kernel modules of ``analysis`` (a key of :data:`KERNEL_MODULES`) that numba
    will compile on this run (none cached)."""
    return [m for m in KERNEL_MODULES.get(analysis, ()) if module_cached(m) is False]


def compile_entry(name: str) -> None:
    """Compile (or load from the cache) entry point ``name`` of :data:`ENTRY_POINTS`."""
    module, function, signature = ENTRY_POINTS[name]
    kernel = getattr(importlib.import_module(module), function)
    if signature == "cfunc":
        as_cfunc(kernel)
    elif signature == "inertial cfunc":
        as_inertial_cfunc(kernel)
    else:
        kernel.compile(signature)


def compile_group(analysis: str, index: int) -> None:
    """Compile the entry points of group ``index`` of ``analysis`` (:data:`GROUPS`)."""
    for name in GROUPS[analysis][index]:
        compile_entry(name)


def _cores() -> int:
    try:
        return len(os.sched_getaffinity(0))
    except AttributeError:  # not on Linux
        return os.cpu_count() or 1


def _children_cpu() -> float:
    """CPU time of this process' finished children [s] (NaN where not known)."""
    if resource is None:
        return float("nan")
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def compile_kernels(analysis: str, processes: int | None = None
                    ) -> tuple[float, list[float]]:
    """Compile the entry points of ``analysis`` into numba's cache, its :data:`GROUPS`
    side by side in ``processes`` processes (default: the CPUs, at most the groups); this
    process compiles the first group and waits for the others. A subprocess that fails
    leaves its kernels to be compiled on first use. Returns the wall time [s] and the CPU
    time of each process [s] (this one first; on idle cores the wall time is about the
    largest, more when other jobs share the cores)."""
    groups = GROUPS.get(analysis, ())
    n = max(1, min(processes or _cores(), len(groups)))
    t0, c0 = time.perf_counter(), time.process_time()
    r0 = _children_cpu()
    children = [subprocess.Popen([sys.executable, "-m", "rotorsfd.kernel_cache", analysis,
                                  str(i)], stdout=subprocess.DEVNULL,
                                 stderr=subprocess.DEVNULL) for i in range(1, n)]
    cpu = []
    try:
        for i in [0, *range(n, len(groups))]:
            compile_group(analysis, i)
        cpu.append(time.process_time() - c0)
    finally:
        for child in children:
            child.wait()
            r1 = _children_cpu()
            cpu.append(r1 - r0)
            r0 = r1
    return time.perf_counter() - t0, cpu


def compile_notice(analysis: str, stream: TextIO | None = None) -> bool:
    """When ``analysis`` would compile kernels: print ``compiling the numerical kernels
    once (modules; about N s on 2 idle cores) ...`` on ``stream`` (stderr), compile them
    (:func:`compile_kernels`) and end the line with the measured time. True if it did."""
    cold = cold_modules(analysis)
    if not cold:
        return False
    out = stream or sys.stderr
    names = ", ".join(m.rsplit(".", 1)[-1] for m in cold)
    n = max(1, min(_cores(), len(GROUPS.get(analysis, ()))))
    print(f"compiling the numerical kernels once ({names}; {n} process"
          f"{'es' if n > 1 else ''}, about {COMPILE_SECONDS.get(analysis, 20)} s on 2 idle cores)"
          " ...", end="", file=out, flush=True)
    seconds, cpu = compile_kernels(analysis, n)
    print(f" done in {seconds:.1f} s (CPU {' + '.join(f'{c:.1f}' for c in cpu)} s), cached "
          "for later runs", file=out, flush=True)
    return True


def main(argv: Sequence[str] | None = None) -> int:
    """``python -m rotorsfd.kernel_cache ANALYSIS GROUP``: compile one group."""
    analysis, index = (argv if argv is not None else sys.argv[1:])[:2]
    compile_group(analysis, int(index))
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
