"""Is numba's on-disk cache of an analysis' compiled kernels warm? And the progress line
that says so when it is not.

The compiled loops (``@njit(cache=True)``) are compiled on their first call and their
machine code is stored in numba's cache (``__pycache__`` beside the sources, or under
``NUMBA_CACHE_DIR``). The first run after an install or an update pays the compilation
once (about :data:`COMPILE_SECONDS` on 2 cores); later runs load the code in a fraction
of a second. :func:`cold_modules` reads each kernel module's cache index the way numba
does (an index whose source stamp does not match the file is stale, as after an edit)
without compiling anything; :func:`compile_notice` prints one line on stderr when an
analysis is about to compile its kernels, so a first run does not look hung.
"""

from __future__ import annotations

import importlib
import sys
from typing import Any, TextIO

__all__ = ["COMPILE_SECONDS", "KERNEL_MODULES", "cold_modules", "compile_notice",
           "module_cached"]

#: analysis -> the modules of the compiled loops it runs
KERNEL_MODULES: dict[str, tuple[str, ...]] = {
    "response": ("rotorsfd.harmonic.aft_kernels", "rotorsfd.harmonic.banded",
                 "rotorsfd.model.sfd_kernels", "rotorsfd.stability.monodromy_kernels"),
    "simulate": ("rotorsfd.timedomain.newmark", "rotorsfd.model.sfd_kernels"),
}
KERNEL_MODULES["bifurcation_diagram"] = KERNEL_MODULES["simulate"]
KERNEL_MODULES["paper"] = tuple(dict.fromkeys(KERNEL_MODULES["response"]
                                              + KERNEL_MODULES["simulate"]))

#: CPU time of the compilation with an empty cache, per analysis [s]: ``rotorsfd response
#: examples/paper_rotor.toml`` took 39.8 s of CPU with an empty ``NUMBA_CACHE_DIR`` and
#: 9.5 s with the cache filled (2 shared cores under load 11, 2026-12-02), so about 30 s;
#: the time-domain loop is about a third of that (rounded up)
COMPILE_SECONDS: dict[str, int] = {"response": 30, "simulate": 10, "bifurcation_diagram": 10,
                                   "paper": 40}


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


def compile_notice(analysis: str, stream: TextIO | None = None) -> bool:
    """Print ``compiling the compiled kernels once (about N s) ...`` on ``stream``
    (stderr) when ``analysis`` will compile kernels; True if it did."""
    cold = cold_modules(analysis)
    if not cold:
        return False
    names = ", ".join(m.rsplit(".", 1)[-1] for m in cold)
    print(f"compiling the numerical kernels once ({names}; about "
          f"{COMPILE_SECONDS.get(analysis, 20)} s, cached for later runs) ...",
          file=stream or sys.stderr, flush=True)
    return True
