"""An element's table fields as continuation parameters (issue 16 item 4): the SFD's
clearance ratio C/R and land length, with exact derivatives, through response and the fold
curve of the paper rotor (its section 4.3 varies C/R at fixed C)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.fold_curve import run_fold_curve
from rotorsfd.continuation.folds import locate_branch_fold
from rotorsfd.errors import ConfigError
from rotorsfd.harmonic import continue_periodic
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import to_real
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.model.build import build_system

ROOT = Path(__file__).resolve().parents[2]
PAPER = ROOT / "examples" / "paper_rotor.toml"
REF = 811.3
U144 = "unbalance[0].magnitude=144.02 g*mm"


@pytest.fixture(scope="module")
def system():
    return build_system(api.load_config(PAPER, [U144]))


@pytest.mark.parametrize("field", ["clearance_ratio", "clearance", "length_to_diameter",
                                   "viscosity"])
def test_sfd_field_derivative_equals_differences(system, field):
    """dF/dp of the film at fixed samples, through the table's geometry (C/R at fixed C
    moves R and L = (L/D) 2R), against central differences of rebuilt elements (1e-7)."""
    e = system.elements["sfd"]
    C = e.clearance
    rng = np.random.default_rng(7)
    q, v = rng.uniform(-0.6, 0.6, (6, 2)) * C, rng.uniform(-1, 1, (6, 2)) * 900 * C
    x = getattr(e.table, field)
    h = 1e-6 * x
    fd = (e.with_parameter(field, x + h).force(q, v)
          - e.with_parameter(field, x - h).force(q, v)) / (2 * h)
    np.testing.assert_allclose(e.dforce(q, v, field), fd, rtol=1e-7,
                               atol=1e-7 * abs(fd).max())


def test_a_derived_field_or_an_unknown_element_is_refused(system):
    with pytest.raises(ConfigError, match=r"elements\.sfd\.radius: .*derived"):
        system.elements["sfd"].dforce(np.zeros(2), np.ones(2), "radius")
    with pytest.raises(ConfigError, match="names no element"):
        system.periodic_problem("elements.front.clearance_ratio", speed=900.0)


def test_branch_in_clearance_ratio_passes_through_rebuilt_configs(system):
    """A branch in C/R at Omega~ = 1.2 (dR/dlam from the film's exact dF/dp) against
    single-point solves of configs with the field set (1e-8 C); dR/dlam against
    differences."""
    speed, H = 1.2 * REF, 4
    problem = system.periodic_problem("elements.sfd.clearance_ratio", speed=speed)
    start = solve_periodic(problem, 0.0045, H, tol=1e-11)
    branch = continue_periodic(problem, 0.0045, 0.0065, H, start.X, tol=1e-11,
                               harmonics_tol=None)
    assert branch.success and branch.lam[-1] == pytest.approx(0.0065)
    C = system.length_scale
    for i in (branch.n_points // 3, 2 * branch.n_points // 3):
        cr = float(branch.lam[i])
        other = build_system(api.load_config(PAPER, [U144,
                                                     f"elements.sfd.clearance_ratio={cr}"]))
        point = solve_periodic(other.periodic_problem("speed"), speed, H, branch.X[i],
                               tol=1e-12)
        np.testing.assert_allclose(branch.X[i], point.X, atol=1e-8 * C)
    hb = CondensedHB(problem, H, 64)
    x = to_real(branch.X[branch.n_points // 2][:, system.nl_dofs])
    lam, h = float(branch.lam[branch.n_points // 2]), 1e-8
    hb.set_shift(x, lam)
    dR = hb.residual(x, lam)[2]
    fd = (hb.residual(x, lam + h, jac=False)[0] - hb.residual(x, lam - h, jac=False)[0])
    np.testing.assert_allclose(dR, fd.ravel() / (2 * h), rtol=1e-6,
                               atol=1e-6 * abs(dR).max())


@pytest.fixture(scope="module")
def curve():
    config = api.load_config(PAPER, [U144])
    return run_fold_curve(config, "elements.sfd.clearance_ratio", "0.485 %", "0.7 %")


@pytest.mark.slow
@pytest.mark.parametrize("cr", [0.0055, 0.0065])
def test_fold_curve_in_clearance_ratio_passes_through_speed_branch_folds(curve, cr):
    """The saddle-node curve in (speed, C/R) at U = 144 g mm passes through the folds of
    speed branches at fixed C/R (1e-4)."""
    assert curve.success, curve.message
    problem = curve.hb.problem.first(cr)
    b = continue_periodic(problem, 0.8 * REF, 1.5 * REF, curve.H, n_samples=curve.n_samples)
    expected = sorted(locate_branch_fold(b, int(i)).lam for i in b.folds())
    on_curve = curve.speeds_at(cr)
    assert len(expected) == len(on_curve) == 2
    np.testing.assert_allclose(on_curve, expected, rtol=1e-4)
