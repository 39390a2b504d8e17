"""Every located bifurcation checked before it is reported.

A bifurcation located on an HB branch with H harmonics and M Floquet intervals per period
may be an artefact of either truncation: a fold pair of a truncated orbit that the
converged orbit does not have, a multiplier that crosses +1 only because the monodromy
is under-resolved. Each one is re-located on a short piece of the branch recomputed with
``H_c`` harmonics (default :func:`~rotorsfd.harmonic.truncation.check_harmonics`: about
1.5 H) and ``factor x M`` intervals (the converged M of the step control where it ran)
on the branch's Craig-Bampton model (``StabilityOptions.basis_intervals``: the modes of
the branch's M, so only H and the step are refined, and a larger M does not bring in
more, lightly damped, modes):

1. the piece starts ``window`` computed points before the bracket of the bifurcation
   (its HB solution padded with zeros and Newton-corrected at H_c) and follows the
   branch in the same direction for the arc length of the bracket plus ``window`` points
   after it, past turning points; bifurcations whose windows overlap (a fold pair) are
   checked on one piece spanning both windows, computed once;
2. a turning point (saddle-node) is located on it by the HB equations alone (the
   multipliers are computed once, at the re-located fold, where one must be +1); any
   other bifurcation from the stability of the piece, computed as for the whole branch
   (:func:`~rotorsfd.stability.branch_stability.branch_stability`);
3. the bifurcation of the same type nearest in the parameter is the re-located one. The
   original is *confirmed* when it exists and moved by at most ``rtol`` (relative);
   otherwise *unconfirmed* (vanished, or moved beyond rtol: the difference is reported).

A branch point (``pitchfork``, ``transcritical`` or untyped ``branch-point``: a multiplier
through +1 without a turn of the branch) is matched by a branch point or a saddle-node of
the check: if the converged branch turns there, the
original was a fold displaced by the truncation.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from rotorsfd.continuation.branch import Branch, BranchPoint
from rotorsfd.continuation.folds import locate_branch_fold
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.truncation import check_harmonics
from rotorsfd.stability.bifurcations import Bifurcation
from rotorsfd.stability.branch_result import BRANCH_POINT_KINDS
from rotorsfd.stability.branch_stability import (
    FOLD_MULTIPLIER_TOL,
    BranchStability,
    FloquetEvaluator,
    StabilityOptions,
    branch_stability,
    reported_kind,
)


@dataclass(frozen=True)
class CheckOptions:
    """How bifurcations are checked (module docstring). ``harmonics``: H_c (None: about
    1.5 H at the bifurcation); ``interval_factor``: M multiplied by it; ``rtol``: relative
    parameter shift allowed; ``window``: computed points either side of the bracket."""

    harmonics: int | None = None
    interval_factor: int = 2
    rtol: float = 1e-3
    window: int = 3


@dataclass(frozen=True)
class BifurcationCheck:
    """The outcome of one check: ``confirmed``; ``lam`` the re-located parameter (None if
    the bifurcation vanished), ``shift`` ``|lam - lam_0| / |lam_0|`` (None likewise), the
    ``H`` and ``n_intervals`` of the check, a one-line ``message``, and ``checked``
    (False: the check itself failed, so nothing is known)."""

    confirmed: bool
    lam: float | None
    shift: float | None
    H: int
    n_intervals: int
    message: str
    checked: bool = True

    @property
    def status(self) -> str:
        return "confirmed" if self.confirmed else "unconfirmed"

    @property
    def vanished(self) -> bool:
        """The bifurcation does not exist at the check's H and M (a truncation artefact)."""
        return self.checked and self.lam is None


#: Points of a check's piece of branch (its step is at least its length over this).
MAX_POINTS = 60
#: Step limiter of the check's continuation (the nonlinear element's validity measure, e.g.
#: the SFD eccentricity ratio): short of contact, where the force is unbounded.
LIMIT_MAX = 0.99
#: Arc-length tolerance (relative to the bracket) of a turning point located on the
#: check's piece: lam(s) is stationary there, so the located lam is exact to about
#: ``curvature x (FOLD_RTOL x bracket)^2``, far below the check's rtol (1e-10, the
#: default of ``locate_branch_fold``, cost two to three more HB re-solves per fold).
FOLD_RTOL = 1e-6


def _matches(kind: str, other: str) -> bool:
    if kind in BRANCH_POINT_KINDS:
        return other in (*BRANCH_POINT_KINDS, "saddle-node")
    return other == kind


def _window(branch: Branch, ia: int, ib: int, window: int) -> tuple[int, int]:
    """The computed points (j0, j1) a check's piece of branch spans around the bracket
    ia..ib: ``window`` points either side, widened to start and end outside the
    bracket's neighbourhood by its width in lam, so the piece holds the bifurcation even
    where the higher H moves it."""
    n = branch.n_points
    j0, j1 = max(0, ia - window), min(n - 1, ib + window)
    near = branch.lam[max(0, ia - 1): min(n, ib + 2)]
    lo, hi = float(near.min()), float(near.max())
    margin = max(hi - lo, 1e-6 * abs(hi))
    while j0 > 0 and lo - margin <= branch.lam[j0] <= hi + margin:
        j0 -= 1
    while j1 < n - 1 and lo - margin <= branch.lam[j1] <= hi + margin:
        j1 += 1
    return j0, j1


def _local_branch(branch: Branch, problem: PeriodicProblem, j0: int, j1: int, H_c: int
                  ) -> Branch:
    """The piece of ``branch`` from its point j0 past its point j1 recomputed with H_c
    harmonics."""
    n = branch.n_points
    s = branch.s if branch.s.size == n else np.arange(n, dtype=float)
    length = 1.5 * float(s[j1] - s[j0])
    direction = np.sign(branch.dlam_ds[j0]) or np.sign(branch.lam[j1] - branch.lam[j0]) or 1
    span = float(np.ptp(branch.lam)) or abs(float(branch.lam[j0])) or 1.0
    lam0 = float(branch.lam[j0])

    def stop(point: BranchPoint) -> bool:
        return point.s >= length

    # steps of half the smallest step of the window, and a tight angle cap: a narrower
    # fold pair than the original one is not stepped over
    steps = branch.ds[j0 + 1: j1 + 1]
    steps = steps[steps > 0]
    ds = float(np.clip(0.5 * steps.min(), 1e-6, 0.02)) if steps.size else 0.005
    ds = max(ds, length / MAX_POINTS)       # bounded work, even where the branch crawled
    return continue_periodic(problem, lam0, lam0 + direction * 10.0 * span, H_c,
                             branch.X[j0], lam_scale=branch.lam_scale, ds=ds, ds_min=1e-8,
                             ds_max=ds, max_angle_deg=5.0,
                             max_points=2 * MAX_POINTS, harmonics_tol=None,
                             limit_max=LIMIT_MAX, callback=stop,
                             start_tangent=branch.tangents[j0])


class _Piece:
    """One recomputed piece of branch shared by the checks whose windows overlap (a fold
    pair is checked on one piece): the piece, its located turning points and its
    stability, each computed once, when first asked for (or the error that stopped it)."""

    def __init__(self, branch: Branch, problem: PeriodicProblem, j0: int, j1: int,
                 H_c: int) -> None:
        self.branch, self.problem, self.j0, self.j1, self.H_c = branch, problem, j0, j1, H_c
        self._local: Branch | Exception | None = None
        self._folds: list[BranchPoint] | None = None
        self._stability: dict[StabilityOptions, BranchStability] = {}

    def local(self) -> Branch:
        if self._local is None:
            try:
                local = _local_branch(self.branch, self.problem, self.j0, self.j1, self.H_c)
                if local.n_points < 2:
                    raise ConvergenceError(f"the piece of branch has {local.n_points} point")
                self._local = local
            except (ConvergenceError, ArithmeticError, ValueError) as exc:
                self._local = exc
        if isinstance(self._local, Exception):
            raise self._local
        return self._local

    def folds(self) -> list[BranchPoint]:
        """The turning points of the piece, located on the HB equations alone."""
        if self._folds is None:
            local = self.local()
            self._folds = [locate_branch_fold(local, int(i), rtol=FOLD_RTOL)
                           for i in local.folds()]
        return self._folds

    def stability(self, options: StabilityOptions) -> BranchStability:
        """The stability of the piece with these options."""
        if options not in self._stability:
            self._stability[options] = branch_stability(self.local(), self.problem, options)
        return self._stability[options]


def check_bifurcations(branch: Branch, problem: PeriodicProblem, stability: BranchStability,
                       options: StabilityOptions, check: CheckOptions | None = None
                       ) -> list[BifurcationCheck]:
    """One :class:`BifurcationCheck` per located bifurcation of ``stability`` (a
    :func:`~rotorsfd.stability.branch_stability.branch_stability` of ``branch``), in its
    order (module docstring)."""
    c = check or CheckOptions()
    Hs = branch.info.get("harmonics")
    out = []
    pieces: list[_Piece] = []
    for b in stability.bifurcations:
        ia, ib = b.info.get("bracket", (0, branch.n_points - 1))
        H_b = int(max(Hs[ia], Hs[ib])) if Hs is not None and len(Hs) == branch.n_points \
            else int(branch.H)
        H_c = c.harmonics or check_harmonics(H_b)
        M_b = int(max(stability.n_intervals[ia], stability.n_intervals[ib])) \
            if stability.n_intervals is not None else options.n_intervals
        M_c = min(c.interval_factor * M_b, max(options.max_intervals, options.n_intervals))
        opts = dataclasses.replace(options, n_intervals=M_c,
                                   basis_intervals=options.basis_intervals
                                   or options.n_intervals,
                                   max_intervals=max(options.max_intervals, M_c),
                                   n_harmonics=None if options.n_harmonics is None
                                   else max(options.n_harmonics, H_c),
                                   outside=False)     # not reported from the check
        j0, j1 = _window(branch, ia, ib, c.window)
        piece = next((p for p in pieces if p.H_c == H_c and p.j0 <= j1 and j0 <= p.j1),
                     None)
        if piece is None:
            piece = _Piece(branch, problem, j0, j1, H_c)
            pieces.append(piece)
        else:   # overlapping windows: one piece spanning both (computed below, once)
            piece.j0, piece.j1 = min(piece.j0, j0), max(piece.j1, j1)
        out.append((b, piece, opts))
    return [_check_one(b, piece, opts, c) for b, piece, opts in out]


def checks_as_configured(branch: Branch, problem: PeriodicProblem,
                         stability: BranchStability, options: StabilityOptions
                         ) -> list[BifurcationCheck] | None:
    """:func:`check_bifurcations` of ``stability``'s located bifurcations when
    ``options.check`` asks for it (``check_rtol`` the tolerance), else None: the check
    ``rotorsfd response`` reports and ``bifurcation-curves`` starts its curves from."""
    if not (options.check and stability.bifurcations):
        return None
    return check_bifurcations(branch, problem, stability, options,
                              CheckOptions(rtol=options.check_rtol))


def _check_one(b: Bifurcation, piece: _Piece, opts: StabilityOptions, c: CheckOptions
               ) -> BifurcationCheck:
    H_c, M_c = piece.H_c, opts.n_intervals
    kind = reported_kind(b)
    where = f"{kind} at lam = {b.lam:.9g}"
    turning = kind == "saddle-node" and b.via == "tangent"
    try:
        if turning:   # a turning point is located on the HB equations alone
            found = piece.folds()
            lams = [p.lam for p in found]
        else:
            lams = [x.lam for x in piece.stability(opts).bifurcations
                    if _matches(kind, reported_kind(x))]
    except (ConvergenceError, ArithmeticError, ValueError) as exc:
        return BifurcationCheck(False, None, None, H_c, M_c,
                                f"{where}: not checked at H = {H_c}, M = {M_c} (the check "
                                f"failed: {' '.join(str(exc).split())})", checked=False)
    if not lams:
        return BifurcationCheck(False, None, None, H_c, M_c,
                                f"{where} unconfirmed: it vanishes at H = {H_c}, M = {M_c} "
                                "(a truncation artefact: raise H or use harmonics = 'auto')")
    k = int(np.argmin([abs(x - b.lam) for x in lams]))
    lam_c = float(lams[k])
    shift = abs(lam_c - b.lam) / max(abs(b.lam), np.finfo(float).tiny)
    ok = shift <= c.rtol
    text = (f"{where} {'confirmed' if ok else 'unconfirmed'}: at H = {H_c}, M = {M_c} it is "
            f"at lam = {lam_c:.9g} ({shift:.1e} relative)")
    if not ok:
        text += f", more than {c.rtol:g}: not converged, raise H and the intervals"
    if turning:   # the exchange of stability there: one multiplier at +1, at M_c fixed
        try:
            mu = FloquetEvaluator(piece.problem, dataclasses.replace(opts, interval_tol=None))(
                lam_c, found[k].X).multipliers
            d = float(np.min(np.abs(mu - 1.0))) if mu.size else np.inf
            text += f"; the multiplier nearest +1 there is {d:.1e} from it"
            if d > FOLD_MULTIPLIER_TOL:
                text += " (the stability next to this fold is not resolved)"
        except (ConvergenceError, ArithmeticError, ValueError):
            pass
    return BifurcationCheck(ok, lam_c, float(shift), H_c, M_c, text)
