"""The records of a time integration: the scheme's options (:class:`StepOptions`), the
state between chunks of steps (:class:`StepState`), the recorded result
(:class:`TimeResult`) and the packed arrays of one run (:class:`PreparedSystem`, built by
:func:`rotorsfd.timedomain.integrate.prepare`)."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np

from rotorsfd.timedomain import newmark as nm


@dataclass(frozen=True)
class StepOptions:
    """How the time step runs: the scheme (``method`` ``"newmark"``, ``"hht"`` with
    ``alpha`` or ``"generalized-alpha"`` with ``rho_inf``) and the tolerances of the
    Newton iteration on the nonlinear DOFs and of the time-varying matrices' fixed point."""

    method: str = "newmark"
    alpha: float = 0.05
    rho_inf: float = 0.9
    newton_rtol: float = 1e-10
    newton_atol: float = 0.0
    max_newton: int = 50
    tv_rtol: float = 1e-12
    max_tv: int = 50

    @classmethod
    def of(cls, options: StepOptions | dict[str, Any] | None) -> StepOptions:
        """An options record from a record, the keywords of :func:`integrate` (e.g.
        ``{"method": "hht", "alpha": 0.05}``) or None (the defaults)."""
        if isinstance(options, StepOptions):
            return options
        return cls(**(options or {}))

    @property
    def scheme(self) -> dict[str, Any]:
        """The scheme keywords of :func:`prepare`."""
        return {"method": self.method, "alpha": self.alpha, "rho_inf": self.rho_inf}

    @property
    def iteration(self) -> dict[str, Any]:
        """The iteration keywords of :func:`run`."""
        return {"newton_rtol": self.newton_rtol, "newton_atol": self.newton_atol,
                "max_newton": self.max_newton, "tv_rtol": self.tv_rtol,
                "max_tv": self.max_tv}


@dataclass
class StepState:
    """Full state of a run at global step ``step``: ``X = [q; v(; a)]`` and the force
    terms of that step (``F`` nonlinear force, ``G = Kinv g``, ``T = Kinv g_tv``)."""

    X: np.ndarray
    F: np.ndarray
    G: np.ndarray
    T: np.ndarray
    step: int
    #: acceleration of the nonlinear DOFs (an inertial force law's input)
    Anl: np.ndarray | None = None

    def copy(self) -> StepState:
        return StepState(self.X.copy(), self.F.copy(), self.G.copy(), self.T.copy(),
                         self.step, None if self.Anl is None else self.Anl.copy())


@dataclass
class TimeResult:
    """Result of :func:`integrate`.

    ``t, q, v``: recorded samples ``(n_samples,)``, ``(n_samples, len(dofs))``;
    ``poincare_t, poincare_q, poincare_v``: samples once per ``poincare_every`` steps
    (once per forcing period by default); ``q_final, v_final``: all DOFs at ``t_final``.
    """

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    dofs: np.ndarray
    poincare_t: np.ndarray
    poincare_q: np.ndarray
    poincare_v: np.ndarray
    q_final: np.ndarray
    v_final: np.ndarray
    t_final: float
    steps_done: int
    dt: float
    omega: float
    steps_per_period: int | None
    success: bool
    status: int
    message: str
    newton_iterations_mean: float = 0.0
    newton_iterations_max: int = 0
    fixed_point_iterations_max: int = 0
    contact_backtracks: int = 0
    elapsed: float = 0.0
    state: StepState | None = field(default=None, repr=False)


@dataclass
class PreparedSystem:
    """Everything the compiled loop needs for one run (``prepare``)."""

    ops: nm.Operators
    kernel: Any
    params: np.ndarray
    M: np.ndarray
    D: np.ndarray
    K: np.ndarray
    n_steps: int
    t0: float
    omega: float
    f0: np.ndarray
    hmult: np.ndarray
    fc: np.ndarray
    fs: np.ndarray
    fj: np.ndarray
    KF0: np.ndarray
    KFc: np.ndarray
    KFs: np.ndarray
    KFj: np.ndarray
    scoef: np.ndarray
    tvcoef: np.ndarray
    tvkind: np.ndarray
    tvmat: np.ndarray
    PX: np.ndarray
    #: the compiled inertial kernel (a force of the acceleration too), None without
    kernel_a: Any = None

    @property
    def n_dof(self) -> int:
        return self.M.shape[0]

    @property
    def nl(self) -> np.ndarray:
        return self.ops.nl
