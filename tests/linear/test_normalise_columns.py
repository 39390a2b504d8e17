"""The column-at-once mode normalisation (issue 17 item 3: 88 calls per Campbell diagram
of the 1280-element rotor) = the previous column loop, bit for bit."""

import numpy as np
import pytest

from rotorsfd.linear.modes import normalise_shapes


def _loop(shapes):
    """The previous implementation: one column at a time."""
    out = shapes.copy()
    trans = np.zeros(shapes.shape[0], dtype=bool)
    trans[0::4] = trans[1::4] = True
    for j in range(shapes.shape[1]):
        col = shapes[:, j]
        sub = np.where(trans, col, 0.0)
        if np.abs(sub).max() < 1e-12 * np.abs(col).max():
            sub = col
        k = int(np.argmax(np.abs(sub)))
        out[:, j] = col / col[k]
    return out


@pytest.mark.parametrize("dtype", [complex, float])
def test_normalise_equals_the_column_loop(dtype):
    rng = np.random.default_rng(11)
    n = 40
    shapes = rng.normal(size=(n, 6)) + (1j * rng.normal(size=(n, 6)) if dtype is complex
                                        else 0.0)
    shapes[0::4, 2] = shapes[1::4, 2] = 0.0          # a pure-tilt column
    shapes[0::4, 3] *= 1e-14                         # translation below 1e-12: tilt rule
    shapes[1::4, 3] *= 1e-14
    shapes[4, 4] = shapes[8, 4] = 50.0               # a tie: the first index wins
    got = normalise_shapes(shapes)
    assert got.dtype == shapes.dtype
    assert np.array_equal(got, _loop(shapes))
    trans = np.zeros(n, dtype=bool)
    trans[0::4] = trans[1::4] = True
    for j in (0, 1, 4, 5):                           # the largest translation is 1
        assert np.max(np.abs(got[trans, j])) == pytest.approx(1.0, abs=1e-15)
