"""The structural modes above the Craig-Bampton cut-off (issue 22 item 4): on the paper
rotor at a stable point (700 rad/s, Omega~ 0.86, H = 3) the largest multiplier of the
unreduced monodromy equals max(reduced, outside); the outside value is exp(lambda T) of the
averaged model (rotorsfd.stability.outside).

Tolerance: the full-model Newmark at N intervals under-damps a mode by the trapezoidal
rule's error, ``log|r(z)^N| = Re(lambda) T (1 - (omega h)^2 / 4 + ...)``: for the least
damped left-out mode (omega = 29210 rad/s, |mu| = 0.9896, log|mu| = -0.0105) at N = 1600,
omega h = 0.164, so the full model's |mu| is high by 0.0105 * 0.164^2 / 4 = 7.1e-5; the
averaging drops the periodic part of the SFD Jacobian at second order. 2e-4 allows both.
The reduced model's own Newmark error at its M = 400 is below 1e-5 at this point.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.stability.branch_options import StabilityOptions
from rotorsfd.stability.floquet_evaluator import FloquetEvaluator
from rotorsfd.stability.outside import exact_multipliers, mode_eigenvalues, newmark_multipliers

ROOT = Path(__file__).resolve().parents[2]
SPEED = 700.0


def _point(overrides: list[str]):
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem

    model = build_model(load_config(ROOT / "examples" / "paper_rotor.toml", overrides))
    system = RotorSystem(model.rotor, model.elements, model.unbalances, model.base_motion)
    problem = system.periodic_problem()
    return problem, solve_periodic(problem, SPEED, H=3).X


@pytest.mark.parametrize(("overrides", "outside_wins"), [
    # light modal damping: the left-out modes are the least damped (|mu| 0.9896 > 0.9236)
    (['rotor.damping.kind="modal"', "rotor.damping.ratio=2e-5"], True),
    # stiffness-proportional damping: the high modes are damped more, the reduced max wins
    (['rotor.damping.kind="rayleigh"', "rotor.damping.beta=2e-8"], False)])
def test_full_model_largest_multiplier_is_max_of_reduced_and_outside(overrides, outside_wins):
    problem, X = _point(overrides)
    red = FloquetEvaluator(problem, StabilityOptions())(SPEED, X)
    out = red.info["max_multiplier_outside"]
    assert red.stable and 0 < out < 1
    assert red.info["n_modes"] == 6 and red.info["omega_cut"] == pytest.approx(
        0.25 * 400 * SPEED / (2 * np.pi))
    full = FloquetEvaluator(problem, StabilityOptions(basis="full")).at(SPEED, X, 1600)
    assert full.method.startswith("newmark") and "-cb" not in full.method
    assert full.info["max_multiplier_outside"] == 0.0
    assert abs(full.max_abs - max(red.max_abs, out)) <= 2e-4
    assert (out > red.max_abs + 0.05) is outside_wins


def test_outside_formulas() -> None:
    """One damped oscillator: the companion eigenvalues are -zeta w +- i w sqrt(1 - zeta^2);
    exp(lambda T) and the trapezoidal map r(lambda h)^N agree for omega h << 1 and the
    latter tends to the unit circle for omega h >> 1 (the full-model Newmark artefact)."""
    w, zeta, T = 1000.0, 0.01, 2 * np.pi / 100.0
    lam = mode_eigenvalues(np.eye(1), [[2 * zeta * w]], [[w * w]])
    ref = -zeta * w + 1j * w * np.sqrt(1 - zeta**2)
    assert np.abs(np.sort_complex(lam) - np.sort_complex([np.conj(ref), ref])).max() \
        <= 1e-9 * w
    exact = abs(exact_multipliers([ref], T)[0])
    assert exact == pytest.approx(np.exp(-zeta * w * T), rel=1e-12)
    # the trapezoidal under-damping of the module docstring: log|r^N| = log|mu| (1 - (wh)^2/4)
    h = T / 4000
    ratio = np.log(abs(newmark_multipliers([ref], T, 4000)[0])) / np.log(exact)
    assert 1 - ratio == pytest.approx((w * h) ** 2 / 4, rel=0.02)
    coarse = abs(newmark_multipliers([ref], T, 2)[0])   # omega h = 31: unresolved
    assert coarse > 0.99 and exact < 0.6


def test_full_basis_refuses_hill() -> None:
    from rotorsfd.errors import ConfigError

    with pytest.raises(ConfigError, match=r"analysis\.stability\.basis"):
        StabilityOptions(method="hill", basis="full")
    with pytest.raises(ConfigError, match=r"analysis\.stability\.basis"):
        StabilityOptions(basis="half")
    assert StabilityOptions(basis="full").method == "newmark"
    assert StabilityOptions(method="generalized-alpha-cb", basis="full").method == \
        "generalized-alpha"
