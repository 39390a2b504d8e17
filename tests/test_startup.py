"""Start-up cost (issue 17 item 5): loading a config or the API imports no heavy package
that it does not use. Each import runs in a fresh interpreter, and the test lists the
heavy packages that ended up in ``sys.modules``; it fails naming them (and the first
rotorsfd module found importing one, from ``python -X importtime``)."""

from __future__ import annotations

import importlib
import json
import os
import re
import subprocess
import sys

import pytest

#: packages that a config load must not import (its model is built without them)
HEAVY = ("numba", "matplotlib", "xarray")
#: and that ``import rotorsfd.api`` must not import either: it imports what it re-exports
#: on first use (``rotorsfd.api.LAZY``)
API_HEAVY = (*HEAVY, "pint", "pydantic", "scipy")


def _run(code: str, *flags: str) -> subprocess.CompletedProcess:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1"}
    return subprocess.run([sys.executable, *flags, "-c", code], capture_output=True,
                          text=True, env=env, timeout=120, check=True)


def importer_of(module: str, package: str) -> str:
    """The module whose import statement loads ``package`` first when importing
    ``module`` (``python -X importtime`` prints a module after its imports, indented one
    level deeper than its importer)."""
    rows = []
    for line in _run(f"import {module}", "-X", "importtime").stderr.splitlines():
        m = re.match(r"import time:\s+\d+ \|\s+\d+ \|( *)(\S+)$", line)
        if m:
            rows.append((len(m[1]), m[2]))
    first = next(i for i, (_, name) in enumerate(rows) if name == package)
    depth = rows[first][0]
    return next((name for d, name in rows[first:] if d < depth), module)


def loaded_heavy(module: str, heavy: tuple[str, ...] = HEAVY) -> tuple[list[str], str]:
    """The packages of ``heavy`` that ``import module`` loads in a fresh interpreter, and
    the module that imports the first of them."""
    code = (f"import sys, json; import {module}; "
            f"print(json.dumps([m for m in {heavy!r} if m in sys.modules]))")
    loaded = json.loads(_run(code).stdout.strip().splitlines()[-1])
    return loaded, importer_of(module, loaded[0]) if loaded else ""


@pytest.mark.parametrize(("module", "heavy"), [
    ("rotorsfd.io.config", HEAVY),           # what every command with a config loads
    ("rotorsfd.analyses.checks", HEAVY),     # rotorsfd config check
    ("rotorsfd.api", API_HEAVY),
    ("rotorsfd.model.base_motion", (*HEAVY, "scipy.integrate")),  # every model build
])
def test_imports_load_no_heavy_package(module, heavy):
    loaded, importer = loaded_heavy(module, heavy)
    assert loaded == [], f"import {module} loads {loaded} (the first one from {importer})"


def test_the_api_names_resolve_on_first_use():
    """Every lazily re-exported name of the API exists in its module (a renamed function
    would otherwise fail only when a script asks for it)."""
    from rotorsfd import api

    for name in api.LAZY:
        assert getattr(api, name) is getattr(importlib.import_module(api.LAZY[name]), name)
    for name in api.__all__:
        assert callable(getattr(api, name)), name
    with pytest.raises(AttributeError, match="no attribute 'run_modall'"):
        api.run_modall  # noqa: B018


@pytest.mark.slow
def test_the_element_kernels_load_when_asked_for():
    """The deferred kernel imports work: an element built from a config gives its compiled
    kernel (numba loaded only then), and the kernel gives the numpy law's force."""
    code = r"""
import sys, json
import numpy as np
from rotorsfd.elements.rub import RubElement
e = RubElement("seal", 2, 1e-4, 1e7, 0.1)
before = "numba" in sys.modules
k, p = e.kernel, e.kernel_params
q, v = np.array([1.2e-4, 0.3e-4]), np.zeros(2)
F, a, b = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
k(q, v, p, F, a, b)
print(json.dumps([before, "numba" in sys.modules, F.tolist(), e.force(q, v).tolist()]))
"""
    p = _run(code)
    before, after, f_kernel, f_numpy = json.loads(p.stdout.strip().splitlines()[-1])
    assert (before, after) == (False, True)
    assert f_kernel == pytest.approx(f_numpy, rel=1e-12)


def test_paper_asks_the_cases_for_figures_only_with_case_plots(monkeypatch, tmp_path):
    """run_cases passes ``plots`` to every runner (False unless asked), in this process."""
    from rotorsfd.paper import run
    from rotorsfd.paper.cases import CASES

    asked = []

    def runner(case, config, out, plots=False):
        asked.append((case.name, out, plots))
        return {}, {}

    monkeypatch.setattr(run, "RUNNERS", {**run.RUNNERS, "modal": runner})
    for plots in (False, True):
        run.run_cases([CASES["modal"]], quick=True, out=tmp_path, workers=1,
                      progress=False, **({"plots": True} if plots else {}))
    assert asked == [("modal", tmp_path / "modal", False), ("modal", tmp_path / "modal", True)]


@pytest.mark.slow
def test_paper_cases_write_their_own_figures_only_when_asked(tmp_path):
    """``rotorsfd paper`` draws the paper's figures from the cases' numbers; each
    analysis' own figures (here the Campbell diagram) are written only with ``plots``,
    its data files always."""
    from rotorsfd.paper.cases import CASES
    from rotorsfd.paper.run import run_case

    for plots in (False, True):
        o = run_case(CASES["modal"], quick=True, out=tmp_path / str(plots), plots=plots)
        assert o.status == "ok", o.message
        files = {p.name for p in (tmp_path / str(plots) / "modal").iterdir()}
        assert {"critical_speeds.csv", "campbell.csv"} <= files
        assert ("campbell.png" in files) is plots


def test_units_without_a_writable_cache_folder():
    """The unit registry is built from pint's on-disk cache of its definitions; where the
    cache folder cannot be made, it is built without it, with the same conversions."""
    code = ("from rotorsfd.io.units import to_si; "
            "print(to_si('5 mil', 'length'), to_si('10 Hz', 'angular_velocity'))")
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "XDG_CACHE_HOME": "/proc/no-such-dir"}
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                       env=env, timeout=120, check=True)
    length, rate = (float(x) for x in p.stdout.split())
    assert length == pytest.approx(5 * 25.4e-6, rel=1e-14)
    assert rate == pytest.approx(20 * 3.141592653589793, rel=1e-14)


def _in_fresh_cache(code: str, cache_dir) -> str:
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "NUMBA_CACHE_DIR": str(cache_dir)}
    p = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                       timeout=600, check=True)
    return p.stdout + p.stderr


@pytest.mark.slow
def test_a_module_is_warm_once_its_kernel_ran(tmp_path):
    """After one SFD kernel call (compiled into the empty cache) its module is cached
    and the others are still cold."""
    out = _in_fresh_cache(
        "import numpy as np\n"
        "from rotorsfd.kernel_cache import cold_modules, module_cached\n"
        "from rotorsfd.model.sfd import SFD\n"
        "assert module_cached('rotorsfd.model.sfd_kernels') is False\n"
        "s = SFD.from_ratios(0.0051, 1.27e-4, 0.00485, 0.325)\n"
        "F, a, b = np.empty(2), np.empty((2, 2)), np.empty((2, 2))\n"
        "s.numba_kernel(np.array([3e-5, -2e-5]), np.array([0.01, 0.02]), s.kernel_params,"
        " F, a, b)\n"
        "print(module_cached('rotorsfd.model.sfd_kernels'), cold_modules('simulate'))\n",
        tmp_path)
    assert "True ['rotorsfd.timedomain.newmark']" in out
