"""Bifurcations checked at more harmonics and intervals, the +1 crossing without a turn,
and the located saddle-nodes inserted into the branch (issues 14 item 3, 27 item 1).

Independent checks: the check's re-located fold against a whole branch computed with the
check's harmonics; the middle branch of the hardening Duffing oscillator is a saddle
(one real multiplier > 1), so a point added between the folds must be unstable; at a
turning point of a converged orbit one multiplier is +1.
"""

import dataclasses
from types import SimpleNamespace

import numpy as np
import pytest

from rotorsfd.continuation.folds import locate_branch_fold
from rotorsfd.harmonic import continue_periodic
from rotorsfd.harmonic.examples import duffing
from rotorsfd.stability.bifurcation_check import CheckOptions, check_bifurcations
from rotorsfd.stability.bifurcations import Bifurcation
from rotorsfd.stability.branch_stability import (
    FloquetEvaluator,
    StabilityOptions,
    branch_stability,
    located_critical,
    reported_kind,
)
from rotorsfd.stability.fold_points import fold_points, with_fold_points

PARS = {"c": 0.05, "k": 1.0, "k3": 1.0, "F": 0.3}     # folds 2.3996 / 1.3292 (H = 15)
OPTS = StabilityOptions(method="newmark", n_intervals=800)


@pytest.fixture(scope="module")
def low_h():
    p = duffing(**PARS)
    b = continue_periodic(p, 0.5, 4.0, 1)
    return p, b, branch_stability(b, p, OPTS)


def test_check_relocates_each_fold_where_more_harmonics_put_it(low_h):
    p, b, st = low_h
    # H = 1: the two folds, and a multiplier through +1 on the middle branch where it
    # does not turn (1.760): reported as a branch point, not a saddle-node
    kinds = [(reported_kind(x), round(x.lam, 2)) for x in st.bifurcations]
    assert kinds == [("saddle-node", 2.39), ("branch-point", 1.76), ("saddle-node", 1.33)]
    checks = check_bifurcations(b, p, st, OPTS, CheckOptions(harmonics=5, rtol=1e-3))
    ref = continue_periodic(p, 0.5, 4.0, 5)
    f5 = sorted(locate_branch_fold(ref, int(i)).lam for i in ref.folds())
    for fold, chk in zip(st.bifurcations, checks, strict=True):
        assert chk.H == 5 and chk.n_intervals == 2 * 800
        if reported_kind(fold) == "branch-point":       # an artefact of H = 1: gone
            assert chk.lam is None and not chk.confirmed and "vanishes" in chk.message
            continue
        expected = min(f5, key=lambda f: abs(f - fold.lam))
        assert chk.lam == pytest.approx(expected, rel=1e-6)
        assert chk.shift == pytest.approx(abs(expected - fold.lam) / fold.lam, rel=1e-4)
    # the upper fold moves 3.3e-3 from H = 1 to 5 (unconfirmed at 1e-3), the lower 4.4e-4
    assert [c.confirmed for c in checks] == [False, False, True]
    assert "unconfirmed" in checks[0].message and " confirmed" in checks[2].message


def test_rows_carry_the_check_and_name_the_multipliers(low_h):
    p, b, st = low_h
    st = dataclasses.replace(st, checks=check_bifurcations(b, p, st, OPTS))
    rows = st.rows()
    assert [r["status"] for r in rows] == ["unconfirmed", "unconfirmed", "confirmed"]
    assert [r["type"] for r in rows] == ["saddle-node", "branch-point", "saddle-node"]
    for r, x in zip(rows, st.bifurcations, strict=True):
        crit = located_critical(x)
        assert np.isfinite(crit) and r["located_multiplier_re"] == crit.real
        if np.isfinite(x.critical):
            assert crit == x.critical
        else:   # H = 1's upper fold has no real multiplier: the one nearest +1
            assert abs(crit - 1) == pytest.approx(np.min(np.abs(x.multipliers - 1)))
        j = r["nearest_point"]
        assert r["nearest_max_multiplier"] == pytest.approx(st.max_multiplier[j])
        assert r["nearest_multiplier_abs"] >= 1.0          # on the unstable side
        assert r["max_multiplier"] == r["nearest_multiplier_abs"]    # the legacy key
        assert r["check_harmonics"] == 3 and r["check_intervals"] == 1600   # H + 2, 2M


def test_located_folds_are_inserted_with_their_multipliers():
    p = duffing(**PARS)
    b = continue_periodic(p, 0.5, 4.0, 7)
    opts = dataclasses.replace(OPTS, interval_tol=1e-6)     # multipliers to ~1e-6
    st = branch_stability(b, p, opts)
    b2, st2, messages = with_fold_points(b, st, FloquetEvaluator(p, opts))
    assert not messages
    ins = b2.info["inserted"]
    assert np.count_nonzero(ins == 1) == 2 and np.count_nonzero(ins == 2) == 0
    assert b2.n_points == b.n_points + 2 and np.all(np.diff(b2.s) >= 0)
    folds = np.flatnonzero(ins == 1)
    np.testing.assert_allclose(np.sort(b2.lam[folds]), np.sort([x.lam for x in
                                                               st.bifurcations]))
    for i in folds:                                          # +1 at a converged fold
        mu = st2.multipliers[i, : st2.n_multipliers[i]]
        assert np.min(np.abs(mu - 1.0)) < 1e-3
    # between the folds the middle branch: a saddle, unstable at every point
    between = np.arange(folds.min() + 1, folds.max())
    assert between.size and not st2.stable[between].any()
    assert st2.max_multiplier[between].max() > 1.01
    # the records point at the same computed points as before, renumbered
    old = np.flatnonzero(ins == 0)
    for x, y in zip(st.bifurcations, st2.bifurcations, strict=True):
        assert old[x.info["point"]] == y.info["point"]
        assert b2.lam[y.info["point"]] == b.lam[x.info["point"]]


def test_a_fold_pair_with_no_point_between_gets_one():
    # two saddle-nodes inside one continuation step: the middle point is added
    branch = SimpleNamespace(s=np.array([0.0, 1.0, 2.0, 3.0]), n_points=4)
    folds = [Bifurcation("saddle-node", s_, 1.0, np.ones(1, complex), 1.0 + 0j, "tangent")
             for s_ in (1.2, 1.4)]
    assert fold_points(branch, SimpleNamespace(bifurcations=folds)) == [
        (1.2, 1), (pytest.approx(1.3), 2), (1.4, 1)]
    folds[1].s = 2.5                                          # a computed point between
    assert fold_points(branch, SimpleNamespace(bifurcations=folds)) == [(1.2, 1), (2.5, 1)]
