"""The receptance blocks of the Neimark-Sacker test function (harmonic/ns_curve.py) on a
rotor above DENSE_MAX_DOF (issue 17 item 2): from the band (one banded LU per shifted
frequency, the nonlinear DOFs' columns only) with no dense n x n matrix formed, equal to
the dense batched LAPACK solve of the same Z(W) = K - W^2 M + i W D to 1e-10; with modal
damping of a few modes (the low-rank term beside the band, by Woodbury) too, and at
theta = 0 (a zero frequency among the shifted ones)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from rotors import forbid_dense_rotor_matrices, uniform_sfd_rotor_raw
from rotorsfd.harmonic.fold_curve import TwoParameterHB
from rotorsfd.harmonic.ns_curve import NeimarkSackerSystem, receptance_blocks, shifted_hill
from rotorsfd.io.config import config_from_dict
from rotorsfd.model.build import build_system
from rotorsfd.model.sparse import DENSE_MAX_DOF

K_PAIRS = 3
SPEED = 600.0


def _family(modal_ratio: float | None):
    """The (speed, unbalance) family of the 420-DOF uniform rotor (104 elements)."""
    system = build_system(config_from_dict(uniform_sfd_rotor_raw(104, modal_ratio)))
    assert system.n_dof == 420 > DENSE_MAX_DOF
    return system.two_parameter_problem("unbalance.magnitude")


def _dense(problem):
    """The same problem with its linear part as plain dense matrices (the dense path)."""
    part = problem.matrices
    return dataclasses.replace(problem, matrices=lambda lam: part(lam),
                               dmatrices=part.derivatives)


@pytest.mark.parametrize("modal_ratio", [None, 0.02])
@pytest.mark.parametrize("theta", [0.0, 0.31])
def test_banded_receptance_blocks_equal_the_dense_solve(monkeypatch, modal_ratio, theta):
    family = _family(modal_ratio)
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        problem = family.first(5e-5)
        assert problem.matrices.lowrank is not None or modal_ratio is None
        blocks = receptance_blocks(problem, SPEED, theta, K_PAIRS)
    ref = receptance_blocks(_dense(problem), SPEED, theta, K_PAIRS)
    assert blocks.shape == ref.shape == (2 * K_PAIRS, problem.m, problem.m)
    # each block against its own size (the blocks span orders of magnitude in W)
    err = np.max(np.abs(blocks - ref), axis=(1, 2)) / np.max(np.abs(ref), axis=(1, 2))
    print(f"modal {modal_ratio}, theta {theta}: largest relative difference {err.max():.1e}")
    assert np.all(err <= 1e-10)
    # the blocks are dynamic stiffnesses of the SFD node: not trivially equal (e.g. 0)
    assert np.all(np.max(np.abs(ref), axis=(1, 2)) > 1e3)


def test_ns_system_of_a_large_rotor_forms_no_dense_matrix(monkeypatch):
    """The Neimark-Sacker system (its HB base condensed on the band, the shifted Hill
    operator from the banded blocks) built and evaluated under the guard; its Hill
    operator equals the one from the dense blocks to 1e-10."""
    family = _family(None)
    H, N = 2, 16
    with monkeypatch.context() as m:
        forbid_dense_rotor_matrices(m)
        p = family.first(5e-5)
        xs0 = np.zeros((2 * H + 1, p.m))
        xs0[1, 0] = xs0[2, 1] = 1e-5            # a small whirl at the SFD
        hb = TwoParameterHB(family, H, N, (SPEED, 5e-5), xs0.ravel(), (SPEED, 5e-5))
        zb = hb.to_z(xs0, SPEED, 5e-5)
        z0 = np.concatenate([zb[:-1], [0.31], zb[-1:]])
        ns = NeimarkSackerSystem(hb, z0, K_PAIRS)
        F, J = ns.evaluate(z0)
        A = ns.hill(z0) / ns.unit
    assert np.all(np.isfinite(F)) and np.all(np.isfinite(J))
    X = hb.coefficients(ns.embed(z0))
    blocks = receptance_blocks(_dense(p), SPEED, 0.31, K_PAIRS)
    ref = shifted_hill(p, X, SPEED, 0.31, K_PAIRS, N, blocks=blocks)
    assert np.max(np.abs(A - ref)) <= 1e-10 * np.max(np.abs(ref))
