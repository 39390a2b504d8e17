"""Physical consequences of the base terms, through rotorsfd.model.Rotor."""

from __future__ import annotations

import numpy as np
import pytest
from base_helpers import make_rotor

from rotorsfd.model import Disk, dof_index
from rotorsfd.model.base_motion import BaseMotion, BaseState, UniformAcceleration
from rotorsfd.model.base_polynomial import MovingBaseRotor
from rotorsfd.model.base_terms import (
    assemble_base,
    base_basis,
    base_static_deflection,
    disk_base_terms,
)
from rotorsfd.model.gravity import Gravity


def _rot90(q: np.ndarray) -> np.ndarray:
    """Rotate a DOF vector by +90 degrees about x: (y, z) -> (-z, y), (ty, tz) -> (-tz, ty)."""
    q = q.reshape(-1, 4)
    return np.column_stack([-q[:, 1], q[:, 0], -q[:, 3], q[:, 2]]).ravel()


def _rot90_matrix(n: int) -> np.ndarray:
    return np.array([_rot90(e) for e in np.eye(n)]).T


def test_fixed_base_terms_vanish_exactly(rotor):
    motion = BaseMotion()
    assert motion.is_fixed and motion.is_constant
    for t in (0.0, 1.3):
        C, K, F = assemble_base(rotor, motion.state(t), speed=900.0)
        assert not C.any() and not K.any() and not F.any()


def test_disk_gyroscopic_moment_under_pitching():
    disk = Disk(1, 12.0, 0.09, 0.05)
    om, wy = 800.0, 3.0
    _, _, F = disk_base_terms(disk, 0.0, BaseState.constant(w=(0.0, wy, 0.0)), om)
    # F = (0, 0, -Ip (Om + wx) wz, +Ip (Om + wx) wy) at x_d = 0
    np.testing.assert_allclose(F, [0.0, 0.0, 0.0, disk.polar_inertia * om * wy], rtol=1e-14)
    # yawing: F_ty = -Ip Om wz
    _, _, F = disk_base_terms(disk, 0.0, BaseState.constant(w=(0.0, 0.0, wy)), om)
    np.testing.assert_allclose(F, [0.0, 0.0, -disk.polar_inertia * om * wy, 0.0], rtol=1e-14)


def test_pitching_total_moment_and_static_deflection(rotor):
    om, wy = 700.0, 4.0
    state = BaseState.constant(w=(0.0, wy, 0.0))
    _, K_b, F = assemble_base(rotor, state, om)
    # total moment about z of F_base = Om wy x total polar inertia (rigid rotation y = x, tz = 1)
    rigid = np.zeros(rotor.n_dof)
    rigid[0::4] = rotor.node_x
    rigid[3::4] = 1.0
    ip_total = sum(d.polar_inertia for d in rotor.disks) + sum(
        e.polar_inertia for e in rotor.shaft_elements)
    assert F @ rigid == pytest.approx(om * wy * ip_total, rel=1e-12)
    # the disk's share is Ip Om wy on its tz DOF
    basis = base_basis(rotor)
    d = rotor.disks[0]
    i_tz = dof_index(d.node, "tz")
    shaft_share = om * wy * (basis.vector("ptz")[i_tz] - d.polar_inertia)
    assert F[i_tz] - shaft_share == pytest.approx(d.polar_inertia * om * wy, rel=1e-12)
    # static deflection solves (K + K_base) q = F_base; nonzero in y, zero in z at this order
    q = base_static_deflection(rotor, state, om)
    np.testing.assert_allclose((rotor.K + K_b) @ q, F, atol=1e-9 * np.abs(F).max())
    assert np.abs(q[0::4]).max() > 0.0
    assert np.abs(q[1::4]).max() == 0.0
    # small K_base: q ~ K^-1 F
    q0 = np.linalg.solve(rotor.K, F)
    np.testing.assert_allclose(q, q0, rtol=1e-3, atol=1e-6 * np.abs(q0).max())


@pytest.mark.parametrize("om", [0.0, 500.0])
def test_pitching_and_yawing_related_by_quarter_turn(om):
    rotor = make_rotor(x_start=-0.2)
    w = 6.0
    R = _rot90_matrix(rotor.n_dof)
    pitch = BaseState.constant(w=(0.0, w, 0.0))
    yaw = BaseState.constant(w=(0.0, 0.0, w))
    Cp, Kp, Fp = assemble_base(rotor, pitch, om)
    Cy, Ky, Fy = assemble_base(rotor, yaw, om)
    np.testing.assert_allclose(Fy, R @ Fp, atol=1e-12 * np.abs(Fp).max() + 1e-300)
    np.testing.assert_allclose(Ky, R @ Kp @ R.T, atol=1e-12 * np.abs(Kp).max())
    np.testing.assert_allclose(Cy, R @ Cp @ R.T, atol=1e-300)
    qp = base_static_deflection(rotor, pitch, om)
    qy = base_static_deflection(rotor, yaw, om)
    np.testing.assert_allclose(qy, _rot90(qp), atol=1e-10 * np.abs(qp).max() + 1e-300)


def test_base_acceleration_equals_gravity_load(rotor):
    a = 3.7
    accel = BaseMotion(z0=UniformAcceleration(a))
    grav = BaseMotion(gravity=Gravity(magnitude=a, direction=(0.0, 0.0, -1.0)))
    assert accel.is_constant and grav.is_constant
    q_a = base_static_deflection(rotor, accel.state(2.0), 300.0)
    q_g = base_static_deflection(rotor, grav.state(2.0), 300.0)
    np.testing.assert_array_equal(q_a, q_g)
    # consistent load: F = -a M r_z (rigid z translation)
    r_z = np.zeros(rotor.n_dof)
    r_z[1::4] = 1.0
    _, _, F = assemble_base(rotor, accel.state(0.0), 0.0)
    np.testing.assert_allclose(F, -a * rotor.M @ r_z, atol=1e-12 * a * rotor.total_mass)
    assert F[1::4].sum() == pytest.approx(-a * rotor.total_mass, rel=1e-12)
    assert (q_a[1::4] < 0).all()


def test_jeffcott_rolling_shifts_whirl_by_rate():
    """Point mass m on isotropic k: m q'' + 2 m wx J q' + (k - m wx^2) q = 0 has the
    base-frame whirl frequencies lambda = -wx +/- sqrt(k/m) (z = y + i z ~ exp(i lambda t))."""
    m, k, wx = 3.0, 2.7e5, 40.0
    C, Kb, _ = disk_base_terms(Disk(1, m, 0.0, 0.0), 0.0, BaseState.constant(w=(wx, 0, 0)), 0.0)
    M2, C2, K2 = m * np.eye(2), C[:2, :2], k * np.eye(2) + Kb[:2, :2]
    A = np.block([[np.zeros((2, 2)), np.eye(2)],
                  [-np.linalg.solve(M2, K2), -np.linalg.solve(M2, C2)]])
    lam = np.sort(np.abs(np.linalg.eigvals(A).imag))
    wn = np.sqrt(k / m)
    np.testing.assert_allclose(lam, np.sort([wn - wx, wn - wx, wn + wx, wn + wx]), rtol=1e-12)


def _whirl_sense(vec: np.ndarray, s: complex, n_dof: int) -> float:
    """+1 if q = Re(v exp(s t)) whirls in the positive sense about x (y -> z), else -1;
    e.g. v = (1, -i) with Im s > 0 gives y = cos, z = sin: positive."""
    q = vec[:n_dof].reshape(-1, 4)
    return -float(np.sign(s.imag * np.sum(np.imag(np.conj(q[:, 0]) * q[:, 1])
                                         + np.imag(np.conj(q[:, 2]) * q[:, 3]))))


def _eigs(M, D, K):
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)],
                  [-np.linalg.solve(M, K), -np.linalg.solve(M, D)]])
    return np.linalg.eig(A)


def test_rolling_equals_fixed_rotor_at_absolute_spin_seen_from_rotating_frame():
    """Axisymmetric undamped rotor, isotropic supports, constant rolling wx: the base-frame
    eigenvalues are those of the fixed-base rotor at spin Omega + wx, with each whirl
    frequency shifted by -wx in the positive sense of rotation about x."""
    rotor = make_rotor(n_elements=4, disk_node=2, stiffness=3e6)
    om, wx = 600.0, 35.0
    sys_b = MovingBaseRotor(rotor, BaseState.constant(w=(wx, 0.0, 0.0)))
    s_b, _ = _eigs(*sys_b.matrices(om))
    s_f, v_f = _eigs(*rotor.matrices(om + wx))
    n = rotor.n_dof
    shifted = []
    for s, v in zip(s_f, v_f.T, strict=True):
        sense = _whirl_sense(v, s, n)
        assert sense != 0.0
        shifted.append(1j * (s.imag - wx * sense * np.sign(s.imag)))
    np.testing.assert_allclose(np.sort(np.imag(s_b)), np.sort(np.imag(shifted)),
                               rtol=1e-7, atol=1e-6)
    assert np.abs(s_b.real).max() < 1e-6 * np.abs(s_b).max()


def test_rolling_unbalance_response_equals_fixed_base_at_absolute_speed():
    """Undamped isotropic rotor: under constant rolling wx the synchronous unbalance orbit
    (base frame, frequency Omega) equals the fixed-base orbit at spin Omega + wx, so the
    resonance peak moves to Omega = Omega_crit - wx (the unbalance force carries
    m e (Omega + wx)^2)."""
    from rotorsfd.model.unbalance import Unbalance, unbalance_harmonics

    rotor = make_rotor(n_elements=4, disk_node=2, stiffness=3e6)
    unb = [Unbalance(2, 1e-4, 0.4)]
    om, wx = 500.0, 30.0

    def orbit(speed, state):
        M, D, K = MovingBaseRotor(rotor, state).matrices(speed)
        Fc, Fs = unbalance_harmonics(unb, rotor, speed, state)
        X = np.linalg.solve(K - speed**2 * M + 1j * speed * D, Fc - 1j * Fs)
        return X

    X_b = orbit(om, BaseState.constant(w=(wx, 0.0, 0.0)))
    X_f = orbit(om + wx, BaseState.fixed())
    np.testing.assert_allclose(np.abs(X_b), np.abs(X_f), rtol=1e-9)
