"""Neimark-Sacker curves in two parameters (harmonic/ns_curve.py) on the rotor on two
journal bearings (examples/journal_bearing_rotor.toml) with a small unbalance: the oil
whirl starts at a secondary Hopf of the unbalance response near 1057 rad/s (a multiplier
pair through the unit circle near -1). The (speed, U) curve started from the one that
Floquet locates on the branch at 1 g mm passes through the secondary Hopf that Floquet
locates, independently (monodromy multipliers through |mu| = 1), on the branch at
1.25 g mm; its theta = sigma / w is the critical multiplier's angle / 2 pi."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.continuation.folds import FoldOptions
from rotorsfd.errors import ConvergenceError
from rotorsfd.harmonic.ns_curve import NeimarkSackerSystem, continue_neimark_sacker
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.io.config import config_from_dict, read_toml
from rotorsfd.model.build import build_system
from rotorsfd.stability.branch_stability import branch_stability

EXAMPLE = Path(__file__).parents[2] / "examples" / "journal_bearing_rotor.toml"
H = 3


@pytest.fixture(scope="module")
def family():
    return build_system(config_from_dict(read_toml(EXAMPLE))).two_parameter_problem(
        "unbalance.magnitude")


def floquet_hopf(family, U: float):
    """(speed, theta, branch, point) of the secondary Hopf of the branch at ``U``."""
    p = family.first(U)
    branch = continue_periodic(p, 950.0, 1150.0, H)
    st = branch_stability(branch, p)
    (b,) = [b for b in st.bifurcations if b.kind == "secondary-hopf"]
    assert abs(abs(b.critical) - 1.0) < 1e-6
    return b.lam, abs(np.angle(b.critical)) / (2 * np.pi), branch.point_at(b.s)


@pytest.fixture(scope="module")
def curve(family):
    lam, theta, pt = floquet_hopf(family, 1e-6)
    hb, leg = continue_neimark_sacker(family, pt.X, pt.lam, 1e-6, theta, (1e-6, 1.3e-6),
                                      H=H, N=32, K=2 * H, scales=(200.0, 1e-6),
                                      options=FoldOptions(ds=0.1, ds_max=0.2))
    return hb, leg, lam, theta


def _on_curve(curve, U):
    hb, leg, *_ = curve
    (z,) = leg.solve_at(U / 1e-6)
    return hb.from_z(leg.system.embed(z))[1], float(z[-2])


def test_curve_starts_at_the_floquet_secondary_hopf(curve):
    _, leg, lam, theta = curve
    assert leg.success, leg.message
    speed, th = _on_curve(curve, 1e-6)
    assert speed == pytest.approx(lam, rel=1e-5)       # measured 1.7e-6
    assert th == pytest.approx(theta, abs=1e-4)


def test_curve_passes_through_the_secondary_hopf_at_another_unbalance(curve, family):
    lam, theta, _ = floquet_hopf(family, 1.25e-6)
    speed, th = _on_curve(curve, 1.25e-6)
    assert speed == pytest.approx(lam, rel=1e-4)       # measured 1.7e-6
    assert th == pytest.approx(theta, abs=1e-4)
    assert 0.49 < th < 0.5


def test_a_start_that_converges_elsewhere_is_refused(family):
    """From the Hopf's orbit but a speed 5 % off, the NS equations converge back near the
    Hopf, 5 % from the speed asked for: not a curve through that point, refused (before,
    such a curve was drawn from wherever Newton landed: the paper's C/R = 0.728 % case
    started its NS curves 200 rad/s from their secondary Hopf points)."""
    _, theta, pt = floquet_hopf(family, 1e-6)
    with pytest.raises(ConvergenceError) as info:
        continue_neimark_sacker(family, pt.X, 1.05 * pt.lam, 1e-6, theta, (1e-6, 1.3e-6),
                                H=H, N=32, K=2 * H, scales=(200.0, 1e-6),
                                options=FoldOptions(ds=0.1, ds_max=0.2))
    assert "converged at" in str(info.value)     # Newton found the Hopf 5 % away


def test_the_border_update_pairs_with_a_complex_null_vector():
    """update_border takes the conjugated null vectors as borders: ``bordered`` pairs a
    border with a vector by the bilinear ``c^T v``, and for a complex null vector v,
    ``v^T v`` can be far below ``|v|^2`` (the unconjugated update left the paper's
    C/R = 0.728 % Neimark-Sacker start with a near-singular bordered matrix: its Newton
    went 200 rad/s away). On a singular complex matrix with known null vectors, the
    updated borders pair with them to |c^T v| = |v| and |w^T b| = |w|."""
    rng = np.random.default_rng(7)
    n = 12
    A = rng.standard_normal((n, n)) + 1j * rng.standard_normal((n, n))
    U, s, Vh = np.linalg.svd(A)
    s[-1] = 0.0
    A = (U * s) @ Vh
    v_null, w_null = np.conj(Vh[-1]), np.conj(U[:, -1])     # A v = 0, w^T A = 0
    ns = object.__new__(NeimarkSackerSystem)
    ns.hill = lambda z: A
    ns.b = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    ns.c = rng.standard_normal(n) + 1j * rng.standard_normal(n)
    ns.update_border(np.zeros(3))
    assert abs(ns.c @ v_null) == pytest.approx(1.0, abs=1e-10)
    assert abs(w_null @ ns.b) == pytest.approx(1.0, abs=1e-10)
    # the unconjugated pairing of the same vector is far from 1 here (what it was before)
    assert abs(v_null @ v_null) < 0.9
