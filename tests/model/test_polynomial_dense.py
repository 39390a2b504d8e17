"""PolynomialTerms' dense values (damping, stiffness and their slopes) from the dense forms
of the stored sparse terms: the same numbers as the scipy.sparse sum made dense (the
reference is that sum, computed here independently), bit for bit."""

from __future__ import annotations

import numpy as np
import pytest
import scipy.sparse as sp

from rotorsfd.model.base_polynomial import DenseLinearPart, PolynomialTerms
from rotorsfd.model.sparse import BandedLinearPart, bandwidths


def _terms(seed: int, n: int = 30) -> tuple:
    rng = np.random.default_rng(seed)
    return tuple(sp.random(n, n, density=0.15, random_state=rng, format="csr")
                 * rng.uniform(-3e5, 3e5) for _ in range(3))


def _sparse_sum(terms: tuple, p: float) -> np.ndarray:
    out = None
    for j, t in enumerate(terms):
        if t is None:
            continue
        x = t if j == 0 else (p if j == 1 else p * p) * t
        out = x if out is None else out + x
    return out.toarray()


def _sparse_slope(terms: tuple, p: float) -> np.ndarray:
    t1, t2 = terms[1], terms[2]
    if t2 is None:
        return t1.toarray()
    out = (2.0 * p) * t2
    return (out if t1 is None else t1 + out).toarray()


@pytest.mark.parametrize("keep", [(0, 1, 2), (0, 1), (1, 2), (0, 2), (1,)])
@pytest.mark.parametrize("p", [0.0, 1.7, -523.25, 1044.3])
def test_dense_values_equal_the_sparse_sum(keep: tuple, p: float) -> None:
    D = tuple(t if j in keep else None for j, t in enumerate(_terms(1)))
    K = tuple(t if j in keep else None for j, t in enumerate(_terms(2)))
    pt = PolynomialTerms(30, D=D, K=K)
    for got, terms in ((pt.damping(p), D), (pt.stiffness(p), K)):
        np.testing.assert_array_equal(got, _sparse_sum(terms, p))
    for got, terms in ((pt.ddamping(p), D), (pt.dstiffness(p), K)):
        if terms[1] is None and terms[2] is None:
            continue
        np.testing.assert_array_equal(got, _sparse_slope(terms, p))


def test_repeated_calls_do_not_alter_the_stored_terms() -> None:
    D = _terms(3)
    pt = PolynomialTerms(30, D=D)
    first = pt.damping(2.5).copy()
    pt.damping(7.0)
    pt.ddamping(-1.0)
    np.testing.assert_array_equal(pt.damping(2.5), first)
    np.testing.assert_array_equal(first, _sparse_sum(D, 2.5))


def test_a_constant_term_is_the_same_object() -> None:
    D = (_terms(4)[0], None, None)
    pt = PolynomialTerms(30, D=D)
    assert pt.damping(1.0) is pt.damping(2.0)


def test_linear_part_stops_reading_at_a_wide_term_with_the_same_choice() -> None:
    """``linear_part``: banded with the band of all the terms when it is narrow (the band
    ``bandwidths`` reads from every term at once), dense as soon as one term is too wide."""
    n = 40
    M = sp.identity(n, format="csr")
    tri = sp.diags([np.ones(n - 2), np.ones(n), 2 * np.ones(n - 1)], [-2, 0, 1],
                   format="csr")
    narrow = PolynomialTerms(n, D=(tri, 3.0 * tri), K=(tri.T.tocsr(),)).linear_part(M)
    assert isinstance(narrow, BandedLinearPart)
    assert narrow.band == bandwidths((M, tri, 3.0 * tri, tri.T)) == (2, 2)
    full = np.random.default_rng(5).normal(size=(n, n))
    wide = PolynomialTerms(n, D=(full, tri), K=(tri,)).linear_part(M)
    assert isinstance(wide, DenseLinearPart)


def test_bandwidths_of_a_dense_array_are_those_of_its_pattern() -> None:
    a = np.zeros((30, 30))
    a[4, 1], a[2, 9], a[17, 17] = 1.0, -2.0, 3.0
    assert bandwidths((a,)) == bandwidths((sp.csr_matrix(a),)) == (3, 7)
    assert bandwidths((np.zeros((5, 5)),)) == (0, 0)
