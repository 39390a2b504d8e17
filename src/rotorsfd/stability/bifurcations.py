"""Bifurcations of periodic solutions along a branch: test functions, detection, location.

Along a branch parametrised by arc length s (parameter lam(s), multipliers mu_i(s) of a
real monodromy), the standard test functions (Kuznetsov, Seydel) are::

    saddle-node (fold)      tau_SN = prod_i (mu_i - 1)          (= det(Phi - I));
                            also a sign change of dlam/ds (tangent's parameter part)
    period doubling         tau_PD = prod_i (mu_i + 1)          (= det(Phi + I))
    secondary Hopf / NS     tau_NS = prod_{i<j} (mu_i mu_j - 1) (bialternate product)

All three are real; a sign change between two converged points brackets a crossing.
Signs are computed from the factors (no overflow). A sign change of tau_NS caused by two
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
from rotorsfd.stability.floquet import CrossingType

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


def crossing_signs(multipliers: ArrayLike) -> dict[str, int]:
    """Signs (+1, -1, 0) of tau_SN, tau_PD, tau_NS (module docstring); complex-conjugate
    factors are positive, so only real factors count."""
    mu = np.asarray(multipliers, dtype=complex).ravel()
    re = mu.real[_is_real(mu)]
    out = {"saddle-node": int(np.prod(np.sign(re - 1.0))),
           "period-doubling": int(np.prod(np.sign(re + 1.0)))}
    # bialternate: real pairs (i<j) contribute sign(mu_i mu_j - 1); complex pairs with
    # their conjugates contribute |.|^2 > 0 except the pair itself: |mu|^2 - 1.
    prod_real = np.outer(re, re)[np.triu_indices(re.size, 1)] - 1.0
    cplx = mu[(~_is_real(mu)) & (mu.imag > 0)]
    out["secondary-hopf"] = int(np.prod(np.sign(prod_real))
                                * np.prod(np.sign(np.abs(cplx) ** 2 - 1.0)))
    return out


def _n_complex_outside(mu: NDArray) -> int:
    return int(np.sum((~_is_real(mu)) & (np.abs(mu) > 1.0)))


def critical_value(kind: CrossingType, multipliers: ArrayLike) -> tuple[float, complex]:
    """Continuous location function and the critical multiplier for a crossing type."""
    mu = np.asarray(multipliers, dtype=complex).ravel()
    real = _is_real(mu)
    if kind == "secondary-hopf":
        cand = mu[~real]
        if cand.size == 0:
            return np.nan, complex(np.nan)
        c = cand[np.argmin(np.abs(np.abs(cand) - 1.0))]
        return abs(c) ** 2 - 1.0, complex(c if c.imag >= 0 else np.conj(c))
    target = 1.0 if kind == "saddle-node" else -1.0
    cand = mu[real].real
    if cand.size == 0:
        return np.nan, complex(np.nan)
    c = cand[np.argmin(np.abs(cand - target))]
    return (c - 1.0 if target > 0 else -c - 1.0), complex(c)


def _changes(x: float, y: float) -> bool:
    """Sign change from x to y; a zero at y counts (once), a zero at x does not."""
    return (x * y < 0) or (y == 0 and x != 0)


def detect(samples: Sequence[BranchSample]) -> list[Bracket]:
    """Brackets of crossings between consecutive samples (sign changes of the tests)."""
    out: list[Bracket] = []
    for a, b in pairwise(samples):
        sa, sb = crossing_signs(a.multipliers), crossing_signs(b.multipliers)
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
                and _n_complex_outside(a.multipliers) != _n_complex_outside(b.multipliers)):
            out.append(Bracket("secondary-hopf", a, b))
    return out


def _value(kind: CrossingType, via: str, p: BranchSample) -> float:
    if via == "tangent":
        return float(p.dlam_ds)
    return critical_value(kind, p.multipliers)[0]


def locate(bracket: Bracket, solve_at: SolveAt, *, rtol: float = 1e-6,
           lam_scale: float | None = None, max_iter: int = 80) -> Bifurcation:
    """Locate a bracketed crossing to ``|lam - lam*| <= rtol * max(|lam|, lam_scale)``.

    Illinois regula falsi on the critical function (``via='tangent'``: on dlam/ds).
    Converged when the parameter values at both bracket ends and at the bracket
    midpoint agree to the tolerance. Raises ``ConvergenceError`` otherwise.
    """
    kind, via = bracket.kind, bracket.via
    a, b = bracket.a, bracket.b
    fa, fb = _value(kind, via, a), _value(kind, via, b)
    if not (np.isfinite(fa) and np.isfinite(fb)) or fa * fb > 0:
        # e.g. the critical multiplier is complex at one end: fall back to bisection on
        # the sign of the test function itself
        fa = float(crossing_signs(a.multipliers)[kind])
        fb = float(crossing_signs(b.multipliers)[kind])
        via = "sign"
    if fb == 0.0:  # the sample lies on the crossing
        _, crit = critical_value(kind, b.multipliers)
        return Bifurcation(kind, b.s, b.lam, b.multipliers, crit, bracket.via, 0,
                           (b.lam, b.lam))
    scale = lam_scale if lam_scale is not None else 0.0
    side = 0
    for it in range(1, max_iter + 1):
        tol = rtol * max(abs(a.lam), abs(b.lam), scale)
        if abs(a.lam - b.lam) <= tol:
            mid = BranchSample.from_solve(0.5 * (a.s + b.s), solve_at(0.5 * (a.s + b.s)))
            if abs(mid.lam - a.lam) <= tol and abs(mid.lam - b.lam) <= tol:
                best = mid
                _, crit = critical_value(kind, best.multipliers)
                return Bifurcation(kind, best.s, best.lam, best.multipliers, crit,
                                   bracket.via, it, (a.lam, b.lam))
        if via == "sign":
            s = 0.5 * (a.s + b.s)
        else:
            s = b.s - fb * (b.s - a.s) / (fb - fa)
            if not (min(a.s, b.s) < s < max(a.s, b.s)):
                s = 0.5 * (a.s + b.s)
        p = BranchSample.from_solve(s, solve_at(s))
        fp = (float(crossing_signs(p.multipliers)[kind]) if via == "sign"
              else _value(kind, via, p))
        if fp == 0.0:
            _, crit = critical_value(kind, p.multipliers)
            return Bifurcation(kind, p.s, p.lam, p.multipliers, crit, bracket.via, it,
                               (p.lam, p.lam))
        if fp * fb < 0:
            a, fa = b, fb
            b, fb = p, fp
            side = 0
        else:
            b, fb = p, fp
            side += 1
            if side >= 2 and via != "sign":
                fa *= 0.5  # Illinois modification
    raise ConvergenceError(f"{kind} not located to rtol={rtol} in {max_iter} iterations "
                           f"(bracket s=[{a.s:.6g}, {b.s:.6g}], lam=[{a.lam:.9g}, "
                           f"{b.lam:.9g}])")


def find_bifurcations(samples: Sequence[BranchSample], solve_at: SolveAt | None = None, *,
                      rtol: float = 1e-6, lam_scale: float | None = None
                      ) -> list[Bifurcation]:
    """Detect crossings along ``samples`` and locate each with ``solve_at`` (if None, the
    estimate is linear interpolation of the critical function between the samples)."""
    found = []
    for br in detect(samples):
        if solve_at is not None:
            found.append(locate(br, solve_at, rtol=rtol, lam_scale=lam_scale))
            continue
        fa, fb = _value(br.kind, br.via, br.a), _value(br.kind, br.via, br.b)
        w = fa / (fa - fb) if np.isfinite(fa) and np.isfinite(fb) and fa != fb else 0.5
        near = br.a if w < 0.5 else br.b
        _, crit = critical_value(br.kind, near.multipliers)
        found.append(Bifurcation(br.kind, br.a.s + w * (br.b.s - br.a.s),
                                 br.a.lam + w * (br.b.lam - br.a.lam), near.multipliers,
                                 crit, br.via, 0, (br.a.lam, br.b.lam)))
    return found


class BifurcationMonitor:
    """Event hook for continuation: call at each converged point; keeps the samples and
    returns the brackets found against the previous point."""

    def __init__(self) -> None:
        self.samples: list[BranchSample] = []
        self.brackets: list[Bracket] = []

    def __call__(self, s: float, lam: float, multipliers: ArrayLike,
                 dlam_ds: float | None = None) -> list[Bracket]:
        p = BranchSample(float(s), float(lam), np.asarray(multipliers, dtype=complex),
                         None if dlam_ds is None else float(dlam_ds))
        self.samples.append(p)
        new = detect(self.samples[-2:]) if len(self.samples) > 1 else []
        self.brackets.extend(new)
        return new
