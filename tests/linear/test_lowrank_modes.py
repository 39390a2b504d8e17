"""Modal damping of a few modes (``rotor.damping.modes``) kept as banded + low-rank in the
sparse eigensolver (Woodbury shift-invert), the critical speeds and the reduced Campbell
model: the same eigenvalues as the dense path with the same damping formed as a full
matrix (scipy.linalg.eig of the 2n state matrix), 1e-10 relative."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp
from linear_helpers import PAPER_K1, PAPER_K21, STEEL

from rotorsfd.linear import campbell, critical_speeds, eigen
from rotorsfd.linear.sparse_modes import pencil_of, sparse_eigen
from rotorsfd.model import Disk, LinearSupport, ModalDamping, Rotor, uniform_shaft
from rotorsfd.model.lowrank import BandedLowRank, project

RTOL = 1e-10


def modal_rotor(n_elements: int = 48, supported: bool = True, ratio: float = 0.02,
                modes: int = 6) -> Rotor:
    """The paper rotor's shaft meshed finer, two disks, a damped right support (or free),
    modal damping ``ratio`` of the lowest ``modes`` modes."""
    shaft = uniform_shaft(0.5994, n_elements, 20.65e-3, 30.15e-3, STEEL)
    disks = [Disk.from_geometry(1 + n_elements // 3, STEEL.density, 30.15e-3, 101.6e-3,
                                50.8e-3),
             Disk.from_geometry(1 + 3 * n_elements // 4, STEEL.density, 30.15e-3, 80e-3,
                                30e-3)]
    supports = [LinearSupport.isotropic(1, PAPER_K1),
                LinearSupport.isotropic(n_elements + 1, PAPER_K21, 3e3)] if supported else []
    return Rotor(shaft, disks=disks, supports=supports,
                 damping=ModalDamping(ratio, modes))


def test_split_damping_is_the_dense_damping():
    rotor = modal_rotor()
    M, D, K = rotor.split_matrices(1500.0)
    assert isinstance(D, BandedLowRank) and D.U.shape == (rotor.n_dof, 6)
    Md, Dd, Kd = rotor.matrices(1500.0)
    assert (M != sp.csr_matrix(Md)).nnz == 0 and (K != sp.csr_matrix(Kd)).nnz == 0
    np.testing.assert_allclose(D.toarray(), Dd, rtol=0, atol=1e-13 * np.abs(Dd).max())
    x = np.random.default_rng(0).standard_normal((rotor.n_dof, 3))
    np.testing.assert_allclose(D @ x, Dd @ x, atol=1e-12 * np.abs(Dd @ x).max())
    np.testing.assert_allclose(x.T @ D, x.T @ Dd, atol=1e-12 * np.abs(Dd @ x).max())
    np.testing.assert_allclose(project(D, x), x.T @ Dd @ x, rtol=1e-12)
    # the pencil keeps the band: the low-rank term beside it
    pencil = pencil_of(rotor)
    assert pencil.half_band <= 7 and pencil.lowrank is not None


@pytest.mark.parametrize("speed", [0.0, 1500.0, 4000.0])
def test_lowrank_sparse_modes_equal_dense(speed):
    rotor = modal_rotor()
    a = sparse_eigen(rotor, speed, 10)
    b = eigen(rotor, speed, 10, "dense")
    assert np.all(a.damping_ratios[:6] > 1e-3)          # the damped modes are in
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=RTOL)
    assert list(a.whirl) == list(b.whirl)


class FullDamping:
    """``rotor`` with its damping handed over as one sparse matrix (the low-rank term
    formed: a full matrix), the path of before."""

    def __init__(self, rotor: Rotor) -> None:
        self.rotor, self.n_dof = rotor, rotor.n_dof

    def matrices(self, speed: float):
        return self.rotor.matrices(speed)

    def sparse_matrices(self, speed: float):
        return tuple(sp.csr_matrix(a) for a in self.rotor.matrices(speed))


def test_lowrank_woodbury_shift_free_rotor():
    """A free rotor: K singular, the shift -w_s (Z = K + sigma D + sigma^2 M with the
    low-rank term inside, inverted by Woodbury); rigid-body modes undamped. Against the
    same solver on the full damping matrix and the dense eig. (At 800 rad/s the free
    rotor's 150 rad/s precession mode is ill-conditioned: 1.5e-10 between the two sparse
    runs, 1.2e-9 to the dense eig, whose backward error there is 9e-16 against 7e-17.)"""
    rotor = modal_rotor(supported=False, ratio=0.05, modes=10)
    a = sparse_eigen(rotor, 0.0, 8)
    assert pencil_of(rotor).lowrank is not None
    full = FullDamping(rotor)
    b = sparse_eigen(full, 0.0, 8)
    assert pencil_of(full).lowrank is None
    assert np.max(a.damping_ratios) > 0.04
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=RTOL)
    np.testing.assert_allclose(a.eigenvalues, eigen(rotor, 0.0, 8, "dense").eigenvalues,
                               rtol=RTOL)


def test_lowrank_critical_speeds_and_campbell_equal_dense():
    rotor = modal_rotor(30)             # 124 DOF: the dense reference's eigs stay cheap
    opts = {"n": 2, "speed_range": (0.0, 6000.0), "n_grid": 41}
    fast = critical_speeds(rotor, method="sparse", **opts)
    ref = critical_speeds(rotor, method="dense", **opts)
    assert len(fast) == 2
    for f, r in zip(fast, ref, strict=True):
        assert f.speed_rad_s == pytest.approx(r.speed_rad_s, rel=RTOL)
    speeds = np.linspace(0.0, 5000.0, 9)
    red = campbell(rotor, speeds, 6, method="sparse")
    dense = campbell(rotor, speeds, 6, method="dense")
    assert red.info["method"] == "reduced"
    np.testing.assert_allclose(red.eigenvalues, dense.eigenvalues, rtol=1e-9)
