"""Critical speeds: root finding vs the Campbell diagram, the paper rotor, the fit."""

from __future__ import annotations

import numpy as np
import pytest
from linear_helpers import STEEL

from rotorsfd.linear import branch_frequency, campbell, critical_speeds
from rotorsfd.linear.fit import fit_support_stiffness
from rotorsfd.model import Disk, LinearSupport, Rotor, uniform_shaft


def campbell_crossings(result, harmonic: float = 1.0) -> list[float]:
    """Linear interpolation of the sign changes of w - h Omega on forward branches."""
    out = []
    g = result.frequencies - harmonic * result.speeds[:, None]
    for j in range(g.shape[1]):
        fwd = result.whirl[:, j] == "forward"
        for k in range(len(result.speeds) - 1):
            if fwd[k] and fwd[k + 1] and g[k, j] * g[k + 1, j] < 0.0:
                s0, s1 = result.speeds[k], result.speeds[k + 1]
                out.append(s0 - g[k, j] * (s1 - s0) / (g[k + 1, j] - g[k, j]))
    return sorted(out)


def test_root_finding_equals_campbell_intersection(paper):
    crit = critical_speeds(paper, n=2)
    assert [c.mode for c in crit] == [1, 2] and all(c.whirl == "forward" for c in crit)
    camp = campbell(paper, np.linspace(0.0, 4000.0, 161), n_modes=6)
    crossings = campbell_crossings(camp)[:2]
    np.testing.assert_allclose([c.speed_rad_s for c in crit], crossings, rtol=2e-4)
    # and the roots are roots: w_i(Omega) = Omega to solver precision
    for c in crit:
        w = branch_frequency(paper, c.speed_rad_s, c.mode, "forward")
        assert abs(w - c.speed_rad_s) < 1e-6 * c.speed_rad_s


def test_paper_rotor_fitted_supports_give_paper_critical_speeds(paper):
    crit = critical_speeds(paper, n=2, speed_range=(0.0, 5000.0))
    np.testing.assert_allclose([c.speed_rad_s for c in crit], [811.3, 2784.6], rtol=2e-6)


def test_backward_and_2x_critical_speeds(paper):
    """Backward 1X roots lie below forward ones; 2X roots lie below the 1X roots."""
    fwd = critical_speeds(paper, n=2, speed_range=(0.0, 5000.0))
    bwd = critical_speeds(paper, n=2, whirl="backward", speed_range=(0.0, 5000.0))
    two = critical_speeds(paper, n=1, harmonic=2.0, speed_range=(0.0, 5000.0))
    assert bwd[0].speed_rad_s < fwd[0].speed_rad_s and bwd[1].speed_rad_s < fwd[1].speed_rad_s
    w = branch_frequency(paper, two[0].speed_rad_s, 1, "forward")
    assert w == pytest.approx(2.0 * two[0].speed_rad_s, rel=1e-6)
    assert two[0].speed_rad_s < 0.55 * fwd[0].speed_rad_s


def small_rotor(k1: float, k2: float) -> Rotor:
    shaft = uniform_shaft(0.6, 6, 0.02, 0.03, STEEL)
    disk = Disk.from_geometry(3, STEEL.density, 0.03, 0.1, 0.05)
    return Rotor(shaft, disks=[disk],
                 supports=[LinearSupport.isotropic(1, k1), LinearSupport.isotropic(7, k2)])


def test_fit_recovers_known_stiffnesses():
    """Targets made by known supports are met again. Two critical speeds do not fix two
    stiffnesses uniquely (the fit from (1e7, 1e7) lands on (1.88e7, 5.16e6), another exact
    solution), so the recovery is checked from a start in the basin of the true pair."""
    true = (2.0e7, 5.0e6)
    targets = [c.speed_rad_s for c in critical_speeds(small_rotor(*true), n=2,
                                                         speed_range=(0.0, 2e4))]
    fit = fit_support_stiffness(small_rotor, targets, x0=(3e7, 3e6))
    assert fit.exact
    np.testing.assert_allclose(fit.stiffnesses, true, rtol=1e-4)
    np.testing.assert_allclose(fit.critical_speeds, targets, rtol=1e-6)


def test_fit_reports_unreachable_targets():
    """Two targets far beyond what supports up to 1e8 N/m allow: not exact, errors reported."""
    fit = fit_support_stiffness(small_rotor, (811.3 * 10, 2784.6 * 10), x0=(1e7, 1e7),
                                bounds=(1e5, 1e8))
    assert not fit.exact
    assert max(abs(r) for r in fit.relative_errors) > 1e-2
    assert "not both met" in fit.message


def test_critical_speeds_equal_synchronous_eigenproblem(paper):
    """Independent check: undamped synchronous whirl q = phi exp(i Omega t) solves
    (K - Omega^2 M + i Omega^2 G) phi = 0, i.e. K phi = Omega^2 (M - i G) phi, a
    generalized eigenproblem for Omega^2 (forward roots: forward mode shapes)."""
    import scipy.linalg

    from rotorsfd.linear import whirl_direction

    m, d0, k = paper.matrices(0.0)
    g = paper.matrices(1.0)[1] - d0
    lam, vec = scipy.linalg.eig(k, m - 1j * g)
    real = (np.abs(lam.imag) < 1e-8 * np.abs(lam)) & (lam.real > 0)
    omega = np.sqrt(lam.real[real])
    fwd = np.array([whirl_direction(v) == "forward" for v in vec[:, real].T])
    expected = np.sort(omega[fwd])[:3]
    crit = critical_speeds(paper, n=3, speed_range=(0.0, 2e4))
    np.testing.assert_allclose([c.speed_rad_s for c in crit], expected, rtol=1e-8)
