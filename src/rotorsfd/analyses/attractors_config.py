"""An attractor census from a configuration or a rotor system: the
:class:`~rotorsfd.analyses.attractors.CensusModel` of a
:class:`~rotorsfd.model.system.RotorSystem` at a speed, and :func:`run_census` of a Config
at one speed or several (the map of coexisting solutions)."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import replace
from typing import Any

import numpy as np

from rotorsfd.analyses.attractors import (
    DEFAULT_HARMONICS,
    DEFAULT_STEPS,
    CensusModel,
    CensusOptions,
    census_map,
)
from rotorsfd.errors import ConfigError


def census_model(system: Any, speed: float, *, reduction: str = "auto",
                 cutoff: float = 40.0, reference_speed: float | None = None) -> CensusModel:
    """:class:`CensusModel` of a :class:`~rotorsfd.model.system.RotorSystem` at ``speed``
    [rad/s] (the reduced step of ``reduction``, as ``simulate``)."""
    from rotorsfd.analyses.td_integration import time_domain_inputs, with_reduction

    if not len(system.elements):
        raise ConfigError("elements", 0, "an attractor census needs a nonlinear element")
    inputs = with_reduction(time_domain_inputs(system, speed), reduction, cutoff)
    full = system.periodic_problem()
    problem = full if system.base.is_constant else None
    scale = np.asarray(full.dof_scale, float)[inputs.nl_dofs]
    return CensusModel(inputs, scale, problem, reference_speed)


def run_census(config: Any, speeds: Sequence[float] | None = None, *,
               speed_ratios: Sequence[float] | None = None, search_path: Any = None,
               options: CensusOptions | None = None, executor: Any = None,
               progress: Any = None) -> list[Any]:
    """Censuses of a Config at ``speeds`` [rad/s] or ``speed_ratios`` (of the
    reference speed); the step: ``options.steps_per_period``, default the integer
    ``[analysis.simulate] steps_per_period`` (400 with ``"auto"``: each attractor's
    ``step_check`` then says what halving it moves); H: ``[analysis.response]``."""
    from rotorsfd.analyses.modal import reference_speed
    from rotorsfd.analyses.simulate import system_from_config

    system = system_from_config(config, search_path)
    ref = reference_speed(config, system)
    sim = config.analysis.simulate
    if speeds is None:
        if speed_ratios is None:
            speeds = [sim.fixed_speed(ref)]
        else:
            speeds = [r * ref for r in speed_ratios]
    o = options or CensusOptions()
    spp, H = sim.steps_per_period, config.analysis.response.harmonics
    o = replace(o, steps_per_period=o.steps_per_period or (
        spp if isinstance(spp, int) else DEFAULT_STEPS),
        harmonics=o.harmonics or (H if isinstance(H, int) else DEFAULT_HARMONICS))
    models = [census_model(system, float(s), reduction=sim.reduction,
                           cutoff=sim.reduction_cutoff, reference_speed=ref)
              for s in speeds]
    return census_map(models, o, executor=executor, progress=progress)
