"""Element and global matrix properties, DOF indexing, disks, supports, damping."""

from __future__ import annotations

import math

import numpy as np
import pytest

from rotorsfd.errors import ConfigError
from rotorsfd.model import (
    Disk,
    LinearSupport,
    Material,
    ModalDamping,
    PointMass,
    RayleighDamping,
    Rotor,
    ShaftElement,
    hollow_circle_shear_coefficient,
    uniform_shaft,
)

STEEL = Material(7810.0, 211e9, 81.783e9)


def paper_like(damping=None) -> Rotor:
    shaft = uniform_shaft(0.5994, 20, 20.65e-3, 30.15e-3, STEEL)
    disk = Disk.from_geometry(8, STEEL.density, 30.15e-3, 101.6e-3, 50.8e-3)
    sup = [LinearSupport(1, 1e7, 2e7, kyz=3e5, kzy=-3e5, cyy=100.0, czz=200.0),
           LinearSupport.isotropic(21, 9e6, damping=50.0)]
    return Rotor(shaft, disks=[disk], point_masses=[PointMass(12, 0.5)], supports=sup,
                 damping=damping)


def test_global_matrix_properties():
    r = paper_like(RayleighDamping(1.0, 1e-6))
    assert r.M.shape == r.K.shape == r.C.shape == r.G.shape == (84, 84)
    np.testing.assert_array_equal(r.M, r.M.T)
    np.testing.assert_allclose(r.G, -r.G.T, atol=0)
    np.linalg.cholesky(r.M)                               # M positive definite
    # K: shaft part symmetric; the cross-coupled support breaks symmetry only at node 1
    asym = r.K - r.K.T
    y1, z1 = r.dof_index(1, "y"), r.dof_index(1, "z")
    assert asym[y1, z1] == pytest.approx(6e5)
    asym[y1, z1] = asym[z1, y1] = 0.0
    assert np.abs(asym).max() == 0.0
    # the free shaft's K is positive semi-definite with exactly 4 rigid-body modes
    free = Rotor(r.shaft_elements, r.disks)
    w = np.linalg.eigvalsh(free.K)
    assert np.sum(np.abs(w) < 1e-6 * w.max()) == 4 and w.min() > -1e-6 * w.max()


def test_total_mass_and_polar_inertia_from_rigid_motions():
    r = paper_like()
    ty = np.zeros(r.n_dof)
    ty[2::4] = 1.0                                         # rigid tilt needs z = -x ty
    ty[1::4] = -(r.node_x - 0.0)
    tz = np.zeros(r.n_dof)
    tz[3::4] = 1.0
    tz[0::4] = r.node_x
    uy = np.zeros(r.n_dof)
    uy[0::4] = 1.0
    assert uy @ r.M @ uy == pytest.approx(r.total_mass, rel=1e-12)
    shaft_ip = sum(e.polar_inertia for e in r.shaft_elements)
    assert ty @ r.G @ tz == pytest.approx(shaft_ip + r.disks[0].polar_inertia, rel=1e-12)
    # rigid motions do not strain the shaft: only the supports resist them
    free = Rotor(r.shaft_elements)
    for v in (ty, tz, uy):
        assert np.abs(free.K @ v).max() < 1e-6 * np.abs(free.K).max()


def test_dof_index_and_positions():
    r = paper_like()
    assert r.n_nodes == 21 and r.n_dof == 84
    assert r.dof_index(1, "y") == 0 and r.dof_index(8, "tz") == 31
    assert r.dof_index(21, "z") == 81
    with pytest.raises(ConfigError):
        r.dof_index(22, "y")
    with pytest.raises(ValueError):
        r.dof_index(3, "x")
    np.testing.assert_allclose(r.node_x[[0, 7, 20]], [0.0, 7 * 0.02997, 0.5994], rtol=1e-12)
    np.testing.assert_allclose(r.element_x, r.node_x[:-1])
    assert Rotor(r.shaft_elements, x_start=0.1).element_x[0] == 0.1


def test_disk_placement_and_geometry():
    d = Disk.from_geometry(8, 7810.0, 30.15e-3, 101.6e-3, 50.8e-3)
    m = 7810.0 * math.pi * 50.8e-3 * (101.6e-3 - 30.15e-3) * (101.6e-3 + 30.15e-3)
    assert d.mass == pytest.approx(m, rel=1e-12)
    assert d.mass == pytest.approx(11.73, abs=0.01)
    assert d.polar_inertia == pytest.approx(0.5 * m * (101.6e-3**2 + 30.15e-3**2), rel=1e-12)
    assert d.diametral_inertia == pytest.approx(
        d.polar_inertia / 2 + m * 50.8e-3**2 / 12, rel=1e-12)
    r = paper_like()
    k = r.dof_index(8, "ty")
    el_ty = sum(e.rotational_mass_matrix()[2, 2] + e.translational_mass_matrix()[2, 2]
                for e in r.shaft_elements[:2]) / 2.0
    assert r.M[k, k] == pytest.approx(d.diametral_inertia + 2 * el_ty, rel=1e-12)
    assert r.G[k, k + 1] > d.polar_inertia > 0.0 and r.G[k + 1, k] < 0.0
    with pytest.raises(ConfigError):
        Rotor(r.shaft_elements, disks=[Disk(22, 1.0, 0.1, 0.1)])


def test_supports_and_with_supports():
    r = Rotor(uniform_shaft(1.0, 4, 0.0, 0.02, STEEL))
    r2 = r.with_supports([LinearSupport(3, 1e6, 2e6, kyz=5e4, cyy=7.0, czy=-3.0)])
    y, z = r.dof_index(3, "y"), r.dof_index(3, "z")
    dk, dc = r2.K - r.K, r2.C - r.C
    assert dk[y, y] == 1e6 and dk[z, z] == 2e6 and dk[y, z] == 5e4 and dk[z, y] == 0.0
    assert dc[y, y] == 7.0 and dc[z, y] == -3.0 and dc[z, z] == 0.0
    assert np.count_nonzero(dk) == 3 and np.count_nonzero(dc) == 2
    assert len(r.supports) == 0 and r2.shaft_elements == r.shaft_elements
    s = LinearSupport.isotropic(2, 5e6, 30.0)
    assert (s.kyy, s.kzz, s.kyz, s.cyy, s.czz) == (5e6, 5e6, 0.0, 30.0, 30.0)


def test_matrices_protocol():
    r = paper_like()
    m, d, k = r.matrices(1000.0)
    np.testing.assert_array_equal(d, r.C + 1000.0 * r.G)
    assert m is r.M and k is r.K


def test_rayleigh_and_modal_damping_matrices():
    base = paper_like()
    ray = paper_like(RayleighDamping(2.0, 3e-6))
    np.testing.assert_allclose(ray.C - base.C, 2.0 * base.M + 3e-6 * base.K, rtol=1e-12)
    iso = Rotor(base.shaft_elements, base.disks,
                supports=[LinearSupport.isotropic(1, 1e7), LinearSupport.isotropic(21, 9e6)])
    mod = Rotor(iso.shaft_elements, iso.disks, supports=iso.supports,
                damping=ModalDamping(0.02))
    import scipy.linalg

    w2, phi = scipy.linalg.eigh(iso.K, iso.M)
    modal_c = phi.T @ mod.C @ phi
    np.testing.assert_allclose(np.diag(modal_c), 2 * 0.02 * np.sqrt(w2), rtol=1e-8)
    off = modal_c - np.diag(np.diag(modal_c))
    assert np.abs(off).max() < 1e-8 * np.abs(np.diag(modal_c)).max()


def test_hutchinson_shear_coefficient():
    nu = 0.3
    solid = hollow_circle_shear_coefficient(0.0, 1.0, nu)
    assert solid == pytest.approx(6 * (1 + nu) ** 2 / (7 + 12 * nu + 4 * nu**2), rel=1e-14)
    assert solid == pytest.approx(0.9252, abs=1e-4)
    thin = hollow_circle_shear_coefficient(0.999999, 1.0, nu)
    assert thin == pytest.approx((1 + nu) / (2 + nu), rel=1e-5)
    # within a few percent of Cowper's formula for the paper's tube
    m2 = (20.65 / 30.15) ** 2
    cowper = 6 * (1 + nu) * (1 + m2) ** 2 / ((7 + 6 * nu) * (1 + m2) ** 2 + (20 + 12 * nu) * m2)
    hut = hollow_circle_shear_coefficient(20.65, 30.15, nu)
    assert 0.0 < hut / cowper - 1.0 < 0.08
    el = ShaftElement(0.03, 20.65e-3, 30.15e-3, STEEL)
    assert el.kappa == pytest.approx(
        hollow_circle_shear_coefficient(20.65e-3, 30.15e-3, STEEL.poisson_ratio))
    assert ShaftElement(0.03, 0.0, 0.03, STEEL, shear_coefficient=0.9).kappa == 0.9


def test_element_quantities_and_bad_input():
    el = ShaftElement(0.5, 0.01, 0.02, STEEL)
    a = math.pi * (0.02**2 - 0.01**2)
    i = math.pi * (0.02**4 - 0.01**4) / 4
    assert el.area == pytest.approx(a) and el.second_moment == pytest.approx(i)
    assert el.mass == pytest.approx(7810 * a * 0.5)
    assert el.polar_moment_mass_per_length == pytest.approx(2 * 7810 * i)
    phi = 12 * 211e9 * i / (el.kappa * 81.783e9 * a * 0.25)
    assert el.shear_parameter == pytest.approx(phi, rel=1e-12)
    mt = el.translational_mass_matrix()
    u = np.array([1.0, 0, 0, 0, 1.0, 0, 0, 0])
    assert u @ mt @ u == pytest.approx(el.mass, rel=1e-12)
    np.testing.assert_allclose(el.mass_matrix(), mt + el.rotational_mass_matrix())
    for bad in (dict(length=-1.0), dict(inner_radius=0.03)):
        kw = dict(length=0.5, inner_radius=0.01, outer_radius=0.02, material=STEEL) | bad
        with pytest.raises(ConfigError):
            ShaftElement(**kw)
    with pytest.raises(ConfigError):
        Material(7810.0, 211e9, 50e9)    # nu = 1.11: impossible
