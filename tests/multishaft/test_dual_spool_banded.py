"""The dual-spool torus above DENSE_MAX_DOF keeps the band (issue 17 item 2): the shipped
dual-spool rotor (examples/dual_spool_unbalance.toml) meshed 8 times finer (130 nodes,
520 DOFs), its linear part as CSR terms and each harmonic condensed from band storage
(quasiperiodic/dual_frequency_banded.py) with no dense n x n matrix formed (under the
guard). Reference: the dense per-harmonic condenser (one LAPACK LU per harmonic) of the
same rotor; the condensed operators, their speed derivatives, the recovered response and
a torus equal to 1e-10."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotors import forbid_dense_rotor_matrices
from rotorsfd.io.config import config_from_dict, read_config
from rotorsfd.model.build import build_system
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.quasiperiodic import TorusLattice, solve_torus
from rotorsfd.quasiperiodic.dual_frequency import HarmonicCondenser, dual_spool_problem
from rotorsfd.quasiperiodic.dual_frequency_banded import BandedHarmonicCondenser

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "dual_spool_unbalance.toml"
FINER = 8
SPEED = 130.0  # below the combined resonance (157.7 rad/s), where both LUs round to ~2e-10


def _finer(raw: dict) -> dict:
    """Every shaft section FINER times finer, every node reference moved with it (the LP
    shaft's nodes 1..13 first, then the HP shaft's)."""
    shafts = raw["rotor"]["shafts"]
    counts = [sum(s["n_elements"] for s in sh["sections"]) for sh in shafts]
    starts = np.cumsum([0, *[c + 1 for c in counts]])

    def node(old: int) -> int:
        i = int(np.searchsorted(starts, old - 1, side="right")) - 1
        return int(starts[i] * FINER - i * (FINER - 1) + (old - 1 - starts[i]) * FINER + 1)

    for sh in shafts:
        for sec in sh["sections"]:
            sec["n_elements"] *= FINER
        for key in ("disks", "supports"):
            for item in sh.get(key, []):
                item["node"] = node(item["node"])
    for b in raw["rotor"].get("intershaft", []):
        b["node"], b["outer_node"] = node(b["node"]), node(b["outer_node"])
    for e in raw["elements"].values():
        e["node"] = node(e["node"])
    for u in raw["unbalance"]:
        u["node"] = node(u["node"])
    return raw


@pytest.fixture(scope="module")
def system():
    coarse = read_config(EXAMPLE)
    system = build_system(config_from_dict(_finer(read_config(EXAMPLE))))
    assert system.n_dof == 4 * FINER * 16 + 8 == 520 > DENSE_MAX_DOF
    small = build_system(config_from_dict(coarse))     # the nodes moved with the mesh
    assert np.allclose(small.rotor.node_x[small.nl_dofs // 4],
                       system.rotor.node_x[system.nl_dofs // 4])
    return system


def test_large_dual_spool_problem_is_banded(system):
    problem = dual_spool_problem(system)
    assert problem.bands is not None and problem.M is None
    assert problem.info["condenser"] is BandedHarmonicCondenser


def test_banded_per_harmonic_condensation_equals_the_dense_one(system, monkeypatch):
    lat = TorusLattice(2, 2)
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        problem = dual_spool_problem(system)
        fast = BandedHarmonicCondenser(problem, lat)
    ref = HarmonicCondenser(problem, lat)      # dense from the same CSR terms
    m_ = problem.m
    rng = np.random.default_rng(3)
    Kr, Cr = np.diag(rng.uniform(1e5, 1e6, m_)), np.diag(rng.uniform(10.0, 100.0, m_))
    for c in (fast, ref):
        c.set_shift(Kr, Cr, 150.0)
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        a = fast.condense(SPEED)
        xs = rng.normal(size=(lat.n_real, m_)) * 1e-5
        G = rng.normal(size=(lat.n_real, m_))
        X1 = fast.recover(a, xs, G)
        d1 = fast.response_derivative(fast.condense(SPEED, deriv=False), G)
    b = ref.condense(SPEED)
    for name in ("Ht", "Pt", "dHt", "dPt"):
        x, y = getattr(a, name), getattr(b, name)
        err = np.abs(x - y).max() / np.abs(y).max()
        print(f"{name}: {err:.1e}")
        assert err <= 1e-10, name
    X2 = ref.recover(b, xs, G)
    assert np.abs(X1 - X2).max() <= 1e-10 * np.abs(X2).max()
    d2 = ref.response_derivative(ref.condense(SPEED, deriv=False), G)
    assert np.abs(d1 - d2).max() <= 1e-10 * np.abs(d2).max()
    with pytest.raises(ValueError, match="diagonal"):
        fast.set_shift(np.ones((m_, m_)), Cr, 150.0)


def test_banded_dual_spool_torus_equals_the_dense_one(system, monkeypatch):
    lat = TorusLattice(3, 3)
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        problem = dual_spool_problem(system)
        got = solve_torus(problem, SPEED, lat, tol=1e-11)
    problem.info["condenser"] = HarmonicCondenser
    ref = solve_torus(problem, SPEED, lat, tol=1e-11)
    err = np.abs(got.X - ref.X).max() / np.abs(ref.X).max()
    print(f"torus: {err:.1e}")
    assert err <= 1e-10
    C, s = system.length_scale, system.nl_dofs
    assert np.abs(ref.X[:, s]).max() > 0.01 * C          # not a trivial zero (0.027 C)
