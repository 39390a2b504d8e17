"""Export of a rotor above DENSE_MAX_DOF (issue 17 item 2): ``fmt="mtx"`` writes the
matrices sparse (Matrix Market coordinate format, from the rotor's CSR matrices) without
forming a dense n x n matrix, and they read back equal to the rotor's dense matrices (and
the re-imported rotor is the same rotor); the npz (dense arrays, 12 n x n base terms) is
refused there with one ConfigError line."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.io

from rotors import forbid_dense_rotor_matrices, uniform_sfd_rotor_raw
from rotorsfd.errors import ConfigError
from rotorsfd.interop.export import element_rotor, export_matrices, write_export
from rotorsfd.io.config import config_from_dict, load_config
from rotorsfd.model.build import build_system
from rotorsfd.model.sparse import DENSE_MAX_DOF


@pytest.fixture(scope="module")
def config():
    return config_from_dict(uniform_sfd_rotor_raw(104))      # 420 DOFs


def test_large_mtx_export_is_sparse_and_exact(config, tmp_path, monkeypatch):
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        files, _ = export_matrices(config, tmp_path / "big", "mtx")
    ref = element_rotor(config)          # the dense matrices, outside the guard
    assert ref.n_dof == 420 > DENSE_MAX_DOF
    for key in "MKCG":
        path = tmp_path / "big" / f"{key}.mtx"
        assert path in files
        assert "coordinate" in path.read_text().splitlines()[0]
        a = scipy.io.mmread(path).toarray()
        b = getattr(ref, key)
        assert a.shape == b.shape == (420, 420)
        assert np.max(np.abs(a - b)) <= 1e-15 * max(np.max(np.abs(b)), 1e-300)
    # the stored entries are the band's, not n^2 (a dense file would be 420^2 lines)
    assert len((tmp_path / "big" / "K.mtx").read_text().splitlines()) < 20 * 420


def test_large_mtx_round_trip_is_the_same_rotor(config, tmp_path):
    toml = write_export(config, tmp_path / "big", "mtx")[-1]
    a, b = build_system(config), build_system(load_config(toml), toml.parent)
    assert b.n_dof == a.n_dof == 420
    for key in "MK":     # the SFD's centring spring is added again from [elements.sfd]
        A, B = getattr(a.rotor, f"{key}_csr").toarray(), np.asarray(getattr(b.rotor, key))
        assert np.max(np.abs(A - B)) <= 1e-12 * np.max(np.abs(A))


def test_large_npz_export_is_refused(config, tmp_path, monkeypatch):
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        with pytest.raises(ConfigError, match=r"format: got 'npz'; npz holds dense arrays "
                           r".*allowed up to 400 DOFs and this rotor has 420; 'mtx'"):
            export_matrices(config, tmp_path / "big.npz", "npz")
    assert not (tmp_path / "big.npz").exists()
