"""Codimension-2 points on fold, period-doubling and Neimark-Sacker curves: detected by
test functions of the Floquet multipliers of the orbit at each point of a curve and
located along the curve's arc by the Illinois method
(:func:`rotorsfd.continuation.folds.locate_on_curve`: each trial point solves the curve's
augmented equations, so the located point is on the curve; its two parameters are within
``xtol`` scaled arc length of the zero of the test function).

At a point of a curve the orbit has its own critical multiplier(s): +1 on a fold curve,
-1 on a period-doubling curve, the pair ``exp(+-2 pi i theta)`` on a Neimark-Sacker curve.
These are removed (the one nearest +1, -1, or the pair nearest ``exp(+-2 pi i theta)``)
and the test functions are smooth symmetric functions of the others, ``mu_j``:

    psi_+1 = prod_j (mu_j - 1),   psi_-1 = prod_j (mu_j + 1),
    psi_circle = prod_{complex pairs} (|mu_j|^2 - 1)

(real: complex pairs give ``|mu - 1|^2 > 0``, so the sign changes exactly where a real
multiplier passes +1 or -1, or a complex pair passes the unit circle). A second multiplier
at the curve's own value (+1 on a fold curve, -1 on a period-doubling curve) is tested by
``((mu_a - t) + (mu_b - t)) prod_{j != a, b} (mu_j - t)``, mu_a and mu_b the two real
multipliers nearest t: removing "the one nearest t" would swap the two where they pass
each other (the computed own multiplier is t only to the monodromy's discretisation
error delta; the zero is where the second is at ``t - delta``). On each curve:

==================  ========================  ========================  ====================
curve               psi_+1 = 0                psi_-1 = 0                psi_circle = 0
==================  ========================  ========================  ====================
saddle-node         1:1 resonance             fold-flip                 fold-Neimark-Sacker
period-doubling     fold-flip                 1:2 resonance             flip-Neimark-Sacker
Neimark-Sacker      fold-Neimark-Sacker       flip-Neimark-Sacker       (double Hopf: none)
==================  ========================  ========================  ====================

On a Neimark-Sacker curve the 1:1 and 1:2 resonances are where theta = sigma / w reaches
0 or 1/2 (the pair meets at +1 or -1): events of the continuation itself
(:func:`rotorsfd.harmonic.ns_curve.continue_neimark_sacker`), located the same way on
``theta`` and ``theta - 1/2``. The cusp (a fold pair meets) is the fold curve's turn in
lam2 (:mod:`rotorsfd.continuation.folds`).

A sign change can also be a jump: a test function of a selection (which multiplier is the
curve's own, which are complex) is discontinuous where the selection changes; a located
zero is kept only if ``|psi|`` there is below ``JUMP_RATIO`` times its values at the
bracket's ends (a smooth simple zero gives ~xtol / step, a jump O(1)).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.folds import FoldBranch, locate_on_curve
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.fold_curve import TwoParameterHB
from rotorsfd.harmonic.problem import PeriodicProblem

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]

#: A multiplier is complex when ``|Im mu| > IMAG_TOL``.
IMAG_TOL = 1e-7
#: A located zero with ``|psi| > JUMP_RATIO * max(|psi_a|, |psi_b|)`` is a jump, dropped.
JUMP_RATIO = 1e-4

#: (curve kind, test) -> codimension-2 type; tests "+1", "-1", "circle"
TYPES = {("saddle-node", "+1"): "1:1 resonance",
         ("saddle-node", "-1"): "fold-flip",
         ("saddle-node", "circle"): "fold-Neimark-Sacker",
         ("period-doubling", "+1"): "fold-flip",
         ("period-doubling", "-1"): "1:2 resonance",
         ("period-doubling", "circle"): "flip-Neimark-Sacker",
         ("Neimark-Sacker", "+1"): "fold-Neimark-Sacker",
         ("Neimark-Sacker", "-1"): "flip-Neimark-Sacker"}
#: the test functions in words (summary, files)
TEST_WORDS = {"+1": "prod (mu_j - 1) over the other multipliers",
              "-1": "prod (mu_j + 1) over the other multipliers",
              "circle": "prod (|mu_j|^2 - 1) over the other complex pairs",
              "theta": "theta = arg(mu) / 2 pi of the Neimark-Sacker pair",
              "theta-1/2": "theta - 1/2 of the Neimark-Sacker pair",
              "turn": "dlam2/ds along the fold curve"}


def other_multipliers(kind: str, mu: ComplexArray, theta: float | None = None
                      ) -> ComplexArray:
    """The multipliers without the curve's own: the one nearest +1 (saddle-node), -1
    (period-doubling) or the pair nearest ``exp(+-2 pi i theta)`` (Neimark-Sacker)."""
    mu = np.asarray(mu, dtype=complex)
    if kind == "saddle-node":
        return np.delete(mu, int(np.argmin(np.abs(mu - 1.0))))
    if kind == "period-doubling":
        return np.delete(mu, int(np.argmin(np.abs(mu + 1.0))))
    if kind == "Neimark-Sacker":
        e = np.exp(2j * np.pi * float(theta))
        i = int(np.argmin(np.abs(mu - e)))
        d = np.abs(mu - np.conj(e))
        d[i] = np.inf
        return np.delete(mu, [i, int(np.argmin(d))])
    raise ValueError(f"curve kind {kind!r}: one of saddle-node, period-doubling, "
                     "Neimark-Sacker")


def _second_at(mu: ComplexArray, target: float) -> float:
    """psi of a second multiplier at ``target`` (+1 on a fold curve, -1 on a
    period-doubling curve): ``((mu_a - t) + (mu_b - t)) prod_{j != a, b} (mu_j - t)``
    with mu_a, mu_b the two real multipliers nearest t (module docstring)."""
    real = np.flatnonzero(np.abs(mu.imag) <= IMAG_TOL * np.maximum(1.0, np.abs(mu)))
    if real.size < 2:   # the curve's own and complex pairs: |mu - t|^2 > 0
        keep = np.delete(mu, real[np.argsort(np.abs(mu[real] - target))][:1])
        return float(np.real(np.prod(keep - target)))
    a, b = real[np.argsort(np.abs(mu[real] - target))][:2]
    rest = np.delete(mu, [a, b])
    return float(np.real((mu[a] + mu[b] - 2 * target) * np.prod(rest - target)))


def codim2_tests(kind: str, mu: ComplexArray, theta: float | None = None
                ) -> dict[str, float]:
    """``{"+1": psi_+1, "-1": psi_-1, "circle": psi_circle}`` (module docstring) of the
    multipliers ``mu`` at a point of a curve of ``kind`` (only the tests of :data:`TYPES`
    for that kind)."""
    mu = np.asarray(mu, dtype=complex)
    rest = other_multipliers(kind, mu, theta)
    out = {"+1": float(np.real(np.prod(rest - 1.0))),
           "-1": float(np.real(np.prod(rest + 1.0)))}
    if kind == "saddle-node":
        out["+1"] = _second_at(mu, 1.0)
    elif kind == "period-doubling":
        out["-1"] = _second_at(mu, -1.0)
    up = rest[rest.imag > IMAG_TOL * np.maximum(1.0, np.abs(rest))]
    out["circle"] = float(np.prod(np.abs(up) ** 2 - 1.0))
    return {k: v for k, v in out.items() if (kind, k) in TYPES}


def critical_multiplier(test: str, rest: ComplexArray) -> complex:
    """The multiplier that makes ``test`` vanish: the one of ``rest`` nearest +1 or -1,
    or the complex one nearest the unit circle (upper half plane)."""
    if test == "+1":
        return complex(rest[np.argmin(np.abs(rest - 1.0))])
    if test == "-1":
        return complex(rest[np.argmin(np.abs(rest + 1.0))])
    up = rest[rest.imag > 0]
    return complex(up[np.argmin(np.abs(np.abs(up) - 1.0))]) if up.size else complex("nan")


@dataclass
class Codim2Point:
    """A located codimension-2 point on a curve.

    ``type`` e.g. "fold-flip"; ``curve`` the kind of curve it was located on and
    ``curve_index`` its number among the curves of that kind; ``lam1, lam2`` the two
    parameters (physical); ``test`` the key of :data:`TEST_WORDS`; ``value`` the test
    function at the located point; ``bracket`` the last bracket (scaled arc length);
    ``multiplier`` the multiplier that reached +1, -1 or the unit circle there (for the
    Neimark-Sacker events the pair's ``exp(2 pi i theta)``); ``z`` the curve's point."""

    type: str
    curve: str
    curve_index: int
    lam1: float
    lam2: float
    test: str
    value: float
    multiplier: complex
    z: FloatArray


def locate_codim2(kind: str, leg: FoldBranch, multipliers: Callable[[FloatArray], ComplexArray],
                  parameters: Callable[[FloatArray], tuple[float, float]], *,
                  theta: Callable[[FloatArray], float] | None = None, curve_index: int = 0,
                  tol: float = 1e-8, xtol: float = 1e-9,
                  values: list[dict[str, float]] | None = None) -> list[Codim2Point]:
    """Codimension-2 points along ``leg`` (a curve of ``kind``): the test functions of
    :func:`codim2_tests` at every point (``multipliers(z)`` the Floquet multipliers of the
    orbit at the leg's point z, ``theta(z)`` the Neimark-Sacker angle), each sign change
    between consecutive points located along the arc to ``xtol`` (scaled arc length) with
    the Newton tolerance ``tol``; jumps (module docstring) dropped. ``parameters(z)`` gives
    the physical (lam1, lam2) of a point. ``values`` (optional, filled) receives the test
    values per point."""
    th = theta or (lambda z: None)

    def tests_at(z: FloatArray) -> dict[str, float]:
        return codim2_tests(kind, multipliers(z), th(z))

    vals = [tests_at(z) for z in leg.z]
    if values is not None:
        values.extend(vals)
    out: list[Codim2Point] = []
    for i in range(len(vals) - 1):
        for key in vals[i]:
            fa, fb = vals[i][key], vals[i + 1][key]
            if not (fa * fb < 0 or (fb == 0.0 and fa != 0.0)):
                continue
            leg.system.update_border(leg.z[i])   # borders of the bracket's start
            try:
                z, _, _, f = locate_on_curve(leg.system, leg.z[i], leg.tangents[i],
                                             leg.z[i + 1],
                                             lambda z_, t_, k=key: tests_at(z_)[k],
                                             fa, fb, tol, xtol=xtol)
            except ConvergenceError:
                continue
            if abs(f) > JUMP_RATIO * max(abs(fa), abs(fb)):
                continue
            mu = multipliers(z)
            rest = other_multipliers(kind, mu, th(z))
            l1, l2 = parameters(z)
            out.append(Codim2Point(TYPES[(kind, key)], kind, curve_index, l1, l2, key, f,
                                   critical_multiplier(key, rest), z))
    return out


def ns_event_point(leg: FoldBranch, parameters: Callable[[FloatArray], tuple[float, float]],
                   curve_index: int = 0) -> Codim2Point | None:
    """The 1:1 or 1:2 resonance where a Neimark-Sacker leg ended (its event 0: theta = 0,
    event 1: theta = 1/2; :func:`rotorsfd.harmonic.ns_curve.continue_neimark_sacker`),
    None if it did not end at one."""
    if leg.ended_at is None:
        return None
    z = leg.z[-1]
    theta = float(z[-2])
    l1, l2 = parameters(z)
    key = ("theta", "theta-1/2")[leg.ended_at]
    kind = ("1:1 resonance", "1:2 resonance")[leg.ended_at]
    value = theta - 0.5 * leg.ended_at
    return Codim2Point(kind, "Neimark-Sacker", curve_index, l1, l2, key, value,
                       complex(np.exp(2j * np.pi * theta)), z)


def curve_orbit(kind: str, hb: TwoParameterHB, leg: FoldBranch, z: FloatArray
                ) -> tuple[float, float, ComplexArray]:
    """(lam1, lam2, X) of the period-1 orbit at the point z of ``leg``, a curve of
    ``kind`` over ``hb``: X (H+1, n_dof) its coefficients in harmonics of w (on a
    period-doubling curve the even harmonics of w/2, ``X_k = X2_{2k}``)."""
    base = z if kind == "saddle-node" else leg.system.embed(z)
    _, lam1, lam2 = hb.from_z(base)
    X = hb.coefficients(base)
    return lam1, lam2, (X[::2] if kind == "period-doubling" else X)


def curve_codim2(kind: str, hb: TwoParameterHB, leg: FoldBranch,
                 multipliers: Callable[[PeriodicProblem, float, ComplexArray], ComplexArray],
                 problem: Callable[[float], PeriodicProblem], *, curve_index: int = 0,
                 tol: float = 1e-8, xtol: float = 1e-9) -> list[Codim2Point]:
    """Every codimension-2 point of ``leg`` (a curve of ``kind`` over ``hb``):
    :func:`locate_codim2` with the multipliers of the period-1 orbit at each point,
    ``multipliers(problem(lam2), lam1, X)`` (e.g. a Floquet evaluator of
    :mod:`rotorsfd.stability`), plus on a Neimark-Sacker curve the 1:1 or 1:2 resonance
    where it ended (:func:`ns_event_point`). ``problem(lam2)`` is the periodic problem in
    lam1 at lam2 (``TwoParameterProblem.first``)."""
    problems: dict[float, PeriodicProblem] = {}

    def mult(z: FloatArray) -> ComplexArray:
        lam1, lam2, X = curve_orbit(kind, hb, leg, z)
        if lam2 not in problems:
            if len(problems) > 8:
                problems.clear()
            problems[lam2] = problem(lam2)
        return multipliers(problems[lam2], lam1, X)

    def params(z: FloatArray) -> tuple[float, float]:
        return curve_orbit(kind, hb, leg, z)[:2]

    theta = (lambda z: float(z[-2])) if kind == "Neimark-Sacker" else None
    out = locate_codim2(kind, leg, mult, params, theta=theta, curve_index=curve_index,
                        tol=tol, xtol=xtol)
    if kind == "Neimark-Sacker":
        end = ns_event_point(leg, params, curve_index)
        if end is not None:
            out.append(end)
    return out
