"""Attractor census (rotorsfd.analyses.attractors): a hardening Duffing oscillator inside
its fold interval has two stable periodic orbits; the census must find both, with the HB
branch's amplitudes, and basin fractions that agree with a dense grid of starts
integrated here by the same scheme (Newmark average acceleration, the same step)."""

import numpy as np
import pytest

from rotorsfd.analyses.attractors import (
    CensusModel,
    CensusOptions,
    census,
    settled,
    settled_period,
    unit_samples,
)
from rotorsfd.analyses.attractors_result import set_distance
from rotorsfd.analyses.td_integration import TimeDomainInputs
from rotorsfd.errors import ConfigError
from rotorsfd.harmonic import continue_periodic, solve_periodic
from rotorsfd.harmonic.examples import duffing
from rotorsfd.timedomain import Forcing, HarmonicLoad
from rotorsfd.timedomain.kernels import cubic_spring_kernel

C, K, K3, F = 0.05, 1.0, 0.1, 0.1        # x'' + C x' + K x + K3 x^3 = F cos(w t)
W = 1.09                                  # inside the fold interval (1.0762, 1.1161)
SCALE, FRACTION, SPP = 3.0, 0.9, 100


def duffing_model(w: float = W) -> CensusModel:
    inputs = TimeDomainInputs(np.eye(1), np.array([[C]]), np.array([[K]]), np.array([0]),
                              cubic_spring_kernel, np.array([0.0, K3]),
                              Forcing(omega=w, harmonics=[HarmonicLoad(1.0, np.array([F]))]),
                              None, w)
    return CensusModel(inputs, np.array([SCALE]), duffing(C, K, K3, F))


@pytest.fixture(scope="module")
def result():
    opts = CensusOptions(n_starts=48, steps_per_period=SPP, displacement_fraction=FRACTION,
                         velocity_fraction=FRACTION, max_periods=600, harmonics=7)
    return census(duffing_model(), opts)


def dense_fraction(n: int = 40, periods: int = 400) -> tuple[float, float]:
    """Fraction of an n x n grid of starts over the census box that ends on the large
    orbit, and the threshold amplitude: the trapezoidal rule (Newmark average
    acceleration) at h = T / SPP, vectorised over the starts, Newton on
    (4/h^2 + 2C/h + K) d = g0 + g1(d) + 4 v0 / h - 2 K q0, g = F cos(w t) - K3 q^3."""
    g = (np.arange(n) + 0.5) / n
    Q, V = np.meshgrid(FRACTION * SCALE * (2 * g - 1), FRACTION * SCALE * W * (2 * g - 1))
    q, v = Q.ravel().copy(), V.ravel().copy()
    T = 2 * np.pi / W
    h = T / SPP
    keff = 4 / h**2 + 2 * C / h + K
    amp = np.zeros_like(q)
    for step in range(periods * SPP):
        t0, t1 = step * h, (step + 1) * h
        g0 = F * np.cos(W * t0) - K3 * q**3
        rhs0 = g0 + F * np.cos(W * t1) + 4 * v / h - 2 * K * q
        d = v * h
        for _ in range(30):
            r = keff * d - rhs0 + K3 * (q + d) ** 3
            dd = r / (keff + 3 * K3 * (q + d) ** 2)
            d -= dd
            if np.max(np.abs(dd)) < 1e-13:
                break
        q, v = q + d, 2 * d / h - v
        if step >= (periods - 1) * SPP:
            amp = np.maximum(amp, np.abs(q))
    return amp, q


def hb_amplitudes() -> list[float]:
    """|X_1| of the two stable HB solutions at W (upper part before the first fold,
    lower after the second) of the Duffing branch."""
    prob = duffing(C, K, K3, F)
    b = continue_periodic(prob, 0.5, 2.0, 7)
    f1, f2 = b.folds()
    out = []
    for sl in (slice(0, f1 + 1), slice(f2 + 1, None)):
        i = np.argmin(np.abs(b.lam[sl] - W))
        out.append(abs(solve_periodic(prob, W, 7, b.X[sl][i], tol=1e-10).X[1, 0]))
    return sorted(out)


def test_duffing_two_orbits_with_hb_amplitudes(result):
    kinds = [(a.motion, len(a.members)) for a in result.attractors]
    assert [k for k, _ in kinds] == ["period-1", "period-1"], result.summary()
    amps = sorted(abs(a.hb["hb_X"][1, 0]) for a in result.attractors)
    assert amps == pytest.approx(hb_amplitudes(), rel=1e-6)
    for a in result.attractors:
        assert a.hb["hb_stable"] and a.hb["hb_max_multiplier"] < 1.0
        # the settled orbit at T/100 against its HB correction: the step's error, of
        # order (w h)^2 / 12 = 3e-4 of the amplitude times the response's sensitivity
        # near the folds (< 1 % of the amplitude)
        assert a.hb["hb_orbit_difference"] < 5e-3
        assert a.hb["step_check"] < 1e-2


@pytest.mark.slow
def test_duffing_basins_against_dense_grid(result):
    amp, _ = dense_fraction(periods=250)
    lo, hi = hb_amplitudes()
    big = amp > 0.5 * (lo + hi)
    assert np.all((np.abs(amp - lo) < 0.05 * lo) | (np.abs(amp - hi) < 0.05 * hi))
    p_dense = float(big.mean())
    large = max(result.attractors, key=lambda a: abs(a.hb["hb_X"][1, 0]))
    p, se = result.fraction(large)
    assert se == pytest.approx(np.sqrt(p * (1 - p) / 48))
    assert 0.05 < p_dense < 0.95
    assert abs(p - p_dense) <= 3 * se, (p, se, p_dense)


def test_settled_period_and_phase_free_matching():
    P = np.tile([[0.1, 0.2], [0.3, -0.1], [-0.2, 0.0]], (6, 1))
    assert settled_period(P, 1e-6, 3, 8) == 3
    assert settled_period(P + 1e-3 * np.arange(18)[:, None], 1e-6, 3, 8) is None
    rolled = np.roll(P[:3], 1, axis=0)
    assert set_distance(P[:3], rolled) == 0.0
    assert set_distance(P[:3], rolled + 0.01) == pytest.approx(0.01)


def test_latin_hypercube_strata_and_grid():
    u = unit_samples(16, 3, "lhs", seed=1)
    assert all(sorted(np.floor(u[:, j] * 16).astype(int)) == list(range(16))
               for j in range(3))
    g = unit_samples(9, 2, "grid")
    assert g.shape == (9, 2)
    assert np.unique(g[:, 0]) == pytest.approx([1 / 6, 0.5, 5 / 6])


def test_bad_options_name_the_field():
    with pytest.raises(ConfigError, match=r"attractors\.sampling"):
        CensusOptions(sampling="random").validate()
    with pytest.raises(ConfigError, match="displacement_fraction"):
        CensusOptions(displacement_fraction=1.5).validate()


@pytest.mark.slow
def test_speed_map_one_table_with_a_speed_column(tmp_path):
    import csv

    from rotorsfd.analyses.attractors import census_map
    from rotorsfd.analyses.attractors_result import write_census

    opts = CensusOptions(n_starts=24, steps_per_period=64, displacement_fraction=FRACTION,
                         velocity_fraction=FRACTION, max_periods=400, harmonics=5)
    maps = census_map([duffing_model(W), duffing_model(1.3)], opts)
    paths = write_census(maps, tmp_path, ["x(0) / 3", "x'(0) / (3 w)"], "Duffing")
    rows = list(csv.DictReader(open(paths["attractors.csv"])))
    per_speed = {}
    for r in rows:
        per_speed.setdefault(float(r["speed_rad_s"]), []).append(r)
    assert sorted(per_speed) == [W, 1.3]
    assert len(per_speed[W]) == 2                   # inside the fold interval: two orbits
    (single,) = per_speed[1.3]                      # above it: one
    assert float(single["basin_fraction"]) == 1.0 and float(single["basin_se"]) == 0.0
    for group_rows in per_speed.values():
        assert sum(float(r["basin_fraction"]) for r in group_rows) == pytest.approx(1.0)
    text = paths["attractors.csv"].read_text() + paths["summary.json"].read_text()
    assert "nan" not in text.lower()
    assert len(list(csv.DictReader(open(paths["starts.csv"])))) == 48


def test_flip_transient_into_a_period_1_orbit_is_not_period_2():
    """Returns r_k (-0.95)^k, r_0 = 1e-2 (a multiplier near -1, close to a period
    doubling): the 2-period differences |mu^2 - 1| r_k = 0.0975 r_k drop below 1e-4 long
    before the one-period ones 1.95 r_k; the census must not call that period-2."""
    k = np.arange(60)
    P = (1e-2 * (-0.95) ** k)[:, None]
    opts = CensusOptions(settle_tol=1e-4, n_max=8, check_periods=10)
    assert settled_period(P, 1e-4, 3, 8) == 2          # the trap
    assert settled(P, opts) is None
    true2 = np.tile([[0.3], [-0.2]], (30, 1))
    assert settled(true2, opts) == 2                   # a true period-2 orbit
    near = np.tile([[0.3], [0.3 + 1e-3]], (30, 1))     # 2 points within cluster_tol
    assert settled_period(near, 1e-4, 3, 8) == 2 and settled(near, opts) is None


def test_capture_by_a_settled_orbit():
    """A start's returns spiralling into a known period-2 cycle (in phase, contracting,
    within capture_tol) are captured by it; the same returns growing, out of phase, far,
    or with capture off, are not."""
    from rotorsfd.analyses.attractors import captured

    cycle = np.array([[0.3, -0.8], [-0.2, -0.9]])
    k = np.arange(20)
    spiral = 4e-3 * 0.8 ** k[:, None] * np.c_[np.cos(2.0 * k), np.sin(2.0 * k)]
    P = cycle[k % 2] + spiral
    o = CensusOptions(capture_tol=5e-3)
    known = [(7, 2, cycle)]
    assert captured(P, known, o) == 7
    assert captured(cycle[k % 2] + spiral[::-1], known, o) is None        # growing
    assert captured(cycle[(k + 1) % 2] + spiral, known, o) == 7            # other phase
    assert captured(cycle[k // 2 % 2] + spiral, known, o) is None          # not a cycle
    assert captured(P + 0.02, known, o) is None                            # too far
    assert captured(P, known, CensusOptions(capture_tol=0.0)) is None
    assert captured(P[:5], known, o) is None                               # too few
    with pytest.raises(ConfigError, match=r"attractors\.capture_tol"):
        CensusOptions(capture_tol=0.02).validate()


def test_capture_keeps_the_census(result):
    """The Duffing census without capture: the same two orbits with the same members
    (the capture only shortens transients), at more periods."""
    off = census(duffing_model(), CensusOptions(
        n_starts=48, steps_per_period=SPP, displacement_fraction=FRACTION,
        velocity_fraction=FRACTION, max_periods=600, harmonics=7, capture_tol=0.0))
    assert np.array_equal(off.labels(), result.labels())
    assert any(r.note.startswith("captured") for r in result.outcomes)
    assert sum(r.periods_run for r in result.outcomes) < \
        sum(r.periods_run for r in off.outcomes)
