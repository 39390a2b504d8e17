"""A periodic branch started from a time-domain orbit: finding coexisting branches and isolas.

A continuation from low speed follows one branch. A time integration can land on another
stable periodic attractor (e.g. started on the HB orbit shifted by half a period, see
:mod:`rotorsfd.analyses.simulate`); this module reads such an orbit and turns it into a
branch with the algorithm of :mod:`rotorsfd.harmonic.orbit_branch`:

1. :func:`fit_periodic_orbit` takes the last recorded period of a ``timeseries.nc`` (or a
   :class:`~rotorsfd.analyses.simulate.SimulationResult`) and gives its Fourier
   coefficients ``X_k = (2/N) sum_j x(t_j) exp(-i k Omega t_j)`` (``X_0`` the mean) in the
   HB convention ``q(t) = Re sum_k X_k exp(i k Omega t)`` with the absolute time of the
   run, so the phase relative to the unbalance force is kept. Only the recorded nodes
   (y, z) are filled; the HB solver needs the SFD journal (the condensed unknowns), the
   other DOFs follow from the linear part.
2. :func:`correct_orbit`: Newton on the HB equations at that speed from the fit
   (:func:`~rotorsfd.harmonic.periodic.solve_periodic`), and :meth:`OrbitFit.difference`:
   the largest difference over the period between the corrected HB orbit and the recorded
   one at the recorded nodes (in units of the SFD clearance): the check that the branch
   starts on the orbit the time domain found.
3. :func:`continue_both_ways`: continuation from that point towards the upper end of the
   speed range; it stops when the branch closes on itself (an isola: the parameter comes
   back across the start speed within ``closure_tol`` of the start point, measured on the
   nonlinear DOFs' coefficients over their length scale), otherwise the other direction is
   continued too and the two legs joined into one branch (lower end first).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from rotorsfd.analyses.simulation_result import SimulationResult
from rotorsfd.analyses.td_start import timeseries_path
from rotorsfd.errors import ConfigError
from rotorsfd.harmonic.orbit_branch import (
    CLOSURE_TOL,
    OrbitFit,
    continue_both_ways,
    correct_orbit,
    fit_samples,
    join_segments,
    problem_lam,
)
from rotorsfd.harmonic.periodic import PeriodicSolution
from rotorsfd.harmonic.problem import PeriodicProblem
from rotorsfd.model import dofs

__all__ = ["CLOSURE_TOL", "OrbitFit", "continue_both_ways", "correct_orbit",
           "fit_periodic_orbit", "fit_samples", "join_segments", "orbit_start",
           "problem_lam"]


def fit_periodic_orbit(timeseries: Any, H: int) -> OrbitFit:
    """:class:`OrbitFit` with H harmonics of the last recorded period of ``timeseries``
    (a ``timeseries.nc``, its directory, or a SimulationResult)."""
    if isinstance(timeseries, SimulationResult):
        r = timeseries
        t, q, nodes, speed = r.t, r.q, list(r.nodes), r.speed
        n_dof, clearance, source = r.q_final.size, r.clearance, "simulation result"
    else:
        import xarray as xr  # deferred: xarray (netCDF) only for a file

        p = timeseries_path(timeseries)
        if not p.is_file():
            raise ConfigError("from_orbit", str(timeseries), "no such file (give a simulate "
                              "output directory or its timeseries.nc)")
        with xr.open_dataset(p) as ds:
            t = np.asarray(ds["time"].values, float)
            q = np.asarray(ds["displacement"].values, float)
            nodes = [int(n) for n in ds["node"].values]
            speed = float(ds.attrs["speed_rad_s"])
            n_dof = int(ds["final_displacement"].size) if "final_displacement" in ds \
                else 4 * max(nodes)
            clearance = ds.attrs.get("clearance_m")
        source = str(p)
    samples = {dofs.dof_index(node, name): q[:, j, d]
               for j, node in enumerate(nodes) for d, name in enumerate(("y", "z"))}
    fit = fit_samples(t, samples, speed, H, n_dof, clearance, source)
    fit.info["nodes"] = nodes
    return fit


def orbit_start(problem: PeriodicProblem, timeseries: Any, H: int,
                **options: Any) -> tuple[PeriodicSolution, OrbitFit, float]:
    """Fit, correct, and the check: (HB solution, fit, max difference over the period
    between the corrected HB orbit and the recorded orbit, in clearances)."""
    fit = fit_periodic_orbit(timeseries, H)
    sol = correct_orbit(problem, fit, H, **options)
    return sol, fit, fit.difference(sol.X)

