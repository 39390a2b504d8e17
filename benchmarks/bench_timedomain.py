"""Time integration of the paper rotor, 2000 periods x 200 steps: our compiled Newmark
integrator vs scipy ``solve_ivp`` (LSODA, Radau) at matched accuracy, and vs ROSS's
Newmark time response of the same linear rotor.

Problem: examples/paper_rotor.toml (84 DOF, pi-film SFD at node 1) at U = 144.02 g mm,
Omega~ = 0.8 (a stable period-1 point), every node displaced 1 um at t = 0, as
``rotorsfd simulate`` builds it (``time_domain_inputs``).

1. Ours: 2000 periods x 200 steps (average acceleration, Newton on the SFD DOFs),
   median of the repeats, after the first call (compilation or cache load: see
   ``coldstart``); SFD DOFs recorded every step. Beside it the reduced step of
   ``rotorsfd simulate`` (``reduction = "auto"``: Craig-Bampton on the SFD DOFs, the
   fixed-interface modes up to 40 Omega and the load residuals; the reduction timed with
   the run) and its last period's SFD orbit against the full step's.
2. Accuracy: from the end state, ``n_short`` periods by ours at 200 steps a period and by
   ours at 4000 (the reference); error = largest relative error of the last period's
   amplitudes (max radial excursion at the SFD, half peak-to-peak y at the disk).
3. scipy: for LSODA and Radau the loosest ``rtol`` of a ladder (``atol = rtol x scale``)
   whose error is at most ours; that run's wall time over ``n_short`` periods
   extrapolated linearly to 2000 periods (one run each: a 2000-period scipy run would take
   hours; stated in the table). Analytic Jacobian supplied, SFD force from the same
   compiled kernel.
4. ROSS (optional; ``pip install --target benchmarks/.ross ross-rotordynamics
   'plotly<7'`` plus its imports, see README): the LINEAR rotor (film off, centring spring
   kept, no damping) under the same unbalance from rest, ``run_time_response(...,
   method='newmark')`` over 5 and 10 periods x 200 steps (after a first call) in a
   subprocess, extrapolated to 2000 periods from the cost per step (the difference of
   the two runs) plus the per-call overhead, against ours on the same linear rotor in
   the same run; the two responses of the disk node are compared (same model and scheme:
   they should agree).
   Skipped with a message when ROSS does not import.

5. Step control (``step_rows``): ``run_simulation`` on paper cases with the automatic
   step (``steps_per_period = "auto"``, step_tolerance 1e-3 C) beside the fixed T/200 with
   its one-halving check (the default ``step_check_periods = 20``), both as the paper
   cases run (2000 periods, 100 Poincare periods, no Lyapunov run), interleaved; the
   target is at most 3x. Cases: Figure 23 (C/R = 0.728 %) at Omega~ 1.025 and 1.075, and
   the paper rotor at U = 144.02 g mm, Omega~ 1.055 (inside the jump region).

``--quick``: 20 periods, ``n_short`` = 1, scipy at rtol 1e-3 only (not matched), no ROSS;
the step-control pair over 300 periods, one case.
Run: ``python -m benchmarks --only timedomain``.
"""

from __future__ import annotations

import json
import math
import os
import time

import numpy as np

from benchmarks.common import ROSS_DIR, W1, Row, median_time, paper_config, paper_system, run_python

SPEED_RATIO = 0.8
RTOLS = (1e-2, 3e-3, 1e-3, 3e-4, 1e-4, 3e-5, 1e-5, 1e-6, 1e-7)


def paper_inputs():
    from rotorsfd.analyses.simulate import time_domain_inputs

    system = paper_system()
    return system, time_domain_inputs(system, SPEED_RATIO * W1)


def ours(inp, spp: int, periods: int, q0, v0, record_dofs=None, **kw):
    from rotorsfd.timedomain import integrate

    return integrate(inp.M, inp.D, inp.K, inp.nl_dofs, inp.kernel, inp.params, inp.forcing,
                     steps_per_period=spp, n_periods=periods, q0=q0, v0=v0,
                     record_dofs=record_dofs, **kw)


def amplitudes(q: np.ndarray) -> np.ndarray:
    """Last-period amplitudes from columns (y_sfd, z_sfd, y_disk)."""
    return np.array([np.max(np.hypot(q[:, 0], q[:, 1])), 0.5 * np.ptp(q[:, 2])])


def scipy_run(inp, method: str, rtol: float, periods: int, q0, v0, t_eval):
    """``solve_ivp`` of the first-order form with the analytic Jacobian (same kernel)."""
    from scipy.integrate import solve_ivp

    n = inp.M.shape[0]
    nl = np.asarray(inp.nl_dofs)
    Minv = np.linalg.inv(inp.M)
    A_q, A_v = -Minv @ inp.K, -Minv @ inp.D
    fo = inp.forcing
    f0 = np.zeros(n) if fo.constant is None else np.asarray(fo.constant, float)
    fc, fs = fo.harmonics[0].cos, fo.harmonics[0].sin
    w = fo.omega
    F = np.zeros(2)
    jq, jv = np.zeros((2, 2)), np.zeros((2, 2))
    Mnl = Minv[:, nl]
    J = np.zeros((2 * n, 2 * n))
    J[:n, n:] = np.eye(n)

    def force(y):
        q = np.ascontiguousarray(y[nl])
        v = np.ascontiguousarray(y[n + nl])
        if inp.kernel(q, v, inp.params, F, jq, jv):
            raise FloatingPointError("journal contact")

    def rhs(t: float, y: np.ndarray) -> np.ndarray:
        force(y)
        g = Minv @ (f0 + fc * math.cos(w * t) + fs * math.sin(w * t)) + Mnl @ F
        return np.concatenate([y[n:], A_q @ y[:n] + A_v @ y[n:] + g])

    def jac(t: float, y: np.ndarray) -> np.ndarray:
        force(y)
        J[n:, :n] = A_q
        J[n:, n:] = A_v
        J[n:, nl] += Mnl @ jq
        J[n:, n + nl] += Mnl @ jv
        return J

    C = 1.27e-4
    scale = np.concatenate([np.full(n, C), np.full(n, C * w)])
    t0 = time.perf_counter()
    sol = solve_ivp(rhs, (0.0, periods * fo.period), np.concatenate([q0, v0]),
                    method=method, rtol=rtol, atol=rtol * scale, jac=jac, t_eval=t_eval)
    return sol, time.perf_counter() - t0


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    from rotorsfd.analyses.simulate import displaced_state

    system, inp = paper_inputs()
    n = inp.M.shape[0]
    P = 20 if quick else 2000
    n_short = 1 if quick else 20
    q0 = displaced_state(n, 1e-6)
    disk = system.rotor.dof_index(system.unbalances[0].node, "y")
    rec = [int(inp.nl_dofs[0]), int(inp.nl_dofs[1]), disk]
    ours(inp, 200, 1, q0, 0.0)  # compiled / cache loaded
    t_ours, _, r = median_time(lambda: ours(inp, 200, P, q0, 0.0), repeat)
    case = (f"paper rotor {n} DOF, Omega~={SPEED_RATIO}, {P} periods x 200 steps")
    rows = [Row("timedomain", case, "ours: compiled Newmark", t_ours, ratio=1.0, ref="ours",
                repeat=repeat, note=f"Newton {r.newton_iterations_mean:.2f} it/step",
                extra={"elapsed_loop_s": r.elapsed})]

    rows.append(reduced_row(inp, P, q0, rec, r, t_ours, repeat, case))

    # accuracy from the end state
    qs, vs = r.q_final.copy(), r.v_final.copy()
    T = inp.forcing.period
    ref = ours(inp, 4000, n_short, qs, vs, record_dofs=rec,
               record_start=(n_short - 1) * 4000)
    amp_ref = amplitudes(ref.q)
    mine = ours(inp, 200, n_short, qs, vs, record_dofs=rec, record_start=(n_short - 1) * 200)
    err_ours = float(np.max(np.abs(amplitudes(mine.q) - amp_ref) / amp_ref))
    rows[0].note += f"; amplitude error {err_ours:.1e} (vs 4000 steps/period)"
    rows[0].extra["amplitude_error"] = err_ours
    t_eval = np.linspace((n_short - 1) * T, n_short * T, 401)
    for method in ("LSODA", "Radau"):
        found = None
        for rtol in (1e-3,) if quick else RTOLS:  # quick: one rtol (smoke only)
            try:
                sol, wall = scipy_run(inp, method, rtol, n_short, qs, vs, t_eval)
            except FloatingPointError:
                continue
            if not sol.success:
                continue
            err = float(np.max(np.abs(amplitudes(sol.y[rec].T) - amp_ref) / amp_ref))
            if err <= err_ours or quick:
                found = (rtol, err, wall, sol)
                break
        if found is None:
            rows.append(Row("timedomain", case, f"scipy {method}", float("nan"),
                            note=f"no rtol down to {RTOLS[-1]:g} reached error {err_ours:.1e}"))
            continue
        rtol, err, wall, sol = found
        est = wall * P / n_short
        rows.append(Row("timedomain", case, f"scipy {method} (extrapolated)", est,
                        ratio=est / t_ours, ref="ours",
                        note=(f"rtol {rtol:g}, error {err:.1e}; {wall:.2f} s for {n_short} "
                              f"periods x {P // n_short} ({sol.nfev} f, {sol.njev} jac)"),
                        extra={"rtol": rtol, "error": err, "short_periods": n_short,
                               "short_wall_s": wall}))
    rows += ross_rows(system, inp, quick, repeat)
    return rows


def reduced_row(inp, P: int, q0, rec: list[int], full, t_full: float, repeat: int,
                case: str) -> Row:
    """The reduced step (``reduction = "auto"``, cutoff 40 Omega) as ``rotorsfd simulate``
    runs it (``with_reduction`` + ``integrate_periods``, timed together), beside the full
    step; the last period's SFD orbit against the full run's, in C."""
    from rotorsfd.analyses.td_integration import integrate_periods, with_reduction

    def reduced():
        t = time.perf_counter()
        ri = with_reduction(inp)
        t_red = time.perf_counter() - t
        return ri, t_red, integrate_periods(
            ri, q0, 0.0, steps_per_period=200, periods=P, record_dofs=rec, record_periods=1,
            poincare_periods=min(100, P))

    reduced()  # first call (numba dispatch of the reduced sizes)
    t_red, _, (ri, t_reduce, tr) = median_time(reduced, repeat)
    red = ri.reduction
    C = 1.27e-4
    diff = float(np.max(np.abs(tr.q[:, :2] - full.q[-tr.q.shape[0]:, :2]))) / C
    amp = float(np.max(np.hypot(tr.q[:, 0], tr.q[:, 1]))) / C
    return Row("timedomain", case, "ours: reduced step (Craig-Bampton, cutoff 40 Omega)",
               t_red, ratio=t_red / t_full, ref="ours", repeat=repeat,
               note=(f"{red.n_dof} of {inp.n_dof} coordinates ({red.n_modes} modes up to "
                     f"{red.model.omegas.max() / inp.speed:.1f} Omega, {red.n_residuals} "
                     f"load residuals), reduction {t_reduce * 1e3:.1f} ms; last period's SFD "
                     f"orbit {diff:.1e} C from the full step's (radius {amp:.3f} C)"),
               extra={"reduced_dof": red.n_dof, "modes": red.n_modes,
                      "reduce_s": t_reduce, "difference_C": diff})


# ---- step control: "auto" beside the fixed T/200 ------------------------------------------

STEP_CASES = (("fig23 (C/R 0.728 %), Omega~ 1.025", "paper/fig23_time_domain.toml", 1.025, ()),
              ("fig23 (C/R 0.728 %), Omega~ 1.075", "paper/fig23_time_domain.toml", 1.075, ()),
              ("paper rotor, U = 144.02 g mm, Omega~ 1.055", "paper_rotor.toml", 1.055,
               ("unbalance[0].magnitude=144.02 g*mm",)))


def step_rows(quick: bool = False, repeat: int = 2) -> list[Row]:
    """Wall time of ``run_simulation`` with ``"auto"`` over the fixed T/200 (item 5)."""
    from benchmarks.common import ROOT, interleaved
    from rotorsfd import api
    from rotorsfd.analyses.simulate import run_simulation

    rows: list[Row] = []
    periods = 300 if quick else 2000
    for label, path, ratio, extra in STEP_CASES[:1] if quick else STEP_CASES:
        cfg = {k: api.load_config(ROOT / "examples" / path, [
            *extra, f"analysis.simulate.steps_per_period={v}",
            f"analysis.simulate.periods={periods}"]) for k, v in (("fixed", 200),
                                                                  ("auto", '"auto"'))}
        for c in cfg.values():  # compile / load the caches once
            run_simulation(c, speed_ratio=ratio, periods=40, poincare_periods=10,
                           lyapunov_periods=0, progress=False)
        res = interleaved({k: (lambda c=c, x=ratio: run_simulation(
            c, speed_ratio=x, lyapunov_periods=0, progress=False))
            for k, c in cfg.items()}, repeat)
        t_fix, _, r_fix = res["fixed"]
        t_auto, _, r_auto = res["auto"]
        case = f"{label}, {periods} periods (simulate, no Lyapunov)"
        fx, au = r_fix.step_check, r_auto.step_check
        rows.append(Row("timedomain", case, "fixed T/200 + one-halving check", t_fix,
                        ratio=1.0, ref="fixed", repeat=repeat,
                        note=(f"{r_fix.motion_name}; halving moves the orbit "
                              f"{fx.error:.2g} C"),
                        extra={"step_error": fx.error, "motion": r_fix.motion_name}))
        ladder = ", ".join(f"{c.difference:.2g}" for c in au.checks)
        rows.append(Row("timedomain", case, 'auto step (tolerance 1e-3 C)', t_auto,
                        ratio=t_auto / t_fix, ref="fixed", repeat=repeat,
                        note=(f"{r_auto.motion_name}; accepted T/{au.steps_per_period}, "
                              f"change per halving {ladder} C"),
                        extra={"steps_per_period": au.steps_per_period,
                               "step_error": au.error, "motion": r_auto.motion_name}))
    return rows


# ---- ROSS: the linear rotor -------------------------------------------------------------

ROSS_CODE = r"""
import json, sys, time, warnings
warnings.filterwarnings("ignore")
t0 = time.perf_counter()
import numpy as np
import ross as rs
t_import = time.perf_counter() - t0
p = json.loads(%r)
mat = rs.Material(name="steel", rho=p["rho"], E=p["E"], G_s=p["G"])
L = p["length"] / p["n_el"]
shaft = [rs.ShaftElement(L=L, idl=2 * p["ri"], odl=2 * p["ro"], material=mat,
                         shear_effects=True, rotary_inertia=True, gyroscopic=True)
         for _ in range(p["n_el"])]
disk = rs.DiskElement.from_geometry(n=p["disk_node"], material=mat, width=p["width"],
                                    i_d=2 * p["d_ri"], o_d=2 * p["d_ro"])
brg = [rs.BearingElement(n=0, kxx=p["k_left"], cxx=0.0),
       rs.BearingElement(n=p["n_el"], kxx=p["k_right"], cxx=0.0)]
rotor = rs.Rotor(shaft, [disk], brg)
w, spp = p["speed"], p["spp"]
T = 2 * np.pi / w
nd = rotor.number_dof


def response(n_steps):
    t = np.arange(n_steps + 1) * T / spp
    F = np.zeros((t.size, rotor.ndof))
    F[:, nd * p["disk_node"] + 0] = p["f"] * np.cos(w * t)
    F[:, nd * p["disk_node"] + 1] = p["f"] * np.sin(w * t)
    t0 = time.perf_counter()
    res = rotor.run_time_response(w, F, t, method="newmark")
    return time.perf_counter() - t0, res


first, _ = response(5)  # first call (compilation, caches)
walls = {}
for n in (p["steps"] // 2, p["steps"]):
    walls[n], res = response(n)
y = res.yout[:, nd * p["disk_node"] + 0]
(na, ta), (nb, tb) = walls.items()
slope = (tb - ta) / (nb - na)
print(json.dumps({"import_s": t_import, "first_s": first, "wall_s": tb, "ndof": rotor.ndof,
                  "per_step_s": slope, "overhead_s": ta - slope * na,
                  "y_disk": y.tolist(), "version": rs.__version__}))
"""


def ross_skipped(case: str, why: str) -> list[Row]:
    print(f"   skipped ROSS: {why}")
    return [Row("timedomain", case, "ROSS Newmark", float("nan"), note=f"skipped: {why}")]


def ross_env() -> dict[str, str]:
    path = [str(ROSS_DIR), os.environ.get("PYTHONPATH", "")]
    return {"PYTHONPATH": os.pathsep.join(p for p in path if p)}


def ross_rows(system, inp, quick: bool, repeat: int) -> list[Row]:
    case = "LINEAR paper rotor (film off), unbalance from rest, 200 steps/period"
    if quick:
        return ross_skipped(case, "not in --quick (importing ROSS alone takes 5-15 s)")
    if not ROSS_DIR.exists():
        return ross_skipped(case, f"ROSS not installed in {ROSS_DIR} (see benchmarks/README.md)")
    from rotorsfd.timedomain import Forcing

    cfg = paper_config()
    sh, dk = cfg.rotor.shaft[0], cfg.rotor.disks[0]
    mat = cfg.materials[sh.material]
    u = system.unbalances[0]
    w = SPEED_RATIO * W1
    P_ross = 10
    P = 20 if quick else 2000
    Fc, Fs = system.unbalance_harmonics(w)
    f = float(np.hypot(Fc, Fs).max())
    p = {"rho": mat.density, "E": mat.young_modulus, "G": mat.shear_modulus,
         "length": sh.length, "n_el": sh.n_elements, "ri": sh.inner_radius,
         "ro": sh.outer_radius, "disk_node": dk.node - 1, "width": dk.thickness,
         "d_ri": dk.inner_radius, "d_ro": dk.outer_radius,
         "k_left": cfg.elements["sfd"].centring_stiffness,
         "k_right": cfg.rotor.supports[0].stiffness,
         "speed": w, "spp": 200, "steps": round(200 * P_ross), "f": f}
    walls, steps, out = [], [], {}
    for _ in range(max(1, repeat)):
        try:
            out = run_python(ROSS_CODE % json.dumps(p), env=ross_env(), timeout=1800)
        except (RuntimeError, OSError, ValueError) as exc:  # ROSS absent or broken
            return ross_skipped(case, f"ROSS failed in a subprocess: {str(exc)[-300:]}")
        walls.append(out["wall_s"])
        steps.append(out["per_step_s"])
    # per-step cost from two lengths (n/2 and n steps), plus the per-call overhead
    t_ross = float(np.median(steps)) * 200 * P + max(0.0, out["overhead_s"])
    # ours on the same linear rotor (no film), same forcing, from rest
    lin = Forcing(omega=w, harmonics=inp.forcing.harmonics)
    disk = system.rotor.dof_index(u.node, "y")

    def run_lin(periods: float):
        from rotorsfd.timedomain import integrate

        return integrate(inp.M, inp.D, inp.K, [], None, None, lin, steps_per_period=200,
                         n_periods=periods, record_dofs=[disk])

    run_lin(1)
    t_lin, _, _ = median_time(lambda: run_lin(P), repeat)
    short = run_lin(P_ross)
    y_ours = short.q[:, 0]
    y_ross = np.asarray(out["y_disk"])
    m = min(y_ours.size, y_ross.size)
    diff = float(np.max(np.abs(y_ours[:m] - y_ross[:m])) / np.max(np.abs(y_ours[:m])))
    return [
        Row("timedomain", case + f", {P} periods", "ours: compiled Newmark (linear)", t_lin,
            ratio=1.0, ref="ours", repeat=repeat),
        Row("timedomain", case + f", {P} periods",
            f"ROSS {out['version']} Newmark (extrapolated)", t_ross, ratio=t_ross / t_lin,
            ref="ours", repeat=repeat,
            note=(f"{P_ross:g} periods in {np.median(walls):.2f} s; per step "
                  f"{np.median(steps) * 1e3:.2f} ms (slope from {P_ross / 2:g} and "
                  f"{P_ross:g} periods) x "
                  f"{200 * P} steps; first call {out['first_s']:.1f} s; "
                  f"{out['ndof']} DOF (6/node); max|y_ours - y_ROSS|/max|y| = {diff:.1e} "
                  f"over {P_ross:g} periods; import {out['import_s']:.1f} s"),
            extra={"periods_run": P_ross, "wall_s": walls, "per_step_s": steps,
                   "overhead_s": out["overhead_s"], "first_s": out["first_s"],
                   "rel_diff_disk_y": diff}),
    ]


if __name__ == "__main__":
    import sys

    from benchmarks.__main__ import main

    sys.exit(main(["--only", "timedomain", *sys.argv[1:]]))
