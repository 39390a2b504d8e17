"""The isola diagnosis of Figure 23 / Table 3: a coexisting attractor of the
C/R = 0.728 % case, the branch through it and the time domain on and down it."""

from __future__ import annotations

from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.paper.case_config import paper_stability
from rotorsfd.paper.cases import Case
from rotorsfd.paper.numbers import response_numbers, td_data, td_numbers


def run_isola(case: Case, config: Any, out: Path | None,
           plots: bool = False) -> tuple[dict, dict]:
    """A coexisting attractor and its isola (Figure 23 / Table 3 diagnosis):
    (a) the time domain at ``find_steps`` steps per period (the paper's T/200) from the HB
    orbit shifted by ``hb_phase`` of the period, which at that step lands near a second
    attractor; (b) the branch through that orbit (``harmonics``; HB-corrected, so it
    does not depend on the step of (a)), continued until it closes, with its
    bifurcations; (c) the time domain at the config's step started on the isola's HB
    orbit at the case's speed: the second attractor at a converged step, and how far the
    HB orbit is from it; (d) the time domain at ``speeds``, each from the previous run's
    final state, at the config's step; (e) the same at ``find_steps`` from (a) at
    ``paper_speeds`` (what the paper's step shows); (d) and (e) with the Lyapunov
    exponent (``lyapunov_periods``)."""
    # deferred: these (loads numba, scipy, pydantic)
    from rotorsfd.analyses.response import run_response
    from rotorsfd.analyses.simulate import SavedState, hb_state, run_simulation
    from rotorsfd.harmonic.periodic import solve_periodic

    # deferred: io.config, model (loads scipy, pydantic)
    from rotorsfd.io.config import with_values
    from rotorsfd.model import dofs

    o = case.options
    H = int(o.get("harmonics", 16))
    n_ly = int(o.get("lyapunov_periods", 200))
    coarse = int(o.get("find_steps", 200))
    cfg = with_values(config, {"analysis.response.harmonics": H})
    a = run_simulation(cfg, progress=False, from_hb=True, hb_phase=float(o["hb_phase"]),
                       steps_per_period=coarse, lyapunov_periods=0)
    if out is not None:
        a.write(out / "a-find", plots=False)
    n: dict[str, Any] = {"find_motion": a.motion_name, **td_numbers(a, "find_")}
    iso = run_response(cfg, from_orbit=a, progress=False,
                       stability_options=paper_stability(cfg))
    if out is not None:
        iso.write(out / "b-isola", plots=False)
    num, data = response_numbers(iso)
    ref = iso.reference_speed
    rows = sorted(data["bifurcations"], key=lambda b: b["speed_ratio"])
    lam = iso.branch.lam / ref
    folds = sorted(float(lam[i]) for i in iso.branch.folds())
    sh = [b for b in rows if b["type"] == "secondary-hopf"]
    n.update({"iso_closed": iso.info.get("closed"), "iso_orbit_difference":
              iso.info.get("orbit_difference"), "bifurcations": num["bifurcations"],
              "success": iso.success, "end": iso.message,
              "iso_fold_lo": folds[0] if folds else None,
              "iso_fold_hi": folds[-1] if folds else None,
              "iso_range": [float(lam.min()), float(lam.max())],
              "iso_pd": [b["speed_ratio"] for b in rows if b["type"] == "period-doubling"]})
    if sh:
        n["iso_sh"] = sh[0]["speed_ratio"]
        n["iso_sh_mu"] = [sh[0]["multiplier_re"], sh[0]["multiplier_im"]]
    if iso.stable is not None:
        st = lam[iso.stable]
        n["iso_stable"] = [float(st.min()), float(st.max())] if st.size else None
    # (c) on the isola's HB orbit at the case's speed (nearest stable point, re-solved)
    speed = a.speed
    pick = np.flatnonzero(iso.stable) if iso.stable is not None and iso.stable.any() \
        else np.arange(lam.size)
    k = int(pick[np.argmin(np.abs(iso.branch.lam[pick] - speed))])
    X = solve_periodic(iso.system.periodic_problem(), speed, H, iso.branch.X[k]).X
    q0, v0 = hb_state(X, speed)
    b = run_simulation(cfg, progress=False, q0=q0, v0=v0, lyapunov_periods=0)
    if out is not None:
        b.write(out / "c-second-attractor", plots=False)
    n.update({"second_motion": b.motion_name, **td_numbers(b, "second_")})
    j = b.column(b.element_node)
    w = np.exp(1j * np.outer(b.t[-int(b.settings["steps_per_period"]):] * speed,
                             np.arange(X.shape[0])))
    hb = np.stack([(w @ X[:, dofs.dof_index(b.element_node, d)]).real for d in ("y", "z")], -1)
    n["second_hb_difference"] = float(np.max(np.hypot(*(
        hb - b.q[-hb.shape[0]:, j, :]).T)) / b.clearance)
    runs, t200 = [], []
    for seq, start, steps, speeds, ly in (
            (runs, b, None, o.get("speeds", ()), n_ly),
            (t200, a, coarse, o.get("paper_speeds", ()), n_ly)):
        state: Any = start
        for s_ in speeds:
            saved = SavedState(state.q_final, state.v_final, state.t_final, state.speed)
            r = run_simulation(config, speed_ratio=float(s_), progress=False,
                               initial_state=saved, steps_per_period=steps,
                               lyapunov_periods=ly)
            tag = f"{s_:g}" if steps is None else f"{s_:g}_T{steps}"
            if out is not None:
                r.write(out / f"d-{tag}", plots=False)
            n[f"motion_{tag}"] = r.motion_name
            n[f"n_distinct_{tag}"] = (r.motion.evidence.get("n_distinct_poincare")
                                      if r.motion is not None else None)
            if ly:
                n[f"lyapunov_{tag}"] = r.lyapunov.per_period if r.lyapunov else None
            n.update(td_numbers(r, f"td_{tag}_"))
            seq.append(td_data(r))
            state = r
    data.update(second=td_data(b), find=td_data(a), runs=runs, runs_t200=t200)
    return n, data


