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
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from rotorsfd.analyses.stability_chart_ltp import MODE_CUTOFF, modal_basis, rotor_ltp_system
from rotorsfd.analyses.stability_chart_rates import (
    RATE_FIELDS,
    RATE_UNITS,
    ROTATIONS,
    ChartParams,
    RateSpec,
    coefficient_target,
    rate_specs_from_config,
    rate_specs_from_motion,
)
from rotorsfd.analyses.stability_chart_result import ChartAxis, ChartResult
from rotorsfd.errors import ConfigError
from rotorsfd.model.base_motion import BaseState
from rotorsfd.stability.chart import StabilityChart, stability_chart
from rotorsfd.stability.floquet import STABILITY_TOL

if TYPE_CHECKING:
    from rotorsfd.io.schema import Config
    from rotorsfd.model.rotor import Rotor
    from rotorsfd.model.system import RotorSystem


def axis_from_config(config: Config, name: str) -> ChartAxis:
    from rotorsfd.io.schema import axis_values, resolve_kind
    from rotorsfd.io.units import KINDS

    axis = getattr(config.analysis.stability_chart, name)
    where = f"analysis.stability_chart.{name}"
    if axis is None:
        raise ConfigError(where, None, "a stability chart needs two axes x and y, e.g. "
                          "x = { parameter = 'base.pitching.frequency', start = '100 rad/s',"
                          " stop = '400 rad/s', n = 100 }")
    path = axis.parameter.strip()
    kind = "angular_velocity" if path == "speed" else resolve_kind(config, path)
    return ChartAxis(path, np.asarray(axis_values(config, axis), float), KINDS[kind].unit)


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


def _natural_frequencies(rotor: Rotor, specs: Sequence[RateSpec], speed: float | None,
                         n: int = 8) -> NDArray:
    """Damped natural frequencies [rad/s] of the rotor with the base rates at their mean."""
    if speed is None:
        return np.zeros(0)
    from rotorsfd.linear.modal import eigen
    from rotorsfd.model.base_polynomial import MovingBaseRotor

    mean = [s.value if s.law in ("constant", "harmonic") else 0.0 for s in specs]
    try:
        return np.asarray(eigen(MovingBaseRotor(rotor, BaseState.constant(w=mean)), speed,
                                n).frequencies, float)
    except Exception:
        return np.zeros(0)


def run_stability_chart(config_or_system: Config | RotorSystem, *,
                        x: tuple[str, Sequence[float]] | None = None,
                        y: tuple[str, Sequence[float]] | None = None,
                        speed: float | None = None, n_intervals: int | None = None,
                        n_modes: int | None = None, workers: int = 1,
                        tol: float = STABILITY_TOL, progress: bool = False,
                        search_path: Path | None = None) -> ChartResult:
    """Max Floquet multiplier of the linear rotor over the grid x times y.

    From a Config: axes, speed and Newmark intervals of ``[analysis.stability_chart]``
    (``x``, ``y``, ``speed``, ``n_intervals`` override them; axis values in SI). From a
    RotorSystem (its rotor and base-rate laws; film and forcing ignored): give ``x``,
    ``y`` as ``(path, values)`` with coefficient paths only, and ``speed`` unless it is an
    axis. ``n_modes``: size of the modal basis (default: see the module docstring).
    ``workers``: threads over grid rows. ``progress``: a tqdm bar on stderr.
    """
    from rotorsfd.model.system import RotorSystem

    config: Config | None = None
    where = "analysis.stability_chart"
    if isinstance(config_or_system, RotorSystem):
        system = config_or_system
        specs = rate_specs_from_motion(system.base)
        rotor0 = system.rotor
        title = ""
        if x is None or y is None:
            raise ValueError("give the axes x and y as (path, values)")
        axes = []
        for ax in (x, y):
            if coefficient_target(ax[0]) is None:
                raise ValueError(f"axis {ax[0]!r}: from a RotorSystem only 'speed' and "
                                 f"base.<rotation>.<{'|'.join(RATE_FIELDS)}> are possible")
            t = coefficient_target(ax[0])
            units = "rad/s" if t is None or t[0] < 0 else RATE_UNITS[t[1]]
            axes.append(ChartAxis(ax[0].strip(), np.asarray(ax[1], float).ravel(), units))
        xa, ya = axes
        intervals = n_intervals or 400
    else:
        from rotorsfd.io.config import with_values
        from rotorsfd.model.build import build_rotor

        config = config_or_system
        sc = config.analysis.stability_chart
        specs = rate_specs_from_config(config)
        xa = (_with_units(config, x, "x") if x is not None
              else axis_from_config(config, "x"))
        ya = (_with_units(config, y, "y") if y is not None
              else axis_from_config(config, "y"))
        speed = sc.speed if speed is None else speed
        intervals = n_intervals or sc.intervals
        title = config.title
        # every axis value pair must make a valid configuration (ranges, law fields)
        for i in (0, -1):
            with_values(config, {a.path: float(a.values[i]) for a in (xa, ya)
                                 if a.path != "speed"})
        rotor0 = build_rotor(config, search_path)
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

    def rotor_at(values: dict[str, float]) -> Rotor:
        if not values:
            return rotor0
        from rotorsfd.io.config import with_values
        from rotorsfd.model.build import build_rotor

        assert config is not None
        return build_rotor(with_values(config, values), search_path)

    # tasks: (index into the grid: a row, a column or a point, callable -> its chart)
    tasks: list[tuple[tuple[Any, Any], Callable[[], StabilityChart]]] = []

    def add(index: tuple[Any, Any], structural: dict[str, float], p1_t, p2_t,
            p1: NDArray, p2: NDArray) -> None:
        def run() -> StabilityChart:
            params = ChartParams(specs, speed, p1_t, p2_t)
            ltp = rotor_ltp_system(rotor_at(structural), params, p1, p2)
            basis = modal_basis(ltp, cutoff, n_modes)
            return stability_chart(ltp, p1, p2, n_intervals=intervals, basis=basis, tol=tol)

        tasks.append((index, run))

    if tx is not None and ty is not None:
        params = ChartParams(specs, speed, tx, ty)
        ltp = rotor_ltp_system(rotor0, params, xa.values, ya.values)
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
        from rotorsfd.errors import ConvergenceError

        raise ConvergenceError("non-finite Floquet multipliers in the stability chart")
    info = {**info, "speed_rad_s": speed, "mode_cutoff_rad_s": cutoff}
    chart = StabilityChart(xa.values, ya.values, max_abs, crit, tol,
                           (xa.name, ya.name), info)
    config_toml = ""
    if not isinstance(config_or_system, RotorSystem):
        from rotorsfd.io.config import show_config

        config_toml = show_config(config_or_system)
    return ChartResult(chart, xa, ya, speed,
                       _natural_frequencies(rotor0, specs, speed), title, config_toml)


def _with_units(config: Config, axis: tuple[str, Sequence[float]], name: str) -> ChartAxis:
    """A ChartAxis from ``(path, SI values)`` with the units of the field at path."""
    from rotorsfd.io.schema import resolve_kind
    from rotorsfd.io.units import KINDS

    path = axis[0].strip()
    try:
        kind = "angular_velocity" if path == "speed" else resolve_kind(config, path)
    except KeyError as exc:
        raise ConfigError(f"analysis.stability_chart.{name}.parameter", path,
                          exc.args[0]) from None
    return ChartAxis(path, np.asarray(axis[1], float).ravel(), KINDS[kind].unit)


__all__ = [
    "ChartAxis",
    "ChartResult",
    "axis_from_config",
    "run_stability_chart",
]
