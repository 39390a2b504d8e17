"""Quasi-periodic Hill method: the Lyapunov (characteristic) exponents of a torus from the
eigenvalues of its Hill matrix (issue 19 item 4).

Linearised about the torus, a perturbation y obeys

    M y'' + Dt(theta) y' + Kt(theta) y = 0,
    Dt = D(theta2) - S^T dF/dv(theta) S,   Kt = K(theta2) - S^T dF/dq(theta) S,

with coefficients on the torus (the base terms in theta2, the film's Jacobian sampled on
the AFT grid and transformed by a 2D FFT). The Floquet-type ansatz
``y = e^{lam t} sum_{k in L} Y_k e^{i k . theta(t)}`` over the full box lattice L
(both signs of k1) gives, with ``omega_k = k1 Omega + k2 w_b``,

    sum_j [(lam + i omega_{k-j})^2 M delta_j0 + (lam + i omega_{k-j}) Dt_j + Kt_j] Y_{k-j} = 0,

a quadratic eigenproblem of size n |L| (solved in companion form). Each exponent appears
|L| times, shifted by i omega_k; the physical ones are sorted out as the eigenvectors whose
weight ``|Y_0|^2 / sum |Y_k|^2`` at the central harmonic is largest (2 n of them). The
model is first reduced by Craig-Bampton on the nonlinear DOFs (fixed-interface modes up to
``omega_max``, as the Floquet analyses do: the undamped high modes would otherwise be
neutral exponents), and every coefficient matrix projected on that basis.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.linalg import eig

from rotorsfd.harmonic.fourier import to_real
from rotorsfd.quasiperiodic.torus_fourier import TorusAFT, TorusLattice, derivative
from rotorsfd.quasiperiodic.torus_linear import TorusProblem, dense_mass
from rotorsfd.stability.reduction import craig_bampton


@dataclass(frozen=True)
class TorusHill:
    """The sorted exponents (2 r,) [1/s] of the reduced model (r coordinates), their
    central-harmonic weights, and the largest real part per rotor period."""

    exponents: NDArray[np.complex128]
    weights: NDArray[np.float64]
    per_period: float

    @property
    def stable(self) -> bool:
        return self.per_period < 0.0


def torus_hill(problem: TorusProblem, lattice: TorusLattice, X: NDArray[np.complex128],
               lam: float, grid: tuple[int, int], omega_max: float) -> TorusHill:
    """Exponents of the torus X (nk, n) at lam (module docstring); ``grid`` the AFT grid
    of the film's Jacobian (N1 > 4 H1, N2 > 4 H2 to resolve its harmonics up to 2H)."""
    if lattice.shape != "box":
        raise ValueError("the Hill matrix is built on the box lattice")
    om, wb = problem.frequencies(lam)
    Dc, Kc = problem.coefficients(lam)
    s = problem.nl_dofs
    M = dense_mass(problem)             # the Hill matrix is dense
    K0 = np.real(Kc[0])
    red = craig_bampton(M, np.real(Dc[0]), 0.5 * (K0 + K0.T), s, omega_max=omega_max)
    P = red.basis
    r = P.shape[1]
    sr = red.nl_dofs
    H1, H2 = lattice.H1, lattice.H2
    # film Jacobian on the torus, two-sided coefficients up to (2 H1, 2 H2)
    aft = TorusAFT(lattice, *grid)
    xs = to_real(X[:, s])
    w = lattice.frequencies(om, wb)
    q, v = aft.sample(xs), aft.sample(derivative(xs, w))
    _, dfq, dfv = problem.elements.force_and_jacobian(q, v)
    N1, N2 = grid
    cq = np.fft.fft2(dfq.reshape(N1, N2, *dfq.shape[1:]), axes=(0, 1)) / (N1 * N2)
    cv = np.fft.fft2(dfv.reshape(N1, N2, *dfv.shape[1:]), axes=(0, 1)) / (N1 * N2)
    kk = [(k1, k2) for k1 in range(-H1, H1 + 1) for k2 in range(-H2, H2 + 1)]
    L = len(kk)
    wk = np.array([k1 * om + k2 * wb for k1, k2 in kk])
    Mr = P.T @ M @ P
    b = Dc.shape[0] - 1

    def base(A: NDArray, j2: int) -> NDArray:
        return A[j2] if j2 >= 0 else np.conj(A[-j2])

    D2 = np.zeros((L, r, L, r), dtype=complex)
    K2 = np.zeros((L, r, L, r), dtype=complex)
    for a, (k1, k2) in enumerate(kk):
        for c, (l1, l2) in enumerate(kk):
            j1, j2 = k1 - l1, k2 - l2
            Dt = np.zeros((r, r), dtype=complex)
            Kt = np.zeros((r, r), dtype=complex)
            if j1 == 0 and abs(j2) <= b:
                Dt += P.T @ base(Dc, j2) @ P
                Kt += P.T @ base(Kc, j2) @ P
            Dt[np.ix_(sr, sr)] -= cv[j1 % N1, j2 % N2]
            Kt[np.ix_(sr, sr)] -= cq[j1 % N1, j2 % N2]
            D2[a, :, c, :] = Dt
            K2[a, :, c, :] = Kt + 1j * wk[c] * Dt
            if a == c:
                D2[a, :, c, :] += 2j * wk[c] * Mr
                K2[a, :, c, :] -= wk[c] ** 2 * Mr
    n = L * r
    Minv = np.linalg.inv(Mr)
    A = np.zeros((2 * n, 2 * n), dtype=complex)
    A[:n, n:] = np.eye(n)
    blk = np.kron(np.eye(L), Minv)
    A[n:, :n] = -blk @ K2.reshape(n, n)
    A[n:, n:] = -blk @ D2.reshape(n, n)
    lam_all, vec = eig(A)
    Y = vec[:n].reshape(L, r, -1)
    energy = np.sum(np.abs(Y) ** 2, axis=1)
    centre = kk.index((0, 0))
    weight = energy[centre] / np.maximum(energy.sum(axis=0), np.finfo(float).tiny)
    keep = np.argsort(-weight)[: 2 * r]
    ex, wt = lam_all[keep], weight[keep]
    order = np.argsort(-ex.real)
    return TorusHill(ex[order], wt[order], float(ex.real.max()) * 2 * np.pi / om)
