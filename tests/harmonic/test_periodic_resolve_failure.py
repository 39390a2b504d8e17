"""continue_periodic never raises on a failed step, including the re-solve of a point
after the adaptive rule changed N_f: the branch ends there with success False, the points
so far, and a message saying at which N_f and lam the re-solve failed.

Case: the paper rotor under constant pitching (examples/paper_pitching.toml, H = 3),
Omega~ 0.9 .. 1.0, where N_f rises 32 -> 64 at Omega~ ~0.952 (then 128, 256, 512 and back
to 256 near 1.0). The re-solve is made to fail by a Newton that reports no convergence
for the continuation system with 64 samples.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest

from rotorsfd.continuation.newton import NewtonResult
from rotorsfd.harmonic import periodic

sys.path.insert(0, str(Path(__file__).parent))
from test_n_samples_rule import W1, _branch, _problem


@pytest.fixture(scope="module")
def problem():
    return _problem()


@pytest.fixture(scope="module")
def reference(problem):
    b = _branch(problem, 0.9, 1.0)
    assert b.success, b.message
    N = b.info["n_samples"]
    i = int(np.argmax(N > 32))      # first point with more samples
    assert N[0] == 32 and N[i] == 64 and 0.94 < b.lam[i] / W1 < 0.96
    return b, i


def _failing_at(n_fail: int, monkeypatch) -> list[int]:
    """Newton of periodic.py fails for systems with N_f = n_fail; returns the N_f of
    every call."""
    real = periodic.newton_extended
    calls: list[int] = []

    def newton(system, z0, *args, **kwargs):
        calls.append(system.N)
        if system.N == n_fail:
            return NewtonResult(z0, None, None, 0, False, np.inf, "forced failure (test)")
        return real(system, z0, *args, **kwargs)

    monkeypatch.setattr(periodic, "newton_extended", newton)
    return calls


def test_failed_resolve_ends_the_branch_with_a_message(problem, reference, monkeypatch):
    ref, i = reference
    calls = _failing_at(64, monkeypatch)
    b = _branch(problem, 0.9, 1.0)                  # does not raise
    assert 64 in calls
    assert not b.success
    assert b.message.startswith("re-solve at N_f=64 failed at lam=")
    lam_msg = float(b.message.split("lam=")[1].split()[0])
    # it failed where the reference branch raised N_f (the point is not stored: the
    # branch ends at the last point with 32 samples, which agree with the reference)
    assert lam_msg == pytest.approx(ref.lam[i], rel=1e-6)
    assert "forced failure (test)" in b.message and "from 32" in b.message
    assert b.n_points == i
    assert np.all(b.info["n_samples"] == 32)
    np.testing.assert_allclose(b.lam, ref.lam[:i], rtol=1e-12)
    np.testing.assert_allclose(b.X, ref.X[:i], rtol=0, atol=1e-12 * np.abs(ref.X).max())
    assert b.n_samples == 32 and b.aliasing.size == i


def test_failed_coarsening_resolve_ends_the_branch(problem, reference, monkeypatch):
    """The halving 512 -> 256 near Omega~ 1.0: the point is stored before N_f comes down,
    so the branch keeps it and ends there."""
    ref, _ = reference
    N = ref.info["n_samples"]
    j = int(np.nonzero(np.diff(N) < 0)[0][0])      # last point with 512
    assert N[j] == 512 and N[j + 1] == 256
    _failing_at(256, monkeypatch)
    # 256 is also used on the way up: start above that point of the reference branch
    k = int(np.nonzero(N == 512)[0][0])
    b = periodic.continue_periodic(problem, ref.lam[k], W1, 3, X0=ref.X[k], tol=1e-6,
                                   ds=0.01, ds_min=1e-6, ds_max=0.05)
    assert not b.success
    assert b.message.startswith("re-solve at N_f=256 failed at lam=")
    assert "lowered from 512" in b.message
    assert b.info["n_samples"][-1] == 512
    assert b.lam[-1] == pytest.approx(float(b.message.split("lam=")[1].split()[0]),
                                      rel=1e-7)
