"""Our numbers beside the paper's: :func:`comparison_rows` turns the claims of
:mod:`rotorsfd.paper.claims` and the case outcomes into :class:`Row` records (quantity,
paper, ours, difference, verdict) for each reading.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np

from rotorsfd.paper.cases import CAL, Outcome, literal_name
from rotorsfd.paper.claims import CLAIMS, Claim

SHORT = {"saddle-node": "SN", "secondary-hopf": "SH", "period-doubling": "PD"}


@dataclass(frozen=True)
class Row:
    """One line of the comparison table: the paper's value, ours in the literal reading
    (``ours``, ``difference``, ``verdict``) and in the calibrated one (``calibrated``,
    ``cal_difference``, ``cal_verdict``; "not run" when the calibrated case did not run).
    A verdict is ``fitted`` where the reading's fit used this number (not a prediction)."""

    section: str
    quantity: str
    paper: str
    ours: str
    difference: str
    verdict: str          # agrees, close, differs, ours only, fitted, not run
    note: str = ""
    calibrated: str = "not run"
    cal_difference: str = ""
    cal_verdict: str = "not run"


def _fmt(x: Any) -> str:
    if x is None:
        return "none"
    if isinstance(x, float):
        return "none" if math.isnan(x) else f"{x:.5g}"
    return str(x)


def _bifs(rows: Sequence[Sequence[Any]]) -> str:
    if not rows:
        return "none"
    return "; ".join(f"{SHORT.get(t, t)} {s:.4f} (|mu| {m:.4f})" for t, s, m, *_ in rows)


def _numeric(claim: Claim, ours: float) -> tuple[str, str]:
    p = float(claim.paper)  # type: ignore[arg-type]
    d = ours - p
    rel = d / p if p else float("inf")
    band = claim.band
    verdict = "ours only" if band is None else ("agrees" if abs(rel) <= band else "differs")
    return f"{d:+.4g} ({100 * rel:+.2f} %)", verdict


def _value(claim: Claim, outcomes: Mapping[str, Outcome]) -> tuple[str, str, str]:
    """(ours, difference, verdict) of a claim."""
    o = outcomes.get(claim.case)
    if o is None:
        return "not run", "", "not run"
    if o.status == "error" or not o.numbers:
        return f"{o.status}: {o.message[:120]}", "", "differs"
    n = o.numbers
    key, _, ref = claim.key.partition(":")
    other = outcomes.get(ref)
    if key == "bifurcations":
        ours = _bifs(n["bifurcations"])
        if not n.get("success", True):
            ours += f" [{n['end']}]"
        types = [b[0] for b in n["bifurcations"]]
        want = str(claim.paper)
        if claim.paper is None:
            return ours, "", "ours only"
        if want.startswith("none"):
            ok = not types
        elif "pair" in want:
            ok = types.count("saddle-node") >= 2
        else:
            ok = "saddle-node" in types
        return ours, "same" if ok else "differs qualitatively", "agrees" if ok else "differs"
    if key == "tab3":
        return _table3(claim, n)
    if key == "disk_peaks":
        peaks = n.get("disk_peaks", [])
        ours = ", ".join(f"{p:.3f}" for p in peaks) or "no peak"
        if isinstance(claim.paper, float):
            if not peaks:
                return ours, "no peak", "differs"
            if "second peak" in claim.quantity:       # the second peak, not the nearest
                if len(peaks) < 2:
                    end = "" if n.get("success", True) else f"; {n['end']}"
                    return ours + end, "no second peak", "differs"
                peaks = peaks[1:2]
            best = min(peaks, key=lambda p: abs(p - claim.paper))
            if abs(best - claim.paper) > 0.05:
                end = "" if n.get("success", True) else f"; {n['end']}"
                return ours + end, "no peak near", "differs"
            diff, verdict = _numeric(claim, best)
            return ours, diff, verdict
        ok = len(peaks) >= 2
        return ours, "same" if ok else "one peak only", "agrees" if ok else "differs"
    if key == "peak_shift_vs" and other and other.numbers:
        d = n["peak_ratio"] - other.numbers["peak_ratio"]
        word = "lower" if d < 0 else "higher" if d > 0 else "same"
        return (f"peak at {n['peak_ratio']:.4f} vs {other.numbers['peak_ratio']:.4f} ({word})",
                f"{d:+.4f}", "agrees" if word == claim.paper else "differs")
    if key == "same_as" and other and other.data and o.data:
        a, b = o.data, other.data
        x = np.linspace(max(a["speed_ratio"].min(), b["speed_ratio"].min()),
                        min(a["speed_ratio"].max(), b["speed_ratio"].max()), 200)
        diff = np.max(np.abs(np.interp(x, a["speed_ratio"], a["defl_1"])
                             - np.interp(x, b["speed_ratio"], b["defl_1"])))
        return (f"max |r~ yaw - r~ pitch| = {diff:.1e}", f"{diff:.1e}",
                "agrees" if diff < 1e-3 else "differs")
    if key == "fold_shift" and other and other.numbers:
        m = other.numbers
        if "sn_hi" not in n or "sn_hi" not in m:
            return _bifs(n["bifurcations"]), "", "ours only"
        return (f"SN {n['sn_hi']:.5f} / {n['sn_lo']:.5f}",
                f"{n['sn_hi'] - m['sn_hi']:+.5f} / {n['sn_lo'] - m['sn_lo']:+.5f}", "ours only")
    if key.startswith("poincare"):          # poincare[_<prefix>]: a journal position
        p = key.removeprefix("poincare")[1:]
        if n.get(p + "poincare_y") is None:
            return "none", "", "ours only"
        ours = (f"({n[p + 'poincare_y']:+.4f}, {n[p + 'poincare_z']:+.4f}) C at T/"
                f"{n[p + 'steps_per_period']}; eps there {n[p + 'eps_poincare']:.4f}, max "
                f"over the orbit {n[p + 'eps_max']:.4f}")
        if n.get(p + "step_check") is not None:
            ours += f"; halving the step moves the orbit {n[p + 'step_check']:.2g} C"
        return ours, "", "ours only"
    if key == "motion" or key.startswith("motion_"):
        alias = {"motion_second": "second_motion", "motion_find": "find_motion"}
        ours = str(n.get(alias.get(key, key)))
        ly = n.get("lyapunov_" + key.removeprefix("motion_"))
        if ly is not None:
            ours += f" (Lyapunov {ly:+.2g}/period)"
        if claim.paper is None:
            return ours, "", "ours only"
        want = str(claim.paper).split(" ")[0]
        ok = ours.startswith(want)
        return ours, "same" if ok else "differs qualitatively", "agrees" if ok else "differs"
    if key == "end_rate":
        v = n.get("end_rate")
        if v is None:
            return "bistable to the end of the range", "", "differs"
        if isinstance(claim.paper, float):
            d = v - claim.paper
            # the paper has no fold pair from its rate claim.paper on (a grid of 1-2 rad/s
            # steps): ours agrees if the cusp lies in the grid step below it; a cusp above
            # it means our model is still bistable at the paper's rate
            ok = claim.paper - 2.0 < v <= claim.paper
            return f"{v:.4f}", f"{d:+.3f} rad/s", "agrees" if ok else "differs"
        return f"{v:.4f}", "", "ours only"
    v = n.get(key)
    if v is None:
        why = n.get(f"{key}_why") or n.get("end")
        extra = f" [{why}]" if why else ""
        return "none" + extra, "no such point", "differs" if claim.paper is not None else ""
    if isinstance(claim.paper, float) and isinstance(v, (int, float)):
        diff, verdict = _numeric(claim, float(v))
        if isinstance(claim.paper, float) and claim.band is None and "mu" in key:
            verdict = "close" if abs(v - claim.paper) < 0.02 else "differs"
        return _fmt(float(v)), diff, verdict
    if isinstance(claim.paper, str):
        if claim.paper == "small" and isinstance(v, float):
            return f"{v:.4f}", "", "agrees" if 0 < v < 0.02 else "differs"
        if claim.paper == "none" and isinstance(v, float):   # an unstable width
            return (f"{v:.3g}", "same" if v == 0 else "a fold pair remains",
                    "agrees" if v == 0 else "differs")
        ok = str(v) == claim.paper
        return _fmt(v), "same" if ok else "differs", "agrees" if ok else "differs"
    return _fmt(v), "", "ours only"


def _table3(claim: Claim, n: Mapping[str, Any]) -> tuple[str, str, str]:
    """Nearest bifurcation of our branch to a Table 3 point."""
    target = float(claim.paper)  # type: ignore[arg-type]
    rows = n.get("bifurcations", [])
    if not rows:
        return "none", "no bifurcation", "differs"
    t, s, m, re, im = min(rows, key=lambda b: abs(b[1] - target))
    ours = f"{SHORT.get(t, t)} {s:.4f} (|mu| {m:.4f}" + (
        f", {re:.4f} {'+' if im >= 0 else '-'} {abs(im):.4f}i)" if abs(im) > 1e-9 else ")")
    want = "SH" if "Hopf" in claim.quantity else "SN"
    d = s - target
    ok = SHORT.get(t, t) == want and abs(d) <= 5e-3 * target
    return ours, f"{d:+.4f} (nearest)", "agrees" if ok else "differs"


def readings(outcomes: Mapping[str, Outcome]) -> dict[str, dict[str, Outcome]]:
    """The outcomes of each reading by their literal case names: ``literal`` (the cases
    without prefix) and ``calibrated`` (the ``cal-*`` cases, prefix removed)."""
    return {"literal": {k: o for k, o in outcomes.items() if not k.startswith(CAL)},
            "calibrated": {literal_name(k): o for k, o in outcomes.items()
                           if k.startswith(CAL)}}


def _judged(claim: Claim, reading: str, outcomes: Mapping[str, Outcome]
            ) -> tuple[str, str, str]:
    """(ours, difference, verdict) of a claim in one reading; ``fitted`` for the numbers
    the reading's fit used (they agree by construction: not a prediction)."""
    if claim.case not in outcomes:
        return "not run", "", "not run"
    ours, diff, verdict = _value(claim, outcomes)
    if reading in claim.fitted and verdict in ("agrees", "close", "ours only"):
        verdict = "fitted"
    return ours, diff, verdict


def comparison_rows(outcomes: Mapping[str, Outcome],
                    claims: Sequence[Claim] = CLAIMS) -> list[Row]:
    """A row per claim whose case ran in either reading (:func:`readings`)."""
    by = readings(outcomes)
    rows = []
    for c in claims:
        if c.case not in by["literal"] and c.case not in by["calibrated"]:
            continue
        ours, diff, verdict = _judged(c, "literal", by["literal"])
        cal, cdiff, cverdict = _judged(c, "calibrated", by["calibrated"])
        paper = "-" if c.paper is None else _fmt(c.paper)
        rows.append(Row(c.section, c.quantity, paper, ours, diff, verdict, c.note,
                        cal, cdiff, cverdict))
    return rows
