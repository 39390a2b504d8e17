"""Stability chart of the linear rotor under time-periodic base rotation (issue 6 item 5,
paper section 3.3 and Figure 6).

The linear rotor (film off, supports and centring spring on) in the base frame::

    M q'' + (C + Omega G + sum_i c_i(t) B_i) q' + (K + sum_i k_i(t) B_i) q = f(t)

with the 12 constant base matrices ``B_i`` of :func:`rotorsfd.model.base_terms.base_basis`
and their scalar coefficients ``c_i, k_i`` from :func:`base_coefficients` of the base
rates ``w(t)`` and ``w'(t)``. Each rotation rate is off, constant or harmonic,
``w = value + a sin(w_b t + phase)`` with ``a`` the rate amplitude or ``A0 w_b`` (angle
amplitude A0, the paper's ``w_by = A0 w_b sin(w_b t)``), all with the same ``w_b``, so the
system is periodic with ``T = 2 pi / w_b`` (no harmonic rate: ``T = 2 pi / Omega``). The
forcing f (unbalance, base acceleration, gyroscopic moment, gravity) does not change the
stability and is left out. The coefficients are linear in Omega
(``k(Omega) = k(0) + Omega (k(1) - k(0))``), so the speed can be an axis too.

Axes ("coefficient" parameters, evaluated inside the coefficient callables, vectorised
over a grid row): ``speed`` and ``base.{rolling,pitching,yawing}.{value, amplitude,
angle_amplitude, frequency, phase}``. Any other scalar config field (a support
stiffness, a disk mass) is a "structural" axis: the model is rebuilt for each of its
values. The monodromy of every point is the average-acceleration Newmark transition of
:func:`rotorsfd.stability.chart.stability_chart` on a Galerkin basis of the lowest
undamped modes of ``(K + constant base terms, M)``: by default every mode below
``MODE_CUTOFF`` times the highest of (2 w_b, Omega) over the grid (at least
``MIN_MODES``), which holds the combination resonances ``omega_i + omega_j = k w_b``
with ``k <= 2`` that the chart can show.

The parts: :mod:`.stability_chart_rates` (the base rates as functions of the chart
parameters), :mod:`.stability_chart_ltp` (the LTP system of a rotor and its modal
basis), :mod:`.stability_chart_result` (the result, its files and plot); this module
checks the axes and runs the grid.
"""


from __future__ import annotations

import sys
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.context import RunContext, build
from rotorsfd.analyses.stability_chart_ltp import MODE_CUTOFF, modal_basis, rotor_ltp_system
from rotorsfd.analyses.stability_chart_rates import (
    RATE_FIELDS,
    RATE_KINDS,
    ROTATIONS,
    ChartParams,
    RateSpec,
    coefficient_target,
    rate_specs_from_config,
    rate_specs_from_motion,
)
from rotorsfd.analyses.stability_chart_result import ChartAxis, ChartResult
from rotorsfd.errors import ConfigError, ConvergenceError
from rotorsfd.io.config import show_config, with_values
from rotorsfd.io.schema import (
    Config,
    ParameterAxis,
    StabilityChartAnalysis,
    axis_values,
    resolve_kind,
)
from rotorsfd.io.units import KINDS, to_si
from rotorsfd.linear.modal import eigen
from rotorsfd.model.system import RotorSystem
from rotorsfd.model.time_terms import linear_part
from rotorsfd.stability.chart import StabilityChart, stability_chart
from rotorsfd.stability.floquet import STABILITY_TOL


@dataclass(frozen=True)
class ConfigSource:
    """What a configuration adds to the system of a chart: the base rates as written (an
    angle amplitude stays one when an axis varies the frequency), the physical kind of an
    axis' field, every axis value checked as a configuration, and the system rebuilt at
    the values of a structural axis (``build(with_values(config, values))``)."""

    config: Config
    search_path: Path | None = None

    def rate_specs(self) -> tuple[RateSpec, RateSpec, RateSpec]:
        return rate_specs_from_config(self.config)

    def kind(self, path: str, where: str) -> str:
        """The ``KINDS`` key of the field at ``path``; ConfigError at ``where``."""
        try:
            return "angular_velocity" if path == "speed" else resolve_kind(self.config, path)
        except KeyError as exc:
            raise ConfigError(where, path, exc.args[0]) from None

    def values(self, axis: ParameterAxis) -> list[float]:
        return axis_values(self.config, axis)

    def check(self, axes: Sequence[ChartAxis]) -> None:
        """ConfigError unless the first and the last value pair of the axes make a valid
        configuration (ranges, the fields a law uses)."""
        for i in (0, -1):
            with_values(self.config, {a.path: float(a.values[i]) for a in axes
                                      if a.path != "speed"})

    def system_at(self, values: dict[str, float]) -> RotorSystem:
        return build(with_values(self.config, values), self.search_path)


def chart_context(config: Config, search_path: Path | None = None) -> RunContext:
    """The context of a chart run from ``config``: its title, the resolved configuration
    and the folder of its files (the chart needs no reference speed and no nodes)."""
    return RunContext(title=config.title, config_toml=show_config(config),
                      search_path=search_path)


def axis_from_config(config: Config, name: str) -> ChartAxis:
    """Axis ``name`` (x or y) of ``[analysis.stability_chart]`` in SI with its units."""
    return chart_axis(getattr(config.analysis.stability_chart, name), name,
                      ConfigSource(config))


def chart_axis(axis: ParameterAxis | tuple[str, Sequence[float]] | None, name: str,
               source: ConfigSource | None = None) -> ChartAxis:
    """A ChartAxis from a settings axis (values with units) or ``(path, SI values)``.
    Without a configuration only ``speed`` and the base-rate fields are axes (their units
    are known); ``source`` gives the kind of any other field."""
    where = f"analysis.stability_chart.{name}"
    if axis is None:
        raise ConfigError(where, None, "a stability chart needs two axes x and y, e.g. "
                          "x = { parameter = 'base.pitching.frequency', start = '100 rad/s',"
                          " stop = '400 rad/s', n = 100 }")
    path = (axis[0] if isinstance(axis, tuple) else axis.parameter).strip()
    target = coefficient_target(path)
    if source is not None:
        kind = source.kind(path, f"{where}.parameter")
    elif target is None:
        raise ValueError(f"axis {path!r}: from a RotorSystem only 'speed' and "
                         f"base.<rotation>.<{'|'.join(RATE_FIELDS)}> are possible")
    else:
        kind = "angular_velocity" if target[0] < 0 else RATE_KINDS[target[1]]
    if isinstance(axis, tuple):
        values = axis[1]
    elif source is not None:
        values = source.values(axis)
    elif axis.values is not None:           # as io.schema.axis_values, the kind known
        values = [to_si(v, kind) for v in axis.values]
    else:
        a, b = to_si(axis.start, kind), to_si(axis.stop, kind)
        values = [a] if axis.n == 1 else [a + (b - a) * i / (axis.n - 1)
                                          for i in range(axis.n)]
    return ChartAxis(path, np.asarray(values, float).ravel(), KINDS[kind].unit)


def _check_axes(x: ChartAxis, y: ChartAxis, specs: Sequence[RateSpec], where: str) -> None:
    if x.path == y.path:
        raise ConfigError(f"{where}.y.parameter", y.path, "must differ from the x axis")
    for name, ax in (("x", x), ("y", y)):
        if ax.values.size == 0 or not np.all(np.isfinite(ax.values)):
            raise ConfigError(f"{where}.{name}", ax.path, "needs finite values")
        target = coefficient_target(ax.path)
        if target is None or target[0] < 0:
            continue
        comp, fld = target
        law = specs[comp].law
        uses = {"off": (), "constant": ("value",), "harmonic": RATE_FIELDS}[law]
        if fld not in uses:
            raise ConfigError(f"{where}.{name}.parameter", ax.path,
                              f"not used with base.{ROTATIONS[comp]}.law = {law!r}")
        if fld == "frequency" and np.any(ax.values <= 0):
            raise ConfigError(f"{where}.{name}", ax.path, "base frequencies must be > 0")
    harmonic = [i for i, s in enumerate(specs) if s.law == "harmonic"]
    for name, ax in (("x", x), ("y", y)):
        if ax.path == "speed" and not harmonic and np.any(ax.values == 0):
            raise ConfigError(f"{where}.{name}", ax.path, "speed 0 without a harmonic base "
                              "rate: no period (T = 2 pi / Omega)")
    freq_axes = {coefficient_target(a.path) for a in (x, y)} & {(i, "frequency")
                                                               for i in harmonic}
    freqs = {specs[i].frequency for i in harmonic}
    if len(harmonic) > 1 and (freq_axes or len(freqs) > 1):
        raise ConfigError("base", [ROTATIONS[i] for i in harmonic],
                          "harmonic base rates must share one fixed frequency (a periodic "
                          "system); make at most one rate harmonic to vary its frequency")
    if harmonic and not freq_axes and not specs[harmonic[0]].frequency > 0:
        raise ConfigError(f"base.{ROTATIONS[harmonic[0]]}.frequency", 0.0, "must be > 0")




def _natural_frequencies(system: RotorSystem, specs: Sequence[RateSpec],
                         speed: float | None, n: int = 8) -> NDArray:
    """Damped natural frequencies [rad/s] of the linear part with the base rates at their
    mean."""
    if speed is None:
        return np.zeros(0)
    mean = [s.value if s.law in ("constant", "harmonic") else 0.0 for s in specs]
    try:
        return np.asarray(eigen(linear_part(system, rates=mean), speed, n).frequencies,
                          float)
    except Exception:
        return np.zeros(0)


def run_stability_chart(config_or_system: Config | RotorSystem,
                        settings: StabilityChartAnalysis | None = None,
                        context: RunContext | None = None, *,
                        x: tuple[str, Sequence[float]] | None = None,
                        y: tuple[str, Sequence[float]] | None = None,
                        speed: float | None = None, n_intervals: int | None = None,
                        n_modes: int | None = None, workers: int = 1,
                        tol: float = STABILITY_TOL, progress: bool = False,
                        search_path: Path | None = None,
                        source: ConfigSource | None = None) -> ChartResult:
    """Max Floquet multiplier of the linear rotor over the grid x times y.

    ``run_stability_chart(system, settings, context=...)``: the linear part of ``system``
    (its rotor and base-rate laws; film and forcing ignored) with ``settings`` the
    ``[analysis.stability_chart]`` section (axes, speed, Newmark intervals; default: its
    defaults) and ``context`` the title and resolved configuration (:class:`RunContext`).
    ``run_stability_chart(config)`` is that call with ``build(config)``,
    ``config.analysis.stability_chart``, :func:`chart_context` and the
    :class:`ConfigSource` of the config (the rates as written, the units of the axes, any
    config field as a "structural" axis: the system rebuilt per value), so the two paths
    cannot disagree; without a source the axes are ``speed`` and the base-rate fields.
    ``x``, ``y`` (``(path, SI values)``), ``speed`` and ``n_intervals`` override the
    settings. ``n_modes``: size of the modal basis (default: see the module docstring).
    ``workers``: threads over grid rows. ``progress``: a tqdm bar on stderr.
    """
    if not isinstance(config_or_system, RotorSystem):
        config = config_or_system
        source = ConfigSource(config, search_path)
        source.rate_specs()          # a callable law: its error before any work
        return run_stability_chart(
            build(config, search_path),
            config.analysis.stability_chart if settings is None else settings,
            context or chart_context(config, search_path), x=x, y=y, speed=speed,
            n_intervals=n_intervals, n_modes=n_modes, workers=workers, tol=tol,
            progress=progress, source=source)
    system = config_or_system
    sc = StabilityChartAnalysis() if settings is None else settings
    ctx = RunContext(search_path=search_path) if context is None else context
    where = "analysis.stability_chart"
    specs = source.rate_specs() if source is not None else rate_specs_from_motion(system.base)
    xa = chart_axis(sc.x if x is None else x, "x", source)
    ya = chart_axis(sc.y if y is None else y, "y", source)
    speed = sc.speed if speed is None else speed
    intervals = n_intervals or sc.intervals
    if source is not None:
        source.check((xa, ya))
    _check_axes(xa, ya, specs, where)
    tx, ty = coefficient_target(xa.path), coefficient_target(ya.path)
    if speed is None and (tx is None or tx[0] >= 0) and (ty is None or ty[0] >= 0):
        raise ConfigError(f"{where}.speed", None, "give the rotor speed (or make 'speed' "
                          "an axis)")
    if speed is not None and not speed > 0:
        raise ConfigError(f"{where}.speed", speed, "must be > 0")
    # the highest excitation frequency over the grid sets the modal basis
    top = [speed or 0.0]
    for ax, t in ((xa, tx), (ya, ty)):
        if t is not None and (t[1] in ("speed", "frequency")):
            top.append(float(np.max(np.abs(ax.values))) * (1.0 if t[1] == "speed" else 2.0))
    top += [2.0 * s.frequency for i, s in enumerate(specs)
            if s.law == "harmonic" and (i, "frequency") not in (tx, ty)]
    cutoff = MODE_CUTOFF * max(top)

    def system_at(values: dict[str, float]) -> RotorSystem:
        if not values:
            return system
        assert source is not None   # a structural axis needs a configuration (chart_axis)
        return source.system_at(values)

    # tasks: (index into the grid: a row, a column or a point, callable -> its chart)
    tasks: list[tuple[tuple[Any, Any], Callable[[], StabilityChart]]] = []

    def add(index: tuple[Any, Any], structural: dict[str, float], p1_t, p2_t,
            p1: NDArray, p2: NDArray) -> None:
        def run() -> StabilityChart:
            params = ChartParams(specs, speed, p1_t, p2_t)
            ltp = rotor_ltp_system(system_at(structural), params, p1, p2)
            basis = modal_basis(ltp, cutoff, n_modes)
            return stability_chart(ltp, p1, p2, n_intervals=intervals, basis=basis, tol=tol)

        tasks.append((index, run))

    if tx is not None and ty is not None:
        params = ChartParams(specs, speed, tx, ty)
        ltp = rotor_ltp_system(system, params, xa.values, ya.values)
        basis = modal_basis(ltp, cutoff, n_modes)
        for i, v in enumerate(xa.values):
            tasks.append(((i, slice(None)), lambda v=v: stability_chart(
                ltp, [v], ya.values, n_intervals=intervals, basis=basis, tol=tol)))
    elif tx is None and ty is not None:
        for i, v in enumerate(xa.values):
            add((i, slice(None)), {xa.path: v}, None, ty, np.zeros(1), ya.values)
    elif tx is not None and ty is None:
        for j, v in enumerate(ya.values):
            add((slice(None), j), {ya.path: v}, None, tx, np.zeros(1), xa.values)
    else:
        for i, v in enumerate(xa.values):
            for j, u in enumerate(ya.values):
                add((i, j), {xa.path: v, ya.path: u}, None, None, np.zeros(1), np.zeros(1))

    max_abs = np.empty((xa.values.size, ya.values.size))
    crit = np.empty(max_abs.shape, complex)
    info: dict[str, Any] = {}
    # deferred: tqdm is heavy (loaded only when this runs)
    from tqdm import tqdm

    with ThreadPoolExecutor(max_workers=max(1, int(workers))) as ex, \
            tqdm(total=len(tasks), desc="stability chart", disable=not progress,
                 file=sys.stderr, leave=False) as bar:
        futures = [(index, ex.submit(run)) for index, run in tasks]
        try:
            for index, fut in futures:
                ch = fut.result()
                max_abs[index] = ch.max_abs.ravel()
                crit[index] = ch.critical.ravel()
                info = ch.info
                bar.update()
        except BaseException:  # an error or Ctrl-C: do not wait for the remaining rows
            ex.shutdown(wait=False, cancel_futures=True)
            raise
    if not np.all(np.isfinite(max_abs)):
        raise ConvergenceError("non-finite Floquet multipliers in the stability chart")
    info = {**info, "speed_rad_s": speed, "mode_cutoff_rad_s": cutoff}
    chart = StabilityChart(xa.values, ya.values, max_abs, crit, tol,
                           (xa.name, ya.name), info)
    return ChartResult(chart, xa, ya, speed, _natural_frequencies(system, specs, speed),
                       ctx.title, ctx.config_toml)


__all__ = [
    "ChartAxis",
    "ChartResult",
    "ConfigSource",
    "axis_from_config",
    "chart_axis",
    "chart_context",
    "run_stability_chart",
]
