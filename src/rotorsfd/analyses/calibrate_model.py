"""The target quantities of a calibration as functions of the fitted fields: f(p), df/dp.

Configs at field values ``p`` are rebuilt by :func:`rotorsfd.io.config.with_values` (the
same validation as ``--set``). Critical speeds and their exact Jacobian rows come from
:class:`~rotorsfd.analyses.calibrate_targets.CriticalSpeedTracker`; the response targets
(folds, bifurcations, peaks) from one ``[analysis.response]`` branch per evaluation. A fold
speed's derivative in a registered continuation parameter (unbalance, base rates, the
film's fields) is exact, from the fold-augmented system at the located fold
(:func:`~rotorsfd.analyses.calibrate_targets.fold_speed_derivative`); every other entry
by central differences with step ``1e-4 |p_j|`` (or ``1e-4 (hi - lo)`` at 0) on rebuilt
configs.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.analyses.calibrate_targets import (
    CriticalSpeedTracker,
    bifurcation_speed,
    fold_points,
    fold_speed_derivative,
    peak_amplitude,
)
from rotorsfd.analyses.linear_model import linear_system
from rotorsfd.errors import ConfigError, ConvergenceError

EXACT = "exact (eigen-derivative)"
EXACT_FOLD = "exact (fold-augmented system)"
FINITE = "central finite differences"


def continuation_parameter(path: str) -> str | None:
    """The registered continuation parameter of a config path, or None."""
    # deferred: analyses.response_words (loads threadpoolctl)
    from rotorsfd.analyses.response_words import system_parameter

    try:
        name = system_parameter(path)
    except ConfigError:
        return None
    return None if name == "speed" else name


class TargetModel:
    """``values(p)`` and ``jacobian(p)`` of the targets of a calibration."""

    def __init__(self, config: Any, fields: Sequence[Any], targets: Sequence[Any],
                 search_path: Path | None = None, fd_step: float = 1e-4) -> None:
        self.config, self.fields, self.targets = config, list(fields), list(targets)
        self.search_path, self.fd_step = search_path, fd_step
        self.critical = [i for i, t in enumerate(self.targets) if t.kind == "critical_speed"]
        self.response = [i for i, t in enumerate(self.targets) if t.kind != "critical_speed"]
        modal = config.analysis.modal
        self.tracker = CriticalSpeedTracker(
            self.system_at, [int(self.targets[i].selector) for i in self.critical],
            modal.whirl, modal.critical_speed_max) if self.critical else None
        self._cache: dict[bytes, np.ndarray] = {}
        self._fold_cache: dict[bytes, dict] = {}
        self.parameters = [continuation_parameter(f.path) for f in self.fields]
        # (target, field) pairs with an exact fold derivative; the rest by differences
        self.exact_fold = {(i, j) for i in self.response for j, name in
                           enumerate(self.parameters)
                           if self.targets[i].kind == "fold_speed" and name is not None}

    def config_at(self, p: Sequence[float]) -> Any:
        # deferred: io.config (loads 1 more rotorsfd module, needed only here)
        from rotorsfd.io.config import with_values

        return with_values(self.config, {f.path: float(v)
                                         for f, v in zip(self.fields, p, strict=True)})

    def system_at(self, p: Sequence[float]) -> Any:
        """The linear system (``rotorsfd modal``'s) of the config at ``p``, built by the
        one builder."""
        return linear_system(self.config_at(p), self.search_path)

    def derivative_kinds(self) -> list[str]:
        out = []
        for i, t in enumerate(self.targets):
            if t.kind == "critical_speed":
                out.append(EXACT)
                continue
            exact = [(i, j) in self.exact_fold for j in range(len(self.fields))]
            out.append(EXACT_FOLD if all(exact) else FINITE if not any(exact) else
                       f"{EXACT_FOLD} for " + ", ".join(
                           f.path for f, e in zip(self.fields, exact, strict=True) if e)
                       + f"; {FINITE} for the others")
        return out

    def response_values(self, p: Sequence[float], derivatives: dict | None = None
                        ) -> np.ndarray:
        """The response targets at ``p`` from one branch (ConvergenceError if one of them
        is not on it); with ``derivatives`` (a dict) also the exact fold derivatives,
        ``derivatives[(i, j)]``, for the pairs in ``exact_fold``."""
        # deferred: analyses.response (loads threadpoolctl)
        from rotorsfd.analyses.response import run_response

        result = run_response(self.config_at(p), search_path=self.search_path,
                              progress=False)
        folds = None
        out = []
        for i in self.response:
            t = self.targets[i]
            if t.kind == "fold_speed":
                folds = fold_points(result) if folds is None else folds
                if not folds:
                    raise ConvergenceError(f"{t.name}: the branch has no saddle-node "
                                           f"({result.message})")
                if t.selector in ("lower", "upper"):
                    k = 0 if t.selector == "lower" else len(folds) - 1
                elif int(t.selector) > len(folds):
                    raise ConvergenceError(f"{t.name}: the branch has {len(folds)} "
                                           "saddle-nodes")
                else:
                    k = int(t.selector) - 1
                point, index = folds[k]
                out.append(float(point.frequency))
                if derivatives is not None:
                    for j, name in enumerate(self.parameters):
                        if (i, j) in self.exact_fold:
                            derivatives[(i, j)] = fold_speed_derivative(
                                result, point, index, name, float(p[j]))
            elif t.kind == "peak_amplitude":
                out.append(peak_amplitude(result, int(t.selector)))
            else:
                out.append(bifurcation_speed(result, t.selector))
        return np.array(out, dtype=float)

    def values(self, p: Sequence[float]) -> np.ndarray:
        """f_i(p) in the order of the targets (cached per p)."""
        p = np.asarray(p, dtype=float)
        key = p.tobytes()
        if key in self._cache:
            return self._cache[key].copy()
        out = np.empty(len(self.targets))
        if self.tracker is not None:
            out[self.critical] = self.tracker.values(p)
        if self.response:
            exact: dict = {}
            out[self.response] = self.response_values(p, exact if self.exact_fold else None)
            self._fold_cache[key] = exact
        self._cache[key] = out.copy()
        return out

    def step(self, j: int, value: float) -> float:
        f = self.fields[j]
        return self.fd_step * (abs(value) if value != 0.0 else f.upper - f.lower)

    def jacobian(self, p: Sequence[float]) -> np.ndarray:
        """df_i/dp_j: exact rows for the critical speeds, central differences for the
        response targets."""
        p = np.asarray(p, dtype=float)
        jac = np.empty((len(self.targets), p.size))
        if self.tracker is not None:
            self.values(p)

            def field_system(j: int, value: float) -> Any:
                q = p.copy()
                q[j] = value
                return self.system_at(q)

            jac[self.critical] = self.tracker.jacobian(p, field_system)
        if self.response:
            if self.exact_fold:
                self.values(p)      # the branch at p and its exact fold derivatives
                for (i, j), value in self._fold_cache[p.tobytes()].items():
                    jac[i, j] = value
            for j in range(p.size):
                rows = [i for i in self.response if (i, j) not in self.exact_fold]
                if not rows:
                    continue
                h = self.step(j, p[j])
                hi, lo = p.copy(), p.copy()
                hi[j] += h
                lo[j] -= h
                diff = (self.response_values(hi) - self.response_values(lo)) / (2 * h)
                for k, i in enumerate(self.response):
                    if (i, j) not in self.exact_fold:
                        jac[i, j] = diff[k]
        return jac
