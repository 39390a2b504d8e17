"""Matrix import (``[rotor.matrices]``) and export (``export_matrices``): the paper rotor
exported and re-imported is the same rotor (matrices, base terms, modes, HB branch), a DOF
map with permutation, signs and dropped DOFs undoes itself, and bad input is one line."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.errors import ConfigError
from rotorsfd.interop.export import dof_table, write_export
from rotorsfd.io.config import config_from_dict, load_config
from rotorsfd.model.build import build_system

PAPER = Path(__file__).resolve().parents[2] / "examples" / "paper_rotor.toml"
SHORT = ["unbalance[0].magnitude=144.02 g*mm", "analysis.stability.enabled=false",
         "analysis.response.speed_range.start_ratio=0.97",
         "analysis.response.speed_range.stop_ratio=1.03"]


def _exported(tmp_path: Path, overrides=(), fmt: str = "npz"):
    config = load_config(PAPER, overrides)
    target = tmp_path / ("paper.npz" if fmt == "npz" else "paper_mtx")
    files = write_export(config, target, fmt)
    return config, files[-1], load_config(files[-1])


@pytest.mark.parametrize("fmt", ["npz", "mtx"])
def test_paper_rotor_round_trip_matrices(tmp_path, fmt):
    config, toml, imported = _exported(tmp_path, fmt=fmt)
    a, b = build_system(config), build_system(imported, toml.parent)
    assert b.rotor.n_nodes == 21 and b.n_dof == 84
    for k in "MKCG":   # the SFD's centring spring is added again from [elements.sfd]
        np.testing.assert_allclose(getattr(b.rotor, k), getattr(a.rotor, k), rtol=0,
                                   atol=1e-12 * np.abs(getattr(a.rotor, k)).max() + 1e-300)
    np.testing.assert_array_equal(b.rotor.node_x, a.rotor.node_x)
    if fmt == "npz":   # the base-motion terms travel in the .npz
        np.testing.assert_allclose(b.basis.matrices, a.basis.matrices, atol=1e-12)
        np.testing.assert_allclose(b.basis.vectors, a.basis.vectors, atol=1e-15)
    else:   # Matrix Market: only the translation loads, f = M r (exact)
        np.testing.assert_allclose(b.basis.vectors[:2], a.basis.vectors[:2], rtol=1e-12,
                                   atol=1e-15)


def test_paper_rotor_round_trip_modes_and_damping(tmp_path):
    """Modal structural damping is computed again on the imported, supported rotor."""
    damped = ["rotor.damping.kind=modal", "rotor.damping.ratio=0.02"]
    config, toml, imported = _exported(tmp_path, damped)
    assert imported.rotor.damping.kind == "modal"
    a, b = build_system(config).rotor, build_system(imported, toml.parent).rotor
    np.testing.assert_allclose(b.C, a.C, atol=1e-9 * np.abs(a.C).max())
    from rotorsfd.linear.modal import eigen

    for speed in (0.0, 2000.0):
        ea, eb = eigen(a, speed, 8).eigenvalues, eigen(b, speed, 8).eigenvalues
        np.testing.assert_allclose(eb, ea, rtol=1e-10)


def test_paper_branch_same_after_import(tmp_path):
    """The issue's check: the paper rotor's HB branch (U = 144.02 g mm, around the
    critical speed) computed on the re-imported matrices is the same branch (1e-10)."""
    config, toml, imported = _exported(tmp_path, SHORT)
    r1 = api.run_response(config, progress=False)
    r2 = api.run_response(imported, search_path=toml.parent, progress=False)
    lam1, lam2 = np.asarray(r1.branch.lam), np.asarray(r2.branch.lam)
    assert lam1.shape == lam2.shape and lam1.size > 10
    np.testing.assert_allclose(lam2, lam1, rtol=1e-10)
    X1, X2 = np.asarray(r1.branch.X), np.asarray(r2.branch.X)
    assert np.abs(X2 - X1).max() <= 1e-10 * np.abs(X1).max()


@pytest.mark.slow
def test_paper_branch_with_pitching_and_stability(tmp_path):
    """Base rotation (the base terms from the .npz) and Floquet stability on the imported
    model: the same branch and the same bifurcations."""
    over = ["unbalance[0].magnitude=144.02 g*mm", "base.pitching.law=constant",
            "base.pitching.value=2 rad/s", "analysis.response.speed_range.start_ratio=0.9",
            "analysis.response.speed_range.stop_ratio=1.15"]
    config, toml, imported = _exported(tmp_path, over)
    r1 = api.run_response(config, progress=False)
    r2 = api.run_response(imported, search_path=toml.parent, progress=False)
    np.testing.assert_allclose(np.asarray(r2.branch.lam), np.asarray(r1.branch.lam),
                               rtol=1e-10)
    X1, X2 = np.asarray(r1.branch.X), np.asarray(r2.branch.X)
    assert np.abs(X2 - X1).max() <= 1e-10 * np.abs(X1).max()
    b1, b2 = r1.bifurcations or [], r2.bifurcations or []
    assert [b["type"] for b in b1] == [b["type"] for b in b2]
    np.testing.assert_allclose([b["speed_ratio"] for b in b2],
                               [b["speed_ratio"] for b in b1], rtol=1e-8)


def _write_user_model(tmp_path: Path, coupled: bool = False) -> dict:
    """The paper rotor's matrices as a 'user' 6-DOF model: rows shuffled, ty stored with
    the opposite sign, an axial (x) and a torsion (tx) DOF per node that couple to nothing
    (unless ``coupled``)."""
    config = load_config(PAPER)
    from rotorsfd.interop.export import element_rotor

    rotor = element_rotor(config)
    n4 = rotor.n_dof
    node, direction = dof_table(rotor.n_nodes)
    direction = np.where(direction == "ty", "-ty", direction)
    sign = np.where(direction == "-ty", -1.0, 1.0)
    nn = rotor.n_nodes
    full_node = np.concatenate([node, np.arange(1, nn + 1), np.arange(1, nn + 1)])
    full_dir = np.concatenate([direction, ["x"] * nn, ["tx"] * nn])
    rng = np.random.default_rng(3)
    order = rng.permutation(full_node.size)
    arrays = {}
    for k in "MKCG":
        a = np.zeros((full_node.size,) * 2)
        a[:n4, :n4] = sign[:, None] * getattr(rotor, k) * sign[None, :]
        if k in "MK":
            a[n4:, n4:] = np.eye(2 * nn)      # axial / torsion: their own little blocks
        arrays[k] = a[np.ix_(order, order)]
    if coupled:
        arrays["K"][order.tolist().index(n4), order.tolist().index(0)] = 1.0
    np.savez(tmp_path / "user.npz", **arrays, dof_node=full_node[order],
             dof_direction=full_dir[order], node_x=rotor.node_x)
    data = {"title": "user model", "rotor": {"matrices": {"file": "user.npz",
                                                          "n_nodes": nn}}}
    return data


def test_user_dof_map_permutation_signs_dropped(tmp_path):
    data = _write_user_model(tmp_path)
    imported = build_system(config_from_dict(data), tmp_path).rotor
    from rotorsfd.interop.export import element_rotor

    ref = element_rotor(load_config(PAPER))
    for k in "MKCG":
        np.testing.assert_allclose(getattr(imported, k), getattr(ref, k), rtol=0,
                                   atol=1e-12 * np.abs(getattr(ref, k)).max() + 1e-300)


def test_user_dof_map_coupled_dropped_dof_refused(tmp_path):
    data = _write_user_model(tmp_path, coupled=True)
    with pytest.raises(ConfigError, match=r"rotor\.matrices\.K.*dropped DOFs"):
        build_system(config_from_dict(data), tmp_path)


def test_base_rotation_needs_the_base_terms(tmp_path):
    _, toml, imported = _exported(tmp_path, fmt="mtx")
    rotating = imported.model_copy(update={"base": imported.base.model_copy(update={
        "pitching": imported.base.pitching.model_copy(update={"law": "constant",
                                                              "value": 2.0})})})
    with pytest.raises(ConfigError, match=r"base\.pitching\.law.*base-motion terms"):
        build_system(rotating, toml.parent)


def test_gravity_on_matrix_market_model_is_exact(tmp_path):
    """Base translation / gravity need only f = M r: the static sag under gravity of the
    Matrix Market model equals the element model's."""
    over = ["gravity.enabled=true"]
    config, toml, imported = _exported(tmp_path, over, fmt="mtx")
    a = api.run_static(config)
    b = api.run_static(imported, search_path=toml.parent)
    qa, qb = np.asarray(a.q), np.asarray(b.q)
    assert np.abs(qa).max() > 1e-7
    np.testing.assert_allclose(qb, qa, rtol=1e-9, atol=1e-12 * np.abs(qa).max())


@pytest.mark.parametrize(("change", "pattern"), [
    ({"file": "missing.npz"}, r"rotor\.matrices\.file: got 'missing\.npz'; no such file"),
    ({"n_nodes": 20}, r"rotor\.matrices\.dof_map\[\d+\]\.node: got 21; must be a node "
                      r"1\.\.20"),
    ({"n_nodes": 22}, r"rotor\.matrices\.dof_map: got '4 DOFs missing'"),
])
def test_bad_matrices_one_line(tmp_path, change, pattern):
    _, toml, imported = _exported(tmp_path)
    bad = imported.model_copy(update={"rotor": imported.rotor.model_copy(update={
        "matrices": imported.rotor.matrices.model_copy(update=change)})})
    with pytest.raises(ConfigError, match=pattern) as err:
        build_system(bad, toml.parent)
    assert "\n" not in str(err.value)


def test_bad_arrays_one_line(tmp_path):
    n = 8
    M = np.eye(n)
    M[0, 1] = 0.5    # unsymmetric
    np.savez(tmp_path / "m.npz", M=M, K=np.eye(n), dof_node=np.repeat([1, 2], 4),
             dof_direction=np.array(["y", "z", "ty", "tz"] * 2), node_x=[0.0, 1.0])
    data = {"rotor": {"matrices": {"file": "m.npz", "n_nodes": 2}}}
    with pytest.raises(ConfigError, match=r"rotor\.matrices\.M: got 'unsymmetric'"):
        build_system(config_from_dict(data), tmp_path)
    np.savez(tmp_path / "m.npz", M=np.eye(n), K=np.eye(n), dof_node=np.repeat([1, 2], 4),
             dof_direction=np.array(["y", "z", "ty", "q"] * 2), node_x=[0.0, 1.0])
    with pytest.raises(ConfigError, match=r"dof_map\[3\]\.direction: got 'q'"):
        build_system(config_from_dict(data), tmp_path)
    np.savez(tmp_path / "m.npz", M=np.eye(n), K=np.eye(n + 1))
    with pytest.raises(ConfigError, match=r"rotor\.matrices\.K: got 'shape \(9, 9\)'"):
        build_system(config_from_dict(data), tmp_path)


@pytest.mark.parametrize(("rotor", "pattern"), [
    ({"matrices": {"file": "m.npz", "n_nodes": 2},
      "shaft": [{"length": 1.0, "n_elements": 2, "outer_radius": 0.01, "material": "s"}]},
     r"rotor\.shaft: got \[.*\]; give the shaft .* its matrices"),
    ({}, r"rotor\.shaft: got .*; give the shaft"),
    ({"matrices": {"mass": "M.mtx", "stiffness": "K.mtx", "n_nodes": 2}},
     r"rotor\.matrices\.dof_map: got nothing; Matrix Market files need a dof_map"),
    ({"matrices": {"file": "m.npz", "mass": "M.mtx", "n_nodes": 2}},
     r"rotor\.matrices"),
])
def test_config_forms_one_line(rotor, pattern):
    data = {"materials": {"s": {"density": 7800, "young_modulus": 2e11,
                                "poisson_ratio": 0.3}}, "rotor": rotor}
    with pytest.raises(ConfigError, match=pattern):
        config_from_dict(data)


def test_cli_export_matrices(tmp_path, capsys):
    from rotorsfd import cli

    target = tmp_path / "paper.npz"
    assert cli.main(["export-matrices", str(PAPER), "-o", str(target)]) == 0
    assert "paper.toml" in capsys.readouterr().out
    assert cli.main(["config", "check", str(tmp_path / "paper.toml")]) == 0
    assert "21 nodes, given by matrices (paper.npz)" in capsys.readouterr().out
    assert cli.main(["export-matrices", str(PAPER), "-o", str(tmp_path / "m"),
                     "--format", "mtx"]) == 0
    assert sorted(p.name for p in (tmp_path / "m").iterdir()) == [
        "C.mtx", "G.mtx", "K.mtx", "M.mtx", "dof_map.csv"]
    assert cli.main(["modal", str(tmp_path / "m.toml"), "-o", str(tmp_path / "out"),
                     "-q"]) == 0
    rows = (tmp_path / "out" / "critical_speeds.csv").read_text().splitlines()
    assert [round(float(r.split(",")[2]), 1) for r in rows[1:3]] == [811.3, 2784.6]


@pytest.mark.slow
def test_stability_chart_on_exported_matrices(tmp_path, monkeypatch):
    """The Figure 6 example (harmonic pitching: the base terms from the .npz) gives the
    same chart on its exported matrices, run from another folder."""
    from rotorsfd.analyses.stability_chart import run_stability_chart

    example = PAPER.parent / "fig6_duchemin_pitching.toml"
    small = ["analysis.stability_chart.intervals=60", "analysis.stability_chart.x.n=2",
             "analysis.stability_chart.y.n=3"]
    config = load_config(example, small)
    toml = write_export(config, tmp_path / "fig6.npz")[-1]
    monkeypatch.chdir(PAPER.parent)
    a = run_stability_chart(config)
    b = run_stability_chart(load_config(toml), search_path=toml.parent)
    assert a.chart.max_abs.shape == (2, 3)
    np.testing.assert_allclose(b.chart.max_abs, a.chart.max_abs, rtol=1e-9)


@pytest.mark.slow
def test_simulation_same_after_import(tmp_path):
    """Time integration on the imported matrices: the same orbit at the journal and at the
    disk (the disk stays an output node of the exported config)."""
    over = ["unbalance[0].magnitude=144.02 g*mm", "analysis.simulate.periods=40",
            "analysis.simulate.poincare_periods=10", "analysis.simulate.steps_per_period=200",
            "analysis.simulate.step_check_periods=0", "analysis.simulate.speed_ratio=1.0"]
    config, toml, imported = _exported(tmp_path, over)
    a = api.run_simulation(config, progress=False)
    b = api.run_simulation(imported, search_path=toml.parent, progress=False)
    assert a.nodes == b.nodes == (1, 8)
    qa, qb = np.asarray(a.q), np.asarray(b.q)
    assert np.abs(qb - qa).max() <= 1e-9 * np.abs(qa).max()
    assert a.motion_name == b.motion_name == "period-1"
