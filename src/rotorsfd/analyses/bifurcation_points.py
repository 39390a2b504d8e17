"""The codimension-2 points of the bifurcation curves in (speed, lam2): located on every
fold, period-doubling and Neimark-Sacker curve by :func:`rotorsfd.harmonic.codim2.curve_codim2`
with the Floquet multipliers of :mod:`rotorsfd.stability` (the stability options of the
speed branch), plus the cusps of the fold curves; in words for the summary and the chart.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from rotorsfd.continuation.folds import FoldBranch
from rotorsfd.harmonic.codim2 import (
    TEST_WORDS,
    Codim2Point,
    curve_codim2,
    curve_orbit,
    ns_event_point,
)
from rotorsfd.harmonic.fold_curve import TwoParameterHB, TwoParameterProblem
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.stability.branch_options import StabilityOptions
from rotorsfd.stability.floquet_evaluator import FloquetEvaluator

#: codimension-2 type -> what meets there, in words (summary, chart legend)
MEANING = {"cusp": "a saddle-node pair meets",
           "1:1 resonance": "two multipliers meet at +1",
           "1:2 resonance": "two multipliers meet at -1: secondary Hopf meets period "
                            "doubling",
           "fold-flip": "saddle-node meets period doubling",
           "fold-Neimark-Sacker": "saddle-node meets secondary Hopf",
           "flip-Neimark-Sacker": "period doubling meets secondary Hopf"}


@dataclass
class Codim2Record:
    """A codimension-2 point in the (speed, lam2) plane: ``type`` (a key of
    :data:`MEANING`), the ``curve`` kind it was located on and its number, the speed and
    second-parameter value, the test function (words) and its value there, and the
    multiplier that reached +1, -1 or the unit circle (real and imaginary parts)."""

    type: str
    curve: str
    curve_index: int
    speed_rad_s: float
    speed_ratio: float
    value: float
    test: str
    test_value: float
    multiplier_re: float
    multiplier_im: float

    @property
    def meaning(self) -> str:
        return MEANING[self.type]


def _record(p: Codim2Point, ref: float) -> Codim2Record:
    mu = complex(p.multiplier)
    return Codim2Record(p.type, p.curve, p.curve_index, float(p.lam1), float(p.lam1 / ref),
                        float(p.lam2), TEST_WORDS[p.test], float(p.value),
                        float(np.nan_to_num(mu.real)), float(np.nan_to_num(mu.imag)))


class _Multipliers:
    """``(problem, lam, X) -> multipliers`` with one Floquet evaluator per problem."""

    def __init__(self, options: StabilityOptions | None) -> None:
        self.options = options
        self._ev: dict[int, tuple[PeriodicProblem, FloquetEvaluator]] = {}

    def __call__(self, problem: PeriodicProblem, lam: float, X: Any) -> np.ndarray:
        key = id(problem)
        if key not in self._ev:
            if len(self._ev) > 8:
                self._ev.clear()
            self._ev[key] = (problem, FloquetEvaluator(problem, self.options))
        return self._ev[key][1](lam, X).multipliers


def codim2_records(family: TwoParameterProblem, ref: float,
                   curves: list[tuple[str, TwoParameterHB | None, list[FoldBranch]]],
                   options: StabilityOptions | None = None, *, multipliers: bool = True
                   ) -> tuple[list[Codim2Record], list[str]]:
    """Codimension-2 records of every curve in ``curves`` (kind, residual, legs), sorted
    by second-parameter value, and the messages of the legs where locating failed. The
    cusps of the fold curves are included (type "cusp", located where ``dlam2/ds = 0``),
    and the 1:1 / 1:2 ends of Neimark-Sacker curves; ``multipliers=False``: only these
    (no Floquet multipliers along the curves)."""
    mult = _Multipliers(options)
    out: list[Codim2Record] = []
    messages: list[str] = []
    for kind, hb, legs in curves:
        for k, leg in enumerate(legs):
            if hb is None:
                continue
            if kind == "saddle-node":
                for c in leg.cusps:
                    _, speed, value = hb.from_z(c.z)
                    out.append(Codim2Record("cusp", kind, k, speed, speed / ref, value,
                                            TEST_WORDS["turn"], 0.0, 1.0, 0.0))
            if not multipliers:
                end = ns_event_point(leg, lambda z, kind=kind, hb=hb, leg=leg: curve_orbit(
                    kind, hb, leg, z)[:2], k) if kind == "Neimark-Sacker" else None
                out.extend([_record(end, ref)] if end is not None else [])
                continue
            try:
                points = curve_codim2(kind, hb, leg, mult, family.first, curve_index=k)
            except (ArithmeticError, ValueError) as exc:
                messages.append(f"codimension-2 points of {kind} curve {k} not located: "
                                f"{exc}")
                continue
            out.extend(_record(p, ref) for p in points)
    out.sort(key=lambda r: (r.value, r.speed_rad_s))
    return out, messages
