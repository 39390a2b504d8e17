"""Floquet stability of every point of a branch of periodic solutions, and its bifurcations
located and classified (paper section 3.2, Tables 1 and 3).

Per point: the multipliers of the perturbation equation along the HB orbit (paper eq. 30)
by :mod:`rotorsfd.stability` (default ``'newmark-cb'``: Newmark, N = 400, on a
Craig-Bampton model that keeps the nonlinear DOFs and the fixed-interface modes with
``omega h <= 1/4``). The reduction basis depends on M and K only, so it is computed once
per branch and again only when K (or M) changes along it (base-rate continuation); D
(gyroscopic, base Coriolis) is projected at every point, ``D_r = Psi^T D Psi``.

Bifurcations, detected between consecutive points by the test functions of
:mod:`rotorsfd.stability.bifurcations` and located along the arc length (``Branch.point_at``)
to a relative parameter tolerance ``rtol`` (default 1e-6):

* saddle-node: a real multiplier through +1 and/or a sign change of dlam/ds. When the
  branch turns, the located point is the turning point ``dlam/ds = 0`` (exact for the
  HB equations; the Newmark multiplier there is ``1 + O(1e-4)``, its discretisation
  error); without a turn (a symmetry-breaking branch point) the multiplier through +1.
  A multiplier crossing +1 within ``fold_merge_rtol`` (1e-3) of a turning point is that
  fold: for a truncated HB orbit they differ by the truncation error (paper rotor under
  pitching, U = 144.02 g mm: 2.6e-4 at H = 3, < 1e-5 at H = 8); the gap is reported.
  So is a crossing farther away when no multiplier crosses +1 across the nearest turning
  point (and no other turn lies between): the isola of the C/R = 0.728 % case has, at
  H = 16 and N = 400, its only +1 crossing at Omega~ 1.0904 and |mu| = 1.037 at the turn
  1.0939; at H = 24, N = 1600 the crossing is in the turning interval.
* period-doubling: a real multiplier through -1 (``det(Phi + I)`` changes sign).
* secondary-hopf: a complex pair leaves the unit circle (``|mu|^2 - 1`` of the pair).

What is reported (``Bifurcation`` records and the rows of ``bifurcations.csv``):
the located parameter (``lam``, ``speed_rad_s``, ``speed_ratio``) and, as in the paper's
Tables 1 and 3, ``max_multiplier``, ``multiplier_re``, ``multiplier_im`` of the critical
multiplier at the *computed branch point nearest to the bifurcation on its unstable side*
(|mu| > 1; like the paper's 1.0048, this value depends on the continuation step). The
critical multiplier evaluated exactly at the located point (``located_re``,
``located_im``: +1, -1 or on the unit circle up to the method's error) is reported too.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.branch import Branch
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.bifurcations import (
    IMAG_TOL,
    Bifurcation,
    Bracket,
    BranchSample,
    critical_value,
    crossing_signs,
    detect,
    find_bifurcations,
    locate,
)
from rotorsfd.stability.floquet import STABILITY_TOL, FloquetResult
from rotorsfd.stability.hill import fourier_coefficients, hill_floquet
from rotorsfd.stability.monodromy import floquet_multipliers
from rotorsfd.stability.orbit import orbit_floquet, orbit_samples
from rotorsfd.stability.reduction import ReducedModel

#: At a turning point of the exact orbit a multiplier is exactly +1; a located one farther
#: from +1 than this says the orbit or the monodromy is not converged there.
FOLD_MULTIPLIER_TOL = 1e-3

METHODS = ("newmark-cb", "newmark", "generalized-alpha", "generalized-alpha-cb", "hill",
           "hill-koopman")
_REDUCED = ("newmark-cb", "generalized-alpha-cb", "hill", "hill-koopman")


@dataclass(frozen=True)
class StabilityOptions:
    """How the multipliers are computed and bifurcations located.

    ``method`` one of :data:`METHODS`; ``n_intervals`` Newmark intervals per period
    (paper: 400); ``n_harmonics`` Hill truncation (default: the orbit's H, at least 8;
    Hill's exponents need at least the harmonics of the orbit: with fewer, on the paper
    rotor near journal contact, a period doubling came out as spurious saddle-nodes);
    ``n_modes`` / ``omega_max`` the kept
    fixed-interface modes (default ``omega_max = M_b / (4 T)`` at each point, ``M_b`` =
    ``basis_intervals``, default ``n_intervals``: the bifurcation check refines the step
    on the branch's reduced model);
    ``interval_tol`` (Newmark methods): step control of the monodromy, see
    :class:`FloquetEvaluator` (None: ``n_intervals`` fixed); ``min_intervals`` /
    ``max_intervals`` its bounds;
    ``check``: re-locate every bifurcation at more harmonics and intervals
    (:mod:`rotorsfd.stability.bifurcation_check`, run by the response analysis), confirmed
    within ``check_rtol`` (relative);
    ``tol`` unstable when ``|mu|max > 1 + tol``; ``rtol`` relative parameter tolerance of
    located bifurcations (``locate=False``: linear interpolation between points);
    ``fold_merge_rtol``: a multiplier crossing +1 within this relative distance of a
    turning point is that fold (the gap, HB truncation, is reported in ``messages``); so
    is one farther away from a turning point across which no multiplier crosses +1.
    """

    method: str = "newmark-cb"
    n_intervals: int = 400
    n_harmonics: int | None = None
    n_modes: int | None = None
    omega_max: float | None = None
    rho_inf: float = 0.6
    tol: float = STABILITY_TOL
    rtol: float = 1e-6
    locate: bool = True
    fold_merge_rtol: float = 1e-3
    interval_tol: float | None = None
    max_intervals: int = 12800
    min_intervals: int = 100
    basis_intervals: int | None = None
    check: bool = False
    check_rtol: float = 1e-3

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise ConfigError("analysis.stability.method", self.method,
                              f"one of {', '.join(METHODS)}")
        if self.interval_tol is not None and not self.interval_tol > 0:
            raise ConfigError("analysis.stability.interval_tolerance", self.interval_tol,
                              "must be > 0")


class _Basis:
    """Craig-Bampton pieces for one (M, K): constraint modes and all fixed-interface modes;
    the modes kept at a point are selected by ``omega_max``/``n_modes`` there."""

    def __init__(self, M: NDArray, K: NDArray, nl: NDArray) -> None:
        import scipy.linalg as sla

        n = M.shape[0]
        self.M, self.K, self.nl = M.copy(), K.copy(), nl
        i = np.setdiff1d(np.arange(n), nl)
        self.i = i
        try:
            self.phi_c = -np.linalg.solve(K[np.ix_(i, i)], K[np.ix_(i, nl)])
        except np.linalg.LinAlgError as exc:
            raise ConfigError("K", "singular interior stiffness", "interior restrained once "
                              "the nonlinear DOFs are fixed") from exc
        Ks = 0.5 * (K[np.ix_(i, i)] + K[np.ix_(i, i)].T)
        Ms = 0.5 * (M[np.ix_(i, i)] + M[np.ix_(i, i)].T)
        w2, self.modes = sla.eigh(Ks, Ms)
        self.omegas = np.sqrt(np.clip(w2, 0.0, None))
        self._models: dict[int, tuple[NDArray, NDArray, NDArray]] = {}

    def matches(self, M: NDArray, K: NDArray) -> bool:
        return ((M is self.M or np.array_equal(M, self.M))
                and (K is self.K or np.array_equal(K, self.K)))

    def reduce(self, D: NDArray, n_modes: int | None, omega_max: float | None
               ) -> ReducedModel:
        keep = np.ones(self.omegas.size, bool)
        if omega_max is not None:
            keep &= self.omegas <= omega_max
        if n_modes is not None:
            keep &= np.arange(self.omegas.size) < n_modes
        k = int(keep.sum())  # modes are sorted: the kept set is the first k
        if k not in self._models:
            m, n = self.nl.size, self.M.shape[0]
            psi = np.zeros((n, m + k))
            psi[self.nl, :m] = np.eye(m)
            psi[np.ix_(self.i, np.arange(m))] = self.phi_c
            psi[np.ix_(self.i, np.arange(m, m + k))] = self.modes[:, :k]
            self._models[k] = (psi, psi.T @ self.M @ psi, psi.T @ self.K @ psi)
        psi, Mr, Kr = self._models[k]
        return ReducedModel(Mr, psi.T @ D @ psi, Kr, psi, np.arange(self.nl.size),
                            self.omegas[:k])


#: The step control starts the next point at M/2 when the error estimate at M is below
#: this fraction of the tolerance: the scheme is second order, so the estimate at M/2 is
#: about 4x, a quarter of the tolerance. (1/8 saves 16-28 % of the monodromy work on the
#: convergence cases, multipliers within 5e-5, but moves the weak secondary Hopf of the
#: U = 360.04 g mm case, |mu| - 1 <= 3.4e-4, from Omega~ 1.2881 to 1.2885.)
HALVE_FRACTION = 1 / 16

#: Multipliers compared by the step control: the largest ones (the critical multipliers
#: of every crossing type lie among them wherever a bifurcation is near).
N_COMPARED = 4


def multiplier_change(a: NDArray, b: NDArray, k: int = N_COMPARED) -> float:
    """Largest change of the moduli of the k largest-modulus multipliers between two
    computations of one spectrum (sorted by modulus): what decides stability and locates
    the crossings. Phases are not compared: an undamped structural mode has ``|mu| = 1``
    at any step (the trapezoidal rule conserves its energy) while its phase error grows
    with the step, irrelevant to stability."""
    a, b = np.sort(np.abs(np.asarray(a, complex)))[::-1], np.sort(np.abs(np.asarray(
        b, complex)))[::-1]
    j = min(k, a.size, b.size)
    return float(np.max(np.abs(a[:j] - b[:j]))) if j else 0.0


class FloquetEvaluator:
    """Multipliers of HB solutions of one problem, reusing the reduction basis while M
    and K stay the same. ``evaluator(lam, X) -> FloquetResult``; ``n_bases`` counts the
    bases computed.

    Step control (``options.interval_tol``, Newmark methods): the monodromy is computed
    at M and M/2 intervals; the scheme is second order, so the error of the M result is
    about ``|mu(M) - mu(M/2)| / 3`` (:func:`multiplier_change` over the largest
    multipliers). Above the tolerance M is doubled (M/2 becomes the old M) until it is met
    or ``max_intervals`` is reached; the M that met it starts the next point, halved when
    the estimate is below :data:`HALVE_FRACTION` of the tolerance (the halved M then
    meets it with a margin of 4). The
    result's ``info`` holds ``n_intervals`` and ``multiplier_error``. The Craig-Bampton
    basis stays the one of ``options.basis_intervals`` or ``n_intervals`` (modes with
    ``omega <= M_b / (4 T)``): the control refines the step on one reduced model."""

    def __init__(self, problem: PeriodicProblem, options: StabilityOptions | None = None
                 ) -> None:
        self.problem = problem
        self.options = options or StabilityOptions()
        self.nl = np.asarray(problem.nl_dofs, dtype=np.intp)
        self._basis: _Basis | None = None
        self.n_bases = 0
        self.n_intervals = int(self.options.n_intervals)

    @property
    def step_controlled(self) -> bool:
        o = self.options
        return o.interval_tol is not None and not o.method.startswith("hill")

    def reduced(self, lam: float, period: float) -> ReducedModel:
        """Craig-Bampton model at lam (modes with ``omega <= M_b / (4 T)``, ``M_b`` the
        options' ``basis_intervals`` or ``n_intervals``, unless ``n_modes``/``omega_max``
        are given)."""
        o = self.options
        M, D, K = self.problem.matrices(lam)
        if self._basis is None or not self._basis.matches(M, K):
            self._basis = _Basis(np.asarray(M, float), np.asarray(K, float), self.nl)
            self.n_bases += 1
        om = o.omega_max
        if o.n_modes is None and om is None:
            om = 0.25 * (o.basis_intervals or o.n_intervals) / period
        return self._basis.reduce(np.asarray(D, float), o.n_modes, om)

    def __call__(self, lam: float, X: NDArray) -> FloquetResult:
        if not self.step_controlled:
            res = self.at(lam, X, self.options.n_intervals)
            res.info.setdefault("n_intervals", self.options.n_intervals)
            return res
        o = self.options
        tol, M = float(o.interval_tol), self.n_intervals
        if o.method in _REDUCED:   # one reduced model and one sampling for M and M/2
            run = self._stepper(lam, X)
            res, coarse = run(M), run(max(M // 2, 1))
        else:
            res, coarse = self.at(lam, X, M), self.at(lam, X, max(M // 2, 1))
            run = None
        err = multiplier_change(res.multipliers, coarse.multipliers) / 3.0
        while err > tol and 2 * M <= o.max_intervals:
            M *= 2
            coarse, res = res, (run(M) if run is not None else self.at(lam, X, M))
            err = multiplier_change(res.multipliers, coarse.multipliers) / 3.0
        halve = err < tol * HALVE_FRACTION and M // 2 >= o.min_intervals
        self.n_intervals = M // 2 if halve else M
        res.info.update(n_intervals=M, multiplier_error=err)
        return res

    def _stepper(self, lam: float, X: NDArray) -> Callable[[int], FloquetResult]:
        """``run(n)``: the multipliers at (lam, X) with n intervals (a reduced Newmark
        method), the reduced model built once; the orbit's Jacobian samples at n are
        reused for n/2 (every other one: the same ``t_j``)."""
        p = self.problem
        w = float(p.frequency(lam))
        T = 2 * np.pi / w
        X = np.asarray(X, dtype=complex)
        Xnl = X[:, self.nl] if X.shape[1] == p.n_dof else X
        red = self.reduced(lam, T)
        cache: dict[int, tuple[NDArray, NDArray]] = {}

        def run(n: int) -> FloquetResult:
            if n not in cache:
                if 2 * n in cache:
                    Jq, Jv = cache[2 * n]
                    cache[n] = (Jq[::2], Jv[::2])
                else:
                    cache[n] = p.nl_jacobian(*orbit_samples(Xnl, w, n))
            Jq, Jv = cache[n]
            return self._reduced_newmark(red, T, Jq, Jv, n, p.n_dof)

        return run

    def _reduced_newmark(self, red: ReducedModel, T: float, Jq: NDArray, Jv: NDArray,
                         n_intervals: int, n_dof: int) -> FloquetResult:
        o = self.options
        res = floquet_multipliers(red.M, red.D, red.K, T, nl_dofs=red.nl_dofs, dFdq=Jq,
                                  dFdv=Jv, n_intervals=n_intervals, reduction=None,
                                  scheme=o.method.removesuffix("-cb"),
                                  rho_inf=o.rho_inf, tol=o.tol)
        res.method += "-cb"
        res.info.update(n_dof_full=n_dof, n_modes=red.omegas.size)
        return res

    def at(self, lam: float, X: NDArray, n_intervals: int) -> FloquetResult:
        """Multipliers at (lam, X) with ``n_intervals`` Newmark intervals (the options'
        method; Hill ignores it)."""
        o, p = self.options, self.problem
        w = float(p.frequency(lam))
        T = 2 * np.pi / w
        X = np.asarray(X, dtype=complex)
        Xnl = X[:, self.nl] if X.shape[1] == p.n_dof else X
        if o.method not in _REDUCED:
            M, D, K = p.matrices(lam)
            return orbit_floquet(M, D, K, Xnl, w, self.nl, p.nl_jacobian, method=o.method,
                                 n_intervals=n_intervals, rho_inf=o.rho_inf, tol=o.tol)
        red = self.reduced(lam, T)    # the basis of the options' M, whatever the step
        if not o.method.startswith("hill"):
            Jq, Jv = p.nl_jacobian(*orbit_samples(Xnl, w, n_intervals))
            return self._reduced_newmark(red, T, Jq, Jv, n_intervals, p.n_dof)
        H = o.n_harmonics if o.n_harmonics is not None else max(8, X.shape[0] - 1)
        L = 2 * H
        q, v = orbit_samples(Xnl, w, 4 * (2 * L + 1), endpoint=False)
        Jq, Jv = p.nl_jacobian(q, v)
        res = hill_floquet(red.M, red.D, red.K, w, nl_dofs=red.nl_dofs,
                           dFdq_hat=fourier_coefficients(Jq, L),
                           dFdv_hat=fourier_coefficients(Jv, L), n_harmonics=H,
                           method="koopman" if o.method == "hill-koopman" else "symmetric",
                           tol=o.tol)
        res.info.update(n_dof_full=p.n_dof, n_modes=red.omegas.size)
        return res


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


def reported_kind(b: Bifurcation) -> str:
    """The type a located bifurcation is reported as: ``branch-point`` for a real
    multiplier through +1 where the branch does not turn (located by the multiplier, not
    merged with a turning point: a symmetry-breaking or transcritical branch point, or a
    truncation artefact), else its crossing type."""
    if b.kind == "saddle-node" and b.via == "multiplier" and not b.info.get("merged"):
        return "branch-point"
    return str(b.kind)


def _pad(rows: list[NDArray]) -> tuple[NDArray[np.complex128], NDArray[np.int64]]:
    counts = np.array([r.size for r in rows], dtype=np.int64)
    out = np.zeros((len(rows), int(counts.max()) if rows else 0), dtype=complex)
    for i, r in enumerate(rows):
        out[i, : r.size] = r
    return out, counts


def _merge_folds(brackets: list[Bracket], samples: list[BranchSample], rtol: float,
                 dead_band: float = STABILITY_TOL
                 ) -> tuple[list[Bracket], dict[int, Bracket]]:
    """One bracket per fold. A multiplier-only saddle-node bracket is the same fold as the
    nearest tangent (turning-point) bracket when it is next to it (within one interval:
    the method's lag), its parameter is within ``rtol`` (relative) of it, or no real
    multiplier crosses +1 across that turning point itself and no other turning point
    lies between them: at a turning point of the exact orbit a multiplier is +1, so a
    turn without a crossing and a crossing without a turn are one fold displaced by the
    numerical error (HB truncation, Floquet discretisation; isola of the C/R 0.728 % case
    at H = 16, N = 400: 3.2e-3 apart, one interval apart at H = 24, N = 1600). Returns the
    kept brackets and, by id of a kept tangent bracket, the merged multiplier one."""
    index = {id(p): i for i, p in enumerate(samples)}
    tang = [b for b in brackets if b.kind == "saddle-node" and b.via == "tangent"]
    turns = sorted(index[id(t.a)] for t in tang)

    def crossless(t: Bracket) -> bool:
        return (crossing_signs(t.a.multipliers, dead_band)["saddle-node"]
                == crossing_signs(t.b.multipliers, dead_band)["saddle-node"])

    out, merged = [], {}
    for b in brackets:
        if b.kind == "saddle-node" and b.via == "multiplier" and tang:
            i = index[id(b.a)]
            t = min(tang, key=lambda x: abs(index[id(x.a)] - i))
            it = index[id(t.a)]
            lam_b = 0.5 * (b.a.lam + b.b.lam)
            lam_t = 0.5 * (t.a.lam + t.b.lam)
            alone = not any(min(i, it) < j < max(i, it) for j in turns)
            if (abs(it - i) <= 1 or abs(lam_b - lam_t) <= rtol * abs(lam_t)
                    or (alone and crossless(t))) and id(t) not in merged:
                merged[id(t)] = b
                continue
        out.append(b)
    return out, merged


def _largest(kind: str, mu: NDArray) -> complex:
    """The multiplier of the crossing type (real > 0, real < 0, complex Im > 0) of
    largest modulus (NaN if none)."""
    mu = np.asarray(mu, dtype=complex)
    real = np.abs(mu.imag) <= IMAG_TOL * np.maximum(1.0, np.abs(mu))
    if kind == "secondary-hopf":
        c = mu[~real & (mu.imag > 0)]
    else:
        c = mu[real & ((mu.real > 0) if kind == "saddle-node" else (mu.real < 0))]
    return complex(c[np.argmax(np.abs(c))]) if c.size else complex(np.nan, np.nan)


def _reported(kind: str, samples: list[BranchSample], ia: int, ib: int, tol: float,
              s_star: float) -> tuple[int, complex]:
    """The computed point nearest to the bifurcation (arc length s*) with a multiplier of
    the crossing type outside the unit circle (|mu| > 1 + tol): its index and that
    multiplier; if there is none, the nearer bracket end."""
    order = sorted(range(len(samples)), key=lambda j: abs(samples[j].s - s_star))
    for j in order:
        c = _largest(kind, samples[j].multipliers)
        if np.isfinite(c) and abs(c) > 1.0 + tol:
            return j, c
    j = ia if abs(samples[ia].s - s_star) <= abs(samples[ib].s - s_star) else ib
    return j, _largest(kind, samples[j].multipliers)


def _floquet_crossing(fold: Bifurcation, bracket: Bracket, solve_at: Callable,
                      o: StabilityOptions, messages: list[str]) -> None:
    """Locate the multiplier crossing merged into ``fold``; store it in
    ``fold.info['floquet_lam']`` and say how far it is from the HB turning point when that
    exceeds ``rtol`` (an estimate of the HB truncation error: raise H)."""
    try:
        c = locate(bracket, solve_at, rtol=o.rtol)
    except (ConvergenceError, ArithmeticError, ValueError):
        return
    fold.info["floquet_lam"] = c.lam
    gap = abs(c.lam - fold.lam) / abs(fold.lam)
    if gap > 10 * o.rtol:
        messages.append(f"saddle-node at lam = {fold.lam:.9g} (turning point): a multiplier "
                        f"crosses +1 at lam = {c.lam:.9g}, {gap:.1e} (relative) away; the "
                        "gap measures the HB truncation and Floquet discretisation error: "
                        "raise H and the Floquet intervals to shrink it")


def _hill_resolution(results: list[FloquetResult]) -> list[str]:
    """A message when Hill's largest multiplier is not resolved by the truncation (its
    ladder defect, :func:`rotorsfd.stability.hill.ladder_defect`, above ``LADDER_TOL``) at
    some points: its value and crossing type are then unreliable."""
    from rotorsfd.stability.hill import LADDER_TOL

    d = np.array([r.info.get("critical_defect", 0.0) for r in results], dtype=float)
    bad = ~(d <= LADDER_TOL)
    if not results or not bad.any():
        return []
    H = results[0].info.get("n_harmonics")
    return [f"hill (H = {H}): the largest multiplier is not resolved by the truncation at "
            f"{int(bad.sum())} of {len(results)} points (ladder defect up to "
            f"{np.nanmax(np.where(bad, d, np.nan)):.1e} > {LADDER_TOL:g}): its value and "
            "crossing type are unreliable there; raise n_harmonics or use newmark-cb"]


def branch_stability(branch: Branch, problem: PeriodicProblem,
                     options: StabilityOptions | None = None, *,
                     progress: Callable[[int, int], None] | None = None) -> BranchStability:
    """Floquet multipliers of every point of ``branch`` (a branch of ``problem``) and its
    bifurcations located to ``options.rtol`` (module docstring).

    ``progress(i, n)`` is called after each point (and with ``i = n`` when locating).
    Bifurcations that cannot be located (re-solve fails, e.g. at journal contact) are
    kept with their interpolated position and a message in ``messages``.
    """
    o = options or StabilityOptions()
    ev = FloquetEvaluator(problem, o)
    t0 = time.perf_counter()
    results = []
    n = branch.n_points
    for i in range(n):
        results.append(ev(float(branch.lam[i]), branch.X[i]))
        if progress is not None:
            progress(i + 1, n)
    t_points = time.perf_counter() - t0
    dlam = branch.dlam_ds if branch.tangents.size else np.full(n, np.nan)
    s = branch.s if branch.s.size == n else np.arange(n, dtype=float)
    samples = [BranchSample(float(s[i]), float(branch.lam[i]), r.multipliers,
                            float(dlam[i]) if np.isfinite(dlam[i]) else None)
               for i, r in enumerate(results)]
    brackets, merged = _merge_folds(detect(samples, o.tol), samples, o.fold_merge_rtol,
                                    o.tol)
    index = {id(p): i for i, p in enumerate(samples)}

    located: dict[float, tuple[Any, FloquetResult]] = {}   # this bracket's re-solves

    def solve_at(s_: float) -> tuple[float, NDArray, float]:
        p = branch.point_at(s_)
        res = ev(p.lam, p.X)
        located[float(s_)] = (p, res)
        return p.lam, res.multipliers, p.dlam_ds

    bifs: list[Bifurcation] = []
    messages: list[str] = _hill_resolution(results)
    can_locate = o.locate and branch.resolver is not None
    for br in brackets:
        ia, ib = index[id(br.a)], index[id(br.b)]
        b = None
        if can_locate:
            located.clear()
            try:
                b = locate(br, solve_at, rtol=o.rtol)
                if float(b.s) in located:   # the point and multipliers there, for reuse
                    b.info["located"] = located[float(b.s)]
            except (ConvergenceError, ArithmeticError, ValueError) as err:
                messages.append(f"{br.kind} between lam = {br.a.lam:.9g} and "
                                f"{br.b.lam:.9g} not located: {err}")
        if b is None:  # interpolated position, multipliers of the nearer end
            est = [x for x in find_bifurcations([br.a, br.b], None, dead_band=o.tol)
                   if x.kind == br.kind]
            b = est[0] if est else Bifurcation(br.kind, br.b.s, br.b.lam, br.b.multipliers,
                                               critical_value(br.kind, br.b.multipliers)[1],
                                               br.via)
        if id(br) in merged:
            b.info["merged"] = True
            if can_locate:
                _floquet_crossing(b, merged[id(br)], solve_at, o, messages)
        if (b.via == "tangent" and b.kind == "saddle-node" and can_locate
                and not abs(b.critical - 1.0) <= FOLD_MULTIPLIER_TOL):
            messages.append(f"saddle-node at lam = {b.lam:.9g} (turning point): the "
                            f"multiplier nearest +1 there is {located_critical(b):.5f}, "
                            "not +1: "
                            "the orbit's truncation (H) or the Floquet step does not "
                            "resolve the exchange of stability at this fold, so the "
                            "stability flags next to it are unreliable; raise H (or use "
                            "harmonics = 'auto') and the intervals")
        if b.via != "tangent" and abs(abs(b.critical) - 1.0) > 0.05:
            messages.append(f"{b.kind} at lam = {b.lam:.9g}: the multiplier at the located "
                            f"point is {b.critical:.4f}, far from the unit circle (a pair "
                            "meeting the real axis, or an unresolved stiff mode): check "
                            "with more intervals or method='hill'")
        j, rep = _reported(br.kind, samples, ia, ib, o.tol, b.s)
        b.info.update(point=j, reported=rep, bracket=(ia, ib))
        bifs.append(b)
    if progress is not None:
        progress(n, n)
    mu, counts = _pad([r.multipliers for r in results])
    le = np.array([r.liouville_error or 0.0 for r in results], dtype=float)
    return BranchStability(
        lam=np.asarray(branch.lam, float).copy(),
        frequency=np.asarray(branch.frequency, float).copy(),
        stable=np.array([r.stable for r in results], dtype=bool),
        max_multiplier=np.array([r.max_abs for r in results], dtype=float),
        critical=np.array([r.critical for r in results], dtype=complex),
        multipliers=mu, n_multipliers=counts,
        liouville_error=np.where(np.isfinite(le), le, 0.0), bifurcations=bifs,
        method=results[0].method if results else o.method, tol=o.tol,
        elapsed=time.perf_counter() - t0, elapsed_points=t_points, n_bases=ev.n_bases,
        messages=messages,
        n_intervals=np.array([r.info.get("n_intervals", o.n_intervals) for r in results],
                             dtype=np.int64),
        multiplier_error=np.array([r.info["multiplier_error"] for r in results], float)
        if results and all("multiplier_error" in r.info for r in results) else None)
