"""Linear analyses at scale (issue 17 items 3 and 6): the first critical speed and
``rotorsfd modal`` (Campbell diagram + critical speeds) of a stepped 1.5 m rotor meshed
in 80 to 2560 elements, sparse shift-invert eigensolver against the dense ``scipy.linalg.eig``
path of before (the honest scipy baseline: the same grid, the same root finder, every
mode of the 2n state matrix at each evaluation).

The rotor (:func:`stepped_rotor_config`, a rotorsfd config dict): a 1.5 m steel shaft in
five sections (16 units of 93.75 mm: radius 25 mm over 3 units, 35 mm over 5, a 1-unit
coupling of 25 mm in a softer, titanium-like material with a hub mass at each end,
35 mm over 4, 25 mm over 3), three disks (units 4, 7 and 11), the SFD with its centring
spring at node 1 and a damped bearing at the last node. The mesh is 80 ... 2560 elements
(N / 16 per unit).

Each row times, from the built model: the first forward critical speed
(``reference_speed``) and the whole ``run_modal`` (reference speed, 81-speed Campbell
diagram of 8 modes, 2 critical speeds). The exponent p of ``time ~ elements^p`` is the
least-squares slope in log-log. The dense baseline (the path of before: every eig solve
of the whole 2n state matrix, the whole grid, the reference speed searched apart) is
measured directly for the first critical speed at 80 elements; elsewhere it is the number
of its eig solves (counted on the same grid and root finder) times one dense eig measured
at that size (<= ``DENSE_MAX`` elements), or extrapolated as (2n)^3 beyond. ``--quick``:
80 and 160 elements, one dense eig at 80, no baseline estimate (no time asserted). The full
run writes ``benchmarks/scale.png`` (time against DOF, log-log, with the exponents).

Then the nonlinear rows (:func:`hb_rows`, issue 17 item 2; ``--hb`` runs only them): an
HB point at every size against the scipy.sparse + splu baseline, with the exponents, and
at 1280 elements the 56-point branch, the branch with the stability of every point and
the peak memory of each workload (:mod:`benchmarks.scale_hb`).
"""

from __future__ import annotations

import sys
import time
from functools import partial
from pathlib import Path
from typing import Any

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import Row, median_time

HERE = Path(__file__).resolve().parent
UNITS = 16                      # the shaft is 16 units of L / 16
LENGTH = 1.5                    # [m]
# (units, outer radius [m], material) of the five sections, left to right
SECTIONS = ((3, 0.025, "steel"), (5, 0.035, "steel"), (1, 0.025, "coupling"),
            (4, 0.035, "steel"), (3, 0.025, "steel"))
DISKS = ((4, 0.15, 0.04), (7, 0.12, 0.03), (11, 0.16, 0.05))   # unit, outer radius, thickness
COUPLING_HUBS = (8, 9)          # units of the hub masses
HUB_MASS = 1.5                  # [kg]
SIZES = (80, 160, 320, 640, 1280, 2560)
QUICK_SIZES = (80, 160)
DENSE_MAX = 160                 # largest mesh of the dense baseline (80 s at 160 elements)
TARGET_SIZE = 1280              # the size of the HB targets (5124 DOF)
DENSE_MODAL_MAX = 320           # largest mesh of the dense modal-damping baseline
DENSE_FULL_MAX = 160            # largest mesh of the dense full-HB baseline


def node_at(unit: int, n_elements: int) -> int:
    """Node (1-based) at ``unit`` of the shaft meshed in ``n_elements``."""
    return 1 + unit * n_elements // UNITS


def stepped_rotor_config(n_elements: int) -> dict[str, Any]:
    """The stepped rotor as a rotorsfd config dict (SI numbers), ``n_elements`` a multiple
    of 16."""
    if n_elements % UNITS:
        raise ValueError(f"n_elements must be a multiple of {UNITS}")
    per_unit = n_elements // UNITS
    unit = LENGTH / UNITS
    shaft = [{"length": u * unit, "n_elements": u * per_unit, "outer_radius": r,
              "material": mat} for u, r, mat in SECTIONS]
    disks = [{"node": node_at(u, n_elements), "material": "steel", "inner_radius": 0.035,
              "outer_radius": ro, "thickness": t}
             for u, ro, t in DISKS]
    last = n_elements + 1
    sfd = {"node": 1, "viscosity": 0.0051, "clearance": 1.27e-4, "clearance_ratio": 0.00485,
           "length_to_diameter": 0.325, "cavitation": "pi", "centring_stiffness": 1e7,
           "centring_damping": 0.0}
    return {
        "title": f"stepped 1.5 m rotor, 3 disks, coupling, SFD, bearing ({n_elements} el.)",
        "materials": {
            "steel": {"density": 7810.0, "young_modulus": 211e9, "shear_modulus": 81.2e9},
            "coupling": {"density": 4500.0, "young_modulus": 110e9, "poisson_ratio": 0.34},
        },
        "rotor": {
            "shaft": shaft, "disks": disks,
            "point_masses": [{"node": node_at(u, n_elements), "mass": HUB_MASS}
                             for u in COUPLING_HUBS],
            "supports": [{"node": last, "name": "bearing", "stiffness": 5e7,
                          "damping": 2e3}],
        },
        **sfd_table(sfd),
        "unbalance": [{"node": node_at(7, n_elements), "magnitude": 1e-4}],
        "reference": {"speed": "first_critical"},
    }


def sfd_table(sfd: dict[str, Any]) -> dict[str, Any]:
    """The SFD as ``[elements.sfd]`` (kind = "sfd") where the schema has elements, else
    the top-level ``[sfd]`` table of before."""
    from rotorsfd.io.schema import Config

    if "elements" in Config.model_fields:
        return {"elements": {"sfd": {"kind": "sfd", **sfd}}}
    return {"sfd": sfd}


def config(n_elements: int) -> Any:
    """Validated :class:`Config` of the stepped rotor."""
    from rotorsfd.io.config import config_from_dict

    return config_from_dict(stepped_rotor_config(n_elements))


def exponent(x, y) -> float:
    """Least-squares slope p of log y = p log x + c."""
    return float(np.polyfit(np.log(x), np.log(y), 1)[0])


def mem_available_gib() -> float:
    try:
        for line in Path("/proc/meminfo").read_text().splitlines():
            if line.startswith("MemAvailable"):
                return int(line.split()[1]) / 2**20
    except OSError:
        pass
    return float("inf")


def modal_from(system: Any, cfg: Any) -> tuple[list, Any, float]:
    """What ``run_modal`` computes from a built linear system: the critical speeds, the
    reference speed (reused) and the Campbell diagram."""
    from rotorsfd import api
    from rotorsfd.linear import campbell, critical_speeds

    m = cfg.analysis.modal
    crit = critical_speeds(system, n=m.n_critical, whirl=m.whirl,
                           speed_range=(0.0, m.critical_speed_max))
    ref = api.reference_speed(cfg, system, crit)
    camp = campbell(system, api.modal_speeds(cfg, ref), m.n_modes)
    return crit, camp, ref


def first_critical(system: Any, cfg: Any, method: str = "auto", full_grid: bool = False
                   ) -> float:
    from rotorsfd.linear import critical_speeds

    top = cfg.analysis.modal.critical_speed_max
    return critical_speeds(system, n=1, speed_range=(0.0, top), method=method,
                           full_grid=full_grid)[0].speed_rad_s


def evaluations_of_dense_path(system: Any, cfg: Any) -> dict[str, int]:
    """Eigen-solves of the dense path of before (whole grid, every mode; reference speed
    searched apart): counted on the sparse solver's calls, the same grid and root finder."""
    import rotorsfd.linear.critical as critical

    calls = [0]
    real = critical.sparse_eigen

    def counting(*args, **kwargs):
        calls[0] += 1
        return real(*args, **kwargs)

    m = cfg.analysis.modal
    critical.sparse_eigen = counting
    try:
        first_critical(system, cfg, "sparse", full_grid=True)
        ref = calls[0]
        critical.critical_speeds(system, n=m.n_critical, whirl=m.whirl, method="sparse",
                                 speed_range=(0.0, m.critical_speed_max), full_grid=True)
        crit = calls[0] - ref
    finally:
        critical.sparse_eigen = real
    return {"reference": ref, "critical": crit, "campbell": m.speed_range.n,
            "modal": ref + crit + m.speed_range.n}


def plot(series: dict[str, list[tuple[int, float]]], dofs: dict[int, int], path: Path
         ) -> None:
    """Time against DOF, log-log, each series with its fitted exponent."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7.5, 4.8))
    for name in ("first critical incl. extraction", "modal incl. extraction", "extraction",
                 "reference: dense path of before (est.)", "modal: dense path of before (est.)"):
        data = series.get(name)
        if not data or len(data) < 2:
            continue
        x, y = np.array(data, float).T
        mark = "s--" if "dense" in name else "o-"
        ax.loglog([dofs[int(v)] for v in x], y, mark, label=f"{name} (p = {exponent(x, y):.2f})")
    ax.set_xlabel("DOF (4 per node)")
    ax.set_ylabel("wall time [s]")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title("stepped 1.5 m rotor: first critical speed and modal, sparse vs dense eig",
                 fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def cold(pencil: Any, fun: Any, *args: Any) -> Any:
    """``fun(*args)`` without an ARPACK start vector left by a previous run."""
    pencil.last_start.clear()
    return fun(*args)


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd import api
    from rotorsfd.linear.modal import dense_eigen
    from rotorsfd.linear.sparse_modes import pencil_of

    sizes = QUICK_SIZES if quick else SIZES
    dense_sizes = (80,) if quick else tuple(n for n in SIZES if n <= DENSE_MAX)
    rows: list[Row] = []
    series: dict[str, list[tuple[int, float]]] = {}
    counts: dict[str, int] = {}
    dense_eval: dict[int, float] = {}
    for n in sizes:
        if n >= 2560 and mem_available_gib() < 12.0:
            rows.append(Row("scale", f"{n} elements", "skipped", 0.0, unit="",
                            note=f"{mem_available_gib():.1f} GiB available (< 12)"))
            continue
        cfg = config(n)
        t0 = time.perf_counter()
        system = api.linear_system(cfg)
        t_build = time.perf_counter() - t0
        dof = system.n_dof
        t0 = time.perf_counter()
        pencil = pencil_of(system)
        t_extract = time.perf_counter() - t0
        case = f"{n} elements ({dof} DOF)"
        rows.append(Row("scale", case, "build model (sparse assembly)", t_build))
        rows.append(Row("scale", case, "sparse pencil: 3 sparse_matrices() calls + band",
                        t_extract, note=f"half band {pencil.half_band}"))
        nnz = sum(x.nnz for pair in pencil.terms or () for x in pair)
        rows.append(Row("scale", case, "storage of M, D, K: sparse (dense)",
                        nnz * 12 / 2**20, unit="MiB",
                        note=f"dense {3 * dof**2 * 8 / 2**20:.4g} MiB"))
        series.setdefault("extraction", []).append((n, t_extract))

        t_first, _, w1 = median_time(partial(cold, pencil, first_critical, system, cfg),
                                     repeat)
        t_modal, _, (crit, camp, _) = median_time(
            partial(cold, pencil, modal_from, system, cfg), 1 if quick else repeat)
        rows.append(Row("scale", case, "first critical speed (sparse)", t_first,
                        repeat=repeat, note=f"{w1:.10g} rad/s"))
        rows.append(Row("scale", case, "modal: critical speeds + Campbell (sparse)",
                        t_modal, repeat=1 if quick else repeat,
                        note=f"Campbell {camp.info.get('method')}, error "
                             f"{camp.info.get('reduced_error', 0.0):.1e}, basis "
                             f"{camp.info.get('basis_size', '-')}; crit "
                             + ", ".join(f"{c.speed_rad_s:.8g}" for c in crit)))
        series.setdefault("first critical incl. extraction", []).append(
            (n, t_first + t_extract))
        series.setdefault("modal incl. extraction", []).append((n, t_modal + t_extract))
        series.setdefault("first critical", []).append((n, t_first))
        series.setdefault("modal", []).append((n, t_modal))
        if not counts and not quick:
            counts = evaluations_of_dense_path(system, cfg)
        if n in dense_sizes:
            t_eval, _, _ = median_time(partial(dense_eigen, system, 300.0, 16), repeat)
            dense_eval[n] = t_eval
            rows.append(Row("scale", case, "dense eig of the 2n state matrix (one speed)",
                            t_eval, repeat=repeat))
            if n == 80 and not quick:
                t0 = time.perf_counter()
                w_dense = first_critical(system, cfg, "dense", full_grid=True)
                t_dense = time.perf_counter() - t0
                rows.append(Row("scale", case, "first critical speed, dense path of before",
                                t_dense, ratio=t_first / t_dense, ref="dense",
                                note=f"{w_dense:.10g} rad/s, sparse - dense: "
                                     f"{abs(w1 / w_dense - 1):.1e} (rel.); "
                                     f"{counts['reference']} eig solves"))
        if dense_eval and counts:
            top = max(dense_eval)
            t_eval = dense_eval.get(n, dense_eval[top] * (n / top) ** 3)
            how = "measured" if n in dense_eval else f"(n/{top})^3 from {top} elements"
            for what, t_new in (("reference", t_first), ("modal", t_modal)):
                est = counts[what] * t_eval
                series.setdefault(f"{what}: dense path of before (est.)", []).append((n, est))
                rows.append(Row("scale", case, f"{what}: dense path of before (estimate)",
                                est, ratio=t_new / est, ref="dense",
                                note=f"{counts[what]} eig solves x {t_eval:.3g} s ({how})"))
    for name, data in series.items():
        if len(data) < 2:
            continue
        x, y = np.array(data, float).T
        rows.append(Row("scale", f"fit over elements {list(map(int, x))}",
                        f"{name}: exponent p (time ~ elements^p)", exponent(x, y), unit="",
                        note=f"{y[-1] / y[0]:.3g}x from {int(x[0])} to {int(x[-1])}",
                        extra={"elements": x.tolist(), "seconds": y.tolist()}))
    if not quick:
        plot(series, {n: 4 * (n + 1) for n in sizes}, HERE / "scale.png")
    if len(dense_eval) >= 2:
        x, y = np.array(sorted(dense_eval.items()), float).T
        rows.append(Row("scale", f"fit over elements {list(map(int, x))}",
                        "dense eig per speed: exponent p", exponent(x, y), unit=""))
    return rows + hb_rows(quick, repeat)


def hb_rows(quick: bool = False, repeat: int = 3) -> list[Row]:
    """HB point / 56-point branch / branch with stability / peak memory, banded against
    the scipy.sparse + splu baseline (:mod:`benchmarks.scale_hb`): the point at every size
    (exponent fitted), the branch, stability and memory at TARGET_SIZE. ``--quick``: 80
    and 160 elements, the branch, stability (checked against FloquetEvaluator) and the
    memory of branch + stability at 160, no baseline branch."""
    from benchmarks import scale_hb as S

    sizes = QUICK_SIZES if quick else SIZES
    target = QUICK_SIZES[-1] if quick else TARGET_SIZE
    rows: list[Row] = []
    fits: dict[str, list[tuple[int, float]]] = {}
    for n in sizes:
        system, problem, w1, opts = S.build(n)
        case = f"{n} elements ({system.n_dof} DOF), HB H={S.H}"
        S.point(problem, w1)                                   # warm-up (kernels, caches)
        t_ours, c_ours, a = S.timed(lambda p=problem, w=w1: S.point(p, w), repeat)
        with S.splu_baseline():
            S.point(problem, w1)
            t_splu, c_splu, b = S.timed(lambda p=problem, w=w1: S.point(p, w), repeat)
        diff = float(np.abs(a.X - b.X).max() / np.abs(b.X).max())
        for key, v in (("HB point, banded", t_ours), ("HB point, banded (CPU)", c_ours),
                       ("HB point, scipy.sparse + splu", t_splu),
                       ("HB point, scipy.sparse + splu (CPU)", c_splu)):
            fits.setdefault(key, []).append((n, v))
        rows += [Row("scale", case, "HB point (banded)", t_ours, repeat=repeat, ratio=1.0,
                     ref="banded", note=f"CPU {c_ours * 1e3:.1f} ms; Omega = 0.8 w1, tol "
                                        f"1e-10, {a.iterations} iter., half band "
                                        f"{problem.matrices.band}"),
                 Row("scale", case, "HB point: scipy.sparse + splu per harmonic", t_splu,
                     repeat=repeat, ratio=t_splu / t_ours, ref="banded",
                     note=f"CPU {c_splu * 1e3:.1f} ms; max |dX|/|X| = {diff:.1e}")]
        if n != target:
            continue
        t_br, c_br, br = S.timed(lambda p=problem, w=w1, o=opts: S.branch(p, w, o), 1)
        t_st, c_st, mu = S.timed(lambda p=problem, b=br: S.stability(p, b), 1)
        rows.append(Row("scale", case, f"{br.n_points}-point branch (banded)", t_br, ratio=1.0,
                        ref="banded", note=f"CPU {c_br:.2f} s; Omega/w1 0.5-"
                                           f"{br.lam[-1] / w1:.3f}, adaptive H, "
                                           f"{c_br / br.n_points * 1e3:.0f} ms CPU/point"))
        with S.no_refinement():
            t_brn, c_brn, brn = S.timed(lambda p=problem, w=w1, o=opts: S.branch(p, w, o), 1)
        rows.append(Row("scale", case, f"{brn.n_points}-point branch: banded, no refinement "
                        "(before)", t_brn, ratio=t_brn / t_br, ref="banded",
                        note=f"CPU {c_brn:.2f} s; Omega/w1 0.5-{brn.lam[-1] / w1:.3f}"))
        if not quick:
            with S.splu_baseline():
                t_brs, c_brs, brs = S.timed(
                    lambda p=problem, w=w1, o=opts: S.branch(p, w, o), 1)
            rows.append(Row("scale", case, f"{brs.n_points}-point branch: scipy.sparse + "
                            "splu", t_brs, ratio=t_brs / t_br, ref="banded",
                            note=f"CPU {c_brs:.2f} s; Omega/w1 0.5-{brs.lam[-1] / w1:.3f}"))
        rows += [Row("scale", case, "branch + stability of every point (banded, sparse CB)",
                     t_br + t_st, ratio=1.0, ref="banded",
                     note=f"CPU {c_br + c_st:.2f} s (Floquet {c_st:.2f} s), M = "
                          f"{S.N_INTERVALS}, max |mu| {mu.max():.6f}")]
        if n == sizes[0] or quick:
            err = S.stability_check(problem, br, mu, br.n_points // 2)
            rows[-1].note += f"; vs FloquetEvaluator (dense basis) {err:.1e}"
        loads = (("point", "HB point"), ("branch", "branch"),
                 ("stability", "branch + stability"),
                 ("point-splu", "HB point, scipy.sparse + splu"))
        for workload, label in loads[2:3] if quick else loads:
            rows.append(Row("scale", case, f"peak memory: {label}", S.peak_memory(n, workload),
                            unit="GiB", note="fresh process: build + workload"))
    rows += modal_rows(quick, repeat) + full_rows(quick, repeat)
    for name, data in fits.items():
        x, y = np.array(data, float).T
        rows.append(Row("scale", f"fit over elements {list(map(int, x))}",
                        f"{name}: exponent p (time ~ elements^p)", exponent(x, y), unit="",
                        note=f"{y[-1] / y[0]:.3g}x from {int(x[0])} to {int(x[-1])}",
                        extra={"elements": x.tolist(), "seconds": y.tolist()}))
    return rows


def modal_rows(quick: bool = False, repeat: int = 3) -> list[Row]:
    """HB point with modal damping of MODAL_MODES modes: banded + low-rank (Woodbury)
    against the dense LAPACK path of before (measured up to DENSE_MODAL_MAX elements)."""
    from benchmarks import scale_hb as S

    sizes = QUICK_SIZES if quick else (80, 320, TARGET_SIZE)
    rows: list[Row] = []
    for n in sizes:
        system, problem, w1, _ = S.build(n, S.MODAL_MODES)
        case = (f"{n} elements ({system.n_dof} DOF), HB H={S.H}, modal damping "
                f"{S.MODAL_RATIO:g} on {S.MODAL_MODES} modes")
        S.point(problem, w1)
        t_lr, c_lr, a = S.timed(lambda p=problem, w=w1: S.point(p, w), repeat)
        rows.append(Row("scale", case, "HB point: banded + low-rank (Woodbury)", t_lr,
                        repeat=repeat, ratio=1.0, ref="low-rank",
                        note=f"CPU {c_lr * 1e3:.1f} ms; {a.iterations} iter."))
        if n > DENSE_MODAL_MAX:
            continue
        dense = S.dense_problem(problem)
        S.point(dense, w1)
        t_d, c_d, b = S.timed(lambda p=dense, w=w1: S.point(p, w), max(1, repeat // 3))
        diff = float(np.abs(a.X - b.X).max() / np.abs(b.X).max())
        rows.append(Row("scale", case, "HB point: dense LAPACK (before)", t_d,
                        repeat=max(1, repeat // 3), ratio=t_d / t_lr, ref="low-rank",
                        note=f"CPU {c_d * 1e3:.1f} ms; max |dX|/|X| = {diff:.1e}"))
    return rows


def full_rows(quick: bool = False, repeat: int = 3) -> list[Row]:
    """The full-model HB point (every DOF an unknown, no condensation) at Omega = 0.97 w1,
    tol 1e-13: CSR Jacobian + SuperLU (``harmonic.full_sparse``) against the dense
    Jacobian + LAPACK of before (up to DENSE_FULL_MAX elements), the condensed point for
    scale."""
    from benchmarks import scale_hb as S
    from rotorsfd.harmonic import full_sparse
    from rotorsfd.harmonic.periodic import solve_periodic

    def full(problem, w1):
        return solve_periodic(problem, 0.97 * w1, S.H, tol=1e-13, condensed=False)

    sizes = QUICK_SIZES if quick else (80, 160, 320, TARGET_SIZE)
    rows: list[Row] = []
    for n in sizes:
        system, problem, w1, _ = S.build(n)
        case = f"{n} elements ({system.n_dof} DOF), full HB H={S.H} ({7 * system.n_dof} unknowns)"
        full(problem, w1)
        t_s, c_s, a = S.timed(lambda p=problem, w=w1: full(p, w), repeat)
        t_c, c_c, _ = S.timed(lambda p=problem, w=w1: solve_periodic(
            p, 0.97 * w, S.H, tol=1e-13, condensed=True), repeat)
        rows += [Row("scale", case, "full HB point: CSR + SuperLU", t_s, repeat=repeat,
                     ratio=1.0, ref="sparse", note=f"CPU {c_s * 1e3:.1f} ms; {a.iterations} iter."),
                 Row("scale", case, "condensed HB point (banded)", t_c, repeat=repeat,
                     ratio=t_c / t_s, ref="sparse", note=f"CPU {c_c * 1e3:.1f} ms")]
        if n > (QUICK_SIZES[0] if quick else DENSE_FULL_MAX):
            continue
        old = full_sparse.SPARSE_MIN_DOF
        full_sparse.SPARSE_MIN_DOF = 10**9                  # the dense FullHB of before
        try:
            t_d, c_d, b = S.timed(lambda p=problem, w=w1: full(p, w), 1)
        finally:
            full_sparse.SPARSE_MIN_DOF = old
        diff = float(np.abs(a.X - b.X).max() / np.abs(b.X).max())
        rows.append(Row("scale", case, "full HB point: dense Jacobian + LAPACK (before)", t_d,
                        ratio=t_d / t_s, ref="sparse",
                        note=f"CPU {c_d * 1e3:.1f} ms; max |dX|/|X| = {diff:.1e}"))
    return rows


if __name__ == "__main__":
    from benchmarks.__main__ import fmt_value

    quick = "--quick" in sys.argv
    bench = (hb_rows if "--hb" in sys.argv else modal_rows if "--modal" in sys.argv
             else full_rows if "--full" in sys.argv else run)
    for r in bench(quick=quick, repeat=1 if quick else 3):
        print(f"{r.case} | {r.method}: {fmt_value(r)}  {r.note}")
