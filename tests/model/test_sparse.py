"""Sparse/banded storage of the linear part (issue 17 item 2): the CSR assembly equals a
dense scatter of the element matrices, the band is the structural 7, the band-storage
condensation equals the dense LAPACK one to 1e-10 and the HB solution through the banded
linear part equals the one through the dense "direct" assembly."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np
import pytest
import scipy.sparse as sp

from rotorsfd.elements.sfd import SFDElement
from rotorsfd.harmonic.condensation import CondensedHB, banded_band
from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, dofs, uniform_shaft
from rotorsfd.model.base_motion import BaseMotion
from rotorsfd.model.damping import RayleighDamping
from rotorsfd.model.disk import PointMass
from rotorsfd.model.sparse import (
    HALF_BAND,
    BandedLinearPart,
    band_to_csr,
    band_to_dense,
    bandwidths,
    to_band,
)
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance
from rotorsfd.sfd import SFD

ROOT = Path(__file__).resolve().parents[2]
STEEL = Material(7810.0, 211e9, 81.783e9)


def rotor(n_elements: int = 12, damping=None) -> Rotor:
    shaft = uniform_shaft(0.9, n_elements, 0.0, 0.03, STEEL)
    mid = 1 + n_elements // 2
    return Rotor(shaft, disks=[Disk.from_geometry(mid, 7810.0, 0.03, 0.12, 0.04)],
                 point_masses=[PointMass(2, 0.8)],
                 supports=[LinearSupport(1, 5e6, 4e6, 1e5, -2e5, 300.0, 200.0),
                           LinearSupport.isotropic(n_elements + 1, 1e7, 150.0)],
                 damping=damping)


def dense_assembly(r: Rotor) -> tuple[np.ndarray, ...]:
    """M, K, C, G by a dense scatter of the element matrices (the assembly of before)."""
    n = r.n_dof
    M, K, G, C = (np.zeros((n, n)) for _ in range(4))
    for i, el in enumerate(r.shaft_elements):
        ix = np.ix_(np.arange(4 * i, 4 * i + 8), np.arange(4 * i, 4 * i + 8))
        M[ix] += el.mass_matrix()
        K[ix] += el.stiffness_matrix()
        G[ix] += el.gyroscopic_matrix()
    for d in r.disks:
        y, z, ty, tz = dofs.node_dofs(d.node)
        M[[y, z, ty, tz], [y, z, ty, tz]] += [d.mass, d.mass, d.diametral_inertia,
                                              d.diametral_inertia]
        G[ty, tz] += d.polar_inertia
        G[tz, ty] -= d.polar_inertia
    for p in r.point_masses:
        y, z = dofs.node_dofs(p.node)[:2]
        M[y, y] += p.mass
        M[z, z] += p.mass
    for s in r.supports:
        ix = np.ix_(dofs.node_dofs(s.node)[:2], dofs.node_dofs(s.node)[:2])
        K[ix] += s.stiffness
        C[ix] += s.damping
    if r.damping is not None:
        C += r.damping.matrix(M, K)
    return M, K, C, G


def test_sparse_assembly_equals_dense_scatter_and_band_is_structural() -> None:
    r = rotor(damping=RayleighDamping(2.0, 1e-5))
    for csr, dense, ref in zip((r.M_csr, r.K_csr, r.C_csr, r.G_csr), (r.M, r.K, r.C, r.G),
                               dense_assembly(r), strict=True):
        assert sp.issparse(csr)
        np.testing.assert_allclose(csr.toarray(), ref, rtol=0, atol=1e-14 * np.abs(ref).max())
        np.testing.assert_array_equal(dense, csr.toarray())
    assert r.M is r.M and r.G is r.G          # dense forms built once
    assert r.band == (HALF_BAND, HALF_BAND) == (7, 7)
    # the base-motion patterns lie in the same band
    system = RotorSystem(r, base=BaseMotion(wy=3.0))
    assert bandwidths(system.basis.sparse_matrices) == (7, 7)
    np.testing.assert_array_equal(system.basis.matrices[3],
                                  system.basis.sparse_matrices[3].toarray())


def test_band_storage_round_trip_and_outside_band() -> None:
    rng = np.random.default_rng(3)
    n, kl, ku = 11, 2, 3
    A = rng.normal(size=(n, n))
    i, j = np.indices((n, n))
    A[(i - j > kl) | (j - i > ku)] = 0.0
    ab = to_band(sp.csr_matrix(A), kl, ku)
    assert ab.shape == (n, kl + ku + 1)
    assert ab[4, ku + 5 - 4] == A[5, 4]
    np.testing.assert_array_equal(band_to_dense(ab, kl, ku), A)
    np.testing.assert_array_equal(band_to_csr(ab, kl, ku).toarray(), A)
    np.testing.assert_array_equal(to_band(A, kl, ku), ab)
    assert bandwidths([A]) == (kl, ku)
    with pytest.raises(ValueError, match="outside the band"):
        to_band(A, kl - 1, ku)


def sfd_system(n_elements: int) -> RotorSystem:
    sfd = SFD(viscosity=0.0051, radius=0.0262, length=0.017, clearance=0.127e-3)
    r = rotor(n_elements)
    return RotorSystem(r, [SFDElement("sfd", 1, sfd)],
                       [Unbalance(1 + n_elements // 2, 2e-5, 0.3)])


def test_banded_condensation_equals_dense_lapack() -> None:
    """Ht, Pt and their lam-derivatives of the band-storage kernel against dense LAPACK
    zgetrf/zgetrs of the same Zt_k (an independent factorisation), 1e-10 relative."""
    problem = sfd_system(40).periodic_problem()
    assert isinstance(problem.matrices, BandedLinearPart)
    assert banded_band(problem.matrices) == (7, 7)
    H, lam = 4, 700.0
    banded = CondensedHB(problem, H, 32)
    # the same problem with plain dense matrices: the condenser scans them (no band given)
    dense = CondensedHB(dataclasses.replace(problem, matrices=lambda lam: problem.matrices(
        lam)), H, 32)
    xs = np.zeros((2 * H + 1, problem.m))
    xs[1, 0] = xs[2, 1] = 3e-5
    banded.set_shift(xs, lam)
    dense.delta, dense._delta_real = banded.delta, banded._delta_real
    assert np.abs(banded.delta).max() > 0.0
    dense._band = (-1, -1)                      # dense LAPACK path
    assert banded_band(dense.problem.matrices) is None
    a, ref = banded.condense(lam), dense.condense(lam)
    for x, y in ((a.Ht, ref.Ht), (a.Pt, ref.Pt), (a.dHt, ref.dHt), (a.dPt, ref.dPt),
                 (a.u, ref.u)):
        assert np.abs(x - y).max() <= 1e-10 * np.abs(y).max()


def test_hb_solution_banded_equals_direct_assembly() -> None:
    """One HB point through the banded linear part and through the dense reference
    assembly (``assembly="direct"``): the same coefficients to 1e-10."""
    system = sfd_system(40)
    lam = 650.0
    a = solve_periodic(system.periodic_problem(), lam, 3, tol=1e-12, condensed=True)
    b = solve_periodic(system.periodic_problem(assembly="direct"), lam, 3, tol=1e-12,
                       condensed=True)
    assert np.abs(a.X - b.X).max() <= 1e-10 * np.abs(b.X).max()
    assert np.abs(a.X).max() > 1e-6


def test_banded_linear_part_dense_view_and_derivatives() -> None:
    r = rotor(8)
    part = BandedLinearPart(r.M_csr, (r.C_csr, r.G_csr), (r.K_csr,))
    M, D, K = part(300.0)
    np.testing.assert_allclose(D, r.C + 300.0 * r.G, rtol=0, atol=1e-13 * np.abs(r.G).max())
    assert part(301.0)[0] is M and part(301.0)[2] is K     # constant: the same objects
    dM, dD, dK = part.derivatives(301.0)
    assert not dM.any() and not dK.any()
    np.testing.assert_array_equal(dD, r.G)
    Ds = part.sparse(300.0)[1]
    np.testing.assert_array_equal(Ds.toarray(), D)


def test_modal_damping_keeps_the_dense_path_with_the_same_results() -> None:
    """A full modal damping matrix has no band: the HB problem gets dense storage
    (DenseLinearPart) and the same solution as the direct assembly."""
    from rotorsfd.model.base_polynomial import DenseLinearPart
    from rotorsfd.model.damping import ModalDamping

    sfd = SFD(viscosity=0.0051, radius=0.0262, length=0.017, clearance=0.127e-3)
    system = RotorSystem(rotor(12, ModalDamping(0.02)), [SFDElement("sfd", 1, sfd)],
                         [Unbalance(7, 2e-5, 0.3)])
    assert system.rotor.band[0] > 3 * HALF_BAND
    problem = system.periodic_problem()
    assert isinstance(problem.matrices, DenseLinearPart)
    assert banded_band(problem.matrices) is None
    a = solve_periodic(problem, 650.0, 3, tol=1e-12, condensed=True)
    b = solve_periodic(system.periodic_problem(assembly="direct"), 650.0, 3, tol=1e-12,
                       condensed=True)
    assert np.abs(a.X - b.X).max() <= 1e-10 * np.abs(b.X).max()


def test_modal_damping_of_a_few_modes_is_the_modal_definition() -> None:
    """``ModalDamping(zeta, modes=r)``: ``Phi^T C_s Phi = diag(2 zeta w)`` on the lowest r
    modes and 0 on the others (the definition, from an independent dense eigh); with
    every mode (``modes = n``) the matrix of ``modes = None``."""
    import scipy.linalg

    from rotorsfd.model.damping import ModalDamping

    r = rotor(10)
    K = r.K
    w2, phi = scipy.linalg.eigh(0.5 * (K + K.T), r.M)
    C = ModalDamping(0.02, modes=4).matrix(r.M_csr, r.K_csr)
    modal = phi.T @ C @ phi
    expect = np.zeros(len(w2))
    expect[:4] = 2 * 0.02 * np.sqrt(w2[:4])
    assert np.abs(modal - np.diag(expect)).max() <= 1e-9 * expect.max()
    full = ModalDamping(0.02).matrix(r.M_csr, r.K_csr)
    every = ModalDamping(0.02, modes=r.n_dof).matrix(r.M_csr, r.K_csr)
    assert np.abs(full - every).max() <= 1e-12 * np.abs(full).max()


def test_modal_damping_factors_by_lanczos_equal_the_dense_eigh() -> None:
    """Above DENSE_EIGH_MAX_DOF the lowest modes come from shift-invert Lanczos on the
    sparse pencil: the same ``U diag(c) U^T`` as from the dense eigh of every mode."""
    from rotorsfd.model.damping import DENSE_EIGH_MAX_DOF, ModalDamping

    r = rotor(110)
    assert r.n_dof > DENSE_EIGH_MAX_DOF
    md = ModalDamping(0.01, modes=5)
    u, c = md.factors(r.M_csr, r.K_csr)                  # Lanczos
    ud, cd = md.factors(r.M, r.K)                        # dense eigh
    np.testing.assert_allclose(c, cd, rtol=1e-9)
    a, b = (u * c) @ u.T, (ud * cd) @ ud.T
    assert np.abs(a - b).max() <= 1e-8 * np.abs(b).max()


def test_low_rank_modal_damping_keeps_the_band_with_the_dense_results() -> None:
    """Modal damping of 6 modes: the rotor keeps its band (7) and the factors, the HB
    linear part is banded with the low-rank term beside it (Woodbury in the
    condensation), and the receptances, particular responses, their lam-derivatives and
    a point solution equal the dense LAPACK path's (the same damping matrix formed dense)
    to 1e-10 -- on the paper rotor and on the 12-element rotor."""
    from rotorsfd import api
    from rotorsfd.io.config import load_config
    from rotorsfd.model.damping import ModalDamping

    cfg = load_config(ROOT / "examples" / "paper_rotor.toml")
    d = cfg.rotor.damping.model_copy(update={"kind": "modal", "ratio": 0.002, "modes": 6})
    paper = api.build_system(cfg.model_copy(update={"rotor": cfg.rotor.model_copy(
        update={"damping": d})}))
    sfd = SFD(viscosity=0.0051, radius=0.0262, length=0.017, clearance=0.127e-3)
    small = RotorSystem(rotor(12, ModalDamping(0.02, modes=6)), [SFDElement("sfd", 1, sfd)],
                        [Unbalance(7, 2e-5, 0.3)])
    for system, lam in ((paper, 800.0), (small, 650.0)):
        assert system.rotor.band == (HALF_BAND, HALF_BAND)
        assert system.rotor.damping_lowrank[0].shape == (system.n_dof, 6)
        p = system.periodic_problem()
        part = p.matrices
        assert isinstance(part, BandedLinearPart) and part.lowrank is not None
        np.testing.assert_allclose(part(lam)[1], system.rotor.C + lam * system.rotor.G,
                                   rtol=0, atol=1e-12 * np.abs(system.rotor.C).max())
        dense = dataclasses.replace(p, matrices=lambda x, f=part: f(x),
                                    dmatrices=part.derivatives)
        a = CondensedHB(p, 3, 64)
        a.set_shift(2e-5 * np.random.default_rng(0).normal(size=(7, 2)), lam)
        b = a.with_problem(dense)
        ca, cb = a.condense(lam), b.condense(lam)
        for f in ("Ht", "Pt", "dHt", "dPt", "u", "C"):
            x, y = getattr(ca, f), getattr(cb, f)
            assert np.abs(x - y).max() <= 1e-10 * np.abs(y).max(), f
        sa = solve_periodic(p, lam, 3, tol=1e-10, condensed=True)
        sb = solve_periodic(dense, lam, 3, tol=1e-10, condensed=True)
        assert np.abs(sa.X - sb.X).max() <= 1e-10 * np.abs(sb.X).max()
