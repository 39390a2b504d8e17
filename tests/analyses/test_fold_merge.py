"""A +1 multiplier crossing away from a turning point: one fold displaced by the numerical
error when no multiplier crosses +1 across the turn itself (the isola of the paper's
C/R = 0.728 % case at H = 16, N = 400: crossing at Omega~ 1.0904, turn at 1.0939 with
|mu| = 1.037 there), a separate crossing when the turn has its own."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.stability.bifurcations import BranchSample, detect
from rotorsfd.stability.branch_stability import _merge_folds

S = np.arange(12, dtype=float)
LAM = 1.094 - 1e-4 * (S - 6.4) ** 2  # turning point between samples 6 and 7
DLAM = -2e-4 * (S - 6.4)


def samples(*real_multipliers):
    """Samples with the given real multiplier sequences plus a stable complex pair."""
    out = []
    for i, s in enumerate(S):
        mu = [m[i] for m in real_multipliers] + [0.8 + 0.2j, 0.8 - 0.2j]
        out.append(BranchSample(s, LAM[i], np.asarray(mu, complex), DLAM[i]))
    return out


def test_displaced_crossing_is_the_fold():
    """The only +1 crossing (between samples 2 and 3, 1.4e-3 of lam below the turn, over
    the 1e-3 merge tolerance and 4 intervals away) is the fold at the turn."""
    mu = 0.988 + 0.005 * S  # through +1 between s = 2 and 3, still rising at the turn
    pts = samples(mu)
    br = detect(pts, 1e-6)
    assert sorted((b.via, b.a.s) for b in br) == [("multiplier", 2.0), ("tangent", 6.0)]
    kept, merged = _merge_folds(br, pts, 1e-3, 1e-6)
    assert [(b.via, b.a.s) for b in kept] == [("tangent", 6.0)]
    (m,) = merged.values()
    assert m.via == "multiplier" and m.a.s == 2.0
    assert abs(m.a.lam - kept[0].a.lam) / kept[0].a.lam == pytest.approx(1.755e-3, rel=1e-3)


def test_crossing_besides_a_fold_with_its_own_crossing_stays():
    """A second multiplier crosses +1 at the turn: the far crossing is another event
    (a branch point), not merged into that fold."""
    mu1 = 0.988 + 0.005 * S
    mu2 = 0.95 + 0.0078 * S  # through +1 between s = 6 and 7, at the turn
    pts = samples(mu1, mu2)
    br = detect(pts, 1e-6)
    kept, merged = _merge_folds(br, pts, 1e-3, 1e-6)
    assert sorted((b.via, b.a.s) for b in kept) == [("multiplier", 2.0), ("tangent", 6.0)]
    assert merged == {}
