"""Receptances of a banded linear part at arbitrary frequencies, onto the nonlinear DOFs.

For each frequency ``W_j`` (any sign, e.g. the shifted ``k w + sigma`` of the
Neimark-Sacker test function, :mod:`rotorsfd.harmonic.ns_curve`)

    Hs(W_j) = S Z(W_j)^{-1} S^T   (m x m),   Z(W) = K - W^2 M + i W D,

from the band storage of M, D, K (``matrices.banded(lam)``,
:class:`rotorsfd.model.sparse.BandedLinearPart`; a low-rank modal damping term
``U diag(c) U^T`` beside the band by Woodbury): one complex banded LU of Z(W_j) and m
right-hand sides, O(n (kl + ku)^2) per frequency, no n x n array. It is one harmonic of the
condensation kernels (:func:`rotorsfd.harmonic.banded.condense_bands`, harmonic ``k = 1``
at ``w = W_j``, zero shift and forcing), so it has their pivoting and, above
``REFINE_MIN_DOF`` DOFs, their step of iterative refinement.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from rotorsfd.harmonic import banded
from rotorsfd.harmonic.banded_lowrank import condense_bands_lowrank

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


def banded_receptances(matrices: object, lam: float, nl_dofs: NDArray[np.int64],
                       W: FloatArray) -> ComplexArray:
    """``Hs(W_j)`` (len(W), m, m) of the linear part ``matrices`` at ``lam`` (module
    docstring; ``matrices`` has ``n``, ``band``, ``banded(lam)`` and optionally
    ``lowrank``). LinAlgError if some Z(W_j) is exactly singular or gives a non-finite
    receptance."""
    kl, ku = (int(b) for b in matrices.band)
    Mb, Db, Kb = matrices.banded(lam)
    lowrank = getattr(matrices, "lowrank", None)
    n = int(matrices.n)
    s = np.ascontiguousarray(nl_dofs, dtype=np.int64)
    m = s.size
    F = np.zeros((2, n), dtype=complex)              # harmonic 1 only; no forcing
    delta = np.zeros((2, m), dtype=complex)          # no shift
    sol = np.zeros((2, n, m + 1), dtype=complex)     # sol[0] stays zero (k_first = 1)
    dsol = np.zeros((2, m, m + 1), dtype=complex)
    Ht, dHt = np.empty((2, 2, m, m), dtype=complex)
    Pt, dPt = np.empty((2, 2, m), dtype=complex)
    refine = banded.refinement_steps(n)
    out = np.empty((len(W), m, m), dtype=complex)
    for j, Wj in enumerate(np.asarray(W, dtype=float)):
        args = (float(Wj), 0.0, kl, ku, s, delta, F, F, False, sol, dsol, Ht, Pt, dHt,
                dPt, refine, 1)
        if lowrank is None or Wj == 0.0:   # at W = 0 the damping term vanishes
            status = banded.condense_bands(Mb, Db, Kb, Mb, Db, Kb, *args)
        else:
            status = condense_bands_lowrank(Mb, Db, Kb, Mb, Db, Kb, *lowrank, *args)
        if status != banded.OK:
            raise np.linalg.LinAlgError(
                f"singular dynamic stiffness Z(W) at W = {Wj:.6g} rad/s (lam = {lam:.6g})")
        out[j] = Ht[1]
    return out
