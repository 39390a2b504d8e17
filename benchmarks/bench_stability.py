"""Floquet multipliers per continuation point, and stability charts on several executors.

``stability`` -- per point of the paper rotor's H = 3 branch (U = 144.02 g mm, the Table 1
case; points before the first fold, on the unstable middle branch between the folds and
past the resonance): our path (Newmark on the Craig-Bampton reduced model, M = 400,
``method='newmark-cb'``, the default of ``[analysis.stability]``), the paper's literal
method (Newmark monodromy of the full 84-DOF model, M = 400) and Hill's method (H = 8 on
the same reduced model). Median time per point, ratio to ours, and the agreement of the
critical multiplier: the multiplier of each method nearest to our critical one, and the
largest |mu| of each (the full model's undamped structural modes sit at |mu| = 1).

``monodromy`` -- the monodromy alone at the same three points, compiled loop
(:mod:`rotorsfd.stability.monodromy_kernels`, the default) vs the numpy loop it replaced
(``compiled=False``, kept as the reference): Newmark on the Craig-Bampton model of the
branch analysis (``FloquetEvaluator.reduced``) at M = 400 and at 2M = 800 (the pair of a
step control), generalized-alpha on it at M = 400, and the paper's full 84-DOF Newmark.
Reported: median time per call (a compiled sample is the mean of 10 calls), the best
sample, the ratio numpy / compiled and the largest distance between the two paths'
multipliers (matched).

``chart`` -- the 100 x 100 stability chart of examples/fig6_duchemin_pitching.toml (linear
single-disk rotor, harmonic base pitching, Omega = 250 rad/s, M = 400) serial, with the
analysis' own thread pool (``workers=2``), on a process pool (rotorsfd.studies
``ProcessExecutor``) and on a Dask ``LocalCluster`` (2 worker processes x 1 thread,
``DaskExecutor``); rows split into chunks, the results checked equal to the serial map.
Pool and cluster start-up are reported on their own (not in the medians).
``--quick``: 8 x 8.

Run: ``python -m benchmarks --only stability`` / ``--only monodromy`` / ``--only chart``.
"""

from __future__ import annotations

import time

import numpy as np

from benchmarks.common import (
    ROOT,
    W1,
    Row,
    interleaved,
    paper_config,
    paper_system,
    response_options,
)

FIG6 = ROOT / "examples" / "fig6_duchemin_pitching.toml"
METHODS = {"newmark-cb": "ours: Newmark, Craig-Bampton (M=400)",
           "newmark": "paper: Newmark, full model (M=400)",
           "hill": "Hill (H=8, reduced model)"}


def pick_points(branch) -> dict[str, int]:
    """Indices of three points: before the folds, on the middle branch, after."""
    folds = branch.folds()
    speed = branch.lam / W1
    out = {"Omega~ 0.8": int(np.argmin(np.abs(speed - 0.8)))}
    if folds.size >= 2:
        out["middle branch"] = int((folds[0] + folds[1]) // 2 + 1)
    out["Omega~ 1.4"] = int(np.argmin(np.abs(speed - 1.4) + 10.0 * (np.arange(speed.size)
                                                                       < (folds.max(initial=0)))))
    return out


def run_points(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.harmonic.periodic import continue_periodic
    from rotorsfd.stability.orbit import orbit_floquet

    problem = paper_system().periodic_problem()
    branch = continue_periodic(problem, 0.5 * W1, 1.6 * W1, 3,
                               **response_options(paper_config()))
    points = pick_points(branch)
    if quick:
        points = dict(list(points.items())[:1])
    rows: list[Row] = []
    for label, i in points.items():
        lam, X, w = branch.lam[i], branch.X[i], branch.frequency[i]
        M, D, K = problem.matrices(lam)

        def floquet(method: str, M=M, D=D, K=K, X=X, w=w):
            return orbit_floquet(M, D, K, X, w, problem.nl_dofs, problem.nl_jacobian,
                                 method=method, n_intervals=400, n_harmonics=8)

        for m in METHODS:  # warm-up
            floquet(m)
        res = interleaved({m: (lambda m=m: floquet(m)) for m in METHODS}, repeat)
        ours = res["newmark-cb"][2]
        mu0 = ours.critical
        case = f"H=3 point Omega~={lam / W1:.4f} ({label})"
        for m, name in METHODS.items():
            t, _, r = res[m]
            near = r.multipliers[np.argmin(np.abs(r.multipliers - mu0))]
            rows.append(Row(
                "stability", case, name, t, ratio=t / res["newmark-cb"][0], ref="ours",
                repeat=repeat,
                note=(f"|mu|max {r.max_abs:.6f} ({'stable' if r.stable else 'unstable'}); "
                      f"mu near ours' critical: {abs(near):.6f}, |d| {abs(near - mu0):.1e}"),
                extra={"max_abs": r.max_abs, "critical": [mu0.real, mu0.imag],
                       "nearest": [near.real, near.imag], "stable": bool(r.stable),
                       "n_multipliers": int(r.multipliers.size)}))
    return rows


def _matched_distance(a: np.ndarray, b: np.ndarray) -> float:
    """Largest distance between two multiplier sets after optimal matching."""
    from scipy.optimize import linear_sum_assignment

    cost = np.abs(a[:, None] - b[None, :])
    i, j = linear_sum_assignment(cost)
    return float(cost[i, j].max())


def run_monodromy(quick: bool = False, repeat: int = 3) -> list[Row]:
    """Compiled vs numpy monodromy loop per point (module docstring, ``monodromy``)."""
    from rotorsfd.harmonic.periodic import continue_periodic
    from rotorsfd.stability.branch_stability import FloquetEvaluator
    from rotorsfd.stability.monodromy import floquet_multipliers
    from rotorsfd.stability.orbit import orbit_samples

    problem = paper_system().periodic_problem()
    branch = continue_periodic(problem, 0.5 * W1, 1.6 * W1, 3,
                               **response_options(paper_config()))
    ev = FloquetEvaluator(problem)
    points = pick_points(branch)
    if quick:
        points = dict(list(points.items())[:1])
    rows: list[Row] = []
    for label, i in points.items():
        lam, w = float(branch.lam[i]), float(branch.frequency[i])
        T = 2 * np.pi / w
        Xnl = np.asarray(branch.X[i], complex)[:, problem.nl_dofs]
        red = ev.reduced(lam, T)
        M, D, K = problem.matrices(lam)
        jac = {}
        for N in (400, 800):
            q, v = orbit_samples(Xnl, w, N)
            jac[N] = problem.nl_jacobian(q, v)
        cases = {f"Newmark-CB M=400 ({red.n_dof} DOF)": (red, "newmark", 400),
                 f"Newmark-CB 2M=800 ({red.n_dof} DOF)": (red, "newmark", 800),
                 f"generalized-alpha-CB M=400 ({red.n_dof} DOF)":
                     (red, "generalized-alpha", 400)}
        if not quick:
            cases[f"paper: full Newmark M=400 ({M.shape[0]} DOF)"] = (None, "newmark", 400)
        for what, (model, scheme, N) in cases.items():
            Mx, Dx, Kx, nl = ((model.M, model.D, model.K, model.nl_dofs) if model is not None
                              else (M, D, K, problem.nl_dofs))

            def call(compiled: bool, Mx=Mx, Dx=Dx, Kx=Kx, nl=nl, scheme=scheme, N=N, T=T,
                     J=jac[N]):
                return floquet_multipliers(Mx, Dx, Kx, T, nl_dofs=nl, dFdq=J[0], dFdv=J[1],
                                           n_intervals=N, reduction=None, scheme=scheme,
                                           compiled=compiled)

            call(True)  # warm-up (numba cache)
            reps = 1 if (model is None and quick) else repeat
            k = 1 if model is None else 10  # a compiled sample: the mean of k calls

            def compiled_k(c=call, k=k):
                return [c(True) for _ in range(k)][-1]

            res = interleaved({"compiled": compiled_k, "numpy": lambda c=call: c(False)},
                              reps)
            (tc, times_c, rc), (tn, times_n, rn) = res["compiled"], res["numpy"]
            tc, times_c = tc / k, [t / k for t in times_c]
            d = _matched_distance(rc.multipliers, rn.multipliers)
            case = f"H=3 point Omega~={lam / W1:.4f} ({label}): {what}"
            rows.append(Row("monodromy", case, "compiled loop (ours)", tc, repeat=reps,
                            ratio=1.0, ref="compiled",
                            note=(f"best {1e3 * min(times_c):.2f} ms; |mu|max "
                                  f"{rc.max_abs:.6f}; max |mu - mu_numpy| {d:.1e}"),
                            extra={"max_abs": rc.max_abs, "distance_to_numpy": d,
                                   "n_dof": int(Mx.shape[0]), "n_intervals": N,
                                   "times": times_c, "calls_per_sample": k}))
            rows.append(Row("monodromy", case, "numpy loop (before)", tn, repeat=reps,
                            ratio=tn / tc, ref="compiled",
                            note=f"best {1e3 * min(times_n):.2f} ms; |mu|max {rn.max_abs:.6f}",
                            extra={"max_abs": rn.max_abs, "times": times_n}))
    return rows


# ---- stability chart ------------------------------------------------------------------------


def chart_axes(n: int) -> tuple[tuple[str, np.ndarray], tuple[str, np.ndarray]]:
    """The Figure 6 config's axes, resampled to n x n."""
    from rotorsfd.analyses.stability_chart import axis_from_config
    from rotorsfd.io.config import load_config

    cfg = load_config(FIG6)
    axes = []
    for name in ("x", "y"):
        a = axis_from_config(cfg, name)
        axes.append((a.path, np.linspace(a.values[0], a.values[-1], n)))
    return axes[0], axes[1]


def chart_rows(x: tuple[str, np.ndarray], y: tuple[str, np.ndarray], workers: int = 1
               ) -> np.ndarray:
    """max |mu| of the Figure 6 chart on the rows ``x`` (a task of the executors)."""
    from rotorsfd.analyses.stability_chart import run_stability_chart
    from rotorsfd.io.config import load_config

    res = run_stability_chart(load_config(FIG6), x=x, y=y, workers=workers)
    return res.chart.max_abs


def _on_executor(ex, x, y, n_chunks: int) -> np.ndarray:
    chunks = np.array_split(np.arange(x[1].size), n_chunks)
    futs = [ex.submit(chart_rows, (x[0], x[1][c]), y) for c in chunks]
    return np.concatenate([f.result() for f in futs], axis=0)


def run_chart(quick: bool = False, repeat: int = 3, workers: int = 2) -> list[Row]:
    from rotorsfd.studies.executors import DaskExecutor, ProcessExecutor

    n = 8 if quick else 100
    x, y = chart_axes(n)
    n_chunks = min(n, 4 * workers)
    chart_rows((x[0], x[1][:1]), (y[0], y[1][:2]))  # warm-up
    t0 = time.perf_counter()
    pool = ProcessExecutor(workers)
    pool.submit(int, 0).result()
    t_pool = time.perf_counter() - t0
    from distributed import LocalCluster

    t0 = time.perf_counter()
    cluster = LocalCluster(n_workers=workers, threads_per_worker=1, processes=True,
                           dashboard_address=None, silence_logs=50)
    dask = DaskExecutor(cluster.scheduler_address)
    t_dask = time.perf_counter() - t0
    try:
        for ex in (pool, dask):  # warm-up: every worker imports and loads the kernels
            _on_executor(ex, (x[0], x[1][:2 * workers]), (y[0], y[1][:2]), 2 * workers)
        res = interleaved({
            "serial": lambda: chart_rows(x, y),
            "threads": lambda: chart_rows(x, y, workers=workers),
            "pool": lambda: _on_executor(pool, x, y, n_chunks),
            "dask": lambda: _on_executor(dask, x, y, n_chunks)}, repeat)
    finally:
        pool.shutdown()
        dask.shutdown()
        cluster.close()
    ref = res["serial"][2]
    case = f"chart {n}x{n} (Fig. 6 config, M=400), {workers} workers"
    names = {"serial": "serial", "threads": f"analysis threads (workers={workers})",
             "pool": f"process pool ({workers} processes)",
             "dask": f"Dask LocalCluster ({workers} procs x 1 thread)"}
    start = {"pool": t_pool, "dask": t_dask}
    rows = []
    for k, name in names.items():
        t, _, out = res[k]
        same = bool(np.allclose(out, ref, rtol=1e-12, atol=0.0))
        note = f"max|mu| same as serial: {same}"
        if k in start:
            note += f"; start-up {start[k]:.2f} s (not in the time)"
        rows.append(Row("chart", case, name, t, ratio=t / res["serial"][0], ref="serial",
                        repeat=repeat, note=note,
                        extra={"equal_to_serial": same, "startup_s": start.get(k),
                               "unstable_fraction": float(np.mean(out > 1 + 1e-5))}))
    return rows


if __name__ == "__main__":
    import sys

    from benchmarks.__main__ import main

    sys.exit(main(["--only", "stability", "--only", "chart", *sys.argv[1:]]))
