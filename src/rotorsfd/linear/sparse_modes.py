"""The lowest complex modes of a large linear rotor by shift-invert Arnoldi (ARPACK).

The pencil of ``M q'' + D q' + K q = 0`` in the state ``x = [q, q' / w_s]`` (velocity
scaled by ``w_s`` so both halves weigh alike in ARPACK's inner product) is
``A x = lambda B x``; with a real shift sigma the operator
``(A - sigma B)^-1 B`` is applied without forming the 2n system:

    Z(sigma) y1 = -(M x2 w_s + (D + sigma M) x1),   Z(sigma) = K + sigma D + sigma^2 M,
    y2 = (x1 + sigma y1) / w_s,

one banded LU of the n x n Z per speed (LAPACK ``dgbtrf``; sparse LU when the band is
wide). Its eigenvalues ``nu = 1 / (lambda - sigma)`` of largest modulus are the lambda
nearest sigma. The lowest modes in damped frequency are asked for: ARPACK's ``k`` is raised
until every retained mode has ``Im lambda < |lambda_k - sigma| / COVER`` (``lambda_k`` the
farthest root found), so no root with ``Im lambda`` below the retained ones and a damping
ratio below ``sqrt(1 - 1 / COVER^2)`` (0.55) can be missed. Roots are then selected as in
the dense path (:func:`rotorsfd.linear.modal.select_modes`), the rigid-body threshold taken
on ``sqrt(max K_ii / M_ii)`` (a lower bound of max|lambda|, which the dense path uses).

M, D, K come from ``system.split_matrices(speed)`` or ``system.sparse_matrices(speed)``
(CSR, no dense n x n array) when the system has them, else from ``system.matrices(speed)``
(dense): their nonzero pattern is extracted once per system at three speeds and stored
sparse as the affine polynomial ``D(speed) = D0 + speed D1`` (same for M and K), checked
at the third speed; a system that is not affine in the speed is re-extracted at every
speed.

Modal damping of a few modes (``rotor.damping.modes``) stays beside the band:
``D = D_b + U diag(c) U^T`` (:class:`rotorsfd.model.lowrank.BandedLowRank`, U n x r), so
``Z(sigma) = Z_b(sigma) + sigma U diag(c) U^T`` with the banded
``Z_b = K + sigma D_b + sigma^2 M``, and by the Woodbury identity

    Z^-1 b = Z_b^-1 b - Y Cap^-1 U^T Z_b^-1 b,   Y = Z_b^-1 U,
    Cap = diag(1 / (sigma c)) + U^T Y   (r x r),

one banded LU and r more solves per speed (at sigma = 0, Z = K: no correction); the
products ``D x`` apply the term as ``U (c * U^T x)``. Exact: the same operator as with
the dense D, up to rounding.
"""

from __future__ import annotations

import weakref
from dataclasses import dataclass, field
from typing import Any

import numpy as np
import scipy.linalg.lapack as lapack
import scipy.sparse as sp
import scipy.sparse.linalg as sla
from scipy.linalg import lu_factor, lu_solve

from rotorsfd.errors import ConvergenceError
from rotorsfd.linear.modes import RIGID_BODY_TOL, LinearDynamics, ModalResult, select_modes
from rotorsfd.model.lowrank import BandedLowRank

COVER = 1.2            # retained modes: Im(lambda) < |farthest root found - sigma| / COVER
BANDED_MAX = 200       # widest half-bandwidth factorised by LAPACK's banded LU
SPEED_PROBE = 1.0e3    # [rad/s] probe speed of the affine extraction
AFFINE_RTOL = 1e-12    # relative check of the affine fit at the third speed


def band_width(a: np.ndarray) -> int:
    """Largest |i - j| of a nonzero a_ij of the dense square ``a``: the nonzeros of the
    diagonals |d| <= h are counted outwards until they are all of ``a``'s (one counting
    pass over ``a``; a full index scan past BANDED_MAX)."""
    total = int(np.count_nonzero(a))
    inside = int(np.count_nonzero(np.diagonal(a)))
    h = 0
    while inside < total and h < min(BANDED_MAX, a.shape[0] - 1):
        h += 1
        inside += int(np.count_nonzero(np.diagonal(a, h)) + np.count_nonzero(np.diagonal(a, -h)))
    if inside == total:
        return h
    i, j = np.divmod(np.flatnonzero(a), a.shape[0])
    return int(np.max(np.abs(i - j)))


def _sparse(a: Any) -> sp.csr_matrix:
    """``a`` (dense, or already sparse) as CSR: read by diagonals within its band."""
    if sp.issparse(a):
        return sp.csr_matrix(a, dtype=float)
    a = np.asarray(a, dtype=float)
    half = band_width(a)
    if half > BANDED_MAX:
        m = sp.csr_matrix(a)
    else:
        offsets = list(range(-half, half + 1))
        m = sp.diags([np.diagonal(a, d) for d in offsets], offsets, shape=a.shape,
                     format="csr")
    m.eliminate_zeros()
    return m


def _affine(s0: sp.csr_matrix, s1: sp.csr_matrix, s2: sp.csr_matrix, h: float
            ) -> tuple[sp.csr_matrix, sp.csr_matrix] | None:
    """(A0, A1) with A(s) = A0 + s A1 from A(0), A(h), A(2h); None if A(2h) disagrees."""
    if s1 is s0 and s2 is s0:                       # the same object: free of the speed
        return s0, sp.csr_matrix(s0.shape)
    slope = (s1 - s0) / h
    diff = s2 - s0 - 2.0 * h * slope
    err = abs(diff).max() if diff.nnz else 0.0
    scale = max(abs(s2).max() if s2.nnz else 0.0, abs(s0).max() if s0.nnz else 0.0, 1e-300)
    return (s0, slope) if err <= AFFINE_RTOL * scale else None


def _matrices(system: LinearDynamics, speed: float) -> tuple[Any, Any, Any]:
    """(M, D, K) at ``speed``: the system's sparse ones when it has them
    (``split_matrices``: D may be a :class:`~rotorsfd.model.lowrank.BandedLowRank`, or
    ``sparse_matrices``, e.g. :class:`~rotorsfd.model.system.RotorSystem`), else dense."""
    for name in ("split_matrices", "sparse_matrices"):
        sparse = getattr(system, name, None)
        if sparse is not None:
            return sparse(speed)
    return system.matrices(speed)


def _split(a: Any) -> tuple[Any, tuple[np.ndarray, np.ndarray] | None]:
    """(the sparse or dense part, the low-rank factors (U, c) or None): the columns with
    ``|c| > 1e-14 max |c|`` (a rigid-body mode's rounding-level damping would put
    ``1 / (sigma c)`` near overflow in the Woodbury capacitance, for a term below 1e-14
    of the damping)."""
    if isinstance(a, BandedLowRank):
        keep = np.abs(a.c) > 1e-14 * np.abs(a.c).max(initial=0.0)
        return a.band, ((a.U[:, keep], a.c[keep]) if np.any(keep) else None)
    return a, None


def _half_band(a: sp.spmatrix) -> int:
    coo = a.tocoo()
    return int(np.abs(coo.row - coo.col).max()) if coo.nnz else 0


@dataclass
class SparsePencil:
    """M, D, K of a system stored sparse: affine in the speed, or re-read per speed."""

    terms: tuple[tuple[sp.csr_matrix, sp.csr_matrix], ...] | None   # (X0, X1) for M, D, K
    n_dof: int
    half_band: int
    scale: float                      # sqrt(max K_ii / M_ii): lower bound of max|lambda|
    state_scale: float                # w_s of the state [q, q' / w_s] (a half-sine's RQ)
    last_start: dict[tuple[int, int], np.ndarray] = field(default_factory=dict)
    #: (U, c): a constant damping term ``U diag(c) U^T`` beside D (not in ``terms``)
    lowrank: tuple[np.ndarray, np.ndarray] | None = None

    @classmethod
    def from_system(cls, system: LinearDynamics) -> SparsePencil:
        """Extract the pattern at speeds 0, h, 2h (h = SPEED_PROBE) once."""
        h = SPEED_PROBE
        samples = [_matrices(system, s) for s in (0.0, h, 2.0 * h)]
        done: dict[int, sp.csr_matrix] = {}      # one conversion per distinct array
        lowrank = _split(samples[0][1])[1]

        def convert(a: Any) -> sp.csr_matrix:
            if id(a) not in done:
                done[id(a)] = _sparse(_split(a)[0])
            return done[id(a)]

        sparse_samples = [[convert(a) for a in sample] for sample in samples]
        terms: list | None = []
        for j in range(3):
            fit = _affine(*(sample[j] for sample in sparse_samples), h)
            if fit is None:
                terms = None
                break
            terms.append(fit)
        mats = sparse_samples[0]
        half = max(_half_band(m) for m in done.values())
        m_d, k_d = mats[0].diagonal(), mats[2].diagonal()
        if np.any(m_d <= 0.0):
            raise ConvergenceError("mass matrix is not positive definite (a diagonal entry "
                                   "<= 0)")
        scale = float(np.sqrt(max(np.max(np.abs(k_d) / m_d), 1e-300)))
        bend = np.zeros(mats[0].shape[0])   # half sine in y: w_s ~ the first bending mode
        bend[0::4] = np.sin(np.pi * (np.arange(bend[0::4].size) + 0.5) / bend[0::4].size)
        w_s = float(np.sqrt(abs(bend @ (mats[2] @ bend)) / (bend @ (mats[0] @ bend))))
        return cls(tuple(terms) if terms is not None else None, mats[0].shape[0],
                   half, scale, w_s if w_s > 1.0 else 1.0, lowrank=lowrank)

    def matrices(self, system: LinearDynamics, speed: float
                 ) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
        """(M, D, K) of ``system`` (the one extracted) at ``speed``, sparse."""
        if self.terms is None:
            return tuple(_sparse(_split(x)[0]) for x in _matrices(system, speed))  # type: ignore
        return tuple(x0 + speed * x1 if x1.nnz else x0 for x0, x1 in self.terms)  # type: ignore


class _Factor:
    """LU of the n x n sparse Z: LAPACK banded when the band is narrow, else SuperLU."""

    def __init__(self, z: sp.csr_matrix) -> None:
        n = z.shape[0]
        half_band = _half_band(z)
        self.banded = half_band <= BANDED_MAX
        if self.banded:
            kl = ku = max(half_band, 1)
            ab = np.zeros((2 * kl + ku + 1, n))
            coo = z.tocoo()
            ab[kl + ku + coo.row - coo.col, coo.col] = coo.data
            lu, piv, info = lapack.dgbtrf(ab, kl, ku)
            if info != 0:
                raise np.linalg.LinAlgError(f"singular Z (dgbtrf info {info})")
            self.lu, self.piv, self.kl, self.ku = lu, piv, kl, ku
        else:
            self.slu = sla.splu(z.tocsc())

    def solve(self, b: np.ndarray) -> np.ndarray:
        if self.banded:
            x, _ = lapack.dgbtrs(self.lu, self.kl, self.ku, b, self.piv)
            return x
        return self.slu.solve(b)


def _needed(res: ModalResult, n_modes: int, whirl: str | None, count: int) -> int:
    """Modes of ``res`` needed: n_modes, or fewer once ``count`` modes of ``whirl`` are in."""
    if whirl is None:
        return n_modes
    hits = np.flatnonzero(res.whirl == whirl) if whirl != "any" else np.arange(res.whirl.size)
    return int(hits[count - 1]) + 1 if hits.size >= count else n_modes


def _operator(pencil: SparsePencil, mats, sigma: float) -> sla.LinearOperator:
    """x -> (A - sigma B)^-1 B x in the scaled state (module docstring)."""
    mass, damping, stiffness = mats
    n, w_s = pencil.n_dof, pencil.state_scale
    z = stiffness + sigma * damping + sigma * sigma * mass if sigma else stiffness
    factor = _Factor(sp.csr_matrix(z))
    d_shift = damping + sigma * mass if sigma else damping
    solve, damp = factor.solve, d_shift.dot
    if pencil.lowrank is not None:             # D = D_b + U diag(c) U^T (module docstring)
        U, c = pencil.lowrank

        def damp(x: np.ndarray) -> np.ndarray:
            return d_shift @ x + U @ (c * (U.T @ x))

        if sigma:
            Y = factor.solve(U)
            cap = np.diag(1.0 / (sigma * c)) + U.T @ Y
            cap_lu = lu_factor(cap)

            def solve(b: np.ndarray) -> np.ndarray:
                x = factor.solve(b)
                return x - Y @ lu_solve(cap_lu, U.T @ x)

    def apply(x: np.ndarray) -> np.ndarray:
        x1, x2 = x[:n], x[n:]
        y1 = -solve(mass @ (w_s * x2) + damp(x1))
        return np.concatenate([y1, (x1 + sigma * y1) / w_s])

    return sla.LinearOperator((2 * n, 2 * n), matvec=apply, dtype=float)


def _arnoldi(op: sla.LinearOperator, k: int, start: np.ndarray | None
             ) -> tuple[np.ndarray, np.ndarray]:
    """The k eigenpairs of largest |nu| (ARPACK); a run that stops at its iteration limit
    with all k converged (defective rigid-body roots) is kept."""
    try:
        return sla.eigs(op, k=k, which="LM", tol=0.0, v0=start)
    except sla.ArpackNoConvergence as exc:
        if exc.eigenvalues.size == k:
            return exc.eigenvalues, exc.eigenvectors
        raise


def sparse_eigen(system: LinearDynamics, speed: float, n_modes: int = 8,
                 whirl: str | None = None, count: int = 0) -> ModalResult:
    """The ``n_modes`` lowest modes at ``speed`` (as :func:`rotorsfd.linear.modal.eigen`),
    or, with ``whirl`` ("forward", "backward", "any") and ``count``, only the lowest ones
    up to the ``count``-th of that whirl (never more than ``n_modes``). The shift is 0, or
    -w_s, -10 w_s when K is singular (rigid-body roots) or ARPACK fails there. ARPACK
    starts from the previous call's Ritz vectors (same ``n_modes``, ``count``), so results
    depend on the call history at round-off level only."""
    pencil = pencil_of(system)
    mats = pencil.matrices(system, speed)
    failure = ""
    for sigma in (0.0, -pencil.state_scale, -10.0 * pencil.state_scale):
        try:
            return _lowest(pencil, _operator(pencil, mats, sigma), sigma, speed, n_modes,
                           whirl, count)
        except (np.linalg.LinAlgError, RuntimeError, sla.ArpackError) as exc:
            failure = f"{type(exc).__name__}: {exc}"
    raise ConvergenceError(f"sparse eigensolver failed at speed {speed} rad/s ({failure})")


def _lowest(pencil: SparsePencil, op: sla.LinearOperator, sigma: float, speed: float,
            n_modes: int, whirl: str | None, count: int) -> ModalResult:
    """ARPACK's k raised until the modes needed are covered (module docstring)."""
    n = pencil.n_dof
    k_max = 2 * n - 2
    target = min(n_modes, 2 * count + 1) if whirl is not None else n_modes
    k = min(2 * target + 6, k_max)
    key = (n_modes, count)
    while True:
        nu, vecs = _arnoldi(op, k, pencil.last_start.get(key))
        lam = sigma + 1.0 / nu
        if not np.all(np.isfinite(lam)):
            raise ConvergenceError(f"non-finite eigenvalues at speed {speed} rad/s")
        reach = float(np.max(np.abs(lam - sigma)))
        scale = max(pencil.scale, reach)
        if sigma == 0.0 and np.any(np.abs(lam) < RIGID_BODY_TOL * scale):
            raise np.linalg.LinAlgError("rigid-body roots at the shift 0: K is singular")
        res = select_modes(lam, vecs[:n], speed, n_modes, scale)
        covered = int(np.count_nonzero(res.frequencies < reach / COVER))
        need = _needed(res, n_modes, whirl, count)
        if need <= covered or k >= k_max:
            pencil.last_start[key] = np.real(vecs @ np.ones(vecs.shape[1]))
            m = min(need, res.eigenvalues.size)
            return ModalResult(res.speed, res.eigenvalues[:m], res.mode_shapes[:, :m],
                               res.whirl[:m])
        k = min(2 * k, k_max)


_PENCILS: dict[int, tuple[weakref.ref, SparsePencil]] = {}


def pencil_of(system: LinearDynamics) -> SparsePencil:
    """The sparse pencil of ``system``, extracted once and kept while the system lives."""
    key = id(system)
    hit = _PENCILS.get(key)
    if hit is not None and hit[0]() is system:
        return hit[1]
    pencil = SparsePencil.from_system(system)
    try:
        ref = weakref.ref(system, lambda _r, key=key: _PENCILS.pop(key, None))
    except TypeError:          # not weak-referenceable: not cached
        return pencil
    _PENCILS[key] = (ref, pencil)
    return pencil


__all__ = ["COVER", "SparsePencil", "band_width", "pencil_of", "sparse_eigen"]
