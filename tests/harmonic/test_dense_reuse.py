"""The dense LAPACK condensation (:func:`rotorsfd.harmonic.dense_condensation.dense_solves`,
the path of a dense modal damping matrix) with the harmonics of a condensation at fewer
harmonics copied (``k_first``) = the full condensation, bit for bit, and = an independent
solve of Zt_k."""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

from rotorsfd.harmonic.dense_condensation import dense_solves

N, S = 24, np.array([3, 17])


def _system(seed: int = 0):
    rng = np.random.default_rng(seed)
    A = rng.normal(size=(N, N))
    K = 1e6 * (A @ A.T + N * np.eye(N))
    M = np.diag(rng.uniform(0.5, 2.0, N))
    D = rng.normal(size=(N, N)) * 30.0           # dense (modal damping on all modes)
    dK, dM, dD = 1e3 * rng.normal(size=(N, N)), np.zeros((N, N)), rng.normal(size=(N, N))
    return M, D, K, dM, dD, dK


def _inputs(H: int = 5, seed: int = 1):
    rng = np.random.default_rng(seed)
    m = S.size
    delta = rng.normal(size=(H + 1, m, m)) * 1e5 + 1j * rng.normal(size=(H + 1, m, m)) * 1e3
    F = rng.normal(size=(H + 1, N)) + 1j * rng.normal(size=(H + 1, N))
    return delta, F, rng.normal(size=(H + 1, N)) + 0j


def _run(H: int, k_first: int = 0, sol=None, dsol=None):
    """dense_solves at H harmonics (the first H + 1 of :func:`_inputs`)."""
    m = S.size
    p = SimpleNamespace(nl_dofs=S, m=m, n_dof=N)
    delta, F, dF = (np.ascontiguousarray(a[: H + 1]) for a in _inputs())
    out = np.full((H + 1, N, m + 1), np.nan, complex) if sol is None else sol
    dout = np.full((H + 1, m, m + 1), np.nan, complex) if dsol is None else dsol
    dense_solves(p, H, delta, *_system(), 310.0, 1.3, F, dF, True, out, dout, k_first)
    return out, dout, delta, F


def test_copied_harmonics_give_the_full_condensation_bit_for_bit() -> None:
    full, dfull, _, _ = _run(5)
    lo, dlo, _, _ = _run(2)                        # the same problem at H = 2
    sol = np.full_like(full, np.nan)
    dsol = np.full_like(dfull, np.nan)
    sol[:3], dsol[:3] = lo[:3], dlo[:3]            # harmonics 0..2 "known"
    _run(5, 3, sol, dsol)
    assert np.array_equal(sol, full) and np.array_equal(dsol, dfull)


def test_the_condensation_solves_zt_k() -> None:
    sol, _, delta, F = _run(4)
    M, D, K, *_ = _system()
    w = 310.0
    for k in range(5):
        Z = K - (k * w) ** 2 * M + 1j * k * w * D
        Z[np.ix_(S, S)] += delta[k]
        ref = np.linalg.solve(Z, np.column_stack([np.eye(N)[:, S], F[k]]))
        rel = np.abs(sol[k] - ref).max() / np.abs(ref).max()
        assert rel <= 1e-15 * np.linalg.cond(Z) + 1e-13, k
