"""Nonlinear workloads of the scaling case (issue 17 item 2): HB point, 56-point branch,
branch with stability, peak memory, on the stepped rotor of :mod:`benchmarks.bench_scale`.

Ours: the linear part in band storage (``model.sparse.BandedLinearPart``) condensed by the
compiled band-storage kernel. The honest baseline (the best a user could write with
scipy): the same condensed HB, Newton, AFT and continuation, with the per-harmonic linear
algebra done by ``scipy.sparse`` + ``splu`` (SuperLU) instead: Z_k assembled as a sparse
matrix from the CSR M, D, K, one ``splu`` per harmonic and lam, the m + 1 right-hand sides
and the m + 1 derivative right-hand sides solved with it (:func:`splu_condense`, swapped in
for ``CondensedHB.condense`` by :func:`splu_baseline`).

Stability: the Floquet multipliers of every branch point by ``FloquetEvaluator`` (the
response analysis' path): the reduced Newmark monodromy (M = 400 intervals, Craig-Bampton
onto the SFD DOFs with the fixed-interface modes up to ``M / (4 T)``: the defaults of
``[analysis.stability]`` without the step control), the basis by
:class:`rotorsfd.stability.reduction.FixedInterfaceBasis` on the CSR matrices above
``DENSE_MAX_DOF`` (sparse LU + shift-invert Lanczos; before, a dense ``eigh`` of the whole
interior, minutes at 1280 elements), and the modes above the cut-off
(``max_multiplier_outside``, shift-invert Arnoldi). At the smallest size the multipliers
are checked against the dense basis.

Peak memory: the peak resident set of a fresh process (``python -m benchmarks.scale_hb
--memory N WORKLOAD``) that builds the model and runs the workload.
"""

from __future__ import annotations

import contextlib
import json
import resource
import subprocess
import sys
import time
from collections.abc import Iterator
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
N_POINTS = 56
H = 3
N_INTERVALS = 400
MODAL_RATIO = 0.002
MODAL_MODES = 6


def splu_condense(self: Any, lam: float, deriv: bool = True) -> Any:
    """``CondensedHB.condense`` by scipy.sparse + splu per harmonic (the baseline)."""
    import scipy.sparse as sp
    import scipy.sparse.linalg as spla

    from rotorsfd.harmonic.condensation import Condensed

    c = self._cache
    if c is not None and c.lam == lam and (c.dHt is not None or not deriv):
        return c
    p, Hh, s, m, n = self.problem, self.H, self.problem.nl_dofs, self.problem.m, \
        self.problem.n_dof
    part = p.matrices
    M, D, K = part.sparse(lam)
    kl, ku = part.band
    dM, dD, dK = (None,) * 3
    if deriv:
        from rotorsfd.model.sparse import band_to_csr

        dM, dD, dK = (band_to_csr(a, kl, ku) for a in part.dbanded(lam))
    w, dw = p.frequency(lam), (p.dfrequency(lam) if deriv else 0.0)
    F = p.forcing(lam, Hh)
    dF = p.dforcing(lam, Hh) if deriv else F
    sol = np.empty((Hh + 1, n, m + 1), dtype=complex)
    dsol = np.empty((Hh + 1, m, m + 1), dtype=complex)
    rhs = np.zeros((n, m + 1), dtype=complex)
    rhs[s, np.arange(m)] = 1.0
    for k in range(Hh + 1):
        kw = k * w
        shift = sp.csr_matrix((self.delta[k].diagonal(), (s, s)), shape=(n, n))
        Z = (K - kw**2 * M + 1j * kw * D + shift).tocsc()
        lu = spla.splu(Z)
        rhs[:, m] = F[k]
        sol[k] = lu.solve(rhs)
        if deriv:
            dZ = (dK - kw**2 * dM - 2 * k * kw * dw * M) + 1j * k * (dw * D + w * dD)
            r2 = -(dZ @ sol[k])
            r2[:, m] += dF[k]
            dsol[k] = lu.solve(r2)[s]
    out = Condensed(lam, sol[:, s, :m].copy(), sol[:, s, m].copy(), sol[:, :, m],
                    sol[:, :, :m], dsol[:, :, :m].copy() if deriv else None,
                    dsol[:, :, m].copy() if deriv else None)
    self._cache = out
    return out


@contextlib.contextmanager
def splu_baseline() -> Iterator[None]:
    """``CondensedHB.condense`` replaced by :func:`splu_condense` inside the block."""
    from rotorsfd.harmonic.condensation import CondensedHB

    ours = CondensedHB.condense
    CondensedHB.condense = splu_condense
    try:
        yield
    finally:
        CondensedHB.condense = ours


@contextlib.contextmanager
def no_refinement() -> Iterator[None]:
    """The banded condensation without its refinement step (the code before it) inside
    the block."""
    from rotorsfd.harmonic import banded

    ours = banded.refinement_steps
    banded.refinement_steps = lambda n: 0
    try:
        yield
    finally:
        banded.refinement_steps = ours


def dense_problem(problem: Any) -> Any:
    """The problem with its linear part as plain dense matrices (no band, no low-rank
    term): the condensation scans them, finds no band and runs dense LAPACK LU (the path
    of modal damping before)."""
    import dataclasses

    part = problem.matrices
    return dataclasses.replace(problem, matrices=lambda lam: part(lam),
                               dmatrices=part.derivatives)


def build(n_elements: int, modal_modes: int | None = None
          ) -> tuple[Any, Any, float, dict[str, Any]]:
    """(system, problem, first critical speed [rad/s], continuation options); with
    ``modal_modes``, modal damping zeta = MODAL_RATIO of that many modes."""
    from benchmarks.bench_scale import config, stepped_rotor_config
    from benchmarks.common import response_options
    from rotorsfd import api
    from rotorsfd.io.config import config_from_dict
    from rotorsfd.linear import critical_speeds

    if modal_modes is None:
        cfg = config(n_elements)
    else:
        d = stepped_rotor_config(n_elements)
        d["rotor"]["damping"] = {"kind": "modal", "ratio": MODAL_RATIO,
                                 "modes": modal_modes}
        cfg = config_from_dict(d)
    system = api.build_system(cfg)
    # w1 of the rotor without the modal damping (its linear analyses form the full
    # damping matrix: not what is measured here; 0.2 % damping moves w1 by ~1e-6)
    plain = system if modal_modes is None else api.build_system(config(n_elements))
    w1 = critical_speeds(plain, n=1, speed_range=(
        0.0, cfg.analysis.modal.critical_speed_max))[0].speed_rad_s
    return system, system.periodic_problem(), w1, response_options(cfg)


def point(problem: Any, w1: float) -> Any:
    """One periodic solution at 0.8 w1 from the linearised guess, tol 1e-10."""
    from rotorsfd.harmonic.periodic import solve_periodic

    return solve_periodic(problem, 0.8 * w1, H, tol=1e-10, condensed=True)


def branch(problem: Any, w1: float, opts: dict[str, Any]) -> Any:
    """The response branch from 0.5 w1, the ``[analysis.response]`` options (adaptive H,
    truncation estimate per point), N_POINTS points."""
    from rotorsfd.harmonic.periodic import continue_periodic

    return continue_periodic(problem, 0.5 * w1, 1.6 * w1, H, condensed=True,
                             **{**opts, "max_points": N_POINTS})


def stability(problem: Any, br: Any) -> np.ndarray:
    """Largest multiplier modulus of every branch point by ``FloquetEvaluator`` (module
    docstring: on a banded model above ``DENSE_MAX_DOF`` it builds the sparse basis)."""
    from rotorsfd.stability.branch_options import StabilityOptions
    from rotorsfd.stability.floquet_evaluator import FloquetEvaluator

    ev = FloquetEvaluator(problem, StabilityOptions(n_intervals=N_INTERVALS))
    return np.array([ev(float(br.lam[j]), br.X[j]).max_abs for j in range(br.n_points)])


def stability_check(problem: Any, br: Any, mu: np.ndarray, j: int) -> float:
    """|max |mu| - the dense basis' (``FixedInterfaceBasis`` on dense M, K: every mode by
    LAPACK)| at point j, the same M and cut-off."""
    from rotorsfd.stability.monodromy import floquet_multipliers
    from rotorsfd.stability.orbit import orbit_samples
    from rotorsfd.stability.reduction import FixedInterfaceBasis

    part, nl = problem.matrices, problem.nl_dofs
    lam = float(br.lam[j])
    M, D, K = part(lam)
    w = float(problem.frequency(lam))
    T = 2 * np.pi / w
    red = FixedInterfaceBasis(M, K, nl).reduce(D, None, 0.25 * N_INTERVALS / T)
    Jq, Jv = problem.nl_jacobian(*orbit_samples(br.X[j][:, nl], w, N_INTERVALS))
    res = floquet_multipliers(red.M, red.D, red.K, T, nl_dofs=red.nl_dofs, dFdq=Jq,
                              dFdv=Jv, n_intervals=N_INTERVALS, reduction=None)
    return abs(float(np.max(np.abs(res.multipliers))) - mu[j])


def peak_memory(n_elements: int, workload: str) -> float:
    """Peak RSS [GiB] of a fresh process running ``workload`` at ``n_elements``."""
    out = subprocess.run([sys.executable, "-m", "benchmarks.scale_hb", "--memory",
                          str(n_elements), workload], cwd=ROOT, capture_output=True,
                         text=True, check=True)
    return float(json.loads(out.stdout.strip().splitlines()[-1])["peak_gib"])


def _memory_main(n_elements: int, workload: str) -> None:
    _, problem, w1, opts = build(n_elements)
    if workload == "point":
        point(problem, w1)
    elif workload in ("branch", "stability"):
        br = branch(problem, w1, opts)
        if workload == "stability":
            stability(problem, br)
    elif workload == "point-splu":
        with splu_baseline():
            point(problem, w1)
    peak = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 2**20
    print(json.dumps({"peak_gib": peak}))


def timed(fun: Any, repeat: int) -> tuple[float, float, Any]:
    """Median wall time, median CPU time of this process (``time.process_time``: what a
    machine shared by other jobs does not inflate) and the last result."""
    walls, cpus, out = [], [], None
    for _ in range(max(1, repeat)):
        t0, c0 = time.perf_counter(), time.process_time()
        out = fun()
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    return float(np.median(walls)), float(np.median(cpus)), out


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "--memory":
        _memory_main(int(sys.argv[2]), sys.argv[3])
