"""How the cost of a continuation point grows: against the number of harmonics H
(3, 5, 8, 12; paper rotor, 20 shaft elements) and against the number of shaft elements
(20, 40, 80, 160; H = 3), condensed and full-model HB.

Time per point = wall time of a short branch (Omega~ from 0.95 upwards, where the film
is strongly nonlinear, U = 144.02 g mm,
the options of ``[analysis.response]``; condensed 10 points, full 3 points) / its number
of points, median of the repeats (the full path at 80 and 160 elements: one run), after a
warm-up. The exponent p of ``time ~ size^p`` is the least-squares slope in log-log.
Writes ``benchmarks/scaling.png`` (``--quick``: ``scaling-quick.png``; H = 3, 5 and 20,
40 elements).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from benchmarks.common import (
    W1,
    Row,
    elements_overrides,
    median_time,
    paper_config,
    paper_system,
    response_options,
)

HERE = Path(__file__).resolve().parent
START = 0.95  # Omega~: the film is active there (near Omega~ 0.5 the orbit is almost
#               linear and the full path accepts its linearised start without iterating)


def time_per_point(problem, opts, H: int, condensed: bool, points: int, repeat: int
                   ) -> float:
    from rotorsfd.harmonic.periodic import continue_periodic

    def branch(n: int):
        return continue_periodic(problem, START * W1, 1.6 * W1, H, condensed=condensed,
                                 **{**opts, "max_points": n})

    branch(1)  # warm-up
    t, _, b = median_time(lambda: branch(points), repeat)
    return t / b.n_points


def exponent(x, y) -> float:
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    Hs = (3, 5) if quick else (3, 5, 8, 12)
    els = (20, 40) if quick else (20, 40, 80, 160)
    opts = response_options(paper_config())
    res: dict[tuple[str, str], list[tuple[int, float]]] = {}
    rows: list[Row] = []
    sweeps = [("H", H, [], H) for H in Hs] + [("elements", n, elements_overrides(n), 3)
                                               for n in els]
    problems: dict[int, object] = {}
    for axis, size, overrides, H in sweeps:
        n_el = size if axis == "elements" else 20
        if n_el not in problems:
            problems[n_el] = paper_system(overrides).periodic_problem()
        problem = problems[n_el]
        for condensed in (True, False):
            path = "condensed" if condensed else "full"
            rep = repeat if (condensed or n_el <= 40) else 1
            pts = 10 if condensed else (2 if n_el >= 80 else 3)
            t = time_per_point(problem, opts, H, condensed, pts, rep)
            res.setdefault((axis, path), []).append((size, t))
            rows.append(Row("scaling", f"{axis} = {size} ({problem.n_dof} DOF, H={H})",
                            f"{path}: per point", t, repeat=rep))
    for (axis, path), data in res.items():
        x, y = np.array(data, float).T
        p = exponent(x, y)
        rows.append(Row("scaling", f"fit over {axis} {list(map(int, x))}",
                        f"{path}: exponent p (time ~ {axis}^p)", p, unit="",
                        note=f"{y[-1] / y[0]:.3g}x from {int(x[0])} to {int(x[-1])}",
                        extra={"sizes": x.tolist(), "seconds_per_point": y.tolist()}))
    plot(res, HERE / ("scaling-quick.png" if quick else "scaling.png"))
    return rows


def plot(res, path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import matplotlib.ticker

    fig, axes = plt.subplots(1, 2, figsize=(9, 3.8), constrained_layout=True)
    for ax, axis, label in ((axes[0], "H", "harmonics H (20 elements)"),
                            (axes[1], "elements", "shaft elements (H = 3)")):
        for kind, mark in (("condensed", "o-"), ("full", "s--")):
            data = res.get((axis, kind))
            if not data:
                continue
            x, y = np.array(data, float).T
            ax.loglog(x, 1e3 * y, mark, label=f"{kind} (p = {exponent(x, y):.2f})")
        sizes = sorted({v for (a, _), d in res.items() if a == axis for v, _ in d})
        if sizes:
            ax.set_xticks(sizes, [str(int(v)) for v in sizes])
            ax.xaxis.set_minor_formatter(matplotlib.ticker.NullFormatter())
        ax.set_xlabel(label)
        ax.set_ylabel("time per continuation point [ms]")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend()
    fig.suptitle("rotorsfd HB continuation, paper rotor from Omega~ 0.95: cost per point")
    fig.savefig(path, dpi=120)
    plt.close(fig)


def plot_from_results(results: Path, out: Path) -> None:
    """Redraw the figure from a results file (rows of the ``scaling`` fits)."""
    import json

    res = {}
    for r in json.loads(Path(results).read_text())["rows"]:
        if r["bench"] == "scaling" and "sizes" in r["extra"]:
            axis = r["case"].split()[2]
            kind = r["method"].split(":")[0]
            res[(axis, kind)] = list(zip(r["extra"]["sizes"], r["extra"]["seconds_per_point"],
                                         strict=True))
    plot(res, out)


if __name__ == "__main__":
    import sys

    if sys.argv[1:2] == ["--plot-from"]:  # python -m benchmarks.bench_scaling --plot-from F
        plot_from_results(Path(sys.argv[2]), HERE / "scaling.png")
        sys.exit(0)
    from benchmarks.__main__ import main

    sys.exit(main(["--only", "scaling", *sys.argv[1:]]))
