"""Stability along a branch: folds located at the branch's turning points (Duffing, to the
1e-6 rule), Newmark (Craig-Bampton) and Hill agree near bifurcations (Duffing, a small
rotor with an SFD), the reported multipliers, the reduction basis reused per (M, K)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.optimize import fsolve, minimize_scalar

from rotorsfd.harmonic.examples import duffing, generic_chain
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.stability import orbit_floquet
from rotorsfd.stability.branch_stability import (
    FloquetEvaluator,
    StabilityOptions,
    branch_stability,
)

C, K1, K3, F = 0.05, 1.0, 0.1, 0.3


@pytest.fixture(scope="module")
def duffing_case():
    p = duffing(c=C, k=K1, k3=K3, F=F)
    b = continue_periodic(p, 0.5, 2.5, 5, ds=0.05, ds_max=0.2)
    assert b.success and len(b.folds()) == 2
    return p, b, branch_stability(b, p)


def turning_point(branch, i: int) -> float:
    """lam at the fold between points i and i+1, by maximising +-lam(s) (Brent, bounded)
    over [s_{i-1}, s_{i+2}] with branch.point_at."""
    sign = np.sign(branch.dlam_ds[i])   # +1: lam has a maximum there
    lo, hi = branch.s[max(i - 1, 0)], branch.s[min(i + 2, branch.n_points - 1)]
    res = minimize_scalar(lambda s: -sign * branch.point_at(s).lam, bounds=(lo, hi),
                          method="bounded", options={"xatol": 1e-10})
    return float(branch.point_at(res.x).lam)


def test_duffing_folds_are_the_turning_points(duffing_case):
    _, b, st = duffing_case
    assert [x.kind for x in st.bifurcations] == ["saddle-node", "saddle-node"]
    for bif, i in zip(st.bifurcations, b.folds(), strict=True):
        lam_turn = turning_point(b, int(i))
        assert abs(bif.lam - lam_turn) <= 1e-6 * lam_turn
        assert bif.via == "tangent"
        # the multiplier exactly at the fold is +1 up to Newmark's O(h^2) error
        assert abs(bif.critical - 1.0) < 5e-3


def test_duffing_h1_folds_match_the_closed_form():
    """H = 1: a^2 [(k - w^2 + 3/4 k3 a^2)^2 + (c w)^2] = F^2 with dG/da = 0 at a fold."""
    p = duffing(c=C, k=K1, k3=K3, F=F)
    b = continue_periodic(p, 0.5, 2.5, 1, ds=0.05, ds_max=0.2)
    st = branch_stability(b, p)
    folds = [x for x in st.bifurcations if x.via == "tangent"]
    assert len(folds) == 2

    def eqs(z):
        a2, w = z
        g = K1 - w**2 + 0.75 * K3 * a2
        return [a2 * (g**2 + (C * w) ** 2) - F**2,
                g**2 + (C * w) ** 2 + a2 * 2 * g * 0.75 * K3]

    for bif in folds:
        pt = b.point_at(bif.s)
        _, w = fsolve(eqs, [abs(pt.X[1, 0]) ** 2, bif.lam], xtol=1e-13)
        assert abs(bif.lam - w) <= 1e-6 * w


def test_duffing_unstable_exactly_between_the_folds(duffing_case):
    _, b, st = duffing_case
    mm = st.max_multiplier
    clear = np.abs(mm - 1.0) > 1e-3          # away from the folds
    middle = b.dlam_ds < 0                   # the turned-back segment
    np.testing.assert_array_equal(~st.stable[clear], middle[clear])
    assert np.all(st.n_multipliers == 2)


def test_reported_multiplier_is_the_nearest_unstable_point(duffing_case):
    _, b, st = duffing_case
    for row, bif in zip(st.rows(), st.bifurcations, strict=True):
        j = row["point"]
        assert not st.stable[j] and abs(b.s[j] - bif.s) == min(
            abs(b.s[k] - bif.s) for k in np.nonzero(~st.stable)[0])
        assert row["max_multiplier"] == pytest.approx(st.max_multiplier[j], rel=1e-14)
        assert row["multiplier_re"] > 1 + st.tol and row["multiplier_im"] == 0.0
        assert row["parameter"] == bif.lam and row["speed_ratio"] == bif.lam


def same(a, b) -> float:
    """Distance of two Floquet results in the well-conditioned quantities: ``|mu|max`` and
    the trace of the monodromy (sum of the multipliers). The critical multiplier itself
    is ill-conditioned (square root) where a complex pair meets the real axis."""
    return max(abs(a.max_abs - b.max_abs), abs(a.multipliers.sum() - b.multipliers.sum()))


def near_bifurcation_points(b, st, k: int = 2) -> list[int]:
    out = set()
    for bif in st.bifurcations:
        ia, ib = bif.info["bracket"]
        out.update(range(max(min(ia, ib) - k, 0), min(max(ia, ib) + k + 1, b.n_points)))
    return sorted(out)


@pytest.mark.parametrize(("n_intervals", "atol"), [(400, 3e-3), (1600, 3e-4)])
def test_newmark_and_hill_agree_near_duffing_folds(duffing_case, n_intervals, atol):
    """Newmark's error is O(h^2): 2.3e-3 at N = 400 on this orbit, 16x less at 1600."""
    p, b, st = duffing_case
    nm = FloquetEvaluator(p, StabilityOptions(n_intervals=n_intervals))
    hill = FloquetEvaluator(p, StabilityOptions(method="hill", n_harmonics=12))
    pts = near_bifurcation_points(b, st)
    assert len(pts) >= 8
    for i in pts:
        a, h = nm(b.lam[i], b.X[i]), hill(b.lam[i], b.X[i])
        assert same(a, h) < atol
        if abs(h.max_abs - 1) > atol:
            assert a.stable == h.stable


@pytest.fixture(scope="module")
def rotor_case(tmp_path_factory):
    """The small rotor of the response tests (SFD at node 1): a saddle-node pair at
    U = 100 g mm."""
    from rotors import small_rotor_toml
    from rotorsfd import api

    path = small_rotor_toml(tmp_path_factory.mktemp("bs") / "small.toml",
                            unbalance="100 g*mm")
    result = api.run_response(api.load_config(path), progress=False)
    return result


def test_rotor_saddle_node_pair_and_methods_agree(rotor_case):
    r = rotor_case
    st = r.info["stability"]
    assert [x.kind for x in st.bifurcations] == ["saddle-node", "saddle-node"]
    lam = [x.lam for x in st.bifurcations]
    assert lam[0] > lam[1]                              # a bistable range between them
    folds = r.branch.folds()
    for bif, i in zip(st.bifurcations, folds, strict=True):
        ends = r.branch.lam[[i, i + 1]]          # a maximum of lam, then a minimum
        assert (bif.lam >= ends.max()) if r.branch.dlam_ds[i] > 0 else (bif.lam <= ends.min())
    problem = r.system.periodic_problem("speed")
    hill = FloquetEvaluator(problem, StabilityOptions(method="hill"))
    # the response ran with the step control (interval_tolerance 1e-4): the same
    # options give its multipliers to that tolerance, whatever M each point settled on
    nm = FloquetEvaluator(problem, StabilityOptions(interval_tol=1e-4))
    for i in near_bifurcation_points(r.branch, st):
        a, h = nm(r.branch.lam[i], r.branch.X[i]), hill(r.branch.lam[i], r.branch.X[i])
        assert abs(a.max_abs - h.max_abs) < 1e-3
        assert min(abs(a.critical - h.critical), abs(a.critical - np.conj(h.critical))) < 2e-3
        assert abs(a.max_abs - st.max_multiplier[i]) < 3e-4
        if abs(h.max_abs - 1) > 1e-3:
            assert a.stable == h.stable == st.stable[i]
    assert st.n_bases == 1                              # M, K do not change with speed


def test_cached_reduction_equals_orbit_floquet(rotor_case):
    r = rotor_case
    problem = r.system.periodic_problem("speed")
    ev = FloquetEvaluator(problem)
    for i in (0, r.branch.n_points // 2, r.branch.n_points - 1):
        M, D, K = problem.matrices(r.branch.lam[i])
        ref = orbit_floquet(M, D, K, r.branch.X[i], r.branch.frequency[i],
                            problem.nl_dofs, problem.nl_jacobian)
        got = ev(r.branch.lam[i], r.branch.X[i])
        np.testing.assert_allclose(got.multipliers, ref.multipliers, atol=1e-10)
    assert ev.n_bases == 1


def test_step_control_and_basis_intervals_against_orbit_floquet(rotor_case):
    # the step control runs M and M/2 on one reduced model with the Jacobian samples of M
    # reused for M/2; basis_intervals keeps the modes of another M (the bifurcation
    # check's): both against orbit_floquet's own Craig-Bampton reduction and sampling
    r = rotor_case
    problem = r.system.periodic_problem("speed")
    i = r.branch.n_points // 2
    lam, X, w = r.branch.lam[i], r.branch.X[i], r.branch.frequency[i]
    T = 2 * np.pi / w
    M, D, K = problem.matrices(lam)
    ctrl = FloquetEvaluator(problem, StabilityOptions(interval_tol=1e-6))(lam, X)
    n = ctrl.info["n_intervals"]
    ref = orbit_floquet(M, D, K, X, w, problem.nl_dofs, problem.nl_jacobian, n_intervals=n,
                        omega_max=0.25 * 400 / T)
    np.testing.assert_allclose(ctrl.multipliers, ref.multipliers, atol=1e-10)
    half = orbit_floquet(M, D, K, X, w, problem.nl_dofs, problem.nl_jacobian,
                         n_intervals=n // 2, omega_max=0.25 * 400 / T)
    err = float(np.max(np.abs(np.sort(np.abs(ref.multipliers))[::-1][:4]
                              - np.sort(np.abs(half.multipliers))[::-1][:4]))) / 3
    assert ctrl.info["multiplier_error"] == pytest.approx(err, rel=1e-6, abs=1e-12)
    kept = FloquetEvaluator(problem, StabilityOptions(n_intervals=3200, basis_intervals=400))
    grown = FloquetEvaluator(problem, StabilityOptions(n_intervals=3200))
    a, g = kept(lam, X), grown(lam, X)
    ref = orbit_floquet(M, D, K, X, w, problem.nl_dofs, problem.nl_jacobian,
                        n_intervals=3200, omega_max=0.25 * 400 / T)
    np.testing.assert_allclose(a.multipliers, ref.multipliers, atol=1e-10)
    assert a.info["n_modes"] < g.info["n_modes"]       # the modes of M = 400, not 3200


def test_basis_recomputed_when_k_changes():
    p = generic_chain()           # K depends on lam
    b = continue_periodic(p, 0.5, 0.6, 2, ds=0.05)
    ev = FloquetEvaluator(p, StabilityOptions(n_modes=2))
    for i in range(b.n_points):
        M, D, K = p.matrices(b.lam[i])
        ref = orbit_floquet(M, D, K, b.X[i], b.frequency[i], p.nl_dofs, p.nl_jacobian,
                            n_modes=2)
        np.testing.assert_allclose(ev(b.lam[i], b.X[i]).multipliers, ref.multipliers,
                                   atol=1e-10)
    assert ev.n_bases == b.n_points


def test_options_reject_unknown_method():
    from rotorsfd.errors import ConfigError

    with pytest.raises(ConfigError):
        StabilityOptions(method="runge-kutta")


def test_rotor_secondary_hopf_located_and_confirmed_by_hill(tmp_path):
    """U = 300 g mm: before journal contact a complex pair leaves the unit circle."""
    from rotors import small_rotor_toml
    from rotorsfd import api

    path = small_rotor_toml(tmp_path / "small.toml", unbalance="300 g*mm")
    r = api.run_response(api.load_config(path), progress=False)
    st = r.info["stability"]
    hopf = [b for b in st.bifurcations if b.kind == "secondary-hopf"]
    assert len(hopf) == 1
    b = hopf[0]
    assert abs(abs(b.critical) - 1) < 1e-5 and b.critical.imag > 1e-2
    row = st.rows(r.reference_speed)[st.bifurcations.index(b)]
    assert row["max_multiplier"] > 1 + st.tol and row["multiplier_im"] > 0
    j = row["point"]
    problem = r.system.periodic_problem("speed")
    hill = FloquetEvaluator(problem, StabilityOptions(method="hill"))(
        r.branch.lam[j], r.branch.X[j])
    assert hill.crossing_type == "secondary-hopf"
    assert abs(hill.max_abs - row["max_multiplier"]) < 1e-4


def test_split_modules_keep_the_names_importable_from_branch_stability():
    """The options, the evaluator and the result live in their own modules (one job each);
    ``rotorsfd.stability.branch_stability`` still exports the same objects."""
    import rotorsfd.stability.branch_stability as bs
    from rotorsfd.stability import branch_options, branch_result, floquet_evaluator

    for module in (branch_options, branch_result, floquet_evaluator):
        for name in bs.__all__:
            if hasattr(module, name):
                assert getattr(bs, name) is getattr(module, name), name
    assert set(bs.__all__) <= set(dir(bs))
    assert bs.FloquetEvaluator is floquet_evaluator.FloquetEvaluator
    assert bs.StabilityOptions is branch_options.StabilityOptions
    assert bs.BranchStability is branch_result.BranchStability
