"""Sparse and banded storage of the rotor's linear matrices (issue 17 item 2).

Structure: shaft element ``i`` couples the 8 DOFs ``4 i ... 4 i + 7`` of its two nodes; a
disk, point mass or support acts on the 4 (2) DOFs of one node; the nonlinear elements'
linear parts are supports. So every matrix of the model (M, C, G, K and the base-motion
patterns) lies inside the band ``|i - j| <= HALF_BAND = 2 * 4 - 1 = 7`` of the DOF order of
:mod:`rotorsfd.model.dofs` (a full modal damping matrix is the exception: it is dense).
The matrices are assembled as CSR (``scipy.sparse``) from the element blocks, without a
dense n x n array; the band of a set of them is read once from their patterns, O(nnz).

Band storage (what the compiled condensation reads, :mod:`rotorsfd.harmonic.banded`)::

    ab[j, ku + i - j] = A[i, j]      for  j - ku <= i <= j + kl,   shape (n, kl + ku + 1)

column j of A is the contiguous row ``ab[j]``. A polynomial ``A(p) = A_0 + p A_1 + p^2 A_2``
in band storage costs O(n (kl + ku + 1)) per evaluation instead of O(n^2).
"""

from __future__ import annotations

from collections.abc import Iterable, Sequence

import numpy as np
import scipy.sparse as sp

from rotorsfd.model.lowrank import with_lowrank

#: Half bandwidth of the beam rotor's matrices: two nodes of 4 DOFs per element.
HALF_BAND = 2 * 4 - 1

#: Models with at most this many DOFs hand dense matrices to the dense-only code paths and
#: LAPACK (faster there); larger ones keep to the sparse/banded paths.
DENSE_MAX_DOF = 400


#: Seed of :func:`lanczos_start`.
START_SEED = 20261203


def lanczos_start(n: int) -> np.ndarray:
    """A fixed start vector (n,) for ARPACK (``v0``): normal deviates of a generator
    seeded with :data:`START_SEED`, so that a shift-invert Lanczos run gives the same
    modes bit for bit on every call (ARPACK's own start is random) while no mode is
    orthogonal to it by a symmetry of the model (as ``ones`` can be)."""
    return np.random.default_rng(START_SEED).standard_normal(int(n))


def assemble(n: int, blocks: Iterable[tuple[np.ndarray, np.ndarray]]) -> sp.csr_matrix:
    """CSR sum of local blocks scattered at ``A[dofs, dofs] += A_local`` (duplicates
    summed), shape (n, n). Each item is one block ``(dofs (k,), A_local (k, k))`` or a
    stack of them ``(dofs (e, k), A_local (e, k, k))``."""
    rows, cols, vals = [], [], []
    for idx, a in blocks:
        idx = np.atleast_2d(np.asarray(idx, dtype=np.int64))
        k = idx.shape[1]
        rows.append(np.repeat(idx, k, axis=1).reshape(-1))
        cols.append(np.tile(idx, (1, k)).reshape(-1))
        vals.append(np.asarray(a, dtype=float).reshape(-1))
    if not rows:
        return sp.csr_matrix((n, n))
    out = sp.coo_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                        shape=(n, n)).tocsr()
    out.sum_duplicates()
    return out


def as_csr(a: object) -> sp.csr_matrix:
    """``a`` (dense or sparse) as a float CSR matrix without explicit zeros."""
    out = sp.csr_matrix(a, dtype=float) if sp.issparse(a) else sp.csr_matrix(
        np.asarray(a, dtype=float))
    out.eliminate_zeros()
    return out


def bandwidths(mats: Iterable[object]) -> tuple[int, int]:
    """(kl, ku): the largest ``i - j`` and ``j - i`` of a nonzero ``A_ij`` over ``mats``
    (sparse, dense or None), read from the patterns."""
    kl = ku = 0
    for a in mats:
        if a is None:
            continue
        if sp.issparse(a):
            coo = a.tocoo()
            nz = coo.data != 0.0
            row, col = coo.row[nz], coo.col[nz]
        else:                                  # the nonzeros of a dense array, no COO copy
            row, col = np.nonzero(np.asarray(a))
        if row.size:
            d = row.astype(np.int64) - col
            kl, ku = max(kl, int(d.max())), max(ku, int(-d.min()))
    return kl, ku


def dense_bandwidths(a: np.ndarray | None) -> tuple[int, int]:
    """``bandwidths((a,))`` of a dense square array (None: zero), read from the outermost
    diagonals inwards: a full matrix (modal damping of every mode) in two diagonals of
    one entry, not a scan of all n^2."""
    if a is None:
        return 0, 0
    n = a.shape[0]

    def outermost(sign: int) -> int:
        for o in range(n - 1, 0, -1):
            if np.any(np.diagonal(a, sign * o)):
                return o
        return 0

    return outermost(-1), outermost(1)


def to_band(a: object, kl: int, ku: int) -> np.ndarray:
    """Band storage (module docstring) of ``a`` (sparse or dense, n x n); ValueError if
    a nonzero lies outside the band."""
    coo = a.tocoo() if sp.issparse(a) else sp.coo_matrix(np.asarray(a, dtype=float))
    n = coo.shape[0]
    ab = np.zeros((n, kl + ku + 1))
    o = ku + coo.row.astype(np.int64) - coo.col
    if coo.nnz and (o.min() < 0 or o.max() > kl + ku):
        raise ValueError(f"a nonzero lies outside the band (kl={kl}, ku={ku})")
    np.add.at(ab, (coo.col, o), coo.data)
    return ab


def band_to_dense(ab: np.ndarray, kl: int, ku: int) -> np.ndarray:
    """The dense n x n matrix of band storage ``ab``."""
    n = ab.shape[0]
    out = np.zeros((n, n))
    j = np.arange(n)
    for o in range(kl + ku + 1):
        i = j + o - ku
        ok = (i >= 0) & (i < n)
        out[i[ok], j[ok]] = ab[ok, o]
    return out


def band_to_csr(ab: np.ndarray, kl: int, ku: int) -> sp.csr_matrix:
    """The CSR matrix of band storage ``ab`` (explicit zeros dropped)."""
    n = ab.shape[0]
    j = np.repeat(np.arange(n), kl + ku + 1)
    i = j + np.tile(np.arange(kl + ku + 1), n) - ku
    ok = (i >= 0) & (i < n) & (ab.reshape(-1) != 0.0)
    return sp.csr_matrix((ab.reshape(-1)[ok], (i[ok], j[ok])), shape=(n, n))


class BandedPolynomial:
    """``A(p) = sum_j p^j A_j`` (j = 0, 1, 2) in band storage, the terms None when zero.

    ``value(p)`` is the same array object at every p when A has no term of degree >= 1;
    ``slope(p) = A_1 + 2 p A_2`` (the shared zero band when constant). Treat the returned
    arrays as read-only.
    """

    def __init__(self, terms: Sequence[np.ndarray | None], zero: np.ndarray) -> None:
        self.terms = tuple(terms) + (None,) * (3 - len(terms))
        self.zero = zero
        self.constant = self.terms[1] is None and self.terms[2] is None

    def value(self, p: float) -> np.ndarray:
        t0, t1, t2 = self.terms
        out = t0
        if t1 is not None:
            out = p * t1 if out is None else out + p * t1
        if t2 is not None:
            out = (p * p) * t2 if out is None else out + (p * p) * t2
        return self.zero if out is None else out

    def slope(self, p: float) -> np.ndarray:
        _, t1, t2 = self.terms
        if t2 is None:
            return self.zero if t1 is None else t1
        out = (2.0 * p) * t2
        return out if t1 is None else t1 + out


class BandedLinearPart:
    """The linear part ``M, D(lam), K(lam)`` of a periodic problem in band storage.

    Callable as the problem's ``matrices(lam) -> (M, D, K)`` (dense arrays, built from the
    band on request; the constant ones once, the same objects at every call), with the
    banded access beside it: ``band`` = (kl, ku), ``banded(lam)`` and ``dbanded(lam)`` ->
    the band storage of (M, D, K) and of their lam-derivatives, ``sparse(lam)`` -> CSR.
    ``derivatives`` is the matching ``dmatrices(lam)`` callable (dense).

    ``lowrank`` = (U (n, r), c (r,)): a constant damping term ``U diag(c) U^T`` beside the
    banded D (modal damping of a few modes): ``banded`` and ``dbanded`` leave it out (the
    condensation applies it by Woodbury, :mod:`rotorsfd.harmonic.banded_lowrank`), the
    dense and sparse forms include it (a full matrix, formed once on request).
    """

    def __init__(self, M: object, D: Sequence[object | None], K: Sequence[object | None],
                 band: tuple[int, int] | None = None,
                 lowrank: tuple[np.ndarray, np.ndarray] | None = None) -> None:
        band = bandwidths([M, *D, *K]) if band is None else band
        kl, ku = band

        def banded(a: object | None) -> np.ndarray | None:
            return None if a is None else to_band(a, kl, ku)

        self._setup(banded(M), [banded(a) for a in D], [banded(a) for a in K], band,
                    lowrank)

    @classmethod
    def of_bands(cls, M: np.ndarray, D: Sequence[np.ndarray | None],
                 K: Sequence[np.ndarray | None], band: tuple[int, int],
                 lowrank: tuple[np.ndarray, np.ndarray] | None = None
                 ) -> BandedLinearPart:
        """The same from terms already in band storage (n, kl + ku + 1) of ``band`` (None
        for a zero term; kept as the objects, treat them as read-only): no pattern read,
        no conversion (e.g. terms summed from bands formed once,
        :class:`~rotorsfd.model.base_polynomial.StoredTerms`)."""
        out = cls.__new__(cls)
        out._setup(M, D, K, band, lowrank)
        return out

    def _setup(self, M: np.ndarray, D: Sequence[np.ndarray | None],
               K: Sequence[np.ndarray | None], band: tuple[int, int],
               lowrank: tuple[np.ndarray, np.ndarray] | None) -> None:
        self.lowrank = lowrank
        self._lowrank_dense: np.ndarray | None = None
        self.n = int(M.shape[0])
        self.band = band
        kl, ku = band
        zero = np.zeros((self.n, kl + ku + 1))
        self.zero = zero
        self.M = BandedPolynomial([M], zero)
        self.D = BandedPolynomial(D, zero)
        self.K = BandedPolynomial(K, zero)
        self._dense: dict[int, tuple[np.ndarray, np.ndarray]] = {}
        self._csr: dict[int, tuple[np.ndarray, sp.csr_matrix]] = {}
        self._last: list = [None, None, None]

    # -- banded --------------------------------------------------------------------------
    def banded(self, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Band storage of (M, D(lam), K(lam))."""
        return self.M.value(lam), self.D.value(lam), self.K.value(lam)

    def dbanded(self, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """Band storage of (dM, dD, dK)/dlam."""
        return self.M.slope(lam), self.D.slope(lam), self.K.slope(lam)

    def csr(self, ab: np.ndarray) -> sp.csr_matrix:
        """CSR matrix of band storage ``ab``, cached for the stored terms and the zero
        (a constant matrix or derivative is converted once; treat it as read-only)."""
        key = id(ab)
        hit = self._csr.get(key)
        if hit is not None and hit[0] is ab:
            return hit[1]
        out = band_to_csr(ab, *self.band)
        if ab is self.zero or any(ab is t for p in (self.M, self.D, self.K) for t in p.terms):
            self._csr[key] = (ab, out)
        return out

    def sparse(self, lam: float) -> tuple[sp.csr_matrix, ...]:
        """(M, D(lam), K(lam)) as CSR (D with the low-rank term: then full)."""
        M, D, K = (self.csr(a) for a in self.banded(lam))
        if self.lowrank is not None:
            D = as_csr(D + self.lowrank_dense())
        return M, D, K

    def split(self, lam: float) -> tuple[sp.csr_matrix, object, sp.csr_matrix]:
        """(M, D(lam), K(lam)) without a dense n x n array: CSR, D with the low-rank term
        a :class:`~rotorsfd.model.lowrank.BandedLowRank` (the band beside the factors)."""
        M, D, K = (self.csr(a) for a in self.banded(lam))
        return M, with_lowrank(D, self.lowrank), K

    def dsplit(self, lam: float) -> tuple[sp.csr_matrix, sp.csr_matrix, sp.csr_matrix]:
        """(dM, dD, dK)/dlam as CSR (the low-rank term is constant: no part of dD)."""
        return tuple(self.csr(a) for a in self.dbanded(lam))   # type: ignore[return-value]

    def stiffness_diagonal(self, lam: float) -> np.ndarray:
        """``K_ii(lam)`` read from band storage (the entries ``ab[i, ku]``), no n x n
        array."""
        return np.array(self.K.value(lam)[:, self.band[1]])

    def lowrank_dense(self) -> np.ndarray:
        """``U diag(c) U^T`` of ``lowrank`` as a dense matrix (formed once)."""
        if self._lowrank_dense is None:
            u, c = self.lowrank
            full = (u * c) @ u.T
            self._lowrank_dense = 0.5 * (full + full.T)
        return self._lowrank_dense

    # -- dense (the PeriodicProblem protocol) --------------------------------------------
    def _as_dense(self, ab: np.ndarray) -> np.ndarray:
        """Dense matrix of ab, cached for the stored terms and the zero (the same object
        back for a constant matrix or derivative)."""
        key = id(ab)
        hit = self._dense.get(key)
        if hit is not None and hit[0] is ab:
            return hit[1]
        out = band_to_dense(ab, *self.band)
        if ab is self.zero or any(ab is t for p in (self.M, self.D, self.K) for t in p.terms):
            self._dense[key] = (ab, out)
        return out

    def __call__(self, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        last = self._last
        if last[0] != lam or last[1] is None:
            M, D, K = (self._as_dense(a) for a in self.banded(lam))
            if self.lowrank is not None:
                D = D + self.lowrank_dense()
            last[0], last[1], last[2] = lam, (M, D, K), None
        return last[1]

    def derivatives(self, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        last = self._last
        if last[0] != lam:
            last[0], last[1], last[2] = lam, None, None
        if last[2] is None:
            last[2] = tuple(self._as_dense(a) for a in self.dbanded(lam))
        return last[2]
