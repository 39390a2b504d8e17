"""The linear part of a torus problem kept in sparse storage: constant CSR matrices and
their lam-dependent Fourier weights in theta2 (issue 17 item 2).

    D_j(lam) = sum_t a_{j,t}(lam) A_t,   K_j(lam) = sum_t c_{j,t}(lam) A_t,   j = 0..b,

with ``A_t`` the rotor's matrices (C, G, K) and the 12 base-motion patterns
(:class:`~rotorsfd.model.base_terms.BaseBasis`), all CSR inside the rotor's band, and
``a, c`` (b + 1, T) complex weights. The torus condenser reads only the band entries
``|I - J| <= beta`` of ``D_j, K_j`` and M (:mod:`~rotorsfd.quasiperiodic.torus_columns`),
so they are formed from the entries of the ``A_t`` alone,

    Dv_j = sum_t a_{j,t} Av_t   ((b + 1, ne) with ne ~ n (2 beta + 1)),

and no dense n x n array exists. :func:`dense_coefficients` forms the dense stacks (the
reference of the tests).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any

import numpy as np
import scipy.sparse as sp
from numpy.typing import NDArray

from rotorsfd.model.sparse import as_csr, bandwidths

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]
IntArray = NDArray[np.int64]
Weights = Callable[[float], tuple[ComplexArray, ComplexArray]]


def band_entries(n: int, beta: int) -> tuple[IntArray, IntArray]:
    """(I, J) of the n x n entries with ``|I - J| <= beta``, row-major (the order of
    :attr:`~rotorsfd.quasiperiodic.torus_columns.ColumnPattern.band_entries`)."""
    i = np.repeat(np.arange(n, dtype=np.int64), 2 * beta + 1)
    j = i + np.tile(np.arange(-beta, beta + 1, dtype=np.int64), n)
    ok = (j >= 0) & (j < n)
    return i[ok], j[ok]


def csr_entries(A: sp.csr_matrix, I: IntArray, J: IntArray) -> FloatArray:
    """``A[I, J]`` (ne,) of a CSR matrix (zeros where A has no entry), O(nnz + ne)."""
    coo = A.tocoo()
    n = A.shape[1]
    keys = coo.row.astype(np.int64) * n + coo.col
    want = I * n + J
    order = np.argsort(keys)
    keys, data = keys[order], coo.data[order]
    pos = np.searchsorted(keys, want)
    pos = np.minimum(pos, max(keys.size - 1, 0))
    out = np.zeros(I.size)
    if keys.size:
        hit = keys[pos] == want
        out[hit] = data[pos[hit]]
    return out


@dataclass
class TorusBands:
    """``M`` and the terms ``A_t`` (CSR, n x n) with the weights ``weights(lam) -> (a, c)``
    and ``dweights(lam)`` their lam-derivatives, each (b + 1, T) complex (module
    docstring)."""

    M: sp.csr_matrix
    terms: Sequence[sp.csr_matrix]
    weights: Weights
    dweights: Weights
    _entries: dict[int, tuple[IntArray, IntArray, FloatArray, FloatArray]] = field(
        default_factory=dict, repr=False)

    def __post_init__(self) -> None:
        self.M = as_csr(self.M)
        self.terms = tuple(as_csr(a) for a in self.terms)

    @property
    def n(self) -> int:
        return int(self.M.shape[0])

    @cached_property
    def beta(self) -> int:
        """Half bandwidth of M and the terms (read once from their patterns)."""
        return max(bandwidths([self.M, *self.terms]))

    def entries(self, beta: int) -> tuple[IntArray, IntArray, FloatArray, FloatArray]:
        """``(I, J, Mv (ne,), Av (T, ne))``: the band entries ``|I - J| <= beta``."""
        hit = self._entries.get(beta)
        if hit is None:
            I, J = band_entries(self.n, beta)
            Av = np.array([csr_entries(a, I, J) for a in self.terms]).reshape(-1, I.size)
            hit = (I, J, csr_entries(self.M, I, J), Av)
            self._entries[beta] = hit
        return hit

    def band(self, lam: float, beta: int, deriv: bool = False
             ) -> tuple[ComplexArray, ComplexArray]:
        """``(Dv, Kv)`` (b + 1, ne) at lam on the entries of :meth:`entries` (``deriv``:
        of dD_j, dK_j)."""
        Av = self.entries(beta)[3]
        a, c = (self.dweights if deriv else self.weights)(lam)
        return np.asarray(a, complex) @ Av, np.asarray(c, complex) @ Av


def two_sided(pos: ComplexArray) -> ComplexArray:
    """(2b + 1, ne) entries for j = -b..b from those for j = 0..b (``A_{-j} = conj(A_j)``)."""
    return np.concatenate([np.conj(pos[:0:-1]), pos])


def dense_coefficients(bands: TorusBands) -> tuple[Callable[[float], Any],
                                                    Callable[[float], Any]]:
    """``coefficients, dcoefficients`` of :class:`~rotorsfd.quasiperiodic.torus_linear.
    TorusProblem` formed dense from ``bands`` (the stacked terms formed once)."""
    cache: dict[str, np.ndarray] = {}

    def mats() -> np.ndarray:
        if "mats" not in cache:
            cache["mats"] = np.array([t.toarray() for t in bands.terms])
        return cache["mats"]

    def stack(w: tuple[ComplexArray, ComplexArray]) -> tuple[ComplexArray, ComplexArray]:
        return tuple(np.tensordot(np.asarray(x, complex), mats(), axes=(1, 0))
                     for x in w)   # type: ignore[return-value]

    return (lambda lam: stack(bands.weights(lam))), (lambda lam: stack(bands.dweights(lam)))
