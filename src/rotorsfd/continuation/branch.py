"""Result of a continuation of periodic solutions: :class:`Branch`, and :class:`BranchPoint`
passed to the event hook at each converged point."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

FloatArray = NDArray[np.float64]
ComplexArray = NDArray[np.complex128]


@dataclass
class BranchPoint:
    """One converged point, as given to the event hook ``callback(point) -> bool | None``.

    ``X`` (H+1, n_dof) complex Fourier coefficients of all DOFs; ``xs`` the solved unknowns
    (real layout, physical units); ``tangent`` unit tangent in scaled unknowns (last entry:
    d(lam/lam_scale)/ds); ``jacobian`` (nu, nu+1) ``[dR/dx, dR/dlam]`` in physical units
    (condensed: the Schur-form residual, see :mod:`rotorsfd.harmonic.condensation`);
    ``s`` the arc length along the branch and ``dlam_ds`` (a fold where it changes sign).
    ``index`` is -1 for a point re-solved between branch points (:meth:`Branch.point_at`).
    """

    index: int
    lam: float
    X: ComplexArray
    xs: FloatArray
    tangent: FloatArray
    jacobian: FloatArray
    iterations: int
    frequency: float
    s: float = 0.0        #: arc length from the first point (scaled units)
    dlam_ds: float = 0.0  #: dlam/ds (physical lam per unit of scaled arc length)


@dataclass
class Branch:
    """A branch of periodic solutions ``q(t) = Re(sum_k X_k exp(i k w t))``.

    Attributes
    ----------
    lam : (n_points,) parameter values.
    X : (n_points, H+1, n_dof) complex Fourier coefficients of all DOFs.
    frequency : (n_points,) fundamental angular frequency w(lam).
    tangents : (n_points, nu+1) tangents in scaled unknowns (x/scale, lam/lam_scale), of
        unit length in the arc-length metric (nonlinear DOFs and lam).
    iterations : (n_points,) Newton iterations of each point.
    ds : (n_points,) arc-length step that produced each point (0 for the first).
    s : (n_points,) arc length from the first point, ``cumsum(ds)`` (scaled units).
    jacobians : (n_points, nu, nu+1) ``[dR/dx, dR/dlam]`` at each point (physical units;
        condensed: Schur-form residual on nl_dofs), or None if not stored.
    aliasing : (n_points,) sampling-error estimate of the N_f rule used
        (``info["n_samples_rule"]``, see :func:`rotorsfd.harmonic.continue_periodic`):
        "adaptive", the change of the scaled residual if N_f doubled; "grow", the relative
        change of the nonlinear-force coefficients
        (:func:`rotorsfd.harmonic.fourier.aliasing_error`).
    success, message : scipy-style outcome.
    H, n_samples, nl_dofs, condensed, lam_scale : the discretisation used.
    """

    lam: FloatArray
    X: ComplexArray
    frequency: FloatArray
    tangents: FloatArray
    iterations: NDArray[np.int64]
    ds: FloatArray
    s: FloatArray
    jacobians: FloatArray | None
    aliasing: FloatArray
    success: bool
    message: str
    H: int
    n_samples: int
    nl_dofs: NDArray[np.int64]
    condensed: bool
    lam_scale: float
    info: dict = field(default_factory=dict)
    resolver: Callable[[float], BranchPoint] | None = field(default=None, repr=False)

    def point_at(self, s: float) -> BranchPoint:
        """Re-solve the branch at arc length s (between two of its points), e.g. to locate a
        bifurcation: ``solve_at = lambda s: (p := branch.point_at(s)).lam, ...``.
        Raises ConvergenceError on failure."""
        if self.resolver is None:
            raise ValueError("this branch cannot re-solve points (no resolver)")
        return self.resolver(s)

    @property
    def dlam_ds(self) -> FloatArray:
        """dlam/ds at each point (physical lam per unit of scaled arc length)."""
        return self.tangents[:, -1] * self.lam_scale

    @property
    def n_points(self) -> int:
        return int(self.lam.size)

    def amplitude(self, dof: int, k: int = 1) -> FloatArray:
        """``|X_k|`` of one DOF along the branch (half peak-to-peak of harmonic k)."""
        return np.abs(self.X[:, k, dof])

    def time_series(self, index: int, n_t: int = 256) -> tuple[FloatArray, FloatArray]:
        """Return t (n_t,) over one period and q(t) (n_t, n_dof) at point ``index``."""
        w = self.frequency[index]
        t = np.arange(n_t) * (2 * np.pi / w) / n_t
        k = np.arange(self.H + 1)
        ph = np.exp(1j * w * np.outer(t, k))
        return t, (ph @ self.X[index]).real

    def folds(self) -> NDArray[np.int64]:
        """Indices i where dlam/ds changes sign between points i and i+1."""
        s = np.sign(self.tangents[:, -1])
        return np.nonzero(s[:-1] * s[1:] < 0)[0]

    def __repr__(self) -> str:
        lo, hi = (self.lam.min(), self.lam.max()) if self.n_points else (np.nan, np.nan)
        return (f"Branch(n_points={self.n_points}, lam=[{lo:.6g}, {hi:.6g}], H={self.H}, "
                f"n_samples={self.n_samples}, condensed={self.condensed}, "
                f"success={self.success}, message={self.message!r})")
