"""A posteriori truncation error of an HB solution: how far the solution would move if
more harmonics were kept.

At a converged solution ``xs`` of the condensed equations with H harmonics, pad it with
zeros to ``H_e > H`` harmonics and take one Newton step of the H_e equations
(:mod:`rotorsfd.harmonic.condensation`, receptance form)::

    R_e(xs_pad) = [ ~0 (k <= H) ;  -Pt_k - Ht_k (G_k(xs) + Delta_k 0) (k > H) ]
    delta = -J_e(xs_pad)^-1 R_e(xs_pad)

``R_e`` at k > H is the response of the linear part to the harmonics of the nonlinear
force (and the forcing) that the H equations drop; ``delta`` adds their feedback on the
retained harmonics. From an H solution accurate to the truncation error e, the step is
accurate to O(e^2) (Newton), so ``|delta / c|`` (the 2-norm over all coefficients of the
nonlinear DOFs in their length scales c, the units of the Newton test; for an SFD, in
clearances) estimates the change of the solution from H to H_e. The default
``H_e = ceil(1.5 H)``, at least H + 2 (:func:`check_harmonics`), sees the next odd
harmonics, which an odd force such as the SFD's excites first.

The estimate costs one condensation at H_e harmonics, one AFT with its Jacobian and one
dense solve of ``m (2 H_e + 1)`` unknowns: about one Newton iteration at 1.5 H.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from rotorsfd.continuation.branch import Branch
from rotorsfd.harmonic.aft_kernels import condensed_assembly
from rotorsfd.harmonic.condensation import CondensedHB
from rotorsfd.harmonic.fourier import default_min_samples, to_real
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.harmonic.residual import nonlinear_coefficients, real_blocks

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass(frozen=True)
class TruncationEstimate:
    """The estimated change of an H-harmonic solution if ``H_check`` harmonics were kept.

    ``error``: 2-norm of the change over all coefficients of the nonlinear DOFs, each over
    its length scale c (the units of the Newton test); ``per_harmonic`` (H_check + 1,):
    the same norm harmonic by harmonic (k = 0..H_check), so ``per_harmonic[H+1:]`` is the
    content of the dropped harmonics; ``delta`` (2 H_check + 1, m): the change itself
    (real layout, physical units)."""

    H: int
    H_check: int
    error: float
    per_harmonic: FloatArray
    delta: FloatArray
    delta_lam: float = 0.0

    def harmonics_needed(self, tol: float) -> int:
        """Smallest H' in (H, H_check] whose dropped content ``|per_harmonic[H'+1:]|`` is
        <= tol (H_check when none): where to raise H to."""
        tail = tail_norms(self.per_harmonic)
        for h in range(self.H + 1, self.H_check):
            if tail[h + 1] <= tol:
                return h
        return self.H_check


def harmonic_norms(x: FloatArray) -> FloatArray:
    """2-norm of each harmonic k = 0..H of real-layout coefficients (2H+1, m):
    ``|x_0|``, then ``sqrt(|Re X_k|^2 + |Im X_k|^2)``."""
    x = np.asarray(x, dtype=float)
    per = np.empty((x.shape[0] + 1) // 2)
    per[0] = np.linalg.norm(x[0])
    per[1:] = np.sqrt((x[1::2] ** 2 + x[2::2] ** 2).sum(axis=1))
    return per


def tail_norms(per: FloatArray) -> FloatArray:
    """``tail[k]`` = 2-norm of the harmonics k..H from :func:`harmonic_norms`."""
    return np.sqrt(np.cumsum(np.asarray(per)[::-1] ** 2)[::-1])


def check_harmonics(H: int) -> int:
    """Default ``H_e`` of :func:`truncation_error`: 1.5 H rounded up, at least H + 2 (the
    next odd harmonic, which an odd force such as the SFD's excites first)."""
    return max(-(-3 * H // 2), H + 2)


def pad_harmonics(xs: FloatArray, H_new: int) -> FloatArray:
    """Real-layout coefficients (2H+1, m) padded with zeros (or truncated) to H_new."""
    xs = np.asarray(xs, dtype=float)
    out = np.zeros((2 * H_new + 1, xs.shape[1]))
    n = min(xs.shape[0], 2 * H_new + 1)
    out[:n] = xs[:n]
    return out


def pad_coefficients(X: ComplexArray, H: int) -> ComplexArray:
    """Complex all-DOF coefficients (h+1, n) zero-padded (or truncated) to (H+1, n)."""
    X = np.asarray(X, dtype=complex)
    if X.shape[0] == H + 1:
        return X
    out = np.zeros((H + 1, X.shape[1]), dtype=complex)
    k = min(X.shape[0], H + 1)
    out[:k] = X[:k]
    return out


def convert_tangent(t: FloatArray | None, H_new: int, m: int) -> FloatArray | None:
    """A vector ``(x ((2H+1) m,), lam)`` of scaled unknowns (a tangent or a point; H from
    its length, m unknowns per harmonic) in the layout of H_new harmonics: the x part
    zero-padded or truncated, lam kept."""
    if t is None:
        return t
    t = np.asarray(t, dtype=float)
    if t.size == (2 * H_new + 1) * m + 1:
        return t
    x = pad_harmonics(t[:-1].reshape(-1, m), H_new).ravel()
    return np.append(x, t[-1])


def estimate_condenser(problem: PeriodicProblem, H: int, H_check: int | None = None,
                       n_samples: int | None = None) -> CondensedHB:
    """The condensation at ``H_e`` harmonics that :func:`truncation_error` of an H
    solution uses (``H_check`` default :func:`check_harmonics`; ``n_samples`` default: the
    power of two >= 8 (H_e + 1), and >= 4 (2 H_e + 1)); pass it to every estimate of a
    branch at that H to keep the band of the matrices found once."""
    He = check_harmonics(H) if H_check is None else int(H_check)
    N = n_samples or max(default_min_samples(He), 4 * (2 * He + 1))
    return CondensedHB(problem, He, int(2 ** np.ceil(np.log2(N))))


def truncation_error(problem: PeriodicProblem, xs: FloatArray, lam: float, *,
                     tangent: FloatArray | None = None, lam_scale: float = 1.0,
                     H_check: int | None = None, n_samples: int | None = None,
                     condenser: CondensedHB | None = None,
                     point: CondensedHB | None = None) -> TruncationEstimate:
    """Estimate of the change of the solution ``xs`` ((2H+1, m) real layout on the
    nonlinear DOFs, or the complex all-DOF coefficients (H+1, n_dof)) at lam if H_check
    harmonics were kept (module docstring).

    The Newton step is taken at fixed lam, or, with the branch ``tangent`` (scaled
    unknowns ``(xs / c, lam / lam_scale)``, as in
    :func:`~rotorsfd.harmonic.periodic.continue_periodic`), on the plane normal to it: the
    bordered system ``[J_s; t^T] du = [-R_s; 0]`` stays regular at a fold, where the
    fixed-lam step is singular. The retained harmonics' own residual (the Newton test's
    remainder) is left out, so only the dropped harmonics drive the step. ``n_samples``:
    AFT samples at H_check (:func:`estimate_condenser`); ``condenser``: that condensation,
    reused from the previous estimate of the branch (its H_check and N then apply).
    ``point``: the H-harmonic condenser that solved xs (its cache at lam): the estimate
    then uses its shift Delta (the step does not depend on Delta but through rounding and
    the second-order term ``dHt_k R_k`` of the dropped harmonics' residual) and copies its
    harmonics ``k <= H`` instead of factorising them again (about 40 % of the estimate
    at H = 1 -> 3 on a large model).
    ``error`` includes the lam component ``dlam / lam_scale``.

    The force coefficients and their Jacobian at H_check come from the AFT in matrix form
    (:func:`~rotorsfd.harmonic.residual.nonlinear_coefficients`: ``dG = P (dF E)``, one
    BLAS product), the condensed residual from the same assembly as the HB residual: at
    the 2 H_check + 1 harmonics of the estimate this is several times cheaper than the
    per-sample compiled loop, and the same numbers (round-off)."""
    xs = np.asarray(xs)
    if np.iscomplexobj(xs):
        xs = to_real(xs[:, problem.nl_dofs] if xs.shape[1] == problem.n_dof else xs)
    xs = np.asarray(xs, dtype=float).reshape(-1, problem.m)
    H, m = (xs.shape[0] - 1) // 2, problem.m
    hb = condenser if condenser is not None else estimate_condenser(problem, H, H_check,
                                                                    n_samples)
    He = hb.H
    if He <= H:
        raise ValueError(f"H_check must exceed H = {H}, got {He}")
    x_pad = pad_harmonics(xs, He)
    if point is None or not hb.adopt_shift(point):
        hb.set_shift(x_pad, lam)
        point = None
    with_dlam = tangent is not None
    cd = hb.condense(lam, deriv=with_dlam, reuse=point)
    w = problem.frequency(lam)
    nl = nonlinear_coefficients(problem, hb.aft, x_pad, w, jac=True, lam=lam)
    if not (np.all(np.isfinite(nl.G)) and np.all(np.isfinite(nl.dG))):
        raise FloatingPointError("non-finite nonlinear force in the truncation estimate")
    nu = (2 * He + 1) * m
    R, dR, J = np.empty_like(x_pad), np.empty_like(x_pad), np.empty((nu, nu))
    zH, zP = np.zeros_like(cd.Ht), np.zeros_like(cd.Pt)
    delta = np.ascontiguousarray(hb.delta, dtype=complex)
    condensed_assembly(x_pad, np.ascontiguousarray(nl.G), np.ascontiguousarray(
        nl.dG.reshape(nu, nu)), np.ascontiguousarray(nl.dGdw), delta, real_blocks(delta),
        cd.Ht, cd.Pt, cd.dHt if with_dlam else zH, cd.dPt if with_dlam else zP,
        problem.dfrequency(lam) if with_dlam else 0.0, True, R, J, dR)
    dforce = problem.law(lam).dforce
    if with_dlam and dforce is not None:   # the force's own dependence on lam
        dR += hb.displacement_of(hb.aft.P @ dforce(nl.q, w * (hb.aft.Ed @ x_pad)), lam)
    R[: 2 * H + 1] = 0.0            # the H equations' own remainder is not truncation
    c = np.tile(problem.dof_scale[problem.nl_dofs], 2 * He + 1)
    Js = J * (c[None, :] / c[:, None])
    rhs = -R.ravel() / c
    if tangent is None:
        du = np.linalg.solve(Js, rhs)
        dlam = 0.0
    else:
        t = np.asarray(tangent, dtype=float)
        A = np.zeros((nu + 1, nu + 1))
        A[:nu, :nu] = Js
        A[:nu, nu] = dR.ravel() * (lam_scale / c)
        A[nu, : t.size - 1] = t[:-1]          # the padded harmonics have no component
        A[nu, nu] = t[-1]
        sol = np.linalg.solve(A, np.append(rhs, 0.0))
        du, dlam = sol[:nu], float(sol[nu])
    scaled = du.reshape(2 * He + 1, m)
    per = harmonic_norms(scaled)
    return TruncationEstimate(H, He, float(np.hypot(np.linalg.norm(scaled), dlam)), per,
                              scaled * c.reshape(2 * He + 1, m), dlam * lam_scale)


#: Per-point columns of a branch's info and their meaning.
POINT_INFO_LONG_NAMES = {
    "harmonics": "harmonics H kept at the point",
    "truncation_error": "estimated change of the solution if about 1.5 H harmonics were "
                        "kept (2-norm over the nonlinear-DOF coefficients in their length "
                        "scales, e.g. SFD clearances)",
    "inserted": "0 computed by the continuation, 1 a located saddle-node, 2 added between "
                "two saddle-nodes",
}


def point_info_columns(branch: Branch) -> dict[str, NDArray[np.generic]]:
    """Per-point columns of a branch's ``info``, when it has them: ``harmonics`` (int),
    ``truncation_error`` (only when computed at every point: never NaN) and ``inserted``
    (:mod:`rotorsfd.stability.fold_points`)."""
    out: dict[str, NDArray[np.generic]] = {}
    n = branch.n_points
    Hs = branch.info.get("harmonics")
    if Hs is not None and np.shape(Hs) == (n,):
        out["harmonics"] = np.asarray(Hs, dtype=np.int32)
    te = branch.info.get("truncation_error")
    if te is not None and np.shape(te) == (n,) and np.all(np.isfinite(te)):
        out["truncation_error"] = np.asarray(te, dtype=float)
    ins = branch.info.get("inserted")
    if ins is not None and np.shape(ins) == (n,):
        out["inserted"] = np.asarray(ins, dtype=np.int32)
    return out
