"""Multi-shaft rotors (issue 20 item 1): per-shaft speeds, coaxial placement, intershaft
bearings. Independent checks: each uncoupled shaft alone at its own speed, a block
assembly of single-shaft rotors, and the symmetric/antisymmetric closed form of two
identical shafts coupled by springs."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.linalg as sla

from rotorsfd.errors import ConfigError
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft
from rotorsfd.model.base_motion import BaseMotion
from rotorsfd.model.base_terms import base_static_deflection
from rotorsfd.model.gravity import Gravity
from rotorsfd.model.multishaft import IntershaftBearing, MultiShaftRotor, Shaft

STEEL = Material(7850.0, 2.1e11, 8.1e10)


def _lp(offset: int = 0) -> dict:
    """A long thin inner shaft (7 nodes), two disks, two supports, nodes from offset + 1."""
    return dict(elements=uniform_shaft(1.2, 6, 0.0, 0.02, STEEL),
                disks=(Disk(offset + 2, 8.0, 0.09, 0.05), Disk(offset + 6, 5.0, 0.06, 0.035)),
                supports=(LinearSupport.isotropic(offset + 1, 2e7, 300.0),
                          LinearSupport(offset + 7, 1.5e7, 2.5e7, cyy=200.0, czz=250.0)))


def _hp(offset: int) -> dict:
    """A short hollow outer shaft (5 nodes) with one heavy disk, nodes from offset + 1."""
    return dict(elements=uniform_shaft(0.5, 4, 0.03, 0.045, STEEL),
                disks=(Disk(offset + 3, 15.0, 0.25, 0.14),),
                supports=(LinearSupport.isotropic(offset + 1, 5e7, 500.0),
                          LinearSupport.isotropic(offset + 5, 4e7, 400.0)))


def _alone(parts: dict, offset: int) -> Rotor:
    """The shaft as a single-shaft Rotor (its nodes renumbered from 1)."""
    return Rotor(parts["elements"],
                 [Disk(d.node - offset, d.mass, d.polar_inertia, d.diametral_inertia)
                  for d in parts["disks"]],
                 supports=[LinearSupport(s.node - offset, s.kyy, s.kzz, s.kyz, s.kzy, s.cyy,
                                         s.czz, s.cyz, s.czy) for s in parts["supports"]])


def _eigenvalues(M, D, K) -> np.ndarray:
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-sla.solve(M, K), -sla.solve(M, D)]])
    return np.linalg.eigvals(A)


def _lowest(lam: np.ndarray, k: int) -> np.ndarray:
    return lam[np.argsort(np.abs(lam))[:k]]


def _match(a: np.ndarray, b: np.ndarray) -> float:
    """Largest relative distance of each of ``a`` to the nearest of ``b``."""
    return float(max(np.min(np.abs(b - x)) / abs(x) for x in a))


def test_single_shaft_equals_rotor() -> None:
    parts = _lp()
    ref = _alone(parts, 0)
    ms = MultiShaftRotor([Shaft("lp", **parts)])
    for name in ("M", "K", "C", "G"):
        np.testing.assert_array_equal(getattr(ms, name), getattr(ref, name))
    np.testing.assert_array_equal(ms.node_x, ref.node_x)
    assert ms.band == ref.band


@pytest.mark.parametrize("ratio", [1.0, 1.7, 0.6])
def test_uncoupled_shafts_have_each_shafts_modes_at_its_own_speed(ratio: float) -> None:
    lp, hp = _lp(), _hp(7)
    ms = MultiShaftRotor([Shaft("lp", **lp), Shaft("hp", speed_ratio=ratio, x_start=0.35,
                                                  **hp)])
    assert ms.n_nodes == 12 and ms.node_x[7] == pytest.approx(0.35)
    a, b = _alone(lp, 0), _alone(hp, 7)
    omega = 1500.0
    lam = _eigenvalues(*ms.matrices(omega))
    lam_a = _eigenvalues(*a.matrices(omega))
    lam_b = _eigenvalues(*b.matrices(ratio * omega))
    ref = np.concatenate([lam_a, lam_b])
    assert _match(_lowest(ref, 24), lam) < 1e-10
    assert _match(_lowest(lam, 24), ref) < 1e-10
    # the hp shaft's gyroscopic splitting is that of its own speed, not of omega
    if ratio != 1.0:
        wrong = _lowest(_eigenvalues(*b.matrices(omega)), 8)
        assert _match(wrong, lam) > 1e-4


def test_coupled_matrices_equal_a_block_assembly() -> None:
    lp, hp = _lp(), _hp(7)
    kb = np.array([[3e6, 2e5], [-1e5, 4e6]])
    cb = np.array([[50.0, 0.0], [0.0, 70.0]])
    bearing = IntershaftBearing(6, 10, kb[0, 0], kb[1, 1], kb[0, 1], kb[1, 0],
                                cb[0, 0], cb[1, 1], 0.0, 0.0)
    ms = MultiShaftRotor([Shaft("lp", **lp), Shaft("hp", speed_ratio=1.4, **hp)], [bearing])
    a, b = _alone(lp, 0), _alone(hp, 7)
    K = sla.block_diag(a.K, b.K)
    C = sla.block_diag(a.C, b.C)
    ia, ib = [20, 21], [36, 37]             # y, z of node 6 and node 10
    for mat, blk in ((K, kb), (C, cb)):
        mat[np.ix_(ia, ia)] += blk
        mat[np.ix_(ib, ib)] += blk
        mat[np.ix_(ia, ib)] -= blk
        mat[np.ix_(ib, ia)] -= blk
    np.testing.assert_allclose(ms.K, K, rtol=0, atol=1e-12 * np.abs(K).max())
    np.testing.assert_allclose(ms.C, C, rtol=0, atol=1e-12 * np.abs(C).max())
    np.testing.assert_allclose(ms.M, sla.block_diag(a.M, b.M), rtol=0, atol=1e-15)
    np.testing.assert_allclose(ms.G, sla.block_diag(a.G, 1.4 * b.G), rtol=0, atol=1e-15)
    om = [800.0, 1900.0]
    _, D, _ = ms.shaft_matrices(om)
    np.testing.assert_allclose(D, C + sla.block_diag(om[0] * a.G, om[1] * b.G), atol=1e-9)
    assert ms.dof_names[36] == "y@hp:3" and ms.dof_names[3] == "tz@lp:1"


def test_identical_shafts_coupled_split_into_symmetric_and_antisymmetric_modes() -> None:
    """Two identical shafts at ratio 1 coupled by springs k (and dampers c) between equal
    nodes: with q1 = q2 the couplings are idle (the modes of one shaft); with q1 = -q2 the
    relative displacement is 2 q1, so each shaft sees a grounded spring 2k (damper 2c)."""
    p1, p2 = _lp(), _lp(7)
    k, c = 8e6, 120.0
    nodes = (3, 5)
    bearings = [IntershaftBearing(n, n + 7, k, k, cyy=c, czz=c) for n in nodes]
    ms = MultiShaftRotor([Shaft("a", **p1), Shaft("b", **p2)], bearings)
    one = _alone(p1, 0)
    anti = one.with_supports([LinearSupport.isotropic(n, 2 * k, 2 * c) for n in nodes])
    omega = 2000.0
    lam = _eigenvalues(*ms.matrices(omega))
    ref = np.concatenate([_eigenvalues(*one.matrices(omega)),
                          _eigenvalues(*anti.matrices(omega))])
    assert _match(_lowest(lam, 24), ref) < 1e-10
    assert _match(_lowest(ref, 24), lam) < 1e-10


def test_gravity_sag_of_uncoupled_shafts_is_each_shafts_own() -> None:
    lp, hp = _lp(), _hp(7)
    ms = MultiShaftRotor([Shaft("lp", **lp), Shaft("hp", speed_ratio=2.0, x_start=0.3, **hp)])
    state = BaseMotion(gravity=Gravity(9.81, (0.0, 0.0, -1.0))).state(0.0)
    q = base_static_deflection(ms, state, 1000.0)
    qa = base_static_deflection(_alone(lp, 0), state, 1000.0)
    qb = base_static_deflection(_alone(hp, 7), state, 2000.0)
    np.testing.assert_allclose(q, np.concatenate([qa, qb]), rtol=1e-10,
                               atol=1e-12 * np.abs(qa).max())
    assert qa[1::4].min() < -1e-6            # a real sag


def test_bad_input() -> None:
    lp, hp = _lp(), _hp(7)
    with pytest.raises(ConfigError, match="speed_ratio"):
        Shaft("hp", speed_ratio=0.0, **hp)
    with pytest.raises(ConfigError, match=r"node of shaft 'hp', 8\.\.12"):
        MultiShaftRotor([Shaft("lp", **lp), Shaft("hp", **{**hp, "disks": (Disk(3, 1, 0, 0),)})])
    with pytest.raises(ConfigError, match="another shaft"):
        MultiShaftRotor([Shaft("lp", **lp), Shaft("hp", **hp)], [IntershaftBearing(2, 5, 1, 1)])
    with pytest.raises(ConfigError, match="first shaft's ratio"):
        MultiShaftRotor([Shaft("lp", speed_ratio=2.0, **lp), Shaft("hp", **hp)])
