"""StabilityOptions.outside: the modes above the Craig-Bampton cut-off (one dense
eigenproblem per point) are computed for the branch's points only; with it off (the
bifurcation check's pieces, the located re-solves) the multipliers and the located
bifurcations are the same, bit for bit, and no max_multiplier_outside is reported (None)."""

from __future__ import annotations

import dataclasses

import numpy as np

from rotorsfd.analyses.response import run_response
from rotorsfd.harmonic import pencil_condensation
from rotorsfd.paper.cases import CASES
from rotorsfd.paper.run import load_case_config
from rotorsfd.stability.branch_stability import StabilityOptions, branch_stability


def test_outside_off_changes_nothing_but_the_outside_column(monkeypatch):
    config = load_case_config(CASES["cal-fig7-u144"])       # damped: outside |mu| < 1
    r = run_response(config, progress=False, stability_options=False,
                     start=1.04 * 811.3, stop=1.07 * 811.3)
    problem = r.system.periodic_problem()
    on = StabilityOptions(interval_tol=1e-4)
    # the LU at every re-solve: the branch's linear part, condensed often, would switch
    # to its pencils (harmonic.pencil_condensation, equal to ~1e-12) part way through
    # the second run and not the first
    monkeypatch.setattr(pencil_condensation, "PENCIL_AFTER", 1 << 60)
    a = branch_stability(r.branch, problem, on)
    b = branch_stability(r.branch, problem, dataclasses.replace(on, outside=False))
    assert np.array_equal(a.multipliers, b.multipliers)
    assert [(x.kind, x.lam) for x in a.bifurcations] == [(x.kind, x.lam)
                                                          for x in b.bifurcations]
    assert len(a.bifurcations) == 2                           # the U = 144.02 fold pair
    assert np.all((a.max_multiplier_outside > 0.5) & (a.max_multiplier_outside < 1.0))
    assert b.max_multiplier_outside is None                  # not computed: not 0.0
