"""The stability of every point of a branch and its located bifurcations, as computed by
:func:`~rotorsfd.stability.branch_stability.branch_stability`, and how each bifurcation
is reported.

What is reported (``Bifurcation`` records and the rows of ``bifurcations.csv``):
the located parameter (``lam``, ``speed_rad_s``, ``speed_ratio``) and, as in the paper's
Tables 1 and 3, ``max_multiplier``, ``multiplier_re``, ``multiplier_im`` of the critical
multiplier at the *computed branch point nearest to the bifurcation on its unstable side*
(|mu| > 1; like the paper's 1.0048, this value depends on the continuation step). The
critical multiplier evaluated exactly at the located point (``located_re``,
``located_im``: +1, -1 or on the unit circle up to the method's error) is reported too.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.stability.bifurcations import Bifurcation


@dataclass
class BranchStability:
    """Stability of every point of a branch and its located bifurcations.

    Attributes
    ----------
    lam, frequency : (n_points,) parameter and fundamental frequency w [rad/s].
    stable : (n_points,) bool, ``|mu|max <= 1 + tol``.
    max_multiplier : (n_points,) ``|mu|max``.
    critical : (n_points,) complex, the multiplier of largest modulus.
    multipliers : (n_points, n_max) complex, each row sorted by decreasing ``|mu|``; only
        the first ``n_multipliers[i]`` entries of row i are multipliers, the rest is 0
        (the reduced model's size may change with the period).
    n_multipliers : (n_points,) int, the count of multipliers of each row.
    liouville_error : (n_points,) ``|sum log|mu| - log det Phi|`` (NaN-free; 0 if n/a).
    bifurcations : located :class:`~rotorsfd.stability.bifurcations.Bifurcation` records,
        in branch order; ``info`` holds ``point`` (nearest computed point on the unstable
        side), ``reported`` (its critical multiplier) and ``bracket`` (the two points).
    method, tol, elapsed (total seconds), elapsed_points (seconds for the points only),
    n_bases (reduction bases computed), messages (bifurcations that could not be located).
    basis : what ``max_multiplier`` covers (``StabilityOptions.basis_label``).
    max_multiplier_outside : (n_points,) ``max |exp(lambda_j T)|`` of the structural modes
        above the reduced basis' cut-off, from the averaged model
        (:mod:`rotorsfd.stability.outside`; 0 for the full basis; None when not computed,
        ``StabilityOptions(outside=False)``); n_modes : (n_points,)
        the fixed-interface modes kept (the interior DOFs for the full basis).
    """

    lam: NDArray[np.float64]
    frequency: NDArray[np.float64]
    stable: NDArray[np.bool_]
    max_multiplier: NDArray[np.float64]
    critical: NDArray[np.complex128]
    multipliers: NDArray[np.complex128]
    n_multipliers: NDArray[np.int64]
    liouville_error: NDArray[np.float64]
    bifurcations: list[Bifurcation]
    method: str
    tol: float
    elapsed: float = 0.0
    elapsed_points: float = 0.0
    n_bases: int = 0
    messages: list[str] = field(default_factory=list)
    n_intervals: NDArray[np.int64] | None = None
    multiplier_error: NDArray[np.float64] | None = None
    checks: list[Any] = field(default_factory=list)
    basis: str = ""
    max_multiplier_outside: NDArray[np.float64] | None = None
    n_modes: NDArray[np.int64] | None = None

    @property
    def n_points(self) -> int:
        return int(self.lam.size)

    def rows(self, reference_speed: float = 1.0,
             speed: Callable[[float], float] | None = None) -> list[dict[str, Any]]:
        """Bifurcation rows (the columns of ``bifurcations.csv``, module docstring):
        ``type`` (:func:`reported_kind`), ``speed_rad_s`` (``speed(lam)``, default lam),
        ``speed_ratio``, ``parameter`` (lam); the critical multiplier at the located point
        (``located_multiplier_re/_im/_abs``: +1, -1 or on the unit circle up to the
        method's error); at the nearest computed point on the unstable side
        (``nearest_point``, its critical multiplier ``nearest_multiplier_re/_im/_abs``,
        the paper's Tables 1 and 3 value) and that point's largest modulus
        ``nearest_max_multiplier``; the check (``status``: confirmed, unconfirmed or not
        checked; ``check_parameter``, ``check_speed_ratio``, ``check_shift``: "" when the
        bifurcation vanished; ``check_harmonics``, ``check_intervals``). The keys
        ``max_multiplier``, ``multiplier_re``, ``multiplier_im`` (= nearest_multiplier_*),
        ``located_re``, ``located_im`` and ``point`` are kept for scripts."""
        out = []
        checks = self.checks if len(self.checks) == len(self.bifurcations) else \
            [None] * len(self.bifurcations)
        for b, chk in zip(self.bifurcations, checks, strict=True):
            sp = float(speed(b.lam)) if speed is not None else float(b.lam)
            rep = complex(b.info.get("reported", b.critical))
            j = int(b.info.get("point", -1))
            rep_im = abs(rep.imag) if b.kind == "secondary-hopf" else rep.imag
            crit = located_critical(b)
            loc_im = abs(crit.imag) if b.kind == "secondary-hopf" else crit.imag
            row: dict[str, Any] = {
                "type": reported_kind(b), "speed_rad_s": sp, "speed_ratio":
                sp / reference_speed, "parameter": float(b.lam),
                "located_multiplier_re": float(crit.real),
                "located_multiplier_im": float(loc_im),
                "located_multiplier_abs": float(abs(crit)),
                "nearest_point": j, "nearest_multiplier_re": rep.real,
                "nearest_multiplier_im": rep_im, "nearest_multiplier_abs": abs(rep),
                "nearest_max_multiplier": float(self.max_multiplier[j])
                if 0 <= j < self.n_points else abs(rep),
                "max_multiplier": abs(rep), "multiplier_re": rep.real,
                "multiplier_im": rep_im, "located_re": crit.real,
                "located_im": crit.imag, "point": j}
            if chk is None:
                row.update(status="not checked", check_parameter="", check_speed_ratio="",
                           check_shift="", check_harmonics=0, check_intervals=0)
            else:
                cs = (float(speed(chk.lam)) if speed is not None else chk.lam) \
                    if chk.lam is not None else None
                row.update(status=chk.status,
                           check_parameter="" if chk.lam is None else chk.lam,
                           check_speed_ratio="" if cs is None else cs / reference_speed,
                           check_shift="" if chk.shift is None else chk.shift,
                           check_harmonics=chk.H, check_intervals=chk.n_intervals)
            out.append(row)
        return out

    def summary(self) -> str:
        """One line per bifurcation and the count of unstable points."""
        lines = [f"stability ({self.method}): {int(np.sum(~self.stable))} of "
                 f"{self.n_points} points unstable, {self.elapsed:.2f} s"]
        for b in self.bifurcations:
            rep = complex(b.info.get("reported", b.critical))
            crit = located_critical(b)
            lines.append(f"{reported_kind(b)} at lam = {b.lam:.9g}: critical multiplier "
                         f"{crit.real:.5f}{crit.imag:+.5f}i at the located "
                         f"point, {rep.real:.5f}{rep.imag:+.5f}i (|mu| {abs(rep):.5f}) at "
                         "the nearest computed point on the unstable side")
        lines.extend(self.messages)
        lines.extend(c.message for c in self.checks)
        return "\n".join(lines)


def located_critical(b: Bifurcation) -> complex:
    """The critical multiplier at the located point: ``b.critical``, or where it has none
    of its crossing type (a turning point of a truncated orbit whose multipliers near +1
    are a complex pair), the multiplier nearest +1 (saddle-node), -1 (period doubling) or
    the unit circle (secondary Hopf)."""
    c = complex(b.critical)
    if np.isfinite(c.real) and np.isfinite(c.imag):
        return c
    mu = np.asarray(b.multipliers, dtype=complex)
    if not mu.size:
        return complex(0.0)
    target = {"saddle-node": np.abs(mu - 1.0), "period-doubling": np.abs(mu + 1.0)}.get(
        b.kind, np.abs(np.abs(mu) - 1.0))
    return complex(mu[int(np.argmin(target))])


#: What a +1 crossing without a turn is reported as: typed on the HB equations
#: (:mod:`~rotorsfd.stability.branch_typing`), or untyped.
BRANCH_POINT_KINDS = ("pitchfork", "transcritical", "branch-point")


def reported_kind(b: Bifurcation) -> str:
    """The type a located bifurcation is reported as: for a real multiplier through +1
    where the branch does not turn (located by the multiplier, not merged with a turning
    point) or a sign change of the bordered HB determinant there, ``pitchfork``
    (symmetry-breaking) or ``transcritical`` as typed on the HB equations, else
    ``branch-point`` (untyped: no branch point of the HB equations next to it, a
    truncation artefact); otherwise its crossing type."""
    if (b.kind == "saddle-node" and b.via in ("multiplier", "determinant")
            and not b.info.get("merged")):
        return str(b.info.get("branch_type") or "branch-point")
    return str(b.kind)

