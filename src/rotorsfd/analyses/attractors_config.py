"""An attractor census from a configuration or a rotor system: the
:class:`~rotorsfd.analyses.attractors.CensusModel` of a
:class:`~rotorsfd.model.system.RotorSystem` at a speed, and :func:`run_census` of a Config
at one speed or several (the map of coexisting solutions): ``run_census(system,
settings=<[analysis.simulate]>, context=RunContext)``, and ``run_census(config)`` the same
call with the config's section and context."""

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
from rotorsfd.analyses.attractors_result import CensusResult
from rotorsfd.analyses.context import RunContext, build, config_context
from rotorsfd.analyses.td_integration import time_domain_inputs, with_reduction
from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import Config, SimulateAnalysis


def census_model(system: Any, speed: float, *, reduction: str = "auto",
                 cutoff: float = 40.0, reference_speed: float | None = None) -> CensusModel:
    """:class:`CensusModel` of a :class:`~rotorsfd.model.system.RotorSystem` at ``speed``
    [rad/s] (the reduced step of ``reduction``, as ``simulate``)."""
    if not len(system.elements):
        raise ConfigError("elements", 0, "an attractor census needs a nonlinear element")
    inputs = with_reduction(time_domain_inputs(system, speed), reduction, cutoff)
    full = system.periodic_problem()
    problem = full if system.base.is_constant else None
    scale = np.asarray(full.dof_scale, float)[inputs.nl_dofs]
    return CensusModel(inputs, scale, problem, reference_speed)


def run_census(config_or_system: Any, speeds: Sequence[float] | None = None, *,
               speed_ratios: Sequence[float] | None = None,
               options: CensusOptions | None = None, settings: SimulateAnalysis | None = None,
               context: RunContext | None = None, search_path: Any = None,
               executor: Any = None, progress: Any = None) -> CensusResult:
    """Censuses (a :class:`CensusResult`, one per speed) at ``speeds`` [rad/s] or
    ``speed_ratios`` (of the reference speed; neither: the ``[analysis.simulate]`` speed)
    with ``options`` (:class:`CensusOptions`).

    ``run_census(system, settings=..., context=...)``: ``settings`` the
    ``[analysis.simulate]`` section (the speed, the step: ``options.steps_per_period``,
    default its integer ``steps_per_period`` (400 with ``"auto"``: each attractor's
    ``step_check`` then says what halving it moves), the reduction), ``context`` the
    reference speed and ``[analysis.response]`` (H of the HB correction: its integer
    ``harmonics``, else 8); defaults: an empty configuration's. ``run_census(config)`` is
    that call with ``build(config)``, ``config.analysis.simulate`` and
    :func:`~rotorsfd.analyses.context.config_context`: the two paths cannot disagree."""
    if isinstance(config_or_system, Config):
        config = config_or_system
        system = build(config, search_path)
        return run_census(system, speeds, speed_ratios=speed_ratios, options=options,
                          settings=config.analysis.simulate if settings is None
                          else settings,
                          context=config_context(config, system, "simulate",
                                                 search_path=search_path),
                          executor=executor, progress=progress)
    system = config_or_system
    sim = settings if settings is not None else SimulateAnalysis()
    ctx = context if context is not None else RunContext(search_path=search_path)
    ref = ctx.reference(system)
    if speeds is None:
        if speed_ratios is None:
            speed = sim.fixed_speed(ref)
            if speed is None:
                raise ConfigError("analysis.simulate.speed", None, "give the census "
                                  "speed: --speed, --speed-ratio or speed/speed_ratio in "
                                  "[analysis.simulate]")
            speeds = [speed]
        else:
            speeds = [r * ref for r in speed_ratios]
    o = options or CensusOptions()
    spp, H = sim.steps_per_period, ctx.response.harmonics
    o = replace(o, steps_per_period=o.steps_per_period or (
        spp if isinstance(spp, int) else DEFAULT_STEPS),
        harmonics=o.harmonics or (H if isinstance(H, int) else DEFAULT_HARMONICS))
    models = [census_model(system, float(s), reduction=sim.reduction,
                           cutoff=sim.reduction_cutoff, reference_speed=ref)
              for s in speeds]
    return CensusResult(census_map(models, o, executor=executor, progress=progress),
                        title=ctx.title)
