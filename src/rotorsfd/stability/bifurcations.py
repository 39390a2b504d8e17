"""Bifurcations of periodic solutions along a branch: test functions, detection, location.

Along a branch parametrised by arc length s (parameter lam(s), multipliers mu_i(s) of a
real monodromy), the standard test functions (Kuznetsov, Seydel) are::

    saddle-node (fold)      tau_SN = prod_i (mu_i - 1)          (= det(Phi - I));
                            also a sign change of dlam/ds (tangent's parameter part)
    period doubling         tau_PD = prod_i (mu_i + 1)          (= det(Phi + I))
    secondary Hopf / NS     tau_NS = prod_{i<j} (mu_i mu_j - 1) (bialternate product)

All three are real; a sign change between two converged points brackets a crossing.
Signs are computed from the factors (no overflow), with a dead band: a multiplier with
``|mu| <= 1 + dead_band`` (default ``STABILITY_TOL``) counts as inside, so round-off on
the neutral multipliers of undamped modes raises no event. A sign change of tau_NS caused by two
*real* multipliers with product 1 (neutral saddle) is not a bifurcation and is ignored.

Location: regula falsi (Illinois) in s on a continuous function of the critical
multiplier (``mu* - 1`` for the real one nearest +1; ``-mu* - 1`` for the real one
nearest -1; ``|mu*|^2 - 1`` for the complex one nearest the unit circle; or dlam/ds for a
fold when the callback provides it), until the parameter is fixed to ``rtol``
relative (checked at the bracket ends and at its midpoint, which also covers the
quadratic lam(s) near a fold).

The caller (continuation) provides ``solve_at(s) -> (lam, multipliers)`` or
``(lam, multipliers, dlam_ds)`` that re-solves the branch at arc length s.
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from itertools import pairwise

import numpy as np
from numpy.typing import ArrayLike, NDArray

from rotorsfd.errors import ConvergenceError
from rotorsfd.stability.floquet import STABILITY_TOL, CrossingType

IMAG_TOL = 1e-9
"""A multiplier is real when ``|Im mu| <= IMAG_TOL * max(1, |mu|)``."""

SolveAt = Callable[[float], tuple]
"""``solve_at(s) -> (lam, multipliers)`` or ``(lam, multipliers, dlam_ds)``."""


@dataclass(frozen=True)
class BranchSample:
    """One converged point: arc length, parameter, multipliers, optional dlam/ds."""

    s: float
    lam: float
    multipliers: NDArray[np.complex128]
    dlam_ds: float | None = None

    @classmethod
    def from_solve(cls, s: float, out: tuple) -> BranchSample:
        lam, mu = out[0], np.asarray(out[1], dtype=complex)
        return cls(float(s), float(lam), mu, float(out[2]) if len(out) > 2 else None)


@dataclass(frozen=True)
class Bracket:
    """A detected crossing between two samples; ``via`` is 'multiplier' or 'tangent'."""

    kind: CrossingType
    a: BranchSample
    b: BranchSample
    via: str = "multiplier"


@dataclass
class Bifurcation:
    """A located bifurcation: type, arc length, parameter, multipliers at that point."""

    kind: CrossingType
    s: float
    lam: float
    multipliers: NDArray[np.complex128]
    critical: complex
    via: str = "multiplier"
    iterations: int = 0
    lam_bracket: tuple[float, float] = (np.nan, np.nan)
    info: dict = field(default_factory=dict)

    @property
    def critical_multiplier(self) -> tuple[float, float, float]:
        """``(Re mu, Im mu, |mu|)`` of the critical multiplier."""
        c = self.critical
        return (c.real, c.imag, abs(c))


def _is_real(mu: NDArray) -> NDArray[np.bool_]:
    return np.abs(mu.imag) <= IMAG_TOL * np.maximum(1.0, np.abs(mu))


def crossing_signs(multipliers: ArrayLike, dead_band: float = 0.0) -> dict[str, int]:
    """Signs (+1, -1, 0) of tau_SN, tau_PD, tau_NS (module docstring); complex-conjugate
    factors are positive, so only real factors count. A multiplier within ``dead_band``
    outside the unit circle counts as inside (numerically neutral multipliers of
    undamped modes then never flip a sign)."""
    mu = np.asarray(multipliers, dtype=complex).ravel()
    re = mu.real[_is_real(mu)]
    sn = np.where((re - 1.0 > 0) & (re - 1.0 <= dead_band), -1.0, np.sign(re - 1.0))
    pd = np.where((re + 1.0 < 0) & (re + 1.0 >= -dead_band), 1.0, np.sign(re + 1.0))
    out = {"saddle-node": int(np.prod(sn)), "period-doubling": int(np.prod(pd))}
    # bialternate: real pairs (i<j) contribute sign(mu_i mu_j - 1); complex pairs with
    # their conjugates contribute |.|^2 > 0 except the pair itself: |mu|^2 - 1.
    prod_real = np.outer(re, re)[np.triu_indices(re.size, 1)] - 1.0
    cplx = np.abs(mu[(~_is_real(mu)) & (mu.imag > 0)]) - 1.0
    ns = np.where((cplx > 0) & (cplx <= dead_band), -1.0, np.sign(cplx))
    out["secondary-hopf"] = int(np.prod(np.sign(prod_real)) * np.prod(ns))
    return out


def _n_complex_outside(mu: NDArray, dead_band: float = 0.0) -> int:
    return int(np.sum((~_is_real(mu)) & (np.abs(mu) > 1.0 + dead_band)))


def _candidates(kind: CrossingType, mu: NDArray) -> NDArray[np.complex128]:
    real = _is_real(mu)
    if kind == "secondary-hopf":
        return mu[(~real) & (mu.imag > 0)]
    c = mu[real]
    return c[c.real > 0] if kind == "saddle-node" else c[c.real < 0]


def critical_value(kind: CrossingType, multipliers: ArrayLike,
                   near: complex | None = None) -> tuple[float, complex]:
    """Location function ``|mu*| - 1`` and the critical multiplier ``mu*`` of a crossing
    type: among the real positive (saddle-node), real negative (period-doubling) or
    complex (secondary Hopf, Im > 0) multipliers, the one nearest to ``near`` if given
    (tracking along the bracket), else the one nearest to the unit circle."""
    cand = _candidates(kind, np.asarray(multipliers, dtype=complex).ravel())
    if cand.size == 0:
        return np.nan, complex(np.nan)
    if near is None or not np.isfinite(near):
        c = cand[np.argmin(np.abs(np.abs(cand) - 1.0))]
    else:
        c = cand[np.argmin(np.abs(cand - near))]
    return float(abs(c) - 1.0), complex(c)


def _crossing_multiplier(kind: CrossingType, a: BranchSample,
                         b: BranchSample) -> complex | None:
    """The multiplier at ``b`` whose continuation from ``a`` (nearest neighbour) crosses
    the unit circle; None if there is no such pair."""
    ca, cb = (_candidates(kind, p.multipliers) for p in (a, b))
    best, dist = None, np.inf
    for x in ca:
        if cb.size == 0:
            break
        y = cb[np.argmin(np.abs(cb - x))]
        if (abs(x) - 1.0) * (abs(y) - 1.0) <= 0 and abs(y - x) < dist:
            best, dist = complex(y), abs(y - x)
    return best


def _changes(x: float, y: float) -> bool:
    """Sign change from x to y; a zero at y counts (once), a zero at x does not."""
    return (x * y < 0) or (y == 0 and x != 0)


def detect(samples: Sequence[BranchSample],
           dead_band: float = STABILITY_TOL) -> list[Bracket]:
    """Brackets of crossings between consecutive samples (sign changes of the tests,
    with multipliers up to ``1 + dead_band`` in modulus counted as inside)."""
    out: list[Bracket] = []
    db = dead_band
    signs = [crossing_signs(p.multipliers, db) for p in samples]   # once per sample
    for (a, b), (sa, sb) in zip(pairwise(samples), pairwise(signs), strict=False):
        fold_tangent = (a.dlam_ds is not None and b.dlam_ds is not None
                        and _changes(a.dlam_ds, b.dlam_ds))
        if _changes(sa["saddle-node"], sb["saddle-node"]):
            out.append(Bracket("saddle-node", a, b, "tangent" if fold_tangent
                               else "multiplier"))
        elif fold_tangent:
            out.append(Bracket("saddle-node", a, b, "tangent"))
        if _changes(sa["period-doubling"], sb["period-doubling"]):
            out.append(Bracket("period-doubling", a, b))
        if (_changes(sa["secondary-hopf"], sb["secondary-hopf"])
                and _n_complex_outside(a.multipliers, db)
                != _n_complex_outside(b.multipliers, db)):
            out.append(Bracket("secondary-hopf", a, b))
    return out


def locate(bracket: Bracket, solve_at: SolveAt, *, rtol: float = 1e-6,
           lam_scale: float | None = None, max_iter: int = 80) -> Bifurcation:
    """Locate a bracketed crossing to ``|lam - lam*| <= rtol * max(|lam|, lam_scale)``.

    Illinois regula falsi in s on ``|mu*| - 1`` of the crossing multiplier, tracked from
    point to point by nearest neighbour (``via='tangent'``: on dlam/ds). Converged when
    the parameter at both bracket ends and at the bracket midpoint agree to the
    tolerance (this also bounds the error at a fold, where lam(s) is quadratic).
    Raises ``ConvergenceError`` otherwise.
    """
    kind, via = bracket.kind, bracket.via
    a, b = bracket.a, bracket.b
    near = None

    def value(p: BranchSample) -> float:
        nonlocal near
        if via == "sign":
            return float(crossing_signs(p.multipliers)[kind])
        if via == "tangent":
            return float(p.dlam_ds)
        f, near = critical_value(kind, p.multipliers, near)
        return f

    def result(p: BranchSample, it: int, lams: tuple[float, float]) -> Bifurcation:
        _, crit = critical_value(kind, p.multipliers, near)
        return Bifurcation(kind, p.s, p.lam, p.multipliers, crit, bracket.via, it, lams)

    if via == "multiplier":
        near = _crossing_multiplier(kind, a, b)
        if near is None:  # no tracked pair: bisection on the test function's sign
            via = "sign"
    fb = value(b)
    fa = value(a)
    if via != "sign" and not (np.isfinite(fa) and np.isfinite(fb) and fa * fb <= 0):
        via = "sign"
        fa, fb = value(a), value(b)
    if fb == 0.0:  # the sample lies on the crossing
        return result(b, 0, (b.lam, b.lam))
    if fa == 0.0:
        return result(a, 0, (a.lam, a.lam))
    scale = lam_scale if lam_scale is not None else 0.0
    for it in range(1, max_iter + 1):
        tol = rtol * max(abs(a.lam), abs(b.lam), scale)
        s = None
        if abs(a.lam - b.lam) <= tol:
            s = 0.5 * (a.s + b.s)
        elif via != "sign":
            s = b.s - fb * (b.s - a.s) / (fb - fa)
            if not (min(a.s, b.s) < s < max(a.s, b.s)):
                s = None
        if s is None:
            s = 0.5 * (a.s + b.s)
        p = BranchSample.from_solve(s, solve_at(s))
        if abs(a.lam - b.lam) <= tol and max(abs(p.lam - a.lam), abs(p.lam - b.lam)) <= tol:
            return result(p, it, (a.lam, b.lam))
        fp = value(p)
        if fp == 0.0:
            return result(p, it, (p.lam, p.lam))
        if fp * fb < 0:
            a, fa = b, fb
        elif via != "sign":
            fa *= 0.5  # Illinois modification
        b, fb = p, fp
    raise ConvergenceError(f"{kind} not located to rtol={rtol} in {max_iter} iterations "
                           f"(bracket s=[{a.s:.6g}, {b.s:.6g}], lam=[{a.lam:.9g}, "
                           f"{b.lam:.9g}])")


def find_bifurcations(samples: Sequence[BranchSample], solve_at: SolveAt | None = None, *,
                      rtol: float = 1e-6, lam_scale: float | None = None,
                      dead_band: float = STABILITY_TOL) -> list[Bifurcation]:
    """Detect crossings along ``samples`` and locate each with ``solve_at`` (if None, the
    estimate is linear interpolation of the critical function between the samples)."""
    found = []
    for br in detect(samples, dead_band):
        if solve_at is not None:
            found.append(locate(br, solve_at, rtol=rtol, lam_scale=lam_scale))
            continue
        if br.via == "tangent":
            fa, fb = float(br.a.dlam_ds), float(br.b.dlam_ds)
        else:
            c = _crossing_multiplier(br.kind, br.a, br.b)
            fa = critical_value(br.kind, br.a.multipliers, c)[0]
            fb = critical_value(br.kind, br.b.multipliers, c)[0]
        w = fa / (fa - fb) if np.isfinite(fa) and np.isfinite(fb) and fa != fb else 0.5
        near = br.a if w < 0.5 else br.b
        _, crit = critical_value(br.kind, near.multipliers, _crossing_multiplier(
            br.kind, br.a, br.b))
        found.append(Bifurcation(br.kind, br.a.s + w * (br.b.s - br.a.s),
                                 br.a.lam + w * (br.b.lam - br.a.lam), near.multipliers,
                                 crit, br.via, 0, (br.a.lam, br.b.lam)))
    return found


class BifurcationMonitor:
    """Event hook for continuation: call at each converged point; keeps the samples and
    returns the brackets found against the previous point."""

    def __init__(self, dead_band: float = STABILITY_TOL) -> None:
        self.dead_band = dead_band
        self.samples: list[BranchSample] = []
        self.brackets: list[Bracket] = []

    def __call__(self, s: float, lam: float, multipliers: ArrayLike,
                 dlam_ds: float | None = None) -> list[Bracket]:
        p = BranchSample(float(s), float(lam), np.asarray(multipliers, dtype=complex),
                         None if dlam_ds is None else float(dlam_ds))
        self.samples.append(p)
        new = detect(self.samples[-2:], self.dead_band) if len(self.samples) > 1 else []
        self.brackets.extend(new)
        return new
