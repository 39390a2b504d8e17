"""Stability charts of linear time-periodic systems over a two-parameter grid.

System (paper Figure 6 kind, e.g. a rotor under harmonic base motion)::

    M x'' + D(t) x' + K(t) x = 0,
    D(t) = sum_i d_i(t, p1, p2) D_i,   K(t) = sum_i k_i(t, p1, p2) K_i,

with constant basis matrices and scalar coefficient functions of period ``T(p1, p2)``.
Each grid point gets the monodromy by the average-acceleration Newmark state transition
(see ``monodromy``) on an optional reduced modal basis ``x = V z`` (Galerkin), vectorised
over the p2 values of a grid row (batched ``solve``/``matmul``) and over rows with a
thread pool (numpy's linear algebra releases the GIL).

Resolution: modes with ``omega h > ~0.5`` (``h = T/N``) are not resolved; the scheme
keeps undamped ones on the unit circle (the trapezoidal map is symplectic) but compresses
their frequencies, so keep the basis to the modes that matter (``n_modes``) and check a
few points with a larger ``n_intervals`` (benchmark pitching chart, A0 = 1, 20 values of
w_b: N = 200 and N = 3200 agree to 1e-3 in max |mu| except at one point, 8e-3).

Large models (issue 17 item 2): above :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs
the matrices may be CSR (a modal damping of a few modes a
:class:`~rotorsfd.model.lowrank.BandedLowRank`), projected term by term
(:func:`~rotorsfd.model.lowrank.project`), and the basis is never the n x n identity:
without ``basis`` or ``n_modes`` it is the :data:`LARGE_MODES` lowest undamped modes,
found by shift-invert Lanczos (:func:`lowest_modes`). The monodromy of a Galerkin basis
depends only on its span, so the sparse eigensolver's basis gives the dense one's
multipliers when the span is the same (no degenerate pair split by the count).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from numpy.typing import ArrayLike, NDArray

from rotorsfd.model.lowrank import project
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.stability.floquet import STABILITY_TOL

LARGE_MODES = 12
"""Modes of the default basis of a model above ``DENSE_MAX_DOF`` DOFs (no identity)."""

Coefficient = Callable[[NDArray, NDArray, NDArray], NDArray]
"""``c(t, p1, p2)`` with numpy broadcasting (t: (N+1, n2), p1: scalar, p2: (1, n2))."""


@dataclass
class LTPSystem:
    """``M x'' + sum d_i D_i x' + sum k_i K_i x = 0``; a term's coefficient None means 1.

    ``period``: a float or a vectorised callable ``T(p1, p2)``.
    """

    M: NDArray[np.float64]
    D_terms: Sequence[tuple[NDArray, Coefficient | None]]
    K_terms: Sequence[tuple[NDArray, Coefficient | None]]
    period: float | Callable[[NDArray, NDArray], NDArray]

    @property
    def n_dof(self) -> int:
        return int(self.M.shape[0])

    @property
    def is_large(self) -> bool:
        """More than ``DENSE_MAX_DOF`` DOFs: the sparse eigensolver, no identity basis."""
        return self.n_dof > DENSE_MAX_DOF

    def constant_stiffness(self) -> Any:
        """Sum of the constant K terms (dense, or CSR when M is sparse)."""
        if sp.issparse(self.M):
            out = sp.csr_matrix(self.M.shape)
            for K, c in self.K_terms:
                if c is None:
                    out = out + (K if sp.issparse(K) else sp.csr_matrix(np.asarray(K)))
            return out.tocsr()
        return sum((np.asarray(K) for K, c in self.K_terms if c is None),
                   np.zeros_like(self.M))

    def modal_basis(self, n_modes: int) -> NDArray[np.float64]:
        """Lowest ``n_modes`` undamped modes of (sum of constant K terms, M): dense
        ``eigh`` up to ``DENSE_MAX_DOF`` DOFs, else :func:`lowest_modes`."""
        K0 = self.constant_stiffness()
        if self.is_large:
            return lowest_modes(K0, self.M, n_modes)[1]
        K0 = 0.5 * (K0 + K0.T)
        M = np.asarray(self.M, float)
        _, V = sla.eigh(K0, 0.5 * (M + M.T), subset_by_index=(0, n_modes - 1))
        return V


def lowest_modes(K: Any, M: Any, count: int) -> tuple[NDArray, NDArray]:
    """``(omega^2 (count,), Phi (n, count))``: the lowest ``count`` undamped modes of the
    symmetric parts of (K, M) (sparse or dense), ``K_s phi = omega^2 M_s phi``, by
    shift-invert Lanczos (ARPACK ``eigsh``) at ``sigma = 0`` (at ``-1`` when K is
    singular) from the deterministic start ``v0_i = 1 + cos(sqrt(2) i)``; ascending,
    mass-normalised. O(nnz) per iteration, no dense n x n array."""
    # deferred: scipy.sparse.linalg is heavy (loaded only when this runs)
    from scipy.sparse.linalg import eigsh

    n = int(M.shape[0])
    if not 1 <= count <= n - 2:
        raise ValueError(f"count must be in 1..{n - 2} for the sparse eigensolver, "
                         f"got {count}")
    Ks = sp.csc_matrix(0.5 * (sp.csr_matrix(K) + sp.csr_matrix(K).T))
    Ms = sp.csc_matrix(0.5 * (sp.csr_matrix(M) + sp.csr_matrix(M).T))
    v0 = 1.0 + np.cos(np.sqrt(2.0) * np.arange(n))
    try:
        lam, V = eigsh(Ks, count, M=Ms, sigma=0.0, which="LM", v0=v0)
    except RuntimeError:                    # "Factor is exactly singular": a free rotor
        lam, V = eigsh(Ks, count, M=Ms, sigma=-1.0, which="LM", v0=v0)
    order = np.argsort(lam)
    lam, V = lam[order], V[:, order]
    V = V / np.sqrt(np.einsum("ij,ij->j", V, Ms @ V))
    return lam, V


@dataclass
class StabilityChart:
    """Result grid: ``max_abs[i, j]`` and ``critical[i, j]`` at ``(p1[i], p2[j])``."""

    p1: NDArray[np.float64]
    p2: NDArray[np.float64]
    max_abs: NDArray[np.float64]
    critical: NDArray[np.complex128]
    tol: float = STABILITY_TOL
    names: tuple[str, str] = ("p1", "p2")
    info: dict = field(default_factory=dict)

    @property
    def stable(self) -> NDArray[np.bool_]:
        return self.max_abs <= 1.0 + self.tol

    def to_dataset(self):
        """xarray Dataset with max_abs, stable, critical_re, critical_im."""
        # deferred: xarray is heavy (loaded only when this runs)
        import xarray as xr

        dims = list(self.names)
        coords = {self.names[0]: self.p1, self.names[1]: self.p2}
        ds = xr.Dataset(
            {"max_abs_multiplier": (dims, self.max_abs),
             "stable": (dims, self.stable.astype(np.int8)),
             "critical_re": (dims, self.critical.real),
             "critical_im": (dims, self.critical.imag)},
            coords=coords,
            attrs={"stability_tol": self.tol, "method": "newmark average acceleration",
                   **{k: str(v) for k, v in self.info.items()}})
        return ds

    def to_netcdf(self, path: str) -> None:
        self.to_dataset().to_netcdf(path)


def _coefs(terms, t, p1, p2) -> NDArray:
    out = np.empty((len(terms), *t.shape))
    for i, (_, c) in enumerate(terms):
        out[i] = 1.0 if c is None else np.broadcast_to(c(t, p1, p2), t.shape)
    return out


def _row(sys_r: dict, p1: float, p2: NDArray, N: int) -> tuple[NDArray, NDArray]:
    """Multipliers' max modulus and critical multiplier for one grid row (batched)."""
    M, Dm, Km = sys_r["M"], sys_r["D"], sys_r["K"]
    r = M.shape[0]
    B = p2.size
    T = np.broadcast_to(np.asarray(sys_r["period"](p1, p2[None, :]) if callable(
        sys_r["period"]) else sys_r["period"], float), (1, B)).ravel()
    h = (T / N)[:, None, None]
    t = np.arange(N + 1)[:, None] * (T / N)[None, :]
    cd = _coefs(sys_r["D_terms"], t, p1, p2[None, :])  # (nd, N+1, B)
    ck = _coefs(sys_r["K_terms"], t, p1, p2[None, :])
    Dt = np.einsum("dtb,dij->tbij", cd, Dm)  # (N+1, B, r, r)
    Kt = np.einsum("dtb,dij->tbij", ck, Km)
    X = np.zeros((B, r, 2 * r))
    V = np.zeros((B, r, 2 * r))
    X[:, :, :r] = np.eye(r)
    V[:, :, r:] = np.eye(r)
    M4 = 4.0 / h**2 * M
    for j in range(N):
        D1, K1 = Dt[j + 1], Kt[j + 1]
        S = M4 + 2.0 / h * D1 + K1
        rhs = (M4 + 2.0 / h * D1 - Kt[j]) @ X + (4.0 / h * M + D1 - Dt[j]) @ V
        Xn = np.linalg.solve(S, rhs)
        V = 2.0 / h * (Xn - X) - V
        X = Xn
    mu = np.linalg.eigvals(np.concatenate([X, V], axis=1))
    k = np.argmax(np.abs(mu), axis=1)
    crit = mu[np.arange(B), k]
    return np.abs(crit), crit


def stability_chart(system: LTPSystem, p1: ArrayLike, p2: ArrayLike, *,
                    n_intervals: int = 200, n_modes: int | None = None,
                    basis: ArrayLike | None = None, tol: float = STABILITY_TOL,
                    workers: int = 1, names: tuple[str, str] = ("p1", "p2")
                    ) -> StabilityChart:
    """Max Floquet multiplier modulus on the grid ``p1 x p2`` (rows p1, columns p2).

    ``basis`` (n, r) or ``n_modes`` (lowest undamped modes of the constant K terms) gives
    a Galerkin reduction; default: the full model up to ``DENSE_MAX_DOF`` DOFs, above it
    the ``LARGE_MODES`` lowest modes (module docstring). ``info`` reports ``n_reduced``
    (the basis size) and ``basis`` (full, modal, given). ``n_intervals``: Newmark intervals per
    period. ``workers``: threads over rows.
    """
    p1 = np.asarray(p1, float).ravel()
    p2 = np.asarray(p2, float).ravel()
    n = system.n_dof
    kind = "given" if basis is not None else "modal" if n_modes is not None else "full"
    if basis is None and n_modes is None and system.is_large:
        n_modes, kind = min(LARGE_MODES, n - 2), "modal (default above DENSE_MAX_DOF)"
    if basis is None and n_modes is not None:
        basis = system.modal_basis(n_modes)
    if basis is None:                      # the full model (<= DENSE_MAX_DOF DOFs)
        V = np.eye(n)

        def proj(X: Any) -> NDArray:
            return V.T @ np.asarray(X, float) @ V
    else:
        V = np.asarray(basis, float)

        def proj(X: Any) -> NDArray:
            return project(X, V)

    sys_r = {"M": proj(system.M),
             "D": np.array([proj(Dm) for Dm, _ in system.D_terms]).reshape(
                 -1, V.shape[1], V.shape[1]),
             "K": np.array([proj(Km) for Km, _ in system.K_terms]).reshape(
                 -1, V.shape[1], V.shape[1]),
             "D_terms": system.D_terms, "K_terms": system.K_terms,
             "period": system.period}
    if len(system.D_terms) == 0:
        sys_r["D_terms"] = [(None, lambda t, a, b: 0.0 * t)]
        sys_r["D"] = np.zeros((1, V.shape[1], V.shape[1]))
    max_abs = np.empty((p1.size, p2.size))
    crit = np.empty((p1.size, p2.size), complex)
    with ThreadPoolExecutor(max_workers=max(1, workers)) as ex:
        for i, (a, c) in enumerate(ex.map(lambda v: _row(sys_r, v, p2, n_intervals), p1)):
            max_abs[i], crit[i] = a, c
    return StabilityChart(p1, p2, max_abs, crit, tol, names,
                          {"n_intervals": n_intervals, "n_dof": n,
                           "n_reduced": V.shape[1], "basis": kind})
