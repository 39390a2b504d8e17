"""Branch switching at a period-doubling point: the period-2 branch by harmonic balance.

At a period-doubling bifurcation of a T-periodic solution ``X`` (a Floquet multiplier
through -1) a 2T-periodic branch is born. In harmonics of ``w/2`` the period-1 solution
has only even harmonics, ``X2_{2k} = X_k`` (:func:`doubled_coefficients`), and it still
solves the period-2 HB equations (:func:`period_doubled`: same system, fundamental
``w/2``, forcing harmonic k moved to 2k). The HB Jacobian at that solution does not couple
even and odd harmonics; its odd block is singular exactly where a multiplier is -1 (the
HB counterpart of the monodromy's eigenvector: ``dq(t + T) = -dq(t)``). That point (the
PD of the HB equations with ``H2`` harmonics, default 4H) is located near the given one
(a monodromy PD: they differ by the truncation of the odd harmonics), its null vector
``phi`` is the direction of the new branch: a point on it is found by Newton on
``R(z) = 0, phi . z = delta`` (scaled units), and the period-2 branch is continued from
there (pseudo arc-length, steps <= delta) away from the period-1 branch. It ends at the
end of the range, or where it reaches the period-1 branch again (another PD: a closed
bubble, ``closed``), or, if it turns back past its first point at a fold, a second leg goes
on towards the other end of the range. Multipliers of the period-2 legs are over 2T
(:meth:`PeriodDoublingSwitch.stability`).
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.branch import Branch
from rotorsfd.continuation.newton import newton_extended, tangent
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.harmonic.hb_system import hb_system
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.harmonic.problem import PeriodicProblem

ComplexArray = NDArray[np.complex128]


def period_n(problem: PeriodicProblem, n: int) -> PeriodicProblem:
    """The same system written with fundamental frequency ``w(lam) / n``: forcing
    harmonic k becomes harmonic k n (the others unforced); ``n = 1``: ``problem`` itself."""
    if n == 1:
        return problem
    m = problem.n_dof

    def spread(F: ComplexArray, Hn: int) -> ComplexArray:
        out = np.zeros((Hn + 1, m), dtype=complex)
        out[0::n] = F[: Hn // n + 1]
        return out

    return PeriodicProblem(
        n_dof=m, nl_dofs=problem.nl_dofs, matrices=problem.matrices,
        dmatrices=problem.dmatrices,
        forcing=lambda lam, H: spread(problem.forcing(lam, H // n), H),
        dforcing=lambda lam, H: spread(problem.dforcing(lam, H // n), H),
        frequency=lambda lam: problem.frequency(lam) / n,
        dfrequency=lambda lam: problem.dfrequency(lam) / n,
        nl_force=problem.nl_force, nl_jacobian=problem.nl_jacobian,
        scaling=problem.scaling, nl_limit=problem.nl_limit,
        name=f"{problem.name} (period {n})", nl_force_jacobian=problem.nl_force_jacobian,
        nl_kernel=problem.nl_kernel, nl_kernel_params=problem.nl_kernel_params,
        nl_at=problem.nl_at, nl_force_jacobians=problem.nl_force_jacobians,
        nl_inertial_kernel=problem.nl_inertial_kernel,
        frequency_line=None if problem.frequency_line is None
        else (problem.frequency_line[0] / n, problem.frequency_line[1] / n))


def period_doubled(problem: PeriodicProblem) -> PeriodicProblem:
    """:func:`period_n` with n = 2: fundamental ``w(lam)/2``, forcing harmonic k becomes
    harmonic 2k (odd harmonics unforced)."""
    return period_n(problem, 2)


def doubled_coefficients(X: ComplexArray, H2: int | None = None) -> ComplexArray:
    """Coefficients in harmonics of ``w/2``: ``X2_{2k} = X_k`` (H2 default 2H)."""
    X = np.asarray(X, dtype=complex)
    H = X.shape[0] - 1
    H2 = 2 * H if H2 is None else int(H2)
    out = np.zeros((H2 + 1, X.shape[1]), dtype=complex)
    k = min(H, H2 // 2)
    out[0: 2 * k + 1: 2] = X[: k + 1]
    return out


def mirrored(X2: ComplexArray) -> ComplexArray:
    """The same period-2 orbit shifted by T (half its period): odd harmonics of ``w/2``
    change sign. A period-2 branch and its mirror are one branch (they meet on the
    period-1 branch at the period-doubling points)."""
    out = np.array(X2, dtype=complex)
    out[1::2] *= -1
    return out


@dataclass
class PeriodDoublingSwitch:
    """The period-2 branch born at a period-doubling point.

    ``legs``: one or two branches continued in ``problem`` (the :func:`period_doubled`
    problem: its ``frequency`` is ``w/2``, so ``X`` are coefficients of harmonics of
    ``w/2``), the second starting where the first turned back;
    ``lam_given``: the period-doubling point passed in (of the period-1 branch, e.g.
    located by the monodromy matrix); ``lam_bifurcation``: the period-doubling point of
    the period-2 HB equations (odd block singular) the branch was switched at;
    ``singular_value``: the smallest singular value of the scaled odd-harmonic HB
    Jacobian there (0 at an exact PD); ``coupling``: the norm of its odd-even block
    relative to the Jacobian (0 in exact arithmetic); ``delta``: the odd amplitude of the
    first point (scaled units); ``closed``: the branch came back as its own mirror
    (:func:`mirrored`): it joins the period-1 branch again at ``lam_rejoin``, a bubble
    between two period-doubling points, fully traced; ``message``: what happened.
    """

    legs: list[Branch]
    problem: PeriodicProblem
    lam_bifurcation: float
    singular_value: float
    coupling: float
    delta: float
    lam_given: float = float("nan")
    closed: bool = False
    lam_rejoin: float | None = None
    message: str = ""

    @property
    def lam(self) -> NDArray[np.float64]:
        """Parameter of every point of the legs, in order."""
        return np.concatenate([b.lam for b in self.legs])

    @property
    def X(self) -> ComplexArray:
        """Coefficients (n_points, H+1, n_dof) of every point of the legs, in order."""
        return np.concatenate([b.X for b in self.legs])

    def subharmonic_amplitude(self, dof: int) -> NDArray[np.float64]:
        """``|X_1|`` (the w/2 component) of one DOF along the legs."""
        return np.abs(self.X[:, 1, dof])

    def odd_amplitude(self, dofs: Any = None) -> NDArray[np.float64]:
        """2-norm of all odd harmonics of ``w/2`` (the part that is not T-periodic) of
        ``dofs`` (default the nonlinear DOFs) along the legs, physical units."""
        d = self.problem.nl_dofs if dofs is None else dofs
        odd = self.X[:, 1::2][:, :, d]
        return np.sqrt(np.sum(np.abs(odd) ** 2, axis=(1, 2)))

    def stability(self, options: Any = None) -> list[Any]:
        """:func:`~rotorsfd.stability.branch_stability.branch_stability` of every leg, its
        multipliers over the period 2T, with ``n_intervals`` per 2T doubled (the same
        time step as the period-1 branch's ``n_intervals`` per T)."""
        # deferred: stability.branch_stability (loads scipy)
        from rotorsfd.stability.branch_stability import StabilityOptions, branch_stability

        o = options or StabilityOptions()
        o2 = replace(o, n_intervals=2 * o.n_intervals)
        return [branch_stability(leg, self.problem, o2) for leg in self.legs]


#: A leg of the period-2 branch has run onto the period-1 branch where its odd part
#: (scaled 2-norm) falls below this fraction of its largest value so far.
REJOIN_FRACTION = 1e-6


def _odd_rows(H2: int, m: int) -> tuple[NDArray[np.intp], NDArray[np.intp]]:
    rows = np.arange(2 * H2 + 1).reshape(-1, 1)
    harmonic = (rows + 1) // 2                       # 0, 1, 1, 2, 2, ...
    odd = np.nonzero(np.broadcast_to(harmonic % 2 == 1, (2 * H2 + 1, m)).ravel())[0]
    even = np.setdiff1d(np.arange((2 * H2 + 1) * m), odd)
    return odd, even


class _PeriodOne:
    """The period-1 solution re-solved at fixed lam in the doubled HB system and the odd
    block of its Jacobian: ``test(lam)`` = sign(det) * smallest singular value (changes
    sign at a period-doubling point of the doubled HB equations)."""

    def __init__(self, system: Any, z0: NDArray, tol: float, name: str) -> None:
        self.system, self.tol, self.name = system, tol, name
        m = system.n // (2 * system.H + 1)
        self.odd, self.even = _odd_rows(system.H, m)
        self.solved: dict[float, Any] = {}
        self.z0 = z0

    def solve(self, lam_z: float) -> Any:
        if lam_z in self.solved:
            return self.solved[lam_z]
        if self.solved:
            near = min(self.solved, key=lambda k: abs(k - lam_z))
            z = self.solved[near].z.copy()
        else:
            z = self.z0.copy()
        z[-1] = lam_z
        z[self.odd] = 0.0
        e = np.zeros(self.system.n + 1)
        e[-1] = 1.0
        res = newton_extended(self.system, z, e, lam_z, self.tol, 30)
        if not res.converged:
            raise ConvergenceError(
                f"{self.name}: the period-1 solution does not solve the period-2 equations "
                f"at lam={lam_z * self.system.lam_scale:.9g}: {res.message}")
        self.solved[lam_z] = res
        return res

    def odd_block(self, lam_z: float) -> NDArray:
        J = self.solve(lam_z).J[:, :-1]
        return J[np.ix_(self.odd, self.odd)]

    def test(self, lam_z: float) -> float:
        B = self.odd_block(lam_z)
        sign, _ = np.linalg.slogdet(B)
        return float(sign * np.linalg.svd(B, compute_uv=False)[-1])


def _locate_pd(p1: _PeriodOne, lam_z: float, lo_z: float, hi_z: float, step_z: float,
               max_steps: int = 40) -> float | None:
    """The nearest sign change of ``p1.test`` around lam_z (steps of step_z outwards on
    both sides within [lo_z, hi_z]), located by Brent's method; None if there is none."""
    # deferred: scipy.optimize is heavy (loaded only when this runs)
    from scipy.optimize import brentq

    f0 = p1.test(lam_z)
    if f0 == 0.0:
        return lam_z
    sides = {1: (lam_z, f0), -1: (lam_z, f0)}
    for k in range(1, max_steps + 1):
        for d in (1, -1):
            if sides[d] is None:
                continue
            x = lam_z + d * k * step_z
            if not lo_z <= x <= hi_z:
                sides[d] = None
                continue
            try:
                f = p1.test(x)
            except ConvergenceError:
                sides[d] = None
                continue
            xa, fa = sides[d]
            if np.sign(f) != np.sign(fa):
                return float(brentq(p1.test, min(xa, x), max(xa, x), xtol=1e-12,
                                    rtol=1e-12))
            sides[d] = (x, f)
        if sides[1] is None and sides[-1] is None:
            break
    return None


def switch_period_doubling(problem: PeriodicProblem, lam: float, X: ComplexArray,
                           lam_range: tuple[float, float], *, H: int | None = None,
                           delta: float = 0.05, locate: bool = True,
                           n_samples: int | None = None, tol: float = 1e-8,
                           limit_max: float = 1.0, **continue_kw: Any
                           ) -> PeriodDoublingSwitch:
    """Continue the period-2 branch from the period-doubling point ``(lam, X)`` of
    ``problem`` (``X`` (H+1, n_dof), e.g. ``branch.point_at(bif.s).X``) within
    ``lam_range = (lo, hi)``.

    ``H``: harmonics of ``w/2`` (default 4 H: 2H of the period-1 part and 2H odd ones).
    2 H would hold the period-1 solution exactly, but the period-2 orbit then has only H
    odd harmonics: on the paper case (examples/paper_clearance.toml, H = 12) the odd
    block is then never singular near the monodromy's PD at 1.0331 (no period-2 branch),
    at 2H + 2 = 26 the bubble is found but unstable everywhere (|mu| 1.08-1.19) and too
    narrow (1.037-1.047); from 32 on it is stable and it converges at 4 H = 48 (PDs
    1.0356 and 1.0479; the period-1 branch at H = 24-32 has them at 1.0358 and 1.0494).
    The period-doubling point of the period-2 HB equations differs from ``lam`` (a PD of
    the period-1 orbit's monodromy matrix) by the truncation of the odd harmonics; with
    ``locate`` (default) it is located first: the period-1 solution is re-solved in the
    doubled system at fixed lam, stepping outwards from ``lam`` (steps of 0.2 % of the
    range or 0.05 % of lam, the larger, at most 40 each way, within the range: a narrow
    range still reaches 2 % of lam, the paper case's 1.0268 at H = 8 to 1.0356 at 4H)
    to the nearest sign change of ``sign(det B) sigma_min(B)``, B the odd block of the
    HB Jacobian; then Brent. The null vector ``phi`` of B there is the direction of the
    period-2 branch (the HB form of the monodromy's eigenvector for -1:
    ``dq(t + T) = -dq(t)``, odd harmonics only).

    ``delta``: odd amplitude ``phi . z`` of the first point (scaled units: fractions of
    the problem's length scale); from it the branch is continued away from the period-1
    branch (the tangent's odd part along ``phi``), towards whichever end of the range
    that is. If it comes back past its first lam (a fold, or a bubble that rejoins the
    period-1 branch and comes back as its mirror), a bubble is recognised by the sign of
    ``phi . z`` (the mirror: ``< 0``) and is complete (``closed``); otherwise a second leg
    goes on from the last point towards the other end. ``continue_kw`` go to
    :func:`~rotorsfd.harmonic.periodic.continue_periodic`.
    Raises ConvergenceError if no period-2 point is found.
    """
    X = np.asarray(X, dtype=complex)
    H2 = 4 * (X.shape[0] - 1) if H is None else int(H)
    p2 = period_doubled(problem)
    X2 = doubled_coefficients(X, H2)
    lo, hi = sorted(lam_range)
    scale = (hi - lo) or max(abs(lam), 1.0)
    system, z0 = hb_system(p2, H2, lam, X2, n_samples, True, scale, limit_max)
    p1 = _PeriodOne(system, z0, tol, problem.name)
    lam_z = float(z0[-1])
    lam_pd_z = None
    if locate:
        lam_pd_z = _locate_pd(p1, lam_z, lo / scale, hi / scale,
                              max(0.002, 5e-4 * abs(lam_z)))
    note = ""
    if lam_pd_z is None:
        lam_pd_z = lam_z
        if locate:
            note = (" (no sign change of the odd block's determinant found near it: switched"
                    " at the given lam along its smallest singular vector)")
    base = p1.solve(lam_pd_z)
    J = base.J[:, :-1]
    _, sv, vt = np.linalg.svd(J[np.ix_(p1.odd, p1.odd)])
    coupling = float(np.linalg.norm(J[np.ix_(p1.even, p1.odd)]) / np.linalg.norm(J))
    a = np.zeros(system.n + 1)
    a[p1.odd] = vt[-1]
    lam_pd = lam_pd_z * scale
    start = newton_extended(system, base.z + delta * a, a, delta, tol, 40)
    if not start.converged:
        raise ConvergenceError(f"{problem.name}: no period-2 point with odd amplitude "
                               f"{delta:g} near lam={lam_pd:.9g}: {start.message}")
    X_start = system.coefficients(start.z)
    lam_start = system.from_z(start.z)[1]
    t = tangent(start.J, a)                          # away from the period-1 branch
    away = hi if t[-1] >= 0.0 else lo

    def along_phi(Xp: ComplexArray) -> float:
        x = to_real(Xp[:, problem.nl_dofs]).ravel() / system.cx
        return float(x @ a[:-1])

    def odd_norm(Xp: ComplexArray) -> float:
        x = to_real(Xp[:, problem.nl_dofs]).ravel() / system.cx
        return float(np.linalg.norm(x[p1.odd]))

    peak = {"odd": 0.0, "lam": None, "prev": None}

    def rejoined(point: Any) -> bool:
        """Stop where the leg reaches the period-1 branch: its odd part vanishes (it runs
        onto it), or changes sign near it (it passes through onto its mirror)."""
        o, f = odd_norm(point.X), along_phi(point.X)
        peak["odd"] = max(peak["odd"], o)
        prev, peak["prev"] = peak["prev"], (point.lam, o, f)
        if o < REJOIN_FRACTION * peak["odd"]:
            peak["lam"] = point.lam
            return True
        if prev is not None and prev[2] * f < 0.0 and min(prev[1], o) <= 2.0 * delta:
            peak["lam"] = prev[0] + (point.lam - prev[0]) * prev[2] / (prev[2] - f)
            return True
        return False

    user_cb = continue_kw.pop("callback", None)

    def callback(point: Any) -> bool:
        stop = rejoined(point)
        return bool(user_cb(point)) or stop if user_cb is not None else stop

    # steps not longer than delta: a step as long as the whole subharmonic (paper case:
    # continue_periodic's default ds_max 0.05, odd amplitude <= 0.03) jumps from the
    # period-2 branch onto the period-1 branch before the next period doubling
    kw = {"tol": 1e-8, "limit_max": limit_max, "lam_scale": scale, "ds": delta / 4,
          "ds_max": delta, **continue_kw, "callback": callback}
    legs = [continue_periodic(p2, lam_start, away, H2, X_start, n_samples=n_samples, **kw)]
    last = legs[0]
    closed, lam_rejoin = False, None
    if peak["lam"] is not None:
        lam_rejoin = float(peak["lam"])
        msg = (f"period-2 branch from the PD at lam={lam_pd:.8g}{note}, first point lam="
               f"{lam_start:.8g}: a closed bubble: it rejoins the period-1 branch at "
               f"lam={lam_rejoin:.8g} (another period doubling; the odd harmonics vanish "
               f"there, beyond it the branch is its own mirror, shifted by T): between "
               f"lam={lam_pd:.8g} and lam={lam_rejoin:.8g}")
        return PeriodDoublingSwitch(legs, p2, lam_pd, float(sv[-1]), coupling, delta,
                                    float(lam), True, lam_rejoin, msg)
    back = (last.n_points > 1 and (last.lam[-1] - lam_start) * (away - lam_start) < 0.0)
    msg = f"period-2 branch from the PD at lam={lam_pd:.8g}{note}, first point lam=" \
          f"{lam_start:.8g}, towards lam={away:.8g}: "
    if back:
        other = hi if away == lo else lo
        msg += (f"turned back at a fold and passed its first point at lam="
                f"{last.lam[-1]:.8g}; second leg towards lam={other:.8g}: ")
        legs.append(continue_periodic(p2, float(last.lam[-1]), other, H2, last.X[-1],
                                      n_samples=n_samples, **kw))
        if peak["lam"] is not None:
            closed, lam_rejoin = True, float(peak["lam"])
            msg += (f"it rejoins the period-1 branch at lam={lam_rejoin:.8g} (another "
                    f"period doubling; the odd harmonics vanish there)")
        else:
            msg += legs[-1].message
    else:
        msg += last.message
    return PeriodDoublingSwitch(legs, p2, lam_pd, float(sv[-1]), coupling, delta,
                                float(lam), closed, lam_rejoin, msg)
