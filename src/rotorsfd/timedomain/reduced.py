"""Reduced time step: Craig-Bampton onto the nonlinear DOFs plus fixed-interface modes.

The integrated system (``forcing.py``)::

    M q'' + D(t) q' + K(t) q = f(t) + F_nl(q[nl], q'[nl])

is projected on the Craig-Bampton basis of :func:`rotorsfd.stability.reduction.craig_bampton`
(``q = Psi p``, ``p = [q_b, eta]``, ``q_b = q[nl]`` the nonlinear DOFs, kept physical;
static constraint modes ``-K_ii^-1 K_ib`` plus the fixed-interface modes with
``omega <= omega_max``). Galerkin projection, term by term::

    M_r = Psi^T M Psi,  D_r = Psi^T D Psi,  K_r = Psi^T K Psi,

(a modal damping of a few modes, ``D = D_b + U diag(c) U^T``, projected from its factors:
``Psi^T D_b Psi + W^T diag(c) W``, ``W = U^T Psi``, :mod:`rotorsfd.model.lowrank`),
    D_r(t) = D_r + sum d_i(t) Psi^T D_i Psi,  K_r(t) = K_r + sum k_i(t) Psi^T K_i Psi,
    f_r(t) = Psi^T f0 + sum_h [Psi^T fc_h cos + Psi^T fs_h sin] + sum_j c_j(t) Psi^T f_j

The time-varying (moving-base) matrices and loads are time-dependent combinations of
constant arrays, so each array is projected once and the coefficients are kept: the
reduced base terms are exact projections, not re-fitted. ``F_nl`` acts on ``p[:m] = q_b``
unchanged (``Psi[nl, :m] = I``, ``Psi[nl, m:] = 0``), so ``Psi^T`` maps it onto the first
``m`` reduced equations.

The constraint modes make the static response to the nonlinear (boundary) forces exact;
loads on interior DOFs (unbalance, gravity, base terms) would keep only their kept-mode
part. So the basis is augmented by their static residuals (modal truncation augmentation:
Dickens, Nakagawa & Wittbrodt, Comput. Struct. 62, 985-998, 1997): for each load vector
``f``, ``x_i = K_ii^-1 f_i`` on the interior (zero at the boundary), made mass-orthogonal
to the kept modes and to the residuals before it, and dropped when nothing is left
(``<= 1e-10`` of its norm). With ``x`` in the span the reduced static solution of
``K q = f + F_b`` is the exact one (Galerkin with the exact solution in the span), for
every combination of the loads.

A physical state enters by the projection that keeps ``q_b`` exactly::

    p_b = q[nl],   eta = G^-1 Phi^T M_s (q - Psi_b q_b),   G = Phi^T M_s Phi

(``Phi = Psi[:, m:]``, ``M_s`` the symmetric part of ``M``): the mass-orthogonal projection
of the interior on the kept modes. It reproduces ``p`` for any ``q = Psi p``, so a run
continued from a recovered state continues exactly. Outputs come back as ``q = Psi p``
(only the rows asked for).

The error of the reduction is that of the dropped fixed-interface modes: a mode at
``omega_j`` driven at ``omega`` responds ``omega_j^2 / (omega_j^2 - omega^2)`` times its
static share, which the constraint modes keep only at ``omega = 0``; with
``omega_max = c omega_top`` (``omega_top`` the highest frequency of interest) the relative
error of the dropped modes' contribution is ``<= 1 / (c^2 - 1)``, times their (small)
static share. Dropped modes above the step's resolution (``omega h >~ 1``) are not
integrated accurately by the full step either.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.linalg as sla
import scipy.sparse as sp
from scipy.sparse.linalg import eigsh, splu

from rotorsfd.errors import ConfigError
from rotorsfd.model.lowrank import BandedLowRank, project
from rotorsfd.stability.reduction import ReducedModel, craig_bampton
from rotorsfd.timedomain.forcing import Forcing, HarmonicLoad, TimeVaryingMatrices

if TYPE_CHECKING:
    from rotorsfd.second_order import SecondOrderSystem

#: Models with more DOFs are projected with CSR matrices (O(nnz) products and solves).
DENSE_MAX = 400


def load_vectors(forcing: Forcing, n: int) -> list[np.ndarray]:
    """The constant arrays of the external load: the constant part, every harmonic's
    cos/sin vector, every series vector (the moving base's loads among them)."""
    out = [] if forcing.constant is None else [forcing.constant]
    for h in forcing.harmonics:
        out += [h.cos] + ([] if h.sin is None else [h.sin])
    out += [f for _, f in forcing.series]
    return [np.broadcast_to(np.asarray(f, dtype=float), (n,)) for f in out]


def sparse_if_large(a: Any) -> Any:
    """``a`` as CSR when the model is large (``> DENSE_MAX`` DOFs; its products and solves
    then cost O(nnz), the beam matrices being banded), else as a dense array."""
    if isinstance(a, BandedLowRank):      # a modal damping of a few modes beside the band
        return a if a.shape[0] > DENSE_MAX else a.toarray()
    if sp.issparse(a):
        return a.tocsr() if a.shape[0] > DENSE_MAX else a.toarray()
    a = np.asarray(a, dtype=float)
    return sp.csr_matrix(a) if a.shape[0] > DENSE_MAX else a


def interior_solve(K: Any, interior: np.ndarray, rhs: np.ndarray) -> np.ndarray:
    """``K_ii^-1 rhs`` (dense LU, or sparse LU of the CSR ``K``)."""
    if sp.issparse(K):
        return splu(sp.csc_matrix(K[interior][:, interior])).solve(rhs)
    return sla.solve(K[np.ix_(interior, interior)], rhs)


def static_residuals(K: Any, M: Any, basis: np.ndarray, boundary: np.ndarray,
                     loads: list[np.ndarray], drop: float = 1e-10) -> np.ndarray:
    """Columns ``x`` (n, j) of the load residuals of the module docstring: ``x_i =
    K_ii^-1 f_i``, mass-orthonormalised against the interior columns of ``basis`` and
    each other (twice, Gram-Schmidt), ``x_b = 0``. ``K, M`` dense or CSR."""
    n = K.shape[0]
    b = np.asarray(boundary, dtype=np.intp).reshape(-1)
    i = np.setdiff1d(np.arange(n), b)
    loads = [f for f in loads if np.any(f[i] != 0.0)]
    if not loads or i.size == 0:
        return np.zeros((n, 0))
    Mii = M[i][:, i] if not isinstance(M, np.ndarray) else M[np.ix_(i, i)]
    Ms = 0.5 * (Mii + Mii.T)
    X = interior_solve(K, i, np.column_stack([f[i] for f in loads]))
    kept = basis[i, b.size:]
    if kept.shape[1]:
        kept = kept / np.sqrt(np.einsum("ij,ij->j", kept, Ms @ kept))
    out = np.zeros((i.size, 0))
    for x in X.T:
        norm0 = math.sqrt(abs(x @ (Ms @ x)))
        for _ in range(2):
            for cols in (kept, out):
                if cols.shape[1]:
                    x = x - cols @ (cols.T @ (Ms @ x))
        norm = math.sqrt(abs(x @ (Ms @ x)))
        if norm > drop * norm0:
            out = np.column_stack([out, x / norm])
    res = np.zeros((n, out.shape[1]))
    res[i] = out
    return res


def sparse_craig_bampton(M: Any, D: Any, K: Any, boundary: np.ndarray,
                         omega_max: float) -> ReducedModel:
    """:func:`~rotorsfd.stability.reduction.craig_bampton` (``omega_max`` form) of CSR
    matrices without a dense n x n array: the constraint modes ``-K_ii^-1 K_ib`` by a
    sparse LU, the fixed-interface modes ``K_ii^s phi = omega^2 M_ii^s phi`` with
    ``omega <= omega_max`` by shift-invert Lanczos at 0 (ARPACK, the count doubled until
    the highest found is above ``omega_max``), mass-normalised. (A stand-in until the
    banded ``craig_bampton`` lands; tested equal to it.)"""
    n = M.shape[0]
    b = np.asarray(boundary, dtype=np.intp).reshape(-1)
    i = np.setdiff1d(np.arange(n), b)
    Kii = sp.csc_matrix(K[i][:, i])
    try:
        lu = splu(Kii)
        phi_c = -lu.solve(np.asarray(K[i][:, b].toarray())) if b.size else \
            np.zeros((i.size, 0))
    except RuntimeError as exc:                   # "Factor is exactly singular"
        raise ConfigError("K", "singular interior stiffness", "interior must be restrained "
                          "once the boundary DOFs are fixed") from exc
    Ks = sp.csc_matrix(0.5 * (Kii + Kii.T))
    Mii = M[i][:, i]
    Ms = sp.csc_matrix(0.5 * (Mii + Mii.T))
    w2_max = float(omega_max) ** 2
    k = min(16, i.size - 2)
    while True:
        w2, modes = eigsh(Ks, k, M=Ms, sigma=0.0, which="LM")
        if w2.max() > w2_max or k >= i.size - 2:
            break
        k = min(2 * k, i.size - 2)
    order = np.argsort(w2)
    w2, modes = w2[order], modes[:, order]
    keep = w2 <= w2_max
    modes = modes[:, keep]
    modes = modes / np.sqrt(np.einsum("ij,ij->j", modes, Ms @ modes))
    m, nm = b.size, modes.shape[1]
    psi = np.zeros((n, m + nm))
    psi[b, :m] = np.eye(m)
    psi[i, :m] = phi_c
    psi[i, m:] = modes
    return ReducedModel(project(M, psi), project(D, psi), project(K, psi), psi,
                        np.arange(m), np.sqrt(np.clip(w2[keep], 0.0, None)))


@dataclass(frozen=True)
class ReducedStep:
    """The reduced system of one run: ``model`` (Craig-Bampton plus the load residuals,
    ``model.basis = Psi``, ``model.omegas`` the kept fixed-interface modes),
    the projected ``forcing`` and ``time_varying`` matrices, the state projector
    ``projector`` (r, n) (module docstring) and the cutoff ``omega_max`` [rad/s]."""

    model: ReducedModel
    forcing: Forcing
    time_varying: TimeVaryingMatrices | None
    projector: np.ndarray
    omega_max: float

    @property
    def basis(self) -> np.ndarray:
        """``Psi`` (n, r): ``q = Psi p``."""
        return self.model.basis

    @property
    def n_dof(self) -> int:
        """Reduced coordinates r = m + kept modes."""
        return self.model.n_dof

    @property
    def n_physical(self) -> int:
        return self.model.basis.shape[0]

    @property
    def n_modes(self) -> int:
        """Kept fixed-interface modes."""
        return int(self.model.omegas.size)

    @property
    def n_residuals(self) -> int:
        """Static load residuals in the basis."""
        return self.n_dof - self.nl_dofs.size - self.n_modes

    @property
    def nl_dofs(self) -> np.ndarray:
        """The nonlinear DOFs in reduced coordinates, ``0..m-1``."""
        return np.asarray(self.model.nl_dofs, dtype=np.int64)

    def reduce(self, q: np.ndarray) -> np.ndarray:
        """``p`` of a physical vector (or a scalar broadcast to every DOF)."""
        q = np.broadcast_to(np.asarray(q, dtype=float), (self.n_physical,))
        return self.projector @ q

    def physical(self, p: np.ndarray, rows: np.ndarray | None = None) -> np.ndarray:
        """``q = Psi p`` (``p`` (r,) or (samples, r)), only ``rows`` if given."""
        psi = self.basis if rows is None else self.basis[np.asarray(rows, dtype=np.intp)]
        return np.asarray(p, dtype=float) @ psi.T

    def stepped(self, system: SecondOrderSystem) -> SecondOrderSystem:
        """The reduced model as the solvers' record: ``system`` (the one this step
        reduces) in the coordinates ``p`` (nonlinear DOFs ``0..m-1``, the same force law,
        no further reduction)."""
        return replace(system, M=self.model.M, D=self.model.D, K=self.model.K,
                       nl_dofs=self.nl_dofs, forcing=self.forcing,
                       time_varying=self.time_varying, reduction=None)


def state_projector(basis: np.ndarray, M: Any, boundary: np.ndarray) -> np.ndarray:
    """``P`` (r, n) with ``p = P q`` (module docstring): the boundary DOFs taken as they
    are, the interior projected mass-orthogonally on the modal columns of ``basis``
    (``M`` dense or CSR)."""
    b = np.asarray(boundary, dtype=np.intp).reshape(-1)
    m = b.size
    n, r = basis.shape
    P = np.zeros((r, n))
    P[np.arange(m), b] = 1.0
    if r > m:
        phi = basis[:, m:]
        Ms = 0.5 * (M + M.T)
        W = np.asarray((Ms @ phi).T)                 # (k, n), Ms symmetric
        G = W @ phi
        Pm = np.linalg.solve(G, W)
        Pm[:, b] -= Pm @ basis[:, :m]                # - G^-1 Phi^T M_s Psi_b (q_b)
        P[m:] = Pm
    return P


def reduce_step(M: np.ndarray, D: np.ndarray, K: np.ndarray, nl_dofs: np.ndarray,
                forcing: Forcing, time_varying: TimeVaryingMatrices | None,
                omega_max: float) -> ReducedStep:
    """Craig-Bampton projection of the integrated system (module docstring), modes kept
    up to ``omega_max`` [rad/s]. Raises :class:`~rotorsfd.errors.ConfigError` (from
    :func:`craig_bampton`) when the interior is not restrained once ``nl_dofs`` are
    fixed."""
    if not omega_max > 0.0:
        raise ValueError(f"omega_max must be > 0, got {omega_max}")
    nl = np.asarray(nl_dofs, dtype=np.int64).reshape(-1)
    M, D, K = (sparse_if_large(a) for a in (M, D, K))
    if isinstance(M, np.ndarray):
        cb = craig_bampton(M, D, K, nl, omega_max=float(omega_max))
    else:
        cb = sparse_craig_bampton(M, D, K, nl, float(omega_max))
    extra = static_residuals(K, M, cb.basis, nl, load_vectors(forcing, M.shape[0]))
    psi = np.hstack([cb.basis, extra])
    model = ReducedModel(project(M, psi), project(D, psi), project(K, psi), psi,
                         cb.nl_dofs, cb.omegas)

    def vec(v: np.ndarray | None) -> np.ndarray | None:
        return None if v is None else psi.T @ np.broadcast_to(np.asarray(v, float),
                                                               (psi.shape[0],))

    def mat(X: np.ndarray) -> np.ndarray:
        return psi.T @ (sparse_if_large(X) @ psi)

    red_forcing = Forcing(
        omega=forcing.omega, constant=vec(forcing.constant),
        harmonics=tuple(HarmonicLoad(h.multiple, vec(h.cos), vec(h.sin))
                        for h in forcing.harmonics),
        series=tuple((c, vec(f)) for c, f in forcing.series))
    red_tv = None
    if time_varying is not None and time_varying.n_terms:
        red_tv = TimeVaryingMatrices(
            damping=tuple((c, mat(X)) for c, X in time_varying.damping),
            stiffness=tuple((c, mat(X)) for c, X in time_varying.stiffness))
    return ReducedStep(model, red_forcing, red_tv, state_projector(psi, M, nl),
                       float(omega_max))


def reduce_system(system: SecondOrderSystem, omega_max: float) -> ReducedStep:
    """:func:`reduce_step` of a :class:`~rotorsfd.second_order.SecondOrderSystem`, modes
    kept up to ``omega_max`` [rad/s]."""
    return reduce_step(system.M, system.D, system.K, system.nl_dofs, system.forcing,
                       system.time_varying, omega_max)
