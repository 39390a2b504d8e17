"""Nonlinear elements through one interface (issue 15 item 5): the paper rotor's single SFD
through the element interface against the previous path, and how the cost grows with the
number of elements.

1. ``elements`` vs ``previous path``: the paper rotor (examples/paper_rotor.toml, pi-film
   SFD at node 1) at the Table 1 unbalance U = 144.02 g mm. The element interface is
   ``RotorSystem.periodic_problem()`` (an ElementSet of one element: its own kernel
   ``sfd_element_kernel`` is passed through, with the numpy law of the ElementSet). The
   previous path is the same PeriodicProblem (same matrices and forcing) with the film's
   own ``SFD.numba_kernel`` / ``kernel_params`` / ``nl_force`` / ``nl_jacobian``, what
   RotorSystem handed the solvers before the element interface. Timed in turn (A B A B):
   one HB point (``solve_periodic`` at Omega~ = 1.03, just below the upper fold, from the
   linearised start, H = 3), the branch (``continue_periodic`` over Omega~ 0.5-1.6 with
   the options of ``[analysis.response]``, H = 3) and 2000 periods x 200 steps of time
   integration at Omega~ = 0.8 (``time_domain_inputs`` + ``integrate_periods``, every node
   displaced 1 um). The two paths must give the same numbers (checked, 1e-9 relative).
2. ``n SFDs``: 1, 2, 4, 8 identical films (the paper's) at distinct nodes of the paper
   rotor (:data:`NODES`: the paper's at node 1 with its centring spring, the others
   without one, away from the disk and the right support), all timed in turn: an HB point
   (as above, N_f = 32 fixed), a Floquet point at that solution (the analysis'
   ``FloquetEvaluator``: Newmark, M = 400, Craig-Bampton model, basis already built as
   along a branch) and 2000 periods x 200 steps. The composite kernel (generated for the
   layout) is timed apart: its first ``as_cfunc`` in a fresh process with an empty cache
   folder (``ROTORSFD_CACHE_DIR``), then in a second fresh process with that folder.

Methods run in turn, the order reversed every other round (A B, B A, ...). Small calls
(an HB point, a Floquet point) are timed as the mean of ``CALLS`` calls, the
median over the repeats (at least 5 of them). ``--quick``: the branch over Omega~ 0.5-0.7,
20 periods, 1 and 2 elements, one repeat (no time asserted; the agreement of the two paths
still is).
Run: ``python -m benchmarks --only elements``.
"""

from __future__ import annotations

import dataclasses
import statistics
import sys
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import W1, Row, paper_config, response_options

#: Nodes of the SFDs: the first n are used (1 is the paper's, with its centring spring).
NODES = (1, 20, 4, 17, 6, 14, 10, 12)
COUNTS = (1, 2, 4, 8)
QUICK_COUNTS = (1, 2)   # --quick: each layout compiles for seconds
HB_RATIO = 1.03     # HB / Floquet point: on the lower branch just below the upper fold
TD_RATIO = 0.8      # time integration: a stable period-1 point (as bench_timedomain)
H = 3
N_SAMPLES = 32
SPP = 200
CALLS = 10          # an HB or Floquet point: mean of this many calls per repeat
AGREE = 1e-9        # the two single-SFD paths must agree to this (relative)


def _model() -> Any:
    from rotorsfd.model.build import build_model

    return build_model(paper_config())


def system_with(model: Any, n: int) -> Any:
    """The paper rotor with ``n`` identical SFDs at ``NODES[:n]``."""
    from rotorsfd.elements.sfd import SFDElement
    from rotorsfd.model.system import RotorSystem

    first = model.elements[0]
    extra = [SFDElement(f"sfd_{node}", node, first.film) for node in NODES[1:n]]
    return RotorSystem(model.rotor, [first, *extra], model.unbalances, model.base_motion)


def previous_problem(problem: Any, film: Any) -> Any:
    """``problem`` with the film's own kernel and numpy law, as RotorSystem built it before
    the element interface (same matrices, forcing, scaling)."""
    c = film.clearance

    def nl_force_jacobian(q: np.ndarray, v: np.ndarray):
        return film.force_and_jacobian(q[..., 0], q[..., 1], v[..., 0], v[..., 1])

    def nl_limit(q: np.ndarray) -> float:
        return float(np.max(np.hypot(q[..., 0], q[..., 1]))) / c

    return dataclasses.replace(problem, nl_force=film.nl_force, nl_jacobian=film.nl_jacobian,
                               nl_force_jacobian=nl_force_jacobian,
                               nl_kernel=film.numba_kernel,
                               nl_kernel_params=film.kernel_params, nl_limit=nl_limit,
                               name="rotor-SFD response in speed (previous path)")


def mean_of(fun: Callable[[], Any], calls: int) -> Callable[[], Any]:
    """A function that calls ``fun`` ``calls`` times and returns the last result; the
    measured time is divided by ``calls`` afterwards."""
    def run() -> Any:
        out = None
        for _ in range(calls):
            out = fun()
        return out
    return run


def interleaved(funs: dict[str, Callable[[], Any]], repeat: int
                ) -> dict[str, tuple[float, list[float], Any]]:
    """Median times of methods run in turn, the order reversed every other round (A B, B A,
    A B, ...): load changes and any cost of running first hit them alike."""
    times: dict[str, list[float]] = {k: [] for k in funs}
    outs: dict[str, Any] = {}
    for i in range(max(1, repeat)):
        for k in (list(funs) if i % 2 == 0 else list(funs)[::-1]):
            t0 = time.perf_counter()
            outs[k] = funs[k]()
            times[k].append(time.perf_counter() - t0)
    return {k: (statistics.median(v), v, outs[k]) for k, v in times.items()}


def _relative(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / max(np.max(np.abs(b)), 1e-300))


def _check(what: str, diff: float) -> None:
    if not diff <= AGREE:
        raise RuntimeError(f"elements: {what} differs between the element interface and the "
                           f"previous path by {diff:.2e} (relative; allowed {AGREE:g})")


def td_run(inputs: Any, periods: int) -> Any:
    """``periods`` x SPP steps from every node displaced 1 um (as ``rotorsfd simulate``)."""
    from rotorsfd.analyses.simulate import displaced_state
    from rotorsfd.analyses.td_integration import integrate_periods

    q0 = displaced_state(inputs.M.shape[0], 1e-6)
    return integrate_periods(inputs, q0, np.zeros_like(q0), steps_per_period=SPP,
                             periods=periods, record_dofs=inputs.nl_dofs[:2],
                             record_periods=1, poincare_periods=min(100, periods))


def single_rows(model: Any, quick: bool, repeat: int) -> list[Row]:
    """Part 1: the paper rotor's SFD through the element interface vs the previous path."""
    from rotorsfd.analyses.td_integration import time_domain_inputs
    from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic

    system = system_with(model, 1)
    film = model.elements[0].film
    new = system.periodic_problem()
    old = previous_problem(new, film)
    problems = {"element interface": new, "previous path": old}
    opts = response_options(paper_config())
    stop = (0.7 if quick else 1.6) * W1
    periods = 20 if quick else 2000
    inp_new = time_domain_inputs(system, TD_RATIO * W1)
    inp_old = dataclasses.replace(inp_new, kernel=film.numba_kernel,
                                  params=film.kernel_params)
    inputs = {"element interface": inp_new, "previous path": inp_old}
    for name, p in problems.items():   # warm-up: caches loaded, first-call costs paid
        solve_periodic(p, HB_RATIO * W1, H, n_samples=N_SAMPLES, tol=opts["tol"])
        continue_periodic(p, 0.5 * W1, stop, H, **{**opts, "max_points": 2})
        td_run(inputs[name], 1)
    ref = "previous path"
    base = {"ref": ref}
    rows: list[Row] = []

    def point(p: Any) -> Any:
        return solve_periodic(p, HB_RATIO * W1, H, n_samples=N_SAMPLES, tol=opts["tol"])

    res = interleaved({k: mean_of(lambda p=p: point(p), CALLS) for k, p in problems.items()},
                      max(repeat, 5) if not quick else repeat)
    diff = _relative(res["element interface"][2].X, res[ref][2].X)
    _check("the HB point", diff)
    case = f"paper rotor, 1 SFD, H={H}, N_f={N_SAMPLES}: HB point Omega~={HB_RATIO}"
    for k, (t, times, sol) in res.items():
        rows.append(Row("elements", case, k, t / CALLS, repeat=len(times),
                        ratio=t / res[ref][0], **base,
                        note=f"{sol.iterations} Newton iterations; max |dX|/|X| = {diff:.1e}",
                        extra={"times_s": [x / CALLS for x in times], "calls": CALLS}))

    res = interleaved({k: lambda p=p: continue_periodic(p, 0.5 * W1, stop, H, **opts)
                       for k, p in problems.items()}, repeat)
    a, b = res["element interface"][2], res[ref][2]
    same = a.n_points == b.n_points and np.allclose(a.lam, b.lam, rtol=1e-12)
    diff = _relative(a.X, b.X) if same else float("nan")
    _check("the branch", diff)
    case = f"paper rotor, 1 SFD, H={H}: branch Omega~ 0.5-{stop / W1:.1f}"
    for k, (t, times, br) in res.items():
        rows.append(Row("elements", case, k, t, repeat=len(times), ratio=t / res[ref][0],
                        **base, note=(f"{br.n_points} points, {len(br.folds())} folds; "
                                      f"max |dX|/|X| = {diff:.1e}"),
                        extra={"times_s": times, "points": br.n_points}))

    res = interleaved({k: lambda i=i: td_run(i, periods) for k, i in inputs.items()}, repeat)
    a, b = res["element interface"][2], res[ref][2]
    diff = _relative(a.q_final, b.q_final)
    _check("the time integration's end state", diff)
    case = f"paper rotor, 1 SFD: {periods} periods x {SPP} steps, Omega~={TD_RATIO}"
    for k, (t, times, tr) in res.items():
        rows.append(Row("elements", case, k, t, repeat=len(times), ratio=t / res[ref][0],
                        **base, note=(f"eps max {tr.max_eccentricity_run:.3f}; end state "
                                      f"max |dq|/|q| = {diff:.1e}"),
                        extra={"times_s": times}))
    return rows


def count_rows(model: Any, quick: bool, repeat: int) -> list[Row]:
    """Part 2: cost of an HB point, a Floquet point and a time run against n elements."""
    from rotorsfd.analyses.td_integration import time_domain_inputs
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.kernels import as_cfunc
    from rotorsfd.stability.branch_stability import FloquetEvaluator, StabilityOptions

    periods = 20 if quick else 2000
    counts = QUICK_COUNTS if quick else COUNTS
    rows: list[Row] = []
    setups: dict[int, dict[str, Any]] = {}
    for n in counts:
        system = system_with(model, n)
        as_cfunc(system.elements.kernel)   # generated and compiled (or loaded) once
        p = system.periodic_problem()
        sol = solve_periodic(p, HB_RATIO * W1, H, n_samples=N_SAMPLES, tol=1e-6)
        floquet = FloquetEvaluator(p, StabilityOptions())
        floquet(HB_RATIO * W1, sol.X)       # the Craig-Bampton basis, built once a branch
        inp = time_domain_inputs(system, TD_RATIO * W1)
        td_run(inp, 1)
        eps = system.elements.limit(_samples(sol.X, p))
        setups[n] = {"problem": p, "X": sol.X, "floquet": floquet, "inputs": inp,
                     "eps": eps}
    label = {n: f"{n} SFD" + ("s" if n > 1 else "") for n in counts}
    where = f"nodes {', '.join(map(str, NODES[:max(counts)]))} (first n)"
    ref = label[counts[0]]

    def add(case: str, res: dict, per: int, note: Callable[[int, Any], str]) -> None:
        for n in counts:
            t, times, out = res[label[n]]
            rows.append(Row("elements", case, label[n], t / per, repeat=len(times),
                            ratio=t / res[ref][0], ref=ref, note=note(n, out),
                            extra={"times_s": [x / per for x in times], "n_elements": n}))

    def hb(n: int) -> Any:
        return solve_periodic(setups[n]["problem"], HB_RATIO * W1, H, n_samples=N_SAMPLES,
                              tol=1e-6)

    small = repeat if quick else max(repeat, 5)
    res = interleaved({label[n]: mean_of(lambda n=n: hb(n), CALLS) for n in counts}, small)
    per_it = {n: res[label[n]][0] / CALLS / max(res[label[n]][2].iterations, 1)
              for n in counts}
    add(f"n SFDs ({where}), H={H}, N_f={N_SAMPLES}: HB point Omega~={HB_RATIO}", res, CALLS,
        lambda n, s: (f"{s.iterations} Newton iterations, {per_it[n] * 1e3:.2f} ms each; "
                      f"eps max {setups[n]['eps']:.3f}"))

    def fl(n: int) -> Any:
        return setups[n]["floquet"](HB_RATIO * W1, setups[n]["X"])

    res = interleaved({label[n]: mean_of(lambda n=n: fl(n), CALLS) for n in counts}, small)
    add(f"n SFDs: Floquet point Omega~={HB_RATIO} (Newmark CB, M=400)", res, CALLS,
        lambda n, f: (f"|mu|max {f.max_abs:.4f}; reduced model "
                      f"{2 * n}+{f.info.get('n_modes', '?')} DOF"))

    res = interleaved({label[n]: lambda n=n: td_run(setups[n]["inputs"], periods)
                       for n in counts}, repeat)
    add(f"n SFDs: {periods} periods x {SPP} steps, Omega~={TD_RATIO}", res, 1,
        lambda n, tr: (f"eps max {tr.max_eccentricity_run:.3f}, Newton max "
                       f"{tr.newton_iterations_max} it/step"))

    return rows + compile_rows(counts, label)


#: Run in a fresh interpreter: the first ``as_cfunc`` of each layout's kernel, in seconds.
_COMPILE = """
import json, time
from benchmarks.bench_elements import _model, system_with
from rotorsfd.kernels import as_cfunc
model, out = _model(), {}
for n in %r:
    system = system_with(model, n)
    t0 = time.perf_counter()
    as_cfunc(system.elements.kernel)
    out[n] = time.perf_counter() - t0
print(json.dumps(out))
"""


def compile_rows(counts: tuple[int, ...], label: dict[int, str]) -> list[Row]:
    """The composite kernel's generation + compilation (first ``as_cfunc`` of the
    layout) in a fresh process with an empty ``ROTORSFD_CACHE_DIR``, then in a second
    fresh process with the same folder (what a disk cache of the layout saves)."""
    import tempfile

    from benchmarks.common import run_python

    with tempfile.TemporaryDirectory(prefix="rotorsfd-bench-") as folder:
        env = {"ROTORSFD_CACHE_DIR": folder}
        cold = run_python(_COMPILE % (tuple(counts),), env=env)
        warm = run_python(_COMPILE % (tuple(counts),), env=env)
    rows = []
    for what, got in (("first process, empty cache folder", cold),
                      ("next process, same cache folder", warm)):
        case = f"n SFDs: composite kernel, generated + compiled: {what}"
        for n in counts:
            rows.append(Row("elements", case, label[n], float(got[str(n)]), repeat=1,
                            note="single element: its own kernel passed through (the process' "
                            "first cfunc, from numba's cache)" if n == 1
                            else "once per layout and process (or loaded from the cache)"))
    return rows


def _samples(X: np.ndarray, problem: Any, n: int = 64) -> np.ndarray:
    """Samples (n, m) over one period of the nonlinear DOFs of coefficients X (H+1, n_dof)."""
    k = np.arange(X.shape[0])
    phase = np.exp(1j * np.outer(np.linspace(0.0, 2 * np.pi, n, endpoint=False), k))
    return np.real(phase @ X[:, problem.nl_dofs])


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    model = _model()
    return single_rows(model, quick, repeat) + count_rows(model, quick, repeat)


if __name__ == "__main__":
    from benchmarks.__main__ import main

    raise SystemExit(main(["--only", "elements", *sys.argv[1:]]))
