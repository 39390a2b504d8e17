"""Above DENSE_MAX_DOF the time-domain record keeps every matrix sparse (issue 17 item 2):
the gyroscopic G as CSR equal to the dense one, and a modal damping of a few modes from a
Lanczos run with a fixed start (bit-identical factors on every call; the same damping as
the dense eigh of every mode)."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp
from tests.model.test_sparse import rotor

from rotorsfd.elements.sfd import SFDElement
from rotorsfd.model.damping import ModalDamping
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.unbalance import Unbalance
from rotorsfd.sfd import SFD


def test_record_gyroscopic_is_csr_above_the_dense_size():
    sfd = SFD(viscosity=0.0051, radius=0.0262, length=0.017, clearance=0.127e-3)
    r = rotor(110)
    system = RotorSystem(r, [SFDElement("sfd", 1, sfd)], [Unbalance(7, 2e-5, 0.3)])
    assert system.n_dof > DENSE_MAX_DOF
    rec = system.second_order(600.0)
    assert sp.issparse(rec.gyroscopic) and sp.issparse(rec.M)
    G = r.G_csr.toarray()                     # the reference: the dense assembly's G
    assert np.array_equal(rec.gyroscopic.toarray(), G)
    assert np.abs(G).max() > 0.0
    D = rec.D.toarray() if sp.issparse(rec.D) else np.asarray(rec.D)
    assert np.allclose(D, r.C_csr.toarray() + 600.0 * G, rtol=0.0, atol=1e-12 * np.abs(D).max())


def test_modal_damping_factors_are_deterministic_and_equal_dense_eigh():
    r = rotor(110)
    M, K = r.M_csr, r.K_csr
    damping = ModalDamping(0.02, modes=5)
    (u1, c1), (u2, c2) = damping.factors(M, K), damping.factors(M, K)
    assert np.array_equal(u1, u2) and np.array_equal(c1, c2)
    full = ModalDamping(0.02).factors(M.toarray(), K.toarray())   # dense eigh, every mode
    C_sparse = (u1 * c1) @ u1.T
    C_dense = (full[0][:, :5] * full[1][:5]) @ full[0][:, :5].T
    assert np.abs(C_sparse - C_dense).max() <= 1e-9 * np.abs(C_dense).max()
