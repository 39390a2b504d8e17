"""The torus of a rotor above DENSE_MAX_DOF keeps the band (issue 17 item 2; below it too
without modal damping): the linear
part as the rotor's CSR matrices and the base patterns with their theta2 weights
(quasiperiodic/torus_bands.py), the condensation from their band entries, no dense n x n
matrix formed (run under the guard that raises if one is). The reference is the dense
path of the same rotor (the dense (b + 1, n, n) stacks, ``banded=False``): the condensed
operators, a torus point, a short branch in the speed and one in the base frequency
equal it to 1e-10. The 420-DOF uniform rotor (104 elements, SFD at node 1) under
harmonic pitching (0.05 rad at 60 rad/s, examples/paper_harmonic_pitching.toml)."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from rotors import forbid_dense_rotor_matrices, uniform_sfd_rotor_raw
from rotorsfd.errors import ConfigError
from rotorsfd.io.config import config_from_dict
from rotorsfd.model.build import build_system
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.quasiperiodic import TorusLattice, continue_torus, solve_torus, torus_problem
from rotorsfd.quasiperiodic.torus_bands import band_entries, csr_entries
from rotorsfd.quasiperiodic.torus_base_parameters import base_parameter_problem
from rotorsfd.quasiperiodic.torus_linear import TorusCondenser

SPEED = 300.0
PITCHING = {"pitching": {"law": "harmonic", "frequency": 60.0, "angle_amplitude": 0.05}}


def _system(modal_ratio: float | None = None):
    raw = uniform_sfd_rotor_raw(104, modal_ratio)
    raw["base"] = PITCHING
    system = build_system(config_from_dict(raw))
    assert system.n_dof == 420 > DENSE_MAX_DOF
    return system


@pytest.fixture(scope="module")
def system():
    return _system()


def _rel(a: np.ndarray, b: np.ndarray) -> float:
    return float(np.abs(a - b).max() / np.abs(b).max())


def test_csr_entries_are_the_band_of_the_matrix():
    """``csr_entries`` on ``band_entries`` against the dense matrix's entries."""
    rng = np.random.default_rng(3)
    A = sp.random(60, 60, density=0.2, random_state=rng, format="csr")
    A = sp.csr_matrix(sp.triu(sp.tril(A, 5), -5))
    I, J = band_entries(60, 7)
    assert np.all(np.abs(I - J) <= 7) and I.size == 60 * 15 - 2 * (7 * 8 // 2)
    np.testing.assert_array_equal(csr_entries(A, I, J), A.toarray()[I, J])


def test_large_rotor_torus_is_banded(system):
    problem = torus_problem(system)
    assert problem.bands is not None and problem.M is None
    assert problem.bands.beta == 7
    small = torus_problem(system, banded=False)
    assert small.bands is None


def test_condensed_operators_equal_the_dense_path(system, monkeypatch):
    """Ht, Pt and their speed derivatives at one speed, with a shift on the SFD DOFs."""
    lat = TorusLattice(3, 2)
    out = {}
    for banded in (True, False):
        with monkeypatch.context() as m:
            if banded:
                forbid_dense_rotor_matrices(m)
            c = TorusCondenser(torus_problem(system, banded=banded), lat)
            c.set_shift(1e6 * np.eye(2), 1e3 * np.eye(2), SPEED)
            out[banded] = c.condense(SPEED)
    for name in ("Ht", "Pt", "dHt", "dPt"):
        err = _rel(getattr(out[True], name), getattr(out[False], name))
        print(f"{name}: {err:.1e}")
        assert err <= 1e-10
    assert np.abs(out[False].Ht).max() > 0 and np.abs(out[False].Pt).max() > 0


def test_torus_point_and_branch_equal_the_dense_path(system, monkeypatch):
    """One torus (Newton to 1e-11) and a short speed branch: every coefficient of every
    DOF equal to 1e-10 of the largest; the journal orbit is large (not a trivial 0)."""
    lat = TorusLattice(3, 2)
    res = {}
    for banded in (True, False):
        with monkeypatch.context() as m:
            if banded:
                forbid_dense_rotor_matrices(m)
            problem = torus_problem(system, banded=banded)
            point = solve_torus(problem, SPEED, lat, tol=1e-11)
            branch = continue_torus(problem, SPEED, 1.04 * SPEED, lat, tol=1e-10,
                                    ds=0.02, max_points=4)
        res[banded] = (point, branch)
    (pb, bb), (pd, bd) = res[True], res[False]
    print(f"point: {_rel(pb.X, pd.X):.1e}")
    assert _rel(pb.X, pd.X) <= 1e-10
    assert np.abs(pd.X[:, system.nl_dofs]).max() > 0.05 * system.length_scale
    assert bb.n_points == bd.n_points >= 3
    np.testing.assert_allclose(bb.lam, bd.lam, rtol=1e-10)
    errs = [_rel(a, b) for a, b in zip(bb.X, bd.X, strict=True)]
    print(f"branch: {max(errs):.1e}")
    assert max(errs) <= 1e-10


def test_base_frequency_problem_is_banded(system, monkeypatch):
    """Continued in base.frequency: the interpolated weights on the CSR terms, a point
    equal to the dense path's."""
    lat = TorusLattice(3, 2)
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        problem = base_parameter_problem(system, "base.frequency", SPEED)
        assert problem.bands is not None
        got = solve_torus(problem, 62.0, lat, tol=1e-11)
    ref = solve_torus(base_parameter_problem(system, "base.frequency", SPEED, banded=False),
                      62.0, lat, tol=1e-11)
    print(f"base.frequency point: {_rel(got.X, ref.X):.1e}")
    assert _rel(got.X, ref.X) <= 1e-10


def test_modal_damping_above_the_threshold_is_refused():
    with pytest.raises(ConfigError, match="modal damping"):
        torus_problem(_system(0.02))


def test_small_rotor_torus_is_banded_and_equals_the_dense_stacks(tmp_path):
    """Below DENSE_MAX_DOF the band is kept too (as fast or faster, benchmarks/README.md):
    the 20-DOF rotor of the torus tests, a torus equal to the dense stacks' to 1e-10; with
    modal damping of a few modes (beside the band) the dense stacks are kept."""
    from torus_models import small_system

    small = small_system(tmp_path, 'pitching = { law = "harmonic", frequency = "60 rad/s", '
                                   'angle_amplitude = "0.05 rad" }')
    assert small.n_dof < DENSE_MAX_DOF
    lat = TorusLattice(3, 2)
    banded = torus_problem(small)
    assert banded.bands is not None
    got = solve_torus(banded, 613.0, lat, tol=1e-11)
    ref = solve_torus(torus_problem(small, banded=False), 613.0, lat, tol=1e-11)
    assert _rel(got.X, ref.X) <= 1e-10
    assert np.abs(ref.X[:, small.nl_dofs]).max() > 0.05 * small.length_scale
    raw = uniform_sfd_rotor_raw(40, modal_ratio=0.02)
    raw["base"] = PITCHING
    modal = build_system(config_from_dict(raw))
    assert modal.n_dof < DENSE_MAX_DOF and torus_problem(modal).bands is None


def test_response_command_on_the_large_rotor_forms_no_dense_matrix(tmp_path, monkeypatch):
    """``rotorsfd response`` (the torus branch, stability off) on the 420-DOF rotor under
    the guard; its first point's 1X line of the SFD journal (node 1, y) equals the dense
    path's torus at the same speed (units of the clearance) to the command's Newton
    tolerance (``analysis.response.tolerance``, 1e-6 on the scaled residual: measured
    1.9e-6 relative)."""
    import csv

    from rotorsfd.cli import main
    from rotorsfd.io.config import to_toml

    raw = uniform_sfd_rotor_raw(104)
    raw["base"] = PITCHING
    raw["reference"] = {"speed": SPEED}
    raw["analysis"] = {"response": {"speed_range": {"start": SPEED, "stop": 1.01 * SPEED}},
                       "stability": {"enabled": False}}
    path = tmp_path / "big.toml"
    path.write_text(to_toml(raw))
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        assert main(["response", str(path), "-o", str(tmp_path / "out"), "-q"]) == 0
    with open(tmp_path / "out" / "torus.csv") as f:
        first = next(csv.DictReader(f))
    system = _system()
    lat = TorusLattice(3, 2)
    ref = solve_torus(torus_problem(system, banded=False), SPEED, lat, tol=1e-11)
    y1 = system.rotor.dof_index(1, "y")
    want = abs(ref.X[lat.index(1, 0), y1]) / system.length_scale
    got = float(first["amp_1_y_1_0"])
    print(f"1X line: {got:.6g} C, dense {want:.6g} C")
    assert want > 1e-3 and abs(got - want) <= 2e-5 * want
