"""HB-AFT residual of the full model and its exact Jacobians.

Substituting ``q = Re(sum_k X_k e^{ik w t})`` into ``M q'' + D q' + K q = f + S^T F_nl``
(S selects nl_dofs) and balancing ``e^{ik w t}`` gives, per harmonic k = 0..H,

    R_k = Z_k X_k - F_k - S^T G_k,     Z_k = K - (k w)^2 M + i k w D,

where ``G_k`` are the Fourier coefficients of ``F_nl(q_nl(t), q_nl'(t))`` computed by AFT
(sample with E, evaluate the force at the N samples, project with P; see
:mod:`rotorsfd.harmonic.fourier`). Real unknowns and residuals use the real layout
``[Re X_0, Re X_1, Im X_1, ...]`` of shape (2H+1, n), flattened harmonic-major.

Jacobians (exact):

- ``dG/dx[a,i,b,j] = sum_n P[a,n] (dF/dq[n,i,j] E[n,b] + w dF/dv[n,i,j] Ed[n,b])``
  (computed from the spectrum of the samples, :mod:`rotorsfd.harmonic.aft_jacobian`)
- ``dR_k/dlam = dZ_k X_k - dF_k - S^T (dG_k/dw dw/dlam + P dF_nl/dlam)``, the last term
  for a force that depends on lam itself (:attr:`NonlinearLaw.dforce`), with
  ``dZ_k = dK - (k w)^2 dM - 2 k^2 w w' M + i k (w' D + w dD)`` and
  ``dG/dw = P (dF/dv . dq/dtau)``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.harmonic.aft_jacobian import force_jacobian_coefficients
from rotorsfd.harmonic.fourier import AFTMatrices, aft_matrices, to_complex, to_real
from rotorsfd.harmonic.problem import NonlinearLaw, PeriodicProblem

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass
class NonlinearCoefficients:
    """AFT result at the nonlinear DOFs: G (2H+1, m), dG/dx (2H+1, m, 2H+1, m), dG/dw."""

    G: FloatArray
    dG: FloatArray | None
    dGdw: FloatArray | None
    q: FloatArray  # (N, m) displacement samples


def law_at(problem: PeriodicProblem, lam: float | None) -> NonlinearLaw:
    """The problem's force law at lam; lam may be omitted only when the law does not
    depend on it."""
    if lam is None:
        if problem.parametric:
            raise ValueError(f"the nonlinear force of {problem.name!r} depends on the "
                             "parameter: pass lam")
        return problem.law(0.0)
    return problem.law(lam)


def nonlinear_coefficients(problem: PeriodicProblem, aft: AFTMatrices, xs: FloatArray,
                           w: float, jac: bool = True, lam: float | None = None
                           ) -> NonlinearCoefficients:
    """AFT: ``G = P F_nl(E xs, w Ed xs)`` and its exact derivatives (module docstring), with
    the force law at lam (:meth:`PeriodicProblem.law`)."""
    law = law_at(problem, lam)
    q = aft.E @ xs
    dq_tau = aft.Ed @ xs
    v = w * dq_tau
    if law.force_jacobians is not None:   # a force of the acceleration too
        return _inertial_coefficients(law, aft, xs, w, jac, q, dq_tau)
    if jac and law.force_jacobian is not None:
        f, dfq, dfv = law.force_jacobian(q, v)
    else:
        f = law.force(q, v)
    G = _project_force(aft, f)
    if not jac:
        return NonlinearCoefficients(G, None, None, q)
    if law.force_jacobian is None:
        dfq, dfv = law.jacobian(q, v)
    m = q.shape[1]
    nh = aft.E.shape[1]
    dG = np.empty((nh, m, nh, m))      # P (dfq E + w dfv Ed), from the samples' spectrum
    force_jacobian_coefficients(np.ascontiguousarray(dfq, dtype=float),
                                np.ascontiguousarray(dfv, dtype=float), w, nh, dG)
    dGdw = aft.P @ np.einsum("nij,nj->ni", dfv, dq_tau)
    return NonlinearCoefficients(G, dG, dGdw, q)


def _project_force(aft: AFTMatrices, f: object) -> FloatArray:
    """``G = P f`` of the force samples f (N, m); FloatingPointError if f is not finite."""
    f = np.asarray(f, dtype=float)
    if not np.all(np.isfinite(f)):
        raise FloatingPointError("non-finite nonlinear force in AFT")
    return aft.P @ f


def _inertial_coefficients(law: NonlinearLaw, aft: AFTMatrices, xs: FloatArray, w: float,
                           jac: bool, q: FloatArray, dq_tau: FloatArray
                           ) -> NonlinearCoefficients:
    """:func:`nonlinear_coefficients` of a law ``F(q, v, a)``: ``a = w^2 Edd xs`` with
    ``Edd = -k^2 E`` per harmonic column, ``dG/dx`` gains ``P (dF/da w^2 Edd)`` and
    ``dG/dw`` gains ``P (2 w dF/da . q''_tau)``."""
    k2 = ((np.arange(aft.E.shape[1]) + 1) // 2) ** 2
    Edd = -aft.E * k2
    ddq_tau = Edd @ xs
    f, dfq, dfv, dfa = law.force_jacobians(q, w * dq_tau, w * w * ddq_tau)
    G = _project_force(aft, f)
    if not jac:
        return NonlinearCoefficients(G, None, None, q)
    N, m = q.shape
    nh = aft.E.shape[1]
    T = (dfq[..., None] * aft.E[:, None, None, :] + w * dfv[..., None] * aft.Ed[:, None, None, :]
         + w * w * dfa[..., None] * Edd[:, None, None, :])
    dG = (aft.P @ T.reshape(N, -1)).reshape(nh, m, m, nh).transpose(0, 1, 3, 2)
    dGdw = aft.P @ (np.einsum("nij,nj->ni", dfv, dq_tau)
                    + 2.0 * w * np.einsum("nij,nj->ni", dfa, ddq_tau))
    return NonlinearCoefficients(G, dG, dGdw, q)


def nonlinear_samples(problem: PeriodicProblem, aft: AFTMatrices, xs: FloatArray,
                      w: float, jac: bool = True, lam: float | None = None
                      ) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """The force at the AFT samples by the law's callables at lam: ``(f (N, m), dF/dq,
    dF/dv (N, m, m), dq/dtau (N, m))``, C-contiguous (dF/dq, dF/dv of shape (1, m, m)
    and not computed when not jac)."""
    law = law_at(problem, lam)
    if law.force_jacobians is not None:
        raise ValueError(f"the force of {problem.name!r} depends on the acceleration: "
                         "its samples need the compiled inertial kernel (nl_inertial_kernel)")
    dq_tau = aft.Ed @ xs
    q, v = aft.E @ xs, w * dq_tau
    if jac and law.force_jacobian is not None:
        f, dfq, dfv = law.force_jacobian(q, v)
    else:
        f = law.force(q, v)
        if jac:
            dfq, dfv = law.jacobian(q, v)
        else:
            dfq = dfv = np.zeros((1, problem.m, problem.m))
    c = np.ascontiguousarray
    return (c(f, dtype=float), c(dfq, dtype=float), c(dfv, dtype=float),
            c(dq_tau, dtype=float))


def dynamic_stiffness(M: FloatArray, D: FloatArray, K: FloatArray, w: float,
                      H: int) -> ComplexArray:
    """``Z_k = K - (k w)^2 M + i k w D`` for k = 0..H, stacked (H+1, n, n)."""
    kw = w * np.arange(H + 1)
    return K[None] - (kw**2)[:, None, None] * M[None] + 1j * kw[:, None, None] * D[None]


def dynamic_stiffness_derivative(problem: PeriodicProblem, lam: float,
                                 H: int) -> ComplexArray:
    """``dZ_k/dlam = dK - (kw)^2 dM - 2 k^2 w w' M + i k (w' D + w dD)``, (H+1, n, n)."""
    M, D, _ = problem.matrices(lam)
    dM, dD, dK = problem.dmatrices(lam)
    w, dw = problem.frequency(lam), problem.dfrequency(lam)
    k = np.arange(H + 1)[:, None, None]
    return dK[None] - (k * w) ** 2 * dM[None] - 2 * k**2 * w * dw * M[None] \
        + 1j * k * (dw * D[None] + w * dD[None])


def real_blocks(A: ComplexArray) -> FloatArray:
    """Real-layout matrix of the per-harmonic complex maps A_k (H+1, p, p): maps the real
    layout of X to that of ``A_k X_k`` (k = 0 block keeps the real part only)."""
    H = A.shape[0] - 1
    p = A.shape[1]
    B = np.zeros((2 * H + 1, p, 2 * H + 1, p))
    B[0, :, 0, :] = A[0].real
    ia = 2 * np.arange(1, H + 1) - 1
    B[ia, :, ia, :] = A[1:].real
    B[ia, :, ia + 1, :] = -A[1:].imag
    B[ia + 1, :, ia, :] = A[1:].imag
    B[ia + 1, :, ia + 1, :] = A[1:].real
    return B.reshape((2 * H + 1) * p, (2 * H + 1) * p)


class FullHB:
    """HB-AFT residual of all DOFs: ``R(x, lam)`` with x the real layout (2H+1, n)."""

    def __init__(self, problem: PeriodicProblem, H: int, N: int) -> None:
        self.problem = problem
        self.H = H
        self.aft = aft_matrices(H, N)
        self.n_unknowns = (2 * H + 1) * problem.n_dof
        self._last: tuple | None = None

    def residual(self, x: FloatArray, lam: float, jac: bool = True
                 ) -> tuple[FloatArray, FloatArray | None, FloatArray | None]:
        """Return R (2H+1, n) and, if jac, dR/dx (nu, nu) and dR/dlam (nu,)."""
        p, H, s = self.problem, self.H, self.problem.nl_dofs
        x = x.reshape(2 * H + 1, p.n_dof)
        M, D, K = p.matrices(lam)
        w = p.frequency(lam)
        Z = dynamic_stiffness(M, D, K, w, H)
        X = to_complex(x)
        nl = nonlinear_coefficients(p, self.aft, x[:, s], w, jac, lam=lam)
        self._last = (lam, x[:, s].copy(), nl.G)
        Rc = np.einsum("kij,kj->ki", Z, X) - p.forcing(lam, H)
        R = to_real(Rc)
        R[:, s] -= nl.G
        if not jac:
            return R, None, None
        nh = 2 * H + 1
        J = real_blocks(Z).reshape(nh, p.n_dof, nh, p.n_dof)
        J[np.ix_(np.arange(nh), s, np.arange(nh), s)] -= nl.dG
        dZ = dynamic_stiffness_derivative(p, lam, H)
        dR = to_real(np.einsum("kij,kj->ki", dZ, X) - p.dforcing(lam, H))
        dR[:, s] -= p.dfrequency(lam) * nl.dGdw
        law = p.law(lam)
        if law.dforce is not None:   # the force's own dependence on lam
            dR[:, s] -= self.aft.P @ law.dforce(nl.q, w * (self.aft.Ed @ x[:, s]))
        nu = self.n_unknowns
        return R, J.reshape(nu, nu), dR.reshape(nu)

    def last_G(self, xs: FloatArray, lam: float) -> FloatArray | None:
        """Nonlinear-force coefficients of the last evaluation if it was at (xs, lam)."""
        if self._last is not None and self._last[0] == lam \
                and np.array_equal(self._last[1], xs):
            return self._last[2]
        return None

    def nl_part(self, x: FloatArray) -> FloatArray:
        """Real-layout coefficients of the nonlinear DOFs (2H+1, m)."""
        return x.reshape(2 * self.H + 1, self.problem.n_dof)[:, self.problem.nl_dofs]
