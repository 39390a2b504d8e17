"""The first run compiles the kernels up front (rotorsfd.kernel_cache, issue 17 item 5),
and the kernels whose compiled variants changed give the numbers of independent
references: a dense numpy solve / numpy sums, and the same source run as plain Python
(``py_func``, every kernel it calls swapped for its ``py_func``) to 1e-12."""

from __future__ import annotations

import contextlib
import os
import re
import subprocess
import sys
from collections.abc import Iterator
from types import ModuleType

import numpy as np
import pytest
from numba.core.registry import CPUDispatcher

from rotorsfd.harmonic import aft_kernels, banded
from rotorsfd.kernel_cache import ENTRY_POINTS, GROUPS, KERNEL_MODULES
from rotorsfd.timedomain.kernels import cubic_spring_kernel

WARM_THEN_RUN = r"""
from numba.core import ccallback, event
from rotorsfd import api
from rotorsfd.io.config import load_config
from rotorsfd.kernel_cache import cold_modules, compile_notice
print("cold:", cold_modules("response"))
assert compile_notice("response")
compiled = []
class Listener(event.Listener):
    def on_start(self, ev):
        pass
    def on_end(self, ev):
        compiled.append(ev.data["dispatcher"].py_func.__qualname__)
event.register("numba:compile", Listener())
_orig = ccallback.CFunc._compile_uncached
def _cfunc(self):
    compiled.append("cfunc " + self._pyfunc.__qualname__)
    return _orig(self)
ccallback.CFunc._compile_uncached = _cfunc
res = api.run_response(load_config("examples/paper_rotor.toml"), progress=False)
print("compiled after the warm-up:", compiled)
print("cold after:", cold_modules("response"))
"""


def test_first_run_compiles_up_front_and_the_run_compiles_nothing(tmp_path):
    """Empty numba cache: the progress line names the cold modules, the processes and the
    measured time; the whole ``response`` of the paper rotor then loads every kernel
    from the cache (no numba compile at all: the signature table matches the solvers')."""
    env = {**os.environ, "OPENBLAS_NUM_THREADS": "1", "NUMBA_CACHE_DIR": str(tmp_path)}
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    p = subprocess.run([sys.executable, "-c", WARM_THEN_RUN], capture_output=True,
                       text=True, env=env, cwd=root, timeout=900, check=True)
    out = p.stdout + p.stderr
    assert "cold: ['rotorsfd.harmonic.aft_kernels', 'rotorsfd.harmonic.banded'" in out
    assert ("compiling the numerical kernels once (aft_kernels, banded, sfd_kernels, "
            "monodromy_kernels; 2 processes, about 15 s on 2 idle cores) ... done in ") in out
    assert re.search(r"\.\.\. done in \d+\.\d s \(CPU \d+\.\d \+ \d+\.\d s\), cached for "
                     r"later runs", out)
    assert "compiled after the warm-up: []" in out
    assert "cold after: []" in out


def test_groups_name_known_entry_points_once():
    """Every group entry is in the table, no entry is compiled by two groups of one
    analysis, and every analysis with kernel modules has groups."""
    for analysis, groups in GROUPS.items():
        names = [n for g in groups for n in g]
        assert len(names) == len(set(names)), analysis
        assert set(names) <= set(ENTRY_POINTS), analysis
    assert set(KERNEL_MODULES) <= set(GROUPS)


@contextlib.contextmanager
def as_python(*modules: ModuleType) -> Iterator[None]:
    """Every numba dispatcher named in ``modules`` swapped for its ``py_func``, so that a
    kernel (``module.name`` inside the block) runs as plain Python all the way down."""
    saved = []
    for module in modules:
        for name, value in list(vars(module).items()):
            if isinstance(value, CPUDispatcher):
                saved.append((module, name, value))
                setattr(module, name, value.py_func)
    try:
        yield
    finally:
        for module, name, value in saved:
            setattr(module, name, value)


def _banded_case(seed: int = 3, n: int = 18, kl: int = 2, ku: int = 3, m: int = 2, H: int = 3):
    rng = np.random.default_rng(seed)

    def band(scale: float, diag: float) -> np.ndarray:
        A = np.zeros((n, n))
        for i in range(n):
            for j in range(max(0, i - kl), min(n, i + ku + 1)):
                A[i, j] = scale * rng.standard_normal()
            A[i, i] += diag
        return A

    dense = [band(0.1, 1.0), band(0.05, 0.2), band(1.0, 8.0), band(0.02, 0.0),
             band(0.01, 0.0), band(0.1, 0.0)]          # M, D, K, dM, dD, dK
    s = np.array([4, 11], dtype=np.int64)
    delta = (rng.standard_normal((H + 1, m)) + 1j * rng.standard_normal((H + 1, m))) * 0.3
    F = rng.standard_normal((H + 1, n)) + 1j * rng.standard_normal((H + 1, n))
    dF = rng.standard_normal((H + 1, n)) + 1j * rng.standard_normal((H + 1, n))
    delta[0] = delta[0].real
    F[0], dF[0] = F[0].real, dF[0].real            # harmonic 0 real: the real LU path
    bands = [banded.dense_to_band(np.ascontiguousarray(A), kl, ku) for A in dense]
    return dense, bands, kl, ku, s, delta, F, dF


def _condense(kernel, bands, kl, ku, s, delta, F, dF, w, dw, refine):
    H1, n = F.shape
    m = s.shape[0]
    sol = np.zeros((H1, n, m + 1), complex)
    dsol = np.zeros((H1, m, m + 1), complex)
    Ht, Pt = np.zeros((H1, m, m), complex), np.zeros((H1, m), complex)
    dHt, dPt = np.zeros((H1, m, m), complex), np.zeros((H1, m), complex)
    status = kernel(*bands, w, dw, kl, ku, s, delta, F, dF, True, sol, dsol, Ht, Pt, dHt,
                    dPt, refine, 0)
    assert status == banded.OK
    return sol, dsol, Ht, Pt, dHt, dPt


def test_condense_bands_without_refinement_matches_python_and_numpy():
    """``refine=None`` (the variant compiled without the refinement, what a model of at
    most 400 DOFs now runs) gives the bits of ``refine=0``, the same numbers as the
    source run as Python (1e-12), and Zt_k^-1 [S^T, F_k] and its lam-derivative rows from
    a dense numpy solve."""
    dense, bands, kl, ku, s, delta, F, dF = _banded_case()
    w, dw = 1.3, 0.7
    fast = _condense(banded.condense_bands, bands, kl, ku, s, delta, F, dF, w, dw, None)
    zero = _condense(banded.condense_bands, bands, kl, ku, s, delta, F, dF, w, dw, 0)
    for a, b in zip(fast, zero, strict=True):
        assert np.array_equal(a, b)
    with as_python(banded):
        ref = _condense(banded.condense_bands, bands, kl, ku, s, delta, F, dF, w,
                        dw, None)
    for a, b in zip(fast, ref, strict=True):
        assert np.max(np.abs(a - b)) <= 1e-12 * np.max(np.abs(b))
    M, D, K, dM, dD, dK = dense
    n, m = K.shape[0], s.shape[0]
    S = np.zeros((m, n))
    S[np.arange(m), s] = 1.0
    for k in range(F.shape[0]):
        kw = k * w
        Z = K - kw**2 * M + 1j * kw * D + S.T @ np.diag(delta[k]) @ S
        x = np.linalg.solve(Z, np.column_stack([S.T, F[k]]))
        dZ = dK - kw**2 * dM - 2 * k**2 * w * dw * M + 1j * k * (dw * D + w * dD)
        y = np.linalg.solve(Z, np.column_stack([np.zeros((n, m)), dF[k]]) - dZ @ x)
        assert np.max(np.abs(fast[0][k] - x)) <= 1e-11 * np.max(np.abs(x))
        assert np.max(np.abs(fast[1][k] - y[s])) <= 1e-11 * np.max(np.abs(y))


def test_force_coefficients_is_the_projection_of_the_kernel_samples():
    """``force_coefficients`` (now ``project_forces`` directly, no ``Literal[False]``
    variant of ``project``) = ``P F(E xs, w Ed xs)`` by numpy for a cubic spring, and =
    its source run as Python (1e-12)."""
    rng = np.random.default_rng(5)
    nh, m, N, w = 7, 2, 16, 1.7
    xs = rng.standard_normal((nh, m)) * 0.3
    E, Ed = rng.standard_normal((N, nh)), rng.standard_normal((N, nh))
    P = rng.standard_normal((nh, N))
    params = np.array([2.0, 5.0])

    def run(fun, kernel):
        q, dq, v = np.zeros((N, m)), np.zeros((N, m)), np.zeros((N, m))
        f, dfq, dfv = np.zeros((N, m)), np.zeros((N, m, m)), np.zeros((N, m, m))
        G = np.zeros((nh, m))
        assert fun(kernel, params, xs, w, E, Ed, P, q, dq, v, f, dfq, dfv, G) == 0
        return G

    G = run(aft_kernels.force_coefficients, aft_kernels.as_kernel_cfunc(cubic_spring_kernel))
    q = E @ xs
    expected = P @ (-params[0] * q - params[1] * q**3)
    assert np.max(np.abs(G - expected)) <= 1e-12 * np.max(np.abs(expected))
    with as_python(aft_kernels):
        ref = run(aft_kernels.force_coefficients, cubic_spring_kernel)
    assert np.max(np.abs(G - ref)) <= 1e-12 * np.max(np.abs(ref))


@pytest.mark.parametrize("n, expected", [(84, None), (400, None), (401, 1)])
def test_refinement_steps(n, expected):
    """None (compiled without the refinement) up to REFINE_MIN_DOF, one step above."""
    assert banded.refinement_steps(n) == expected
