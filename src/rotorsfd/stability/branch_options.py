"""Options of the Floquet stability of a branch (:mod:`rotorsfd.stability.branch_stability`):
the method, the Newmark intervals and their step control, the location and the check of
bifurcations."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

from rotorsfd.errors import ConfigError
from rotorsfd.stability.floquet import STABILITY_TOL

#: At a turning point of the exact orbit a multiplier is exactly +1; a located one farther
#: from +1 than this says the orbit or the monodromy is not converged there.
FOLD_MULTIPLIER_TOL = 1e-3

METHODS = ("newmark-cb", "newmark", "generalized-alpha", "generalized-alpha-cb", "hill",
           "hill-koopman")
#: The methods on the Craig-Bampton reduced model (the basis once per (M, K)).
REDUCED_METHODS = ("newmark-cb", "generalized-alpha-cb", "hill", "hill-koopman")
#: ``basis = "full"``: the unreduced counterpart of each reduced time-stepping method.
FULL_METHODS = {"newmark-cb": "newmark", "generalized-alpha-cb": "generalized-alpha",
                "newmark": "newmark", "generalized-alpha": "generalized-alpha"}
BASES = ("reduced", "full")


@dataclass(frozen=True)
class StabilityOptions:
    """How the multipliers are computed and bifurcations located.

    ``method`` one of :data:`METHODS`; ``n_intervals`` Newmark intervals per period
    (paper: 400); ``n_harmonics`` Hill truncation (default: the orbit's H, at least 8;
    Hill's exponents need at least the harmonics of the orbit: with fewer, on the paper
    rotor near journal contact, a period doubling came out as spurious saddle-nodes);
    ``n_modes`` / ``omega_max`` the kept
    fixed-interface modes (default ``omega_max = M_b / (4 T)`` at each point, ``M_b`` =
    ``basis_intervals``, default ``n_intervals``: the bifurcation check refines the step
    on the branch's reduced model);
    ``interval_tol`` (Newmark methods): step control of the monodromy, see
    :class:`~rotorsfd.stability.floquet_evaluator.FloquetEvaluator`
    (None: ``n_intervals`` fixed); ``min_intervals`` /
    ``max_intervals`` its bounds;
    ``check``: re-locate every bifurcation at more harmonics and intervals
    (:mod:`rotorsfd.stability.bifurcation_check`, run by the response analysis), confirmed
    within ``check_rtol`` (relative);
    ``tol`` unstable when ``|mu|max > 1 + tol``; ``rtol`` relative parameter tolerance of
    located bifurcations (``locate=False``: linear interpolation between points);
    ``fold_merge_rtol``: a multiplier crossing +1 within this relative distance of a
    turning point is that fold (the gap, HB truncation, is reported in ``messages``); so
    is one farther away from a turning point across which no multiplier crosses +1.
    ``basis``: ``"reduced"`` (the method as given) or ``"full"`` (the unreduced monodromy
    of the whole model for a check: ``newmark-cb`` becomes ``newmark``,
    ``generalized-alpha-cb`` ``generalized-alpha``; Hill has no full form).
    ``outside``: compute ``max_multiplier_outside`` (the modes above the Craig-Bampton
    cut-off, one dense eigenproblem per point) at every point of the branch; off, the
    branch has no ``max_multiplier_outside`` (None, no column written). The bifurcation
    check's pieces and the located re-solves never report it and run with it off (the
    multipliers and bifurcations are the same).
    """

    method: str = "newmark-cb"
    n_intervals: int = 400
    n_harmonics: int | None = None
    n_modes: int | None = None
    omega_max: float | None = None
    rho_inf: float = 0.6
    tol: float = STABILITY_TOL
    rtol: float = 1e-6
    locate: bool = True
    fold_merge_rtol: float = 1e-3
    interval_tol: float | None = None
    max_intervals: int = 12800
    min_intervals: int = 100
    basis_intervals: int | None = None
    check: bool = False
    check_rtol: float = 1e-3
    basis: str = "reduced"
    outside: bool = True

    def __post_init__(self) -> None:
        if self.method not in METHODS:
            raise ConfigError("analysis.stability.method", self.method,
                              f"one of {', '.join(METHODS)}")
        if self.basis not in BASES:
            raise ConfigError("analysis.stability.basis", self.basis,
                              f"one of {', '.join(BASES)}")
        if self.basis == "full":
            if self.method not in FULL_METHODS:
                raise ConfigError("analysis.stability.basis", self.basis,
                                  "'full' needs a Newmark or generalized-alpha method, not "
                                  f"{self.method!r}")
            object.__setattr__(self, "method", FULL_METHODS[self.method])
        if self.interval_tol is not None and not self.interval_tol > 0:
            raise ConfigError("analysis.stability.interval_tolerance", self.interval_tol,
                              "must be > 0")

    @property
    def basis_label(self) -> str:
        """What the multipliers cover, for the files' ``floquet_basis``."""
        if self.method in REDUCED_METHODS:
            cut = (f"{self.n_modes} modes" if self.n_modes is not None else
                   f"omega <= {self.omega_max:g} rad/s" if self.omega_max is not None else
                   f"omega <= M_b / (4 T), M_b = {self.basis_intervals or self.n_intervals}")
            return ("craig-bampton: the nonlinear DOFs plus the fixed-interface modes with "
                    + cut)
        return "full: every DOF of the model"

    @classmethod
    def from_section(cls, section: Any, **changes: Any) -> StabilityOptions:
        """The options of an ``[analysis.stability]`` section
        (:class:`~rotorsfd.io.schema.StabilityAnalysis`; ``interval_tol`` only with
        ``adaptive_intervals``), ``changes`` (fields of this class) applied last."""
        st = section
        return cls(**{"method": st.method, "n_intervals": st.intervals, "n_modes": st.n_modes,
                      "tol": st.tolerance, "rtol": st.locate_tolerance,
                      "interval_tol": st.interval_tolerance if st.adaptive_intervals
                      else None, "max_intervals": st.max_intervals,
                      "check": st.check_bifurcations, "check_rtol": st.check_tolerance,
                      "basis": st.basis, **changes})
