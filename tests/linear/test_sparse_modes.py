"""Sparse shift-invert modes, critical speeds and the reduced Campbell model against the
dense ``scipy.linalg.eig`` path (the reference at small n)."""

from __future__ import annotations

import numpy as np
import pytest
from linear_helpers import PAPER_K1, PAPER_K21, STEEL

from rotorsfd.linear import branch_frequency, campbell, critical_speeds, eigen, mac
from rotorsfd.linear.reduced import ReducedModes, reduced_modes
from rotorsfd.linear.sparse_modes import band_width, pencil_of, sparse_eigen
from rotorsfd.model import Disk, LinearSupport, Rotor, uniform_shaft


def damped_rotor(n_elements: int = 60) -> Rotor:
    """The paper rotor meshed finer (node of the disk at L/3), a second disk at 3L/4 and a
    damped right support (complex modes, 4 (n_elements + 1) DOF)."""
    shaft = uniform_shaft(0.5994, n_elements, 20.65e-3, 30.15e-3, STEEL)
    disks = [Disk.from_geometry(1 + n_elements // 3, STEEL.density, 30.15e-3, 101.6e-3,
                                50.8e-3),
             Disk.from_geometry(1 + 3 * n_elements // 4, STEEL.density, 30.15e-3, 80e-3,
                                30e-3)]
    return Rotor(shaft, disks=disks,
                 supports=[LinearSupport.isotropic(1, PAPER_K1),
                           LinearSupport.isotropic(n_elements + 1, PAPER_K21, 3e3)])


class SpeedSquared:
    """The paper rotor with a stiffness growing as speed^2 (not affine in the speed)."""

    def __init__(self, rotor: Rotor, k2: float) -> None:
        self.rotor, self.n_dof = rotor, rotor.n_dof
        self.extra = np.zeros((rotor.n_dof, rotor.n_dof))
        for d in ("y", "z"):
            i = rotor.dof_index(21, d)
            self.extra[i, i] = k2

    def matrices(self, speed: float):
        m, d, k = self.rotor.matrices(speed)
        return m, d, k + speed**2 * self.extra


def assert_same_modes(a, b, rtol: float) -> None:
    assert a.eigenvalues.size == b.eigenvalues.size
    np.testing.assert_allclose(a.eigenvalues, b.eigenvalues, rtol=rtol)
    assert list(a.whirl) == list(b.whirl)
    assert np.all(np.diag(mac(a.mode_shapes, b.mode_shapes)) > 1.0 - 1e-8)


@pytest.mark.parametrize("speed", [0.0, 1500.0, 4000.0])
def test_sparse_modes_equal_dense_paper_rotor(paper, speed):
    assert_same_modes(sparse_eigen(paper, speed, 12), eigen(paper, speed, 12, "dense"), 1e-9)


def test_sparse_modes_equal_dense_damped_mid_size_rotor():
    rotor = damped_rotor(60)
    a, b = eigen(rotor, 2000.0), eigen(rotor, 2000.0, method="dense")   # auto: sparse
    assert rotor.n_dof > 200 and np.all(a.damping_ratios > 1e-5)
    assert_same_modes(a, b, 1e-8)


def test_sparse_modes_free_rotor_drops_rigid_body():
    """No support: K is singular (rigid-body roots at 0, the shift moves off 0). At 500
    rad/s the lowest root is the rigid forward precession Omega Ip / Id of the cylinder
    (6 r^2 / (3 r^2 + L^2)); the flexible modes match the dense path."""
    r, length, speed = 0.02, 0.6, 500.0
    rotor = Rotor(uniform_shaft(length, 20, 0.0, r, STEEL))
    a, b = sparse_eigen(rotor, speed, 6), eigen(rotor, speed, 6, "dense")
    precession = speed * 6 * r**2 / (3 * r**2 + length**2)
    assert a.whirl[0] == "forward"
    assert a.frequencies[0] == pytest.approx(precession, rel=1e-5)
    np.testing.assert_allclose(a.eigenvalues[1:], b.eigenvalues[1:], rtol=1e-8)
    assert list(a.whirl) == list(b.whirl)


def test_not_affine_system_is_read_at_every_speed(paper):
    system = SpeedSquared(paper, 5.0)
    assert pencil_of(system).terms is None
    for speed in (0.0, 3000.0):
        assert_same_modes(sparse_eigen(system, speed, 8), eigen(system, speed, 8, "dense"),
                          1e-9)


def test_pencil_is_extracted_once_per_system(paper):
    assert pencil_of(paper) is pencil_of(paper)
    (_, m1), (_, d1), (_, k1) = pencil_of(paper).terms
    assert m1.nnz == 0 and k1.nnz == 0 and d1.nnz > 0       # D = C + speed G
    np.testing.assert_allclose(d1.toarray(), paper.G, rtol=1e-14, atol=0.0)


def test_band_width_of_a_banded_matrix():
    rng = np.random.default_rng(3)
    a = np.zeros((40, 40))
    for d in range(-5, 4):
        a += np.diag(rng.uniform(1.0, 2.0, 40 - abs(d)), d)
    assert band_width(a) == 5
    a[0, 30] = 1.0
    assert band_width(a) == 30
    assert band_width(np.zeros((5, 5))) == 0


def test_sparse_critical_speeds_equal_dense_paper_rotor(paper):
    dense = critical_speeds(paper, n=3, method="dense")
    sparse = critical_speeds(paper, n=3, method="sparse")
    assert [c.mode for c in sparse] == [c.mode for c in dense]
    np.testing.assert_allclose([c.speed_rad_s for c in sparse],
                               [c.speed_rad_s for c in dense], rtol=1e-8)
    back = critical_speeds(paper, n=2, whirl="backward", harmonic=2.0, method="sparse")
    ref = critical_speeds(paper, n=2, whirl="backward", harmonic=2.0, method="dense")
    np.testing.assert_allclose([c.speed_rad_s for c in back],
                               [c.speed_rad_s for c in ref], rtol=1e-8)


def test_early_stop_equals_full_grid(paper):
    """The scan stops once n sign changes are bracketed: the same roots (to the round-off
    of ARPACK's start vector, which the previous call sets)."""
    every = critical_speeds(paper, n=4, method="sparse", full_grid=True)
    assert len(every) == 4
    for n in (1, 2, 4):
        full, early = every[:n], critical_speeds(paper, n=n, method="sparse")
        assert [c.mode for c in early] == [c.mode for c in full]
        np.testing.assert_allclose([c.speed_rad_s for c in early],
                                   [c.speed_rad_s for c in full], rtol=1e-13)


def test_sparse_critical_speeds_are_dense_roots_mid_size_rotor():
    """Each sparse root Omega_c of the 244-DOF rotor is a root of the dense path's
    g(Omega) = w(Omega) - Omega: the Newton correction -g/g' of the dense g is < 1e-8."""
    rotor = damped_rotor(60)
    crit = critical_speeds(rotor, n=2)                          # auto: sparse
    assert len(crit) == 2
    for c in crit:
        w0 = c.speed_rad_s
        h = 1e-4 * w0
        g = [branch_frequency(rotor, s, c.mode, method="dense") - s
             for s in (w0 - h, w0, w0 + h)]
        slope = (g[2] - g[0]) / (2 * h)
        assert abs(g[1] / slope) < 1e-8 * w0


def test_reduced_campbell_equals_dense_paper_rotor(paper):
    speeds = np.linspace(0.0, 4000.0, 41)
    red = campbell(paper, speeds, 6, method="sparse")
    ref = campbell(paper, speeds, 6, method="dense")
    assert red.info["method"] == "reduced" and red.info["reduced_error"] < 1e-9
    np.testing.assert_allclose(red.eigenvalues, ref.eigenvalues, rtol=1e-8)
    np.testing.assert_array_equal(red.whirl, ref.whirl)


def test_campbell_not_affine_system_solves_every_speed(paper):
    system = SpeedSquared(paper, 5.0)
    speeds = np.linspace(0.0, 3000.0, 8)
    sparse = campbell(system, speeds, 4, method="sparse")
    assert sparse.info["method"] == "sparse"
    np.testing.assert_allclose(sparse.eigenvalues,
                               campbell(system, speeds, 4, method="dense").eigenvalues,
                               rtol=1e-8)


def test_reduced_campbell_equals_dense_mid_size_rotor():
    """The 244-DOF damped rotor (method auto: reduced), 9 speeds to 6000 rad/s, tracked
    through the gyroscopic splitting: the same branches as the dense path."""
    rotor = damped_rotor(60)
    speeds = np.linspace(0.0, 6000.0, 9)
    red = campbell(rotor, speeds, 6)
    ref = campbell(rotor, speeds, 6, method="dense")
    assert red.info["method"] == "reduced"
    np.testing.assert_allclose(red.eigenvalues, ref.eigenvalues, rtol=1e-8)
    np.testing.assert_array_equal(red.whirl, ref.whirl)


def test_reduced_model_refines_and_reports_its_error(paper):
    """An unreachable tol: the failing midpoints become snapshots (3 -> 5), the error kept
    is the largest one measured at the 4 new midpoints against exact solves, and the
    Campbell diagram then falls back to the exact solve at every speed."""
    model = reduced_modes(paper, 0.0, 8000.0, 8, tol=1e-16, max_snapshots=5)
    assert len(model.snapshots) == 5 and len(model.checks) == 4
    assert isinstance(model, ReducedModes) and 1e-16 < model.error < 1e-10
    measured = max(np.max(np.abs(model.eigen(s, 8).eigenvalues
                                 / sparse_eigen(paper, s, 10).eigenvalues[:8] - 1.0))
                   for s in model.checks)
    assert abs(measured - model.error) < 1e-12
    speeds = np.linspace(0.0, 8000.0, 9)
    camp = campbell(paper, speeds, 4, method="sparse", tol=1e-16)
    assert camp.info["method"] == "sparse" and camp.info["reduced_error"] > 1e-16
    np.testing.assert_allclose(camp.eigenvalues,
                               campbell(paper, speeds, 4, method="dense").eigenvalues,
                               rtol=1e-8)


def test_run_modal_reuses_the_reference_speed():
    from rotorsfd import api

    config = api.load_config("examples/paper_rotor.toml", ["reference.speed=first_critical",
                                                         "analysis.modal.speed_range.n=5"])
    result = api.run_modal(config)
    assert result.reference_speed == result.critical_speeds[0].speed_rad_s
    assert result.reference_speed == api.reference_speed(config)
