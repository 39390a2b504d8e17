"""Time-step control of a transient run (a run-up, a coast-down, an event, a shock).

A transient has no steady state to compare, so the whole run is: the run at ``T/N`` (T the
period of the run's highest speed) and the run at ``T/2N`` from the same initial state
give the orbit radius ``r(t)`` at the node compared (the first element with a clearance,
in C; else the first output node, in its largest radius) at the common times, and

    d = max_t |r_N(t) - r_2N(t)| / scale

is the change of one halving (the finer run is about d / 3 from the converged one:
Newmark is second order; :mod:`rotorsfd.analyses.step_control` says the same for steady
runs). The radius is used, not y and z, because a jump's timing and a whirl's phase drift
apart between steps long before the amplitude does.

``"auto"``: from ``T/200``, halve until ``d <= step_tolerance`` or the finer step would
pass ``max_steps_per_period``; the finer run of the last pair is the result. A fixed step
is checked by one halving (``step_check_periods > 0``) and keeps its own run; either way
a step that fails the tolerance gives a warning naming the change and what to set.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rotorsfd.analyses.runup import SpeedLawRun

START = 200
"""The first step of ``"auto"`` (the paper's T/200)."""


@dataclass
class TransientStep:
    """What the step control did: ``halvings`` as (N, 2N, d)."""

    mode: str
    steps_per_period: int
    tolerance: float
    unit: str
    node: int
    max_steps_per_period: int
    halvings: list[tuple[int, int, float]] = field(default_factory=list)

    @property
    def difference(self) -> float | None:
        return self.halvings[-1][2] if self.halvings else None

    @property
    def converged(self) -> bool:
        d = self.difference
        return d is not None and d <= self.tolerance

    def line(self) -> str:
        if not self.halvings:
            return f"time step T/{self.steps_per_period} ({self.mode}), not checked"
        ladder = ", ".join(f"T/{a} -> T/{b} {d:.2g}" for a, b, d in self.halvings)
        return (f"time step ({self.mode}): T/{self.steps_per_period}; change of the radius "
                f"at node {self.node} per halving ({self.unit}): {ladder} (tolerance "
                f"{self.tolerance:g})")

    def warning(self) -> str | None:
        if not self.halvings or self.converged:
            return None
        a, b, d = self.halvings[-1]
        if self.mode == "auto":
            return (f"the time step did not converge to step_tolerance = {self.tolerance:g} "
                    f"{self.unit} by max_steps_per_period = {self.max_steps_per_period}: the "
                    f"last halving (T/{a} to T/{b}) still moves the orbit radius by {d:.3g} "
                    f"{self.unit}; raise analysis.simulate.max_steps_per_period")
        return (f"time step T/{a} is too coarse for this transient: halving it moves the "
                f"orbit radius by {d:.3g} {self.unit} (step_tolerance {self.tolerance:g}); "
                f'set analysis.simulate.steps_per_period = "auto" (or a larger integer)')

    def as_dict(self) -> dict[str, Any]:
        d = self.difference
        return {"mode": self.mode, "steps_per_period": self.steps_per_period,
                "tolerance": self.tolerance, "unit": self.unit, "node": self.node,
                "difference": d, "estimated_error": None if d is None else d / 3.0,
                "converged": self.converged if self.halvings else None,
                "halvings": [{"steps_per_period": [a, b], "difference": x}
                             for a, b, x in self.halvings],
                "warning": self.warning()}


def radius_difference(coarse: SpeedLawRun, fine: SpeedLawRun, node: int,
                      scale: float) -> float:
    """``d`` of the module docstring (``fine`` at half the step of ``coarse``)."""
    r_c, r_f = coarse.radius(node), fine.radius(node)
    n = min(r_c.size, r_f[::2].size)
    if not np.allclose(coarse.t[:n], fine.t[: 2 * n : 2], rtol=0.0, atol=1e-9):
        raise ValueError("the two runs do not share their times")
    return float(np.max(np.abs(r_c[:n] - r_f[: 2 * n : 2]))) / scale


def controlled_run(run: Callable[[int], SpeedLawRun], steps: int | str, *, node: int,
                   clearance: float | None, tolerance: float, max_steps: int,
                   check: bool) -> tuple[SpeedLawRun, TransientStep]:
    """The run of ``steps`` per period (``"auto"`` or an integer; ``run(N)`` integrates at
    T/N from the initial state) with its step control (module docstring)."""
    auto = steps == "auto"
    n = START if auto else int(steps)
    coarse = run(n)
    scale = clearance if clearance else max(float(np.max(coarse.radius(node))), 1e-300)
    unit = "C" if clearance else "max radius"
    info = TransientStep("auto" if auto else "fixed", n, tolerance, unit, node,
                         max_steps)
    if not auto and not check:
        return coarse, info
    while True:
        fine = run(2 * n)
        d = radius_difference(coarse, fine, node, scale)
        info.halvings.append((n, 2 * n, d))
        if not auto:
            return coarse, info
        info.steps_per_period = 2 * n
        if d <= tolerance or 4 * n > max_steps:
            return fine, info
        coarse, n = fine, 2 * n
