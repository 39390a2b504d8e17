"""Branches of a census' attractors (rotorsfd.analyses.attractor_branches): a hardening
Duffing oscillator inside its fold interval has two stable orbits on one S-shaped branch.
Traced from the census, that branch must be the one a continuation from low frequency
finds (its located folds to 1e-8), with both attractors on it (the second not traced again) and
the unstable middle orbit crossed too; Floquet stability along it: stable outside the
folds, unstable between."""

import numpy as np
import pytest

from rotorsfd.analyses.attractor_branches import trace_attractor_branches
from rotorsfd.analyses.attractors import CensusModel, CensusOptions, census
from rotorsfd.analyses.td_integration import TimeDomainInputs
from rotorsfd.continuation.folds import locate_branch_fold
from rotorsfd.errors import ConfigError
from rotorsfd.harmonic import continue_periodic, solve_periodic
from rotorsfd.harmonic.examples import duffing
from rotorsfd.harmonic.orbit_branch import SAME_TOL, crossings, on_branch
from rotorsfd.timedomain import Forcing, HarmonicLoad
from rotorsfd.timedomain.kernels import cubic_spring_kernel

C, K, K3, F = 0.05, 1.0, 0.1, 0.1        # x'' + C x' + K x + K3 x^3 = F cos(w t)
W, H = 1.09, 7                            # inside the fold interval (1.0762, 1.1161)


def fold_speeds(branch) -> np.ndarray:
    """The branch's turning points in lam, ascending, each located by
    ``locate_branch_fold`` (dlam/ds = 0 on the re-solved branch)."""
    return np.sort([locate_branch_fold(branch, int(i)).lam for i in branch.folds()])


@pytest.fixture(scope="module")
def traced():
    inputs = TimeDomainInputs(np.eye(1), np.array([[C]]), np.array([[K]]), np.array([0]),
                              cubic_spring_kernel, np.array([0.0, K3]),
                              Forcing(omega=W, harmonics=[HarmonicLoad(1.0, np.array([F]))]),
                              None, W)
    problem = duffing(C, K, K3, F)
    opts = CensusOptions(n_starts=24, steps_per_period=100, displacement_fraction=0.9,
                         velocity_fraction=0.9, max_periods=600, harmonics=H)
    c = census(CensusModel(inputs, np.array([3.0]), problem), opts)
    return problem, c, trace_attractor_branches(problem, c, 0.5, 2.0)


def test_both_orbits_on_one_branch_with_the_low_frequency_folds(traced):
    problem, c, branches = traced
    periodic = [b for b in branches if c.attractors[b.attractor].period == 1]
    assert len(periodic) == 2
    first, second = periodic
    assert first.traced and not first.closed
    assert second.on_branch_of == first.attractor and not second.traced
    reference = continue_periodic(problem, 0.5, 2.0, H)       # independent: from w = 0.5
    f_ref, f_got = fold_speeds(reference), fold_speeds(first.branch)
    assert f_ref.size == f_got.size == 2
    np.testing.assert_allclose(f_got, f_ref, rtol=1e-8)
    np.testing.assert_allclose(f_got, [1.0762, 1.1161], atol=1e-4)
    lo, hi = first.speed_range()
    assert lo == pytest.approx(0.5, rel=1e-9) and hi == pytest.approx(2.0, rel=1e-9)


def test_the_three_orbits_at_the_census_speed_are_crossed(traced):
    """The branch crosses w = W three times: at the two stable HB orbits and the
    unstable middle one, each solved here by Newton from the reference branch."""
    problem, _, branches = traced
    branch = branches[0].branch if branches[0].traced else branches[1].branch
    found = crossings(problem, branch, W)
    assert len(found) == 3
    reference = continue_periodic(problem, 0.5, 2.0, H)
    lam = reference.lam
    hits = np.nonzero((lam[:-1] - W) * (lam[1:] - W) < 0)[0]
    assert hits.size == 3
    for j in hits:
        sol = solve_periodic(problem, W, H, reference.X[j], condensed=True)
        assert on_branch(problem, branch, W, sol.X)
        shifted = sol.X.copy()
        shifted[1, 0] += 10 * SAME_TOL
        assert not on_branch(problem, branch, W, shifted)


def test_stability_along_the_branch(traced):
    """Stable below the lower fold point in the arc and above the upper, unstable on the
    middle part: the Floquet stability of the traced branch against its fold indices."""
    _, _, branches = traced
    b = next(b for b in branches if b.traced)
    i, j = sorted(b.branch.folds())
    assert b.stable[: i - 1].all() and b.stable[j + 2:].all()
    assert not b.stable[i + 2: j - 1].any()


def test_range_without_the_census_speed_is_rejected(traced):
    problem, c, _ = traced
    with pytest.raises(ConfigError, match="census speed"):
        trace_attractor_branches(problem, c, 1.2, 2.0)


@pytest.mark.slow
def test_paper_census_branches_the_main_branch_and_the_isola(tmp_path):
    """Figure 23's case (C/R = 0.728 %) at Omega~ = 1.075 from the command line: the
    main branch open and the plain speed branch from Omega~ = 0.5 (its 1X amplitude at
    Omega~ = 0.9 to 2e-3 C, the file's points interpolated); the isola closed
    between its folds 1.0259 / 1.0939 (README, from `response --from-orbit` of a
    time-domain orbit: a different start), to the branch's point spacing (2e-3)."""
    import csv
    from pathlib import Path

    from rotorsfd.analyses.context import build
    from rotorsfd.analyses.response import run_response
    from rotorsfd.cli import main
    from rotorsfd.io.config import load_config

    config_path = Path(__file__).resolve().parents[2] / "examples/paper/fig23_time_domain.toml"
    out = tmp_path / "census"
    status = main(["attractors", str(config_path), "--speed-ratio", "1.075", "--starts", "24",
                   "--harmonics", "16", "--workers", "2", "--branches", "-o", str(out),
                   "--quiet"])
    assert status == 0
    rows = list(csv.DictReader(open(out / "attractor_branches.csv")))
    kinds = {r["branch"] for r in rows if r["on_branch_of"] == r["attractor"]}
    assert {"open", "isola"} <= kinds
    isola = next(r for r in rows if r["branch"] == "isola")
    ref = 811.3
    lo, hi = float(isola["speed_min_rad_s"]) / ref, float(isola["speed_max_rad_s"]) / ref
    assert lo == pytest.approx(1.0259, abs=2e-3) and hi == pytest.approx(1.0939, abs=2e-3)
    main_row = next(r for r in rows if r["branch"] == "open")
    traced = list(csv.DictReader(open(out / f"branch_motion{int(main_row['attractor']) + 1}.csv")))
    assert float(traced[0]["speed_rad_s"]) == pytest.approx(0.5 * ref, rel=1e-3)

    config = load_config(config_path, overrides=["analysis.response.harmonics=16"])
    plain = run_response(config, progress=False, stability_options=False)
    problem = build(config, config_path.parent).periodic_problem()
    d0 = int(problem.nl_dofs[0])
    scale = float(problem.dof_scale[d0])
    at = 0.9 * ref                           # below the isola: one crossing of each
    (X,) = crossings(problem, plain.branch, at)
    speed = np.array([float(r["speed_rad_s"]) for r in traced])
    amp = np.array([float(r["amplitude_1x_dof0"]) for r in traced])
    k = int(np.nonzero((speed[:-1] - at) * (speed[1:] - at) <= 0)[0][0])
    w = (at - speed[k]) / (speed[k + 1] - speed[k])
    assert (1 - w) * amp[k] + w * amp[k + 1] == pytest.approx(abs(X[1, d0]) / scale,
                                                              abs=2e-3)


def test_branches_outside_the_speed_range_is_one_line_exit_2(tmp_path, capsys):
    """--branches with a census speed outside [analysis.response] speed_range (the
    default 0.5-1.6) is refused before any integration."""
    from pathlib import Path

    from rotorsfd.cli import main

    config = Path(__file__).resolve().parents[2] / "examples/paper/fig23_time_domain.toml"
    status = main(["attractors", str(config), "--speed-ratio", "1.7", "--branches",
                   "-o", str(tmp_path / "x")])
    err = capsys.readouterr().err.strip().splitlines()
    assert status == 2 and len(err) == 1
    assert "--branches" in err[0] and "1.7" in err[0] and "speed_range" in err[0]
    assert not (tmp_path / "x" / "attractors.csv").exists()


def duffing_census(w: float):
    inputs = TimeDomainInputs(np.eye(1), np.array([[C]]), np.array([[K]]), np.array([0]),
                              cubic_spring_kernel, np.array([0.0, K3]),
                              Forcing(omega=w, harmonics=[HarmonicLoad(1.0, np.array([F]))]),
                              None, w)
    opts = CensusOptions(n_starts=24, steps_per_period=100, displacement_fraction=0.9,
                         velocity_fraction=0.9, max_periods=600, harmonics=H)
    return census(CensusModel(inputs, np.array([3.0]), duffing(C, K, K3, F)), opts)


def fine_crossings(problem, branch, w: float) -> np.ndarray:
    """The branch's orbits at ``w``: Newton to 1e-13 from the coefficients interpolated
    between the points around each crossing, sorted by |X_1| (independent of
    on_branch's tolerance)."""
    lam = branch.lam
    out = []
    d = lam - w
    for j in np.nonzero((d[:-1] * d[1:] < 0) | (d[:-1] == 0))[0]:
        a = (w - lam[j]) / (lam[j + 1] - lam[j])
        X0 = (1 - a) * branch.X[j] + a * branch.X[j + 1]
        out.append(solve_periodic(problem, w, branch.H, X0, tol=1e-13).X)
    return np.array(sorted(out, key=lambda X: abs(X[1, 0])))


def test_a_stride_traces_each_branch_once(monkeypatch):
    """Two census speeds inside the fold interval: both have their two stable orbits on
    the one S-branch. Over the stride it is traced once (at the first speed) and taken at
    the second; run apart, each speed traces it: the same branch (its orbits at 16 speeds
    over the range and at the census speeds to 1e-10, its range and its folds to 1e-8)
    with half the traces."""
    from rotorsfd.analyses import attractor_branches as ab

    problem = duffing(C, K, K3, F)
    speeds = (1.09, 1.10)
    censuses = [duffing_census(w) for w in speeds]
    calls = []
    trace = ab.continue_both_ways

    def counted(*args, **kw):
        calls.append(args[1])
        return trace(*args, **kw)

    monkeypatch.setattr(ab, "continue_both_ways", counted)
    stride = ab.trace_census_branches(problem, censuses, 0.5, 2.0, stability=False)
    n_stride = len(calls)
    apart = [ab.trace_attractor_branches(problem, c, 0.5, 2.0, stability=False)
             for c in censuses]
    assert n_stride == 1 and len(calls) - n_stride == 2
    result = ab.AttractorBranches(censuses, stride, np.array([0]), np.array([3.0]))
    assert result.traces == 1
    for k, (mine, theirs) in enumerate(zip(stride, apart, strict=True)):
        assert [b.on_branch_of for b in mine] == [b.on_branch_of for b in theirs]
        assert [b.traced for b in mine] == [b.traced for b in theirs]
        got = next(b for b in mine if b.traced)
        ref = next(b for b in theirs if b.traced)
        assert got.info["traced_at"] == speeds[0]
        assert got.branch is next(b for b in stride[0] if b.traced).branch
        assert ref.info["traced_at"] == speeds[k]
        assert got.closed == ref.closed
        np.testing.assert_allclose(got.speed_range(), ref.speed_range(), rtol=1e-10)
        np.testing.assert_allclose(fold_speeds(got.branch), fold_speeds(ref.branch),
                                   rtol=1e-8)
        for w in (*np.linspace(0.55, 1.95, 16), *speeds):
            a, b = fine_crossings(problem, got.branch, w), fine_crossings(problem,
                                                                         ref.branch, w)
            assert a.shape == b.shape and a.shape[0] in (1, 3)
            assert np.max(np.abs(a - b)) / 3.0 < 1e-10         # measured 8e-14
