"""Time-varying base terms of a rotor above DENSE_MAX_DOF keep the band (issue 17 item 2):
``time_varying_terms`` hands the CSR patterns, ``second_order_system`` of a moving base
CSR (and banded + low-rank) matrices, equal to the dense assembly of the same terms."""

from __future__ import annotations

import numpy as np
import scipy.sparse as sp

from rotors import uniform_sfd_rotor_raw
from rotorsfd.io.config import config_from_dict
from rotorsfd.model import base_terms, time_terms
from rotorsfd.model.base_terms import BaseBasis, keeps_band, time_varying_terms
from rotorsfd.model.build import build_system
from rotorsfd.model.lowrank import BandedLowRank, dense
from rotorsfd.model.rotor import Rotor
from rotorsfd.model.sparse import DENSE_MAX_DOF

SPEED = 300.0


def _system(modal: bool = True):
    raw = uniform_sfd_rotor_raw(100, modal_ratio=0.02 if modal else None)
    raw["base"] = {"pitching": {"law": "harmonic", "frequency": 120.0,
                                "angle_amplitude": 2e-3},
                   "rolling": {"law": "harmonic", "frequency": 70.0,
                               "angle_amplitude": 1e-3}}
    return build_system(config_from_dict(raw))


def test_keeps_band_is_the_dense_threshold():
    assert not keeps_band(DENSE_MAX_DOF) and keeps_band(DENSE_MAX_DOF + 1)


def test_time_varying_terms_sparse_equal_dense():
    system = _system()
    t = np.linspace(0.0, 0.1, 9)
    got = time_varying_terms(system.basis, system.base, SPEED)
    ref = time_varying_terms(system.basis, system.base, SPEED, sparse=False)
    for pairs, ref_pairs in zip(got[:2], ref[:2], strict=True):
        assert len(pairs) == len(ref_pairs) > 0
        for (c, X), (c_r, X_r) in zip(pairs, ref_pairs, strict=True):
            assert sp.issparse(X) and isinstance(X_r, np.ndarray)
            np.testing.assert_array_equal(c(t), c_r(t))
            np.testing.assert_array_equal(X.toarray(), X_r)


def test_moving_base_record_keeps_the_band(monkeypatch):
    """The record at one speed: no dense rotor matrix or base stack formed; CSR (the modal
    damping banded + low-rank), equal to the dense path (thresholds raised) to 1e-12."""
    system = _system()
    assert system.n_dof > DENSE_MAX_DOF and not system.base.is_constant

    def boom(self):
        raise AssertionError("a dense n x n matrix was formed")

    with monkeypatch.context() as m:
        for name in ("M", "C", "K", "G"):
            m.setattr(Rotor, name, property(boom))
        m.setattr(BaseBasis, "matrices", property(boom))
        rec = system.second_order(SPEED)
    assert sp.issparse(rec.M) and sp.issparse(rec.K) and sp.issparse(rec.gyroscopic)
    assert isinstance(rec.D, BandedLowRank)
    tv = rec.time_varying
    assert tv is not None and tv.n_terms > 0
    assert all(sp.issparse(X) for _, X in (*tv.damping, *tv.stiffness))
    with monkeypatch.context() as m:
        m.setattr(time_terms, "DENSE_MAX_DOF", 10**9)
        m.setattr(base_terms, "DENSE_MAX_DOF", 10**9)
        ref = _system().second_order(SPEED)
    assert isinstance(ref.D, np.ndarray) and isinstance(ref.K, np.ndarray)
    for a, b in ((rec.M, ref.M), (rec.D, ref.D), (rec.K, ref.K),
                 (rec.gyroscopic, ref.gyroscopic)):
        assert np.max(np.abs(dense(a) - b)) <= 1e-12 * np.max(np.abs(b))
    t = np.linspace(0.0, 0.05, 5)
    for kind in ("damping", "stiffness"):
        pairs, ref_pairs = getattr(tv, kind), getattr(ref.time_varying, kind)
        assert len(pairs) == len(ref_pairs)
        for (c, X), (c_r, X_r) in zip(pairs, ref_pairs, strict=True):
            np.testing.assert_array_equal(c(t), c_r(t))
            np.testing.assert_array_equal(dense(X), X_r)
