"""The linear terms of a rotor on a moving base as polynomials in one parameter, assembled
once: the speed (degree 1) or a constant base rate (degree 2), for the continuation's
linear part (:class:`PolynomialTerms`, :class:`DenseLinearPart`; :class:`StoredTerms` the
same linear part summed from terms stored once, for the many problems of a
two-parameter family) and the LinearDynamics view of a rotor on a base in a constant state
(:class:`MovingBaseRotor`). The coefficients and the basis they multiply are
:mod:`rotorsfd.model.base_terms`.
"""

from __future__ import annotations

from functools import cache, cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp

from rotorsfd.model.base_motion import BaseState
from rotorsfd.model.base_terms import (
    RATE_NAMES,
    BaseBasis,
    BaseCoefficients,
    base_basis,
    base_coefficient_derivatives,
    base_coefficients,
    base_rate_derivative,
    sum_terms,
)
from rotorsfd.model.lowrank import with_lowrank
from rotorsfd.model.sparse import (
    DENSE_MAX_DOF,
    BandedLinearPart,
    as_csr,
    bandwidths,
    dense_bandwidths,
    to_band,
)

# ---------------------------------------------------------------------------------------
# polynomial form in one parameter (the linear part of a continuation, assembled once)
# ---------------------------------------------------------------------------------------
#: Variables in which the coefficients are polynomials: the speed (degree 1) and a constant
#: base rate (degree 2), the rest of the base motion held (in a rate, the origin
#: acceleration a0 = v0' + w x v0 follows it: affine).
POLYNOMIAL_VARIABLES: tuple[str, ...] = ("speed", "wx", "wy", "wz")


def coefficient_polynomial(state: BaseState, speed: float, variable: str
                           ) -> tuple[BaseCoefficients, BaseCoefficients, BaseCoefficients]:
    """(c0, c1, c2) with coefficients(p) = c0 + p c1 + p^2 c2 exactly (algebraically), p
    the speed or one base rate (``variable`` in POLYNOMIAL_VARIABLES), the rest of
    (state, speed) held; the value of p in (state, speed) itself is ignored. In a rate,
    the rest of the base motion is held (v0, v0', g) and the origin acceleration
    a0 = v0' + w x v0 follows it (``BaseState.with_rate``): ``state`` must be consistent
    (a0 that of its own rates, as ``BaseMotion.state`` gives).

    The coefficients (module docstring) are affine in Omega and at most quadratic in each
    rate: c0 is their value at p = 0, c1 their p-derivative there and c2 half the second
    derivative, which does not depend on the state (small integers, found exactly from
    the derivative at p = 1 and p = 0 with everything else zero).
    """
    if variable not in POLYNOMIAL_VARIABLES:
        raise ValueError(f"variable must be one of {POLYNOMIAL_VARIABLES}, not {variable!r}")
    if variable == "speed":
        c2 = BaseCoefficients(np.zeros(12), np.zeros(12), np.zeros(8))
        return (base_coefficients(state, 0.0),
                base_coefficient_derivatives(state, 0.0)["speed"], c2)
    # the state at p = 0: the origin acceleration a0 = v0' + w x v0 follows the rate
    # (affine in it: its slope e_i x v0 is in c1, :func:`base_rate_derivative`)
    st0 = state.with_rate(RATE_NAMES.index(variable) - 1, 0.0)
    return (base_coefficients(st0, speed), base_rate_derivative(st0, speed, variable),
            _curvature(variable))


@cache
def _curvature(variable: str) -> BaseCoefficients:
    """c2 of :func:`coefficient_polynomial` for a rate (free of the state: found once per
    rate; read-only arrays)."""
    i = RATE_NAMES.index(variable) - 1
    zero = BaseState.fixed()
    unit = BaseState(np.eye(3)[i], np.zeros(3), np.zeros(3), np.zeros(3), np.zeros(3))
    d1 = base_coefficient_derivatives(unit, 0.0)[variable]
    d0 = base_coefficient_derivatives(zero, 0.0)[variable]
    c2 = BaseCoefficients(0.5 * (d1.c_C - d0.c_C), 0.5 * (d1.c_K - d0.c_K),
                          0.5 * (d1.c_F - d0.c_F))
    for a in (c2.c_C, c2.c_K, c2.c_F):
        a.setflags(write=False)
    return c2


def _add(a: Any, b: Any) -> Any:
    """a + b, None for zero; dense if either is dense (never an np.matrix)."""
    if a is None:
        return b
    if b is None:
        return a
    if sp.issparse(a) != sp.issparse(b):
        a, b = (x.toarray() if sp.issparse(x) else x for x in (a, b))
    return a + b


def _uniform(terms: tuple) -> tuple:
    """The matrix terms all sparse, or all dense if one of them is dense."""
    if all(t is None or sp.issparse(t) for t in terms):
        return terms
    return tuple(t.toarray() if sp.issparse(t) else t for t in terms)


class PolynomialTerms:
    """Damping, stiffness and load as polynomials in one parameter p, assembled once:

        D(p) = sum_j p^j D_j,  K(p) = sum_j p^j K_j,  F(p) = sum_j p^j F_j   (j = 0, 1, 2)

    with ``None`` for a zero term; the matrix terms are stored as given (scipy.sparse from
    the rotor and the base basis; dense arrays are accepted). ``damping(p)``,
    ``stiffness(p)`` and their derivatives return dense arrays (built on request: one
    scaled add per nonzero term of degree >= 1); a quantity with no such term is the same
    array object at every p (so that callers can tell it is constant, as the condensation's
    band scan does), a zero one and a constant one's derivative the shared ``zero``
    (``zero_vector``). ``sparse_damping(p)`` etc. give CSR without a dense n x n array and
    :meth:`banded` the band-storage form of the HB solvers. Treat the returned arrays as
    read-only.
    """

    def __init__(self, n: int, D: tuple = (), K: tuple = (), F: tuple = (),
                 lowrank: tuple[np.ndarray, np.ndarray] | None = None) -> None:
        self.n = n
        #: (U, c): a constant damping term ``U diag(c) U^T`` beside D (modal damping of a
        #: few modes); in damping(p) and sparse_damping(p), apart in :meth:`linear_part`
        self.lowrank = lowrank
        self._lowrank_dense: np.ndarray | None = None
        self.D, self.K, self.F = (tuple(t) + (None,) * (3 - len(t)) for t in (D, K, F))
        self.D, self.K = _uniform(self.D), _uniform(self.K)
        self.zero_vector = np.zeros(n)
        self._dense: dict[Any, tuple[Any, np.ndarray]] = {}

    @cached_property
    def zero(self) -> np.ndarray:
        """The shared dense n x n zero (built on first use)."""
        return np.zeros((self.n, self.n))

    @classmethod
    def of_base(cls, basis: BaseBasis, state: BaseState, speed: float, variable: str
                ) -> PolynomialTerms:
        """C_base, K_base, F_base of the base state as polynomials in ``variable``
        (:func:`coefficient_polynomial`), only the nonzero coefficients combined (sparse)."""
        cos = coefficient_polynomial(state, speed, variable)
        mats = basis.sparse_matrices
        return cls(basis.n_dof, tuple(sum_terms(c.c_C, mats) for c in cos),
                   tuple(sum_terms(c.c_K, mats) for c in cos),
                   tuple(sum_terms(c.c_F, basis.vectors) for c in cos))

    def plus(self, D: tuple = (), K: tuple = (),
             lowrank: tuple[np.ndarray, np.ndarray] | None = None) -> PolynomialTerms:
        """A copy with the polynomial coefficients ``D``, ``K`` (None: zero) added
        (``plus(D=(C, G))`` adds C + p G); an added term alone is kept as the object;
        ``lowrank`` a low-rank damping term (this one's if None; at most one)."""
        def add(a: tuple, b: tuple) -> tuple:
            b = tuple(b) + (None,) * (3 - len(b))
            return tuple(_add(y, x) for x, y in zip(a, b, strict=True))
        if lowrank is not None and self.lowrank is not None:
            raise ValueError("one low-rank damping term only")
        return PolynomialTerms(self.n, add(self.D, D), add(self.K, K), self.F,
                               self.lowrank if lowrank is None else lowrank)

    def constant(self, p: float) -> PolynomialTerms:
        """The polynomials frozen at p (degree 0: D(p), K(p), F(p))."""
        return PolynomialTerms(self.n, (self._value(self.D, p),), (self._value(self.K, p),),
                               (self._value(self.F, p),), self.lowrank)

    def banded(self, M: Any, band: tuple[int, int] | None = None) -> BandedLinearPart:
        """(M, D(p), K(p)) in band storage (:class:`rotorsfd.model.sparse.BandedLinearPart`,
        the band read from the patterns unless given)."""
        return BandedLinearPart(M, self.D, self.K, band, self.lowrank)

    def linear_part(self, M: Any) -> BandedLinearPart | DenseLinearPart:
        """The ``matrices`` callable of an HB problem: :meth:`banded` when the band is
        narrow enough for the banded condensation to pay off (``3 (kl + ku + 1) < n``, the
        beam rotor's 7 + 7 + 1 from 46 DOFs on), else :class:`DenseLinearPart` (a full
        modal damping matrix)."""
        kl = ku = 0
        for term in (M, *self.D, *self.K):     # bandwidths() of all, term by term
            a, b = bandwidths((term,))
            kl, ku = max(kl, a), max(ku, b)
            if 3 * (kl + ku + 1) >= self.n:    # too wide already: the rest need not be read
                return DenseLinearPart(M, self)
        return self.banded(M, (kl, ku))

    @staticmethod
    def _value(terms: tuple, p: float) -> Any:
        out = terms[0]
        if terms[1] is not None:
            out = p * terms[1] if out is None else out + p * terms[1]
        if terms[2] is not None:
            out = (p * p) * terms[2] if out is None else out + (p * p) * terms[2]
        return out

    @staticmethod
    def _slope(terms: tuple, p: float) -> Any:
        if terms[2] is None:
            return terms[1]
        out = (2.0 * p) * terms[2]
        return out if terms[1] is None else terms[1] + out

    def _dense_value(self, terms: tuple, p: float, slope: bool = False) -> np.ndarray:
        """Dense ``_value(terms, p)`` (``slope``: ``_slope``) from the dense forms of the
        stored terms (each built once), in the same order of operations as the sparse sum,
        so the same numbers (a scaled add of dense arrays instead of a scipy.sparse product
        and sum per call, 0.3 ms each, and their CSR construction). A constant or zero
        value is the stored object (or the shared zero) as before."""
        if slope:
            if terms[2] is None:
                return self._as_dense(terms[1])
            t1, t2 = terms[1], terms[2]
            out = (2.0 * p) * self._as_dense(t2)
            return out if t1 is None else self._as_dense(t1) + out
        if terms[1] is None and terms[2] is None:
            return self._as_dense(terms[0])
        out = None if terms[0] is None else self._as_dense(terms[0])
        if terms[1] is not None:
            d1 = self._as_dense(terms[1])
            out = p * d1 if out is None else out + p * d1
        if terms[2] is not None:
            d2 = self._as_dense(terms[2])
            out = (p * p) * d2 if out is None else out + (p * p) * d2
        return out

    def _as_dense(self, a: Any) -> np.ndarray:
        """Dense form of a value: the shared zero for None, the array itself if dense, a
        sparse stored term's dense form built once (the same object at every call)."""
        if a is None:
            return self.zero
        if not sp.issparse(a):
            return a
        hit = self._dense.get(id(a))
        if hit is not None and hit[0] is a:
            return hit[1]
        out = a.toarray()
        if any(a is t for t in self.D + self.K):
            self._dense[id(a)] = (a, out)
        return out

    def _as_sparse(self, a: Any) -> sp.csr_matrix:
        """CSR form of a value (a stored CSR term itself: the same object at every call)."""
        if a is None:
            return sp.csr_matrix((self.n, self.n))
        return a if sp.issparse(a) and a.format == "csr" else as_csr(a)

    def _lowrank(self) -> np.ndarray:
        """``U diag(c) U^T`` of :attr:`lowrank`, dense (formed once)."""
        if self._lowrank_dense is None:
            u, c = self.lowrank
            full = (u * c) @ u.T
            self._lowrank_dense = 0.5 * (full + full.T)
        return self._lowrank_dense

    def dense_terms(self) -> tuple[tuple, tuple]:
        """The coefficients ``(D_0, D_1, D_2), (K_0, K_1, K_2)`` dense (None: zero), the
        low-rank damping term added to D_0."""
        D = [None if a is None else self._as_dense(a) for a in self.D]
        if self.lowrank is not None:
            D[0] = self._lowrank() if D[0] is None else D[0] + self._lowrank()
        return tuple(D), tuple(None if a is None else self._as_dense(a) for a in self.K)

    def damping(self, p: float) -> np.ndarray:
        out = self._dense_value(self.D, p)
        if self.lowrank is None:
            return out
        if not self._constant(self.D):
            return out + self._lowrank()
        hit = self._dense.get("lowrank")          # a constant D: the same object back
        if hit is None or hit[0] is not out:
            hit = self._dense["lowrank"] = (out, out + self._lowrank())
        return hit[1]

    @staticmethod
    def _constant(terms: tuple) -> bool:
        return terms[1] is None and terms[2] is None

    def stiffness(self, p: float) -> np.ndarray:
        return self._dense_value(self.K, p)

    def load(self, p: float) -> np.ndarray:
        out = self._value(self.F, p)
        return self.zero_vector if out is None else out

    def ddamping(self, p: float) -> np.ndarray:
        return self._dense_value(self.D, p, slope=True)

    def dstiffness(self, p: float) -> np.ndarray:
        return self._dense_value(self.K, p, slope=True)

    def dload(self, p: float) -> np.ndarray:
        out = self._slope(self.F, p)
        return self.zero_vector if out is None else out

    def sparse_damping(self, p: float) -> sp.csr_matrix:
        """D(p) as CSR (with a low-rank term: a full matrix)."""
        out = self._as_sparse(self._value(self.D, p))
        return out if self.lowrank is None else as_csr(out + self._lowrank())

    def sparse_stiffness(self, p: float) -> sp.csr_matrix:
        """K(p) as CSR."""
        return self._as_sparse(self._value(self.K, p))

    def split_damping(self, p: float) -> Any:
        """D(p) without a dense n x n array: CSR, or with a low-rank term a
        :class:`~rotorsfd.model.lowrank.BandedLowRank` (the CSR rest beside it)."""
        return with_lowrank(self._as_sparse(self._value(self.D, p)), self.lowrank)


class DenseLinearPart:
    """``matrices(lam) -> (M, D(lam), K(lam))`` dense from :class:`PolynomialTerms` (the
    same objects for the same lam, and for constant ones at every lam); ``derivatives``
    is the matching ``dmatrices``."""

    def __init__(self, M: Any, terms: PolynomialTerms) -> None:
        self.M = M.toarray() if sp.issparse(M) else np.asarray(M, dtype=float)
        self.terms = terms
        self._last: list = [None, None, None]

    def __call__(self, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        last = self._last
        if last[0] != lam:
            last[0], last[1], last[2] = lam, None, None
        if last[1] is None:
            last[1] = (self.M, self.terms.damping(lam), self.terms.stiffness(lam))
        return last[1]

    def derivatives(self, lam: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        last = self._last
        if last[0] != lam:
            last[0], last[1], last[2] = lam, None, None
        if last[2] is None:
            t = self.terms
            last[2] = (t.zero, t.ddamping(lam), t.dstiffness(lam))
        return last[2]

    def polynomial(self) -> tuple[np.ndarray, tuple, tuple]:
        """``(M, (D_0, D_1, D_2), (K_0, K_1, K_2))`` dense (None: a zero term), with
        ``D(lam) = sum_j lam^j D_j`` (the low-rank damping term in D_0), ``K`` alike."""
        return (self.M, *self.terms.dense_terms())



class StoredTerms:
    """The rotor's linear matrices (M, C, G, K) and the 12 base-motion patterns of
    ``basis`` (None: a fixed base only), stored once in the form the HB linear part
    takes: band storage when the band of all of them is narrow (``storage == "band"``),
    else dense arrays (a full modal damping; ``"dense"``, up to
    :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs; beyond, nothing is stored:
    ``None``). The HB linear part of any base state (:meth:`linear_part`) is then a few
    scaled adds of the stored terms: what ``PolynomialTerms.of_base(...).plus(...)
    .linear_part(M)`` gives (the same operations in the same order on the same numbers,
    so the same bits, and the same band, read from the nonzeros), without the sparse
    sums, the pattern scans and the conversions at each new parameter value (the
    fold-curve Newton builds two problems per evaluation)."""

    def __init__(self, rotor: Any, basis: BaseBasis | None = None) -> None:
        self.rotor = rotor
        self.basis = basis
        self.n = n = int(rotor.n_dof)
        self.lowrank = getattr(rotor, "damping_lowrank", None)  # modal damping, few modes
        C = rotor.C_csr if self.lowrank is None else rotor.C_band_csr
        own = (rotor.M_csr, C, rotor.G_csr, rotor.K_csr)
        patterns = () if basis is None else basis.sparse_matrices
        self.band = kl, ku = bandwidths((*own, *patterns))
        self.storage = ("band" if 3 * (kl + ku + 1) < n else
                        "dense" if n <= DENSE_MAX_DOF else None)
        self.M = self.C = self.G = self.K = None
        self.patterns: Any = ()
        if self.storage == "band":
            self.M, self.C, self.G, self.K = (to_band(a, kl, ku) for a in own)
            self.patterns = tuple(to_band(a, kl, ku) for a in patterns)
            self._used_by_M = np.any(self.M != 0.0, axis=0)   # the diagonals M occupies
        elif self.storage == "dense":
            self.M, self.C, self.G, self.K = (a.toarray() for a in own)
            self.patterns = () if basis is None else basis.matrices   # the shared stack
            self._M_band = dense_bandwidths(self.M)

    def linear_part(self, variable: str, state: BaseState | None = None, speed: float = 0.0,
                    at: float | None = None
                    ) -> tuple[BandedLinearPart | DenseLinearPart, PolynomialTerms] | None:
        """``(matrices, load)`` of the linear part in ``variable`` ("speed" or a rate of
        POLYNOMIAL_VARIABLES, at the fixed ``speed``) about ``state`` (None: a fixed base,
        no base terms; else the base terms of :meth:`PolynomialTerms.of_base`), frozen
        at ``at`` if given (:meth:`PolynomialTerms.constant`): ``linear_part(M)`` (a
        :class:`BandedLinearPart` or :class:`DenseLinearPart`) and the load as
        PolynomialTerms (its ``load``, ``dload``). None where nothing is stored or the
        base terms are asked for without a basis."""
        if self.storage is None or (state is not None and self.basis is None):
            return None
        if state is None:
            D: tuple = (self.C, self.G)
            K: tuple = (self.K,)
            F: tuple = ()
        else:
            cos = coefficient_polynomial(state, 0.0 if variable == "speed" else speed,
                                         variable)
            own = (self.C, self.G) if variable == "speed" else (self.C + speed * self.G,)
            own += (None,) * (3 - len(own))
            D = tuple(_add(y, sum_terms(c.c_C, self.patterns))
                      for c, y in zip(cos, own, strict=True))
            K = tuple(_add(y, sum_terms(c.c_K, self.patterns))
                      for c, y in zip(cos, (self.K, None, None), strict=True))
            F = tuple(sum_terms(c.c_F, self.basis.vectors) for c in cos)
        D, K = (t + (None,) * (3 - len(t)) for t in (D, K))
        if at is not None:
            value = PolynomialTerms._value
            D, K = ((value(t, at), None, None) for t in (D, K))
            if F:
                F = (value(F, at),)
        if self.storage == "dense":
            return self._dense_part(D, K, F)
        band = self._nonzero_band((*D, *K))
        kl, ku = band
        if 3 * (kl + ku + 1) >= self.n:
            return None
        M, D, K = self._cut(self.M, band), self._cut(D, band), self._cut(K, band)
        return (BandedLinearPart.of_bands(M, D, K, band, self.lowrank),
                PolynomialTerms(self.n, F=F))

    def _dense_part(self, D: tuple, K: tuple, F: tuple
                    ) -> tuple[BandedLinearPart | DenseLinearPart, PolynomialTerms]:
        """:meth:`PolynomialTerms.linear_part` of dense terms (the band read term by term,
        banded if it is narrow)."""
        terms = PolynomialTerms(self.n, D, K, F, self.lowrank)
        kl, ku = self._M_band
        for term in (*D, *K):
            if 3 * (kl + ku + 1) >= self.n:
                break
            a, b = dense_bandwidths(term)
            kl, ku = max(kl, a), max(ku, b)
        if 3 * (kl + ku + 1) >= self.n:
            return DenseLinearPart(self.M, terms), terms
        return BandedLinearPart(self.M, D, K, (kl, ku), self.lowrank), terms

    def _nonzero_band(self, terms: tuple) -> tuple[int, int]:
        """(kl, ku) of the nonzeros of M and band-stored terms (what ``bandwidths`` reads
        from the sparse forms)."""
        ku = self.band[1]
        used = self._used_by_M.copy()
        for t in terms:
            if used[0] and used[-1]:                   # the whole band: the rest need
                break                                  # not be read
            if t is not None:
                used |= np.any(t != 0.0, axis=0)
        offsets = np.flatnonzero(used) - ku            # i - j of each used diagonal
        if not offsets.size:
            return 0, 0
        return max(0, int(offsets.max())), max(0, int(-offsets.min()))

    def _cut(self, terms: Any, band: tuple[int, int]) -> Any:
        """Band-stored term(s) in the narrower ``band`` (the same objects if it is the
        full band)."""
        if isinstance(terms, tuple):
            return tuple(self._cut(t, band) for t in terms)
        if terms is None or band == self.band:
            return terms
        lo = self.band[1] - band[1]
        return np.ascontiguousarray(terms[:, lo: lo + band[0] + band[1] + 1])


class MovingBaseRotor:
    """LinearDynamics view of a rotor on a base in a constant state.

    ``matrices(speed) -> (M, C + speed G + C_base, K + K_base)``; ``force(speed) -> F_base``
    (the base terms assembled once as polynomials in the speed, :class:`PolynomialTerms`).
    """

    def __init__(self, rotor, state: BaseState) -> None:
        self.rotor = rotor
        self.state = state
        self.basis = base_basis(rotor)
        self.n_dof = rotor.n_dof
        self._terms: PolynomialTerms | None = None

    @property
    def terms(self) -> PolynomialTerms:
        if self._terms is None:
            r = self.rotor
            lowrank = getattr(r, "damping_lowrank", None)  # modal damping of a few modes
            C = r.C_csr if lowrank is None else r.C_band_csr
            self._terms = PolynomialTerms.of_base(self.basis, self.state, 0.0, "speed").plus(
                D=(C, r.G_csr), K=(r.K_csr,), lowrank=lowrank)
        return self._terms

    def matrices(self, speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        t = self.terms
        return self.rotor.M, t.damping(speed), t.stiffness(speed)

    def sparse_matrices(self, speed: float) -> tuple[sp.csr_matrix, sp.csr_matrix,
                                                      sp.csr_matrix]:
        """(M, D, K) at ``speed`` as CSR (no dense n x n array)."""
        t = self.terms
        return self.rotor.M_csr, t.sparse_damping(speed), t.sparse_stiffness(speed)

    def split_matrices(self, speed: float) -> tuple[sp.csr_matrix, Any, sp.csr_matrix]:
        """(M, D, K) at ``speed`` without a dense n x n array: CSR, D a
        :class:`~rotorsfd.model.lowrank.BandedLowRank` with modal damping of a few modes."""
        t = self.terms
        return self.rotor.M_csr, t.split_damping(speed), t.sparse_stiffness(speed)

    def force(self, speed: float) -> np.ndarray:
        return self.terms.load(speed).copy()


