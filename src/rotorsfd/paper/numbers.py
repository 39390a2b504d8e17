"""The numbers and plot data of a case's results: what the report compares with the paper
and the figures draw (plain floats, lists and arrays; the results themselves are not
kept).
"""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np

#: A disk peak stands out from the troughs on both sides by this fraction of the largest
#: value (2 %: Figure 15's second peak at 9 rad/s, Omega~ 1.392, rises 3 % of the main
#: peak above its trough, plainly a local maximum in the figure; the earlier 5 % missed it,
#: and a smooth branch has no wiggles at that level).
PEAK_PROMINENCE = 0.02


def local_peaks(x: np.ndarray, y: np.ndarray, rel: float = PEAK_PROMINENCE) -> list[float]:
    """x of the local maxima of y(x) along the branch (arc order) that stand out by ``rel``
    of the largest value from the lowest point on both sides up to a higher value."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    out = []
    top = float(np.max(y)) if y.size else 0.0
    for i in range(1, y.size - 1):
        if y[i] >= y[i - 1] and y[i] > y[i + 1]:
            left = y[:i][::-1]
            right = y[i + 1:]
            lmin = min(left[: np.argmax(left > y[i])].min(initial=y[i]) if np.any(left > y[i])
                       else left.min(), y[i])
            rmin = min(right[: np.argmax(right > y[i])].min(initial=y[i])
                       if np.any(right > y[i]) else right.min(), y[i])
            if y[i] - max(lmin, rmin) > rel * top:
                out.append(float(x[i]))
    return out


def wave(X: np.ndarray, n: int = 256) -> np.ndarray:
    """y(theta) on n phases from coefficients X_k (k = 0..H)."""
    k = np.arange(X.shape[-1])
    th = 2 * np.pi * np.arange(n + 1) / n
    return (X @ np.exp(1j * np.outer(k, th))).real


def response_numbers(result: Any, orbits: Sequence[float] = ()) -> tuple[dict, dict]:
    """Numbers and plot data of a :class:`~rotorsfd.analyses.response.ResponseResult`."""
    # deferred: model (loads scipy)
    from rotorsfd.model import dofs

    table = result.table()
    s = np.asarray(table["speed_ratio"], float)
    C = result.clearance
    rows = [{k: (float(v) if isinstance(v, (int, float, np.number))
                 and not isinstance(v, bool) else v) for k, v in b.items()}
            for b in (result.bifurcations or [])]
    sn = sorted((b for b in rows if b["type"] == "saddle-node"), key=lambda b: b["speed_ratio"])
    n: dict[str, Any] = {"bifurcations": [(b["type"], b["speed_ratio"], b["max_multiplier"],
                                           b["multiplier_re"], b["multiplier_im"])
                                          for b in rows],
                         "success": result.success, "n_points": int(s.size),
                         "H": int(result.branch.H)}
    if sn:
        n.update(sn_hi=sn[-1]["speed_ratio"], sn_hi_mu=sn[-1]["max_multiplier"],
                 sn_lo=sn[0]["speed_ratio"], sn_lo_mu=sn[0]["max_multiplier"])
    if len(sn) >= 2:
        n["width"] = sn[-1]["speed_ratio"] - sn[0]["speed_ratio"]
    ecc = np.asarray(table[f"defl_{result.system.primary_node}"], float)
    n["ended"] = getattr(result, "ended", "range" if result.success else "failed")
    n["end"] = (f"reached Omega~ = {s[-1]:.4f}" if result.success else
                f"ended at Omega~ = {s[-1]:.4f} where the journal reached eps = "
                f"{ecc[-1]:.3f} (the film's limit, max_eccentricity)" if n["ended"] == "limit"
                else f"stopped at Omega~ = {s[-1]:.4f}, eps = {ecc[-1]:.3f}")
    n["message"] = result.message
    sfd = result.system.primary_node
    d1 = np.asarray(table[f"defl_{sfd}"])
    i = int(np.argmax(d1))
    n["peak_ratio"], n["peak_defl"] = float(s[i]), float(d1[i])
    h = [np.asarray(table[f"amp_{sfd}_y_h{k}"])[i] for k in range(1, result.branch.H + 1)]
    n["dominant"] = ("1X" if h[0] > 5 * max(h[1:], default=0.0)
                     else f"mixed (h1/h2 = {h[0] / max(h[1], 1e-30):.2f})")
    disk = [d.node for d in result.system.rotor.disks]
    if disk and f"amp_{disk[0]}_y_h1" in table:
        n["disk_peaks"] = local_peaks(s, np.asarray(table[f"amp_{disk[0]}_y_h1"]))
    data: dict[str, Any] = {k: np.asarray(v) for k, v in table.items()}
    data["bifurcations"] = rows
    data["nodes"] = list(result.nodes)
    data["H"] = int(result.branch.H)
    data["clearance"] = C
    X = result.branch.X
    for node in result.nodes:
        for d in ("y", "z"):
            w = wave(X[:, :, dofs.dof_index(node, d)], 128) / C
            data[f"max_{node}_{d}"] = w.max(axis=1)
            data[f"min_{node}_{d}"] = w.min(axis=1)
    orb = []
    for target in orbits:
        j = int(np.argmin(np.abs(s - target)))
        orb.append((float(s[j]), wave(X[j, :, dofs.dof_index(sfd, "y")]) / C,
                    wave(X[j, :, dofs.dof_index(sfd, "z")]) / C))
    data["orbits"] = orb
    return n, data



def td_numbers(r: Any, prefix: str = "") -> dict[str, Any]:
    """Step, journal Poincare point (last, in C), the eccentricity there and the orbit's
    maximum, and the step check of a SimulationResult (keys ``prefix + ...``)."""
    j = r.column(r.element_node if r.element_node in r.nodes else r.plot_node)
    scale = r.clearance or 1.0
    y, z = (float(r.poincare_q[-1, j, k] / scale) for k in (0, 1))
    chk = r.step_check.as_dict() if r.step_check is not None else {}
    return {prefix + k: v for k, v in {
        "steps_per_period": int(r.settings["steps_per_period"]), "poincare_y": y,
        "poincare_z": z, "eps_poincare": float(np.hypot(y, z)),
        "eps_max": r.max_eccentricity, "step_check": chk.get("difference")}.items()}


def td_data(r: Any, keep_periods: int = 20) -> dict[str, Any]:
    """Orbit, phase and Poincare arrays of a SimulationResult at its journal, in C."""
    c = r.column(r.plot_node)
    scale = r.clearance or 1.0
    keep = keep_periods * int(r.settings["steps_per_period"])
    return {"y": r.q[-keep:, c, 0] / scale, "z": r.q[-keep:, c, 1] / scale,
            "vy": r.v[-keep:, c, 0] / (scale * r.speed),
            "py": r.poincare_q[:, c, 0] / scale, "pz": r.poincare_q[:, c, 1] / scale,
            "pvy": r.poincare_v[:, c, 0] / (scale * r.speed),
            "speed_ratio": r.speed_ratio, "motion": r.motion_name,
            "steps": int(r.settings["steps_per_period"])}



def turning_points(result: Any) -> list[float]:
    """Omega~ of the turning points of a response branch (``dlam/ds = 0``, located on the
    HB equations alone, relative 1e-6 of the bracket in s, as the response's stability
    locates its tangent saddle-nodes), in increasing order."""
    # deferred: continuation.folds (loads scipy)
    from rotorsfd.continuation.folds import locate_branch_fold

    b = result.branch
    return sorted(locate_branch_fold(b, int(i), rtol=1e-6).lam / result.reference_speed
                  for i in b.folds())


