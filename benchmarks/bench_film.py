"""Squeeze film models (issue 18): the cost of one force + Jacobian evaluation of the
finite-length film against the short film, the paper rotor's branch with each, and the
figure of ``docs/sfd.md`` comparing the models on one damper.

1. ``per sample``: the compiled kernel of one sample (force and exact Jacobian) in a
   compiled loop over 512 states (eps uniform in [0, 0.9], random velocities), for the
   short film, the finite film's eps table (default grid) and the finite film's
   grid solver on grids 32 x 2, 48 x 4 (the default), 64 x 8 and 128 x 8 (theta nodes x
   axial intervals of the half land), pi and Guembel films; the ratio is to the short
   film's time in the same run.
2. ``branch``: the paper rotor (examples/paper_rotor.toml, L/D = 0.325, pi film) at the
   Table 1 unbalance, HB continuation over Omega~ 0.5-1.6 with ``[analysis.response]``'s
   options, H = 3, short film vs the finite film with open ends (default grid, eps
   table, and the grid solver at every sample): time, the fold speeds and the largest
   eccentricity ratio along the branch. Skipped by ``--quick``.

Figure: ``python -m benchmarks.bench_film --figure docs/sfd_models.png``.
Run: ``python -m benchmarks --only film``.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import W1, Row, interleaved, paper_config, paper_system, response_options

MU, C, CR, LD = 0.0051, 1.27e-4, 0.00485, 0.325  # the paper's damper
GRIDS = ((32, 2), (48, 4), (64, 8), (128, 8))
QUICK_GRIDS = ((32, 2), (48, 4))
N_STATES = 512


def _states(n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    eps = rng.uniform(0.0, 0.9, n)
    psi = rng.uniform(-np.pi, np.pi, n)
    q = np.ascontiguousarray(np.stack([eps * C * np.cos(psi), eps * C * np.sin(psi)], 1))
    v = np.ascontiguousarray(rng.normal(size=(n, 2)) * 300 * C)
    return q, v


def _loop() -> Any:
    from numba import njit

    @njit
    def loop(kernel, q, v, params, F, dq, dv):  # type: ignore[no-untyped-def]
        s = 0
        for i in range(q.shape[0]):
            s += kernel(q[i], v[i], params, F, dq, dv)
        return s

    return loop


def per_sample_rows(quick: bool, repeat: int) -> list[Row]:
    """Part 1: one sample's force and Jacobian, short film vs finite film grids."""
    from rotorsfd.model.film_finite import FiniteSFD
    from rotorsfd.sfd import SFD

    loop = _loop()
    q, v = _states(64 if quick else N_STATES)
    F, dq, dv = np.empty(2), np.empty((2, 2)), np.empty((2, 2))
    rows: list[Row] = []
    for model in ("pi", "guembel"):
        films: dict[str, Any] = {"short": SFD.from_ratios(MU, C, CR, LD, cavitation=model)}
        films["finite 48 x 4, eps table"] = FiniteSFD.from_ratios(MU, C, CR, LD, model)
        for n, m in (QUICK_GRIDS if quick else GRIDS):
            films[f"finite {n} x {m}, solver"] = FiniteSFD.from_ratios(
                MU, C, CR, LD, model, n_theta=n, n_axial=m, table=False)
        calls = {}
        for name, film in films.items():
            kernel, params = film.numba_kernel, film.kernel_params
            if loop(kernel, q, v, params, F, dq, dv) != 0:  # warm-up (compiles)
                raise RuntimeError(f"{name}: contact in the benchmark states")
            calls[name] = lambda k=kernel, p=params: loop(k, q, v, p, F, dq, dv)
        res = interleaved(calls, repeat)
        ref = res["short"][0]
        for name, (t, times, _) in res.items():
            rows.append(Row("film", f"{model} film, L/D = {LD}: force + Jacobian of one "
                            "sample (compiled loop)", name, t / q.shape[0], repeat=len(times),
                            ratio=t / ref, ref="short",
                            extra={"times_s": [x / q.shape[0] for x in times]}))
    return rows


def branch_summary(film_length: str, overrides: list[str] | None = None
                   ) -> dict[str, Any]:
    """The paper rotor's HB branch with the short or the finite film: time, fold speeds
    (Omega / W1) and the largest eccentricity ratio of the SFD along the branch."""
    from rotorsfd.harmonic.periodic import continue_periodic

    ov = [f"elements.sfd.film_length={film_length}", *(overrides or [])]
    system = paper_system(ov)
    problem = system.periodic_problem()
    opts = response_options(paper_config())
    t0 = time.perf_counter()
    br = continue_periodic(problem, 0.5 * W1, 1.6 * W1, 3, **opts)
    seconds = time.perf_counter() - t0
    eps = np.array([np.hypot(*br.time_series(i, 64)[1][:, br.nl_dofs[:2]].T).max()
                    for i in range(br.n_points)]) / C
    return {"seconds": seconds, "points": br.n_points, "folds": br.lam[br.folds()] / W1,
            "eps_max": float(eps.max()), "lam": br.lam / W1, "eps": eps}


def branch_rows(repeat: int) -> list[Row]:
    """Part 2: the paper rotor's branch, short vs finite film (first calls compile)."""
    cases = {"short": ("short", []), "finite, eps table": ("finite", []),
             "finite, solver": ("finite", ["elements.sfd.film_table=false"])}
    for film, ov in cases.values():
        branch_summary(film, ov)  # warm-up
    res = interleaved({k: lambda c=c: branch_summary(*c) for k, c in cases.items()}, repeat)
    rows = []
    for name, (t, times, s) in res.items():
        rows.append(Row("film", "paper rotor (L/D = 0.325, pi film), HB branch Omega~ "
                        "0.5-1.6, H = 3", name, t, repeat=len(times),
                        ratio=t / res["short"][0], ref="short",
                        note=(f"{s['points']} points; folds at Omega~ = "
                              + ", ".join(f"{x:.4f}" for x in s["folds"])
                              + f"; max eps = {s['eps_max']:.4f}"),
                        extra={"times_s": times}))
    return rows


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    rows = per_sample_rows(quick, repeat)
    if not quick:
        rows += branch_rows(repeat)
    return rows


def figure(path: Path) -> None:
    """Force against eccentricity, against L/D and against whirl speed on the paper's
    damper: short film, finite film (open ends, an end seal beta = 1, a sealed land)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    from rotorsfd.model.film_finite import FiniteSFD
    from rotorsfd.sfd import SFD

    omega = 811.3  # whirl speed of the circular centred orbit [rad/s] (the first critical)
    models = {"short film": SFD.from_ratios(MU, C, CR, LD),
              "finite, open ends": FiniteSFD.from_ratios(MU, C, CR, LD, "pi"),
              "finite, end seal beta = 1": FiniteSFD.from_ratios(MU, C, CR, LD, "pi",
                                                                 end_flow=1.0),
              "finite, sealed land": FiniteSFD.from_ratios(MU, C, CR, LD, "pi",
                                                           end_flow=0.0)}
    eps = np.linspace(0.02, 0.9, 45)
    fig, ax = plt.subplots(1, 3, figsize=(14, 4.3))
    for (name, film), color in zip(models.items(), ("k", "C0", "C1", "C2"), strict=True):
        fr, ft = film.force(eps * C, 0 * eps, 0 * eps, eps * C * omega)
        ax[0].semilogy(eps, -ft, color=color, label=f"{name}: -F_t")
        ax[0].semilogy(eps, -fr, color=color, ls="--", label=f"{name}: -F_r")
    ax[0].set(xlabel="eccentricity ratio eps", ylabel="force [N]",
              title=f"circular centred orbit, pi film, Omega = {omega} rad/s")
    ax[0].legend(fontsize=6.5)
    lds = np.linspace(0.05, 1.0, 20)
    for e, color in zip((0.0, 0.5, 0.8), ("C0", "C1", "C3"), strict=True):
        ratio = []
        for ld in lds:
            st = (e * C, 0.0, 0.0, max(e, 0.05) * C * omega)
            short = np.hypot(*SFD.from_ratios(MU, C, CR, ld).force(*st))
            fin = np.hypot(*FiniteSFD.from_ratios(MU, C, CR, ld, "pi").force(*st))
            ratio.append(fin / short)
        ax[1].plot(lds, ratio, color=color, marker=".", label=f"eps = {e}")
    ax[1].axvline(LD, color="0.6", lw=0.8)
    ax[1].set(xlabel="L/D", ylabel="|F| finite / |F| short", ylim=(0, 1.05),
              title="finite length against the short film (open ends)")
    ax[1].legend(fontsize=8)
    speeds = np.linspace(100.0, 3000.0, 30)
    e = 0.5
    for (name, film), color in zip(models.items(), ("k", "C0", "C1", "C2"), strict=True):
        ft = np.array([film.force(e * C, 0.0, 0.0, e * C * w)[1] for w in speeds])
        ax[2].loglog(speeds, -ft, color=color, label=name)
    ax[2].set(xlabel="whirl speed Omega [rad/s]", ylabel="-F_t [N]")
    ax[2].text(0.97, 0.04, f"circular orbit, eps = {e}:\nevery film model is linear in "
               "Omega", transform=ax[2].transAxes, ha="right", fontsize=8)
    rho = 860.0  # a turbine oil [kg/m^3]: the squeeze Reynolds number on the top axis
    top = ax[2].secondary_xaxis("top", functions=(lambda w: rho * w * C**2 / MU,
                                                  lambda r: r * MU / (rho * C**2)))
    top.set_xlabel("Re_s = rho Omega C^2 / mu, rho = 860 kg/m^3 (fluid inertia, not "
                   "modelled, matters from Re_s ~ 1)", fontsize=8)
    top.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
    ax[2].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--quick", action="store_true")
    ap.add_argument("--figure", type=Path, default=None, help="draw the docs figure here")
    a = ap.parse_args(argv)
    if a.figure is not None:
        figure(a.figure)
        print(f"wrote {a.figure}")
        return
    for r in run(a.quick, 1 if a.quick else 3):
        ratio = "" if r.ratio is None else f" ({r.ratio:.3g}x {r.ref})"
        print(f"{r.case} | {r.method}: {r.value * 1e6:.2f} us{ratio} {r.note}"
              if r.value < 1e-2 else f"{r.case} | {r.method}: {r.value:.2f} s{ratio} {r.note}")


if __name__ == "__main__":
    main()
