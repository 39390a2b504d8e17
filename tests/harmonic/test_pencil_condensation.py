"""The condensation from one eigendecomposition per harmonic
(:mod:`rotorsfd.harmonic.pencil_condensation`, the dense path of a branch on a full modal
damping matrix) against independent dense solves of ``Zt_k = Z_k + S^T Delta_k S`` formed
from the problem's own ``matrices(lam)``, and its lam-derivatives against central
differences of those solves."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.harmonic import pencil_condensation as pcm
from rotorsfd.harmonic.branch_switching import period_doubled
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_system

CALIBRATED = Path(__file__).parents[2] / "examples" / "paper_rotor_calibrated.toml"
#: a fixed base, and a constant pitching rate (base terms in every coefficient of Z_k)
BASES = [(), ("base.pitching.law=constant", "base.pitching.value=10 rad/s")]


def _problem(*overrides: str, parameter: str = "speed", speed: float | None = None):
    system = build_system(load_config(CALIBRATED, overrides))
    return system.periodic_problem(parameter, speed=speed)


def _condenser(problem, H: int, lam: float) -> CondensedHB:
    """A condenser at H harmonics with a shift from a circular orbit of 0.3 C."""
    hb = CondensedHB(problem, H, 4 * H + 4)
    xs = np.zeros((2 * H + 1, problem.m))
    c = float(problem.dof_scale[problem.nl_dofs[0]])
    xs[1, 0] = xs[2, 1] = 0.3 * c
    hb.set_shift(xs, lam)
    return hb


def _lu(problem, delta: np.ndarray, lam: float, H: int):
    """(Ht, Pt, u, C) by a dense solve of Zt_k per harmonic (the definition)."""
    M, D, K = problem.matrices(lam)
    w, s, n, m = problem.frequency(lam), problem.nl_dofs, problem.n_dof, problem.m
    F = problem.forcing(lam, H)
    E = np.eye(n)[:, s]
    u, C = np.empty((H + 1, n), complex), np.empty((H + 1, n, m), complex)
    for k in range(H + 1):
        Z = K - (k * w) ** 2 * M + 1j * k * w * D
        Z[np.ix_(s, s)] += delta[k]
        sol = np.linalg.solve(Z, np.column_stack([E, F[k]]))
        C[k], u[k] = sol[:, :m], sol[:, m]
    return C[:, s], u[:, s], u, C


def _forced(monkeypatch) -> None:
    """The pencils from the first condensation on (no count to wait for)."""
    monkeypatch.setattr(pcm, "PENCIL_AFTER", 0)


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.max(np.abs(a - b)) / np.max(np.abs(b)))


@pytest.mark.parametrize("overrides", BASES, ids=["fixed base", "pitching base"])
def test_pencil_condensation_equals_dense_solves(monkeypatch, overrides) -> None:
    _forced(monkeypatch)
    p = _problem(*overrides)
    H = 6
    hb = _condenser(p, H, 900.0)
    for lam in (880.0, 905.5, 1040.0, 1250.0):      # across the first critical speeds
        cd = hb.condense(lam)
        assert cd.u_ is None and cd.recovery is not None   # served by the pencils
        Ht, Pt, u, C = _lu(p, hb.delta, lam, H)
        assert _rel(cd.Ht, Ht) < 1e-8 and _rel(cd.Pt, Pt) < 1e-8
        assert _rel(cd.u, u) < 1e-8 and _rel(cd.C, C) < 1e-8


@pytest.mark.parametrize("overrides", BASES, ids=["fixed base", "pitching base"])
def test_pencil_derivatives_equal_central_differences(monkeypatch, overrides) -> None:
    _forced(monkeypatch)
    p = _problem(*overrides)
    H, lam, h = 4, 960.0, 1e-3
    hb = _condenser(p, H, lam)
    cd = hb.condense(lam)
    (Hp, Pp, _, _), (Hm, Pm, _, _) = (_lu(p, hb.delta, lam + e, H) for e in (h, -h))
    assert _rel(cd.dHt, (Hp - Hm) / (2 * h)) < 1e-6
    assert _rel(cd.dPt, (Pp - Pm) / (2 * h)) < 1e-6


def test_period_doubled_problem_uses_the_halved_frequency_line(monkeypatch) -> None:
    _forced(monkeypatch)
    p = period_doubled(_problem())
    assert p.frequency_line == (0.0, 0.5)
    H, lam = 6, 1010.0
    hb = _condenser(p, H, lam)
    cd = hb.condense(lam)
    assert cd.u_ is None
    Ht, Pt, _, _ = _lu(p, hb.delta, lam, H)
    assert _rel(cd.Ht, Ht) < 1e-8 and _rel(cd.Pt, Pt) < 1e-8


def test_constant_linear_part_in_another_parameter(monkeypatch) -> None:
    # continuing in the unbalance: Z_k does not depend on lam (d = 0: P = I, Q = Z_k^-1)
    _forced(monkeypatch)
    p = _problem(parameter="unbalance[0].magnitude", speed=1000.0)
    H, U = 5, 3.6e-4
    hb = _condenser(p, H, U)
    for lam in (U, 1.7 * U):
        cd = hb.condense(lam)
        assert cd.u_ is None
        Ht, Pt, u, C = _lu(p, hb.delta, lam, H)
        assert _rel(cd.Ht, Ht) < 1e-10 and _rel(cd.Pt, Pt) < 1e-10
        assert _rel(cd.u, u) < 1e-10 and _rel(cd.C, C) < 1e-10
        assert np.max(np.abs(cd.dHt)) == 0.0


def test_the_lu_serves_until_the_count_and_where_the_check_fails(monkeypatch) -> None:
    p = _problem()
    H, lam = 3, 950.0
    monkeypatch.setattr(pcm, "PENCIL_AFTER", 3)
    hb = _condenser(p, H, lam)
    served = []
    for i in range(5):
        hb._cache = None
        served.append(hb.condense(lam + i).u_ is None)
    assert served == [False, False, False, True, True]
    # a check no decomposition can meet: every later condensation keeps the LU
    monkeypatch.setattr(pcm, "PENCIL_AFTER", 0)
    monkeypatch.setattr(pcm, "PENCIL_RTOL", 0.0)
    q = _problem()
    hb = _condenser(q, H, lam)
    cd = hb.condense(lam)
    assert cd.u_ is not None
    Ht, _, _, _ = _lu(q, hb.delta, lam, H)
    assert _rel(cd.Ht, Ht) < 1e-12


def test_a_singular_leading_coefficient_keeps_the_lu(monkeypatch, capfd) -> None:
    # continuing in the pitching rate: K(w) = K_0 + w^2 K_2 with K_2 (centripetal) singular
    _forced(monkeypatch)
    p = _problem(*BASES[1], parameter="base.pitching.value", speed=1000.0)
    hb = _condenser(p, 4, 10.0)
    cd = hb.condense(12.0)
    assert cd.u_ is not None                    # the LU served
    Ht, Pt, _, _ = _lu(p, hb.delta, 12.0, 4)
    assert _rel(cd.Ht, Ht) < 1e-12 and _rel(cd.Pt, Pt) < 1e-12
    assert "illegal value" not in capfd.readouterr().err
