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
"""

from __future__ import annotations

import sys
import threading
from collections.abc import Callable, Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.linalg as sla
from numpy.typing import NDArray

from rotorsfd.errors import ConfigError
from rotorsfd.io.schema import split_path
from rotorsfd.model.base_motion import BaseMotion, BaseState, Harmonic
from rotorsfd.model.base_terms import MATRIX_NAMES, base_basis, base_coefficients
from rotorsfd.stability.chart import LTPSystem, StabilityChart, stability_chart
from rotorsfd.stability.floquet import STABILITY_TOL

if TYPE_CHECKING:
    from rotorsfd.io.schema import Config
    from rotorsfd.model.rotor import Rotor
    from rotorsfd.model.system import RotorSystem

ROTATIONS: tuple[str, ...] = ("rolling", "pitching", "yawing")
RATE_FIELDS: tuple[str, ...] = ("value", "amplitude", "angle_amplitude", "frequency", "phase")
_UNITS = {"value": "rad/s", "amplitude": "rad/s", "angle_amplitude": "rad",
          "frequency": "rad/s", "phase": "rad"}
MODE_CUTOFF: float = 3.0
MIN_MODES: int = 4
_PROBE_T = np.sqrt(2.0) * np.arange(1, 8)[:, None] / 3.7  # irrational sample times [s]


# ---------------------------------------------------------------------------------------
# base rates as functions of the chart parameters
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class RateSpec:
    """One base rotation rate: ``law`` off / constant / harmonic and its fields (SI).

    ``amplitude`` is the rate amplitude; if None (or if an axis sets the angle
    amplitude), ``angle_amplitude * frequency``.
    """

    law: str = "off"
    value: float = 0.0
    amplitude: float | None = None
    angle_amplitude: float | None = None
    frequency: float = 0.0
    phase: float = 0.0

    def law_at(self, values: dict[str, Any]) -> Harmonic:
        """The rate as a :class:`Harmonic` law whose fields may be arrays (``values``:
        field -> value overriding this spec)."""
        get = {f: values.get(f, getattr(self, f)) for f in RATE_FIELDS}
        if self.law == "off":
            return Harmonic(0.0, 0.0)
        if self.law == "constant":
            return Harmonic(0.0, 0.0, 0.0, get["value"])
        freq = get["frequency"]
        if "angle_amplitude" not in values and (self.amplitude is not None
                                                or "amplitude" in values):
            amp = get["amplitude"]
        else:
            a0 = get["angle_amplitude"]
            amp = (0.0 if a0 is None else a0) * freq
        return Harmonic(amp, freq, _or0(get["phase"]), _or0(get["value"]))


def _or0(v: Any) -> Any:
    return 0.0 if v is None else v


def rate_specs_from_config(config: Config) -> tuple[RateSpec, RateSpec, RateSpec]:
    """The three rotation rates of ``[base]``; ConfigError for a callable law."""
    out = []
    for name in ROTATIONS:
        c = getattr(config.base, name)
        if c.law == "callable":
            raise ConfigError(f"base.{name}.law", c.law, "a stability chart needs 'off', "
                              "'constant' or 'harmonic' base rates (a known period)")
        out.append(RateSpec(c.law, c.value or 0.0, c.amplitude, c.angle_amplitude,
                            c.frequency or 0.0, c.phase or 0.0))
    return tuple(out)  # type: ignore[return-value]


def rate_specs_from_motion(motion: BaseMotion | None) -> tuple[RateSpec, RateSpec, RateSpec]:
    """The three rotation rates of a :class:`BaseMotion` (harmonic laws keep their rate
    amplitude); ValueError for other laws."""
    if motion is None:
        return RateSpec(), RateSpec(), RateSpec()
    out = []
    for name, law in zip(ROTATIONS, motion.rotation, strict=True):
        if law.kind == "off":
            out.append(RateSpec())
        elif law.kind == "constant":
            out.append(RateSpec("constant", float(law.c)))
        elif law.kind == "harmonic":
            out.append(RateSpec("harmonic", law.mean, law.amplitude, None, law.frequency,
                                law.phase))
        else:
            raise ValueError(f"base {name} law {law.kind!r}: a stability chart needs off, "
                             "constant or harmonic rates")
    return tuple(out)  # type: ignore[return-value]


def coefficient_target(path: str) -> tuple[int, str] | None:
    """``(-1, 'speed')`` for ``speed``, ``(component, field)`` for a base-rate field,
    None for any other (structural) path."""
    path = path.strip()
    if path == "speed":
        return -1, "speed"
    try:
        parts = split_path(path)
    except ValueError:
        return None
    if len(parts) == 3 and parts[0] == "base" and parts[1] in ROTATIONS \
            and parts[2] in RATE_FIELDS:
        return ROTATIONS.index(str(parts[1])), str(parts[2])
    return None


@dataclass(frozen=True)
class _Params:
    """Maps the chart parameters (p1, p2) to the speed and the three rate laws."""

    specs: tuple[RateSpec, ...]
    speed: float | None
    p1: tuple[int, str] | None = None   # what p1 is (None: unused)
    p2: tuple[int, str] | None = None

    def resolve(self, p1: Any, p2: Any) -> tuple[Any, list[Harmonic]]:
        over: list[dict[str, Any]] = [{}, {}, {}]
        speed = self.speed
        for target, value in ((self.p1, p1), (self.p2, p2)):
            if target is None:
                continue
            comp, name = target
            if comp < 0:
                speed = value
            else:
                over[comp][name] = value
        return speed, [s.law_at(o) for s, o in zip(self.specs, over, strict=True)]

    def period(self, p1: Any, p2: Any) -> NDArray:
        """``2 pi / w_b`` (``2 pi / Omega`` without a harmonic rate), broadcast."""
        speed, laws = self.resolve(p1, p2)
        freqs = [np.asarray(law.frequency, float) for law, s in zip(laws, self.specs,
                                                                      strict=True)
                 if s.law == "harmonic"]
        shape = np.broadcast_shapes(np.shape(p1), np.shape(p2))
        w = np.broadcast_to(freqs[0] if freqs else np.asarray(speed, float), shape)
        return 2.0 * np.pi / w

    def coefficients(self, t: NDArray, p1: Any, p2: Any) -> tuple[NDArray, NDArray]:
        """``(c_C, c_K)`` (12, *t.shape) of the base matrices at times t."""
        speed, laws = self.resolve(p1, p2)
        shape = np.broadcast_shapes(np.shape(t), np.shape(p1), np.shape(p2))
        w = np.array([np.broadcast_to(law.value(t), shape) for law in laws])
        dw = np.array([np.broadcast_to(law.d1(t), shape) for law in laws])
        state = BaseState(w=w, dw=dw, a0=np.zeros_like(w))
        c0 = base_coefficients(state, 0.0)
        c1 = base_coefficients(state, 1.0)
        om = np.asarray(speed, float)
        return c0.c_C + om * (c1.c_C - c0.c_C), c0.c_K + om * (c1.c_K - c0.c_K)


class _CoefficientCache:
    """Per-thread cache of the last ``_Params.coefficients`` call (every term of a grid
    row asks for the same arrays)."""

    def __init__(self, params: _Params) -> None:
        self.params = params
        self.local = threading.local()

    def get(self, t: NDArray, p1: Any, p2: Any) -> tuple[NDArray, NDArray]:
        key = (t.shape, t.tobytes(), np.asarray(p1).tobytes(), np.asarray(p2).tobytes())
        if getattr(self.local, "key", None) != key:
            self.local.value = self.params.coefficients(t, p1, p2)
            self.local.key = key
        return self.local.value

    def term(self, which: int, i: int) -> Callable[[NDArray, Any, Any], NDArray]:
        return lambda t, p1, p2: self.get(np.asarray(t, float), p1, p2)[which][i]


# ---------------------------------------------------------------------------------------
# the LTP system of a rotor
# ---------------------------------------------------------------------------------------
def rotor_ltp_system(rotor: Rotor, params: _Params, p1_probe: NDArray, p2_probe: NDArray
                     ) -> LTPSystem:
    """The LTPSystem of ``rotor`` under the base rates of ``params``.

    Base terms whose coefficient is zero at every probe point (``p1_probe`` x
    ``p2_probe`` x a few times) are dropped; those constant there are folded into the
    constant matrices.
    """
    basis = base_basis(rotor)
    cache = _CoefficientCache(params)
    M = np.asarray(rotor.M, float)
    D0 = np.asarray(rotor.C, float).copy()
    K0 = np.asarray(rotor.K, float).copy()
    d_terms: list[tuple[NDArray, Any]] = []
    k_terms: list[tuple[NDArray, Any]] = []
    speed_is_axis = (params.p1 is not None and params.p1[0] < 0) or \
        (params.p2 is not None and params.p2[0] < 0)
    if speed_is_axis:
        which = 1 if params.p1 is not None and params.p1[0] < 0 else 2
        d_terms.append((np.asarray(rotor.G, float),
                        (lambda t, a, b: a + 0.0 * t) if which == 1 else
                        (lambda t, a, b: b + 0.0 * t)))
    else:
        D0 += float(params.speed) * np.asarray(rotor.G, float)
    probes = [params.coefficients(_PROBE_T, float(a), np.asarray(p2_probe)[None, :])
              for a in np.atleast_1d(p1_probe)]
    for which, (const, terms) in enumerate(((D0, d_terms), (K0, k_terms))):
        values = np.concatenate([p[which].reshape(12, -1) for p in probes], axis=1)
        for i in range(len(MATRIX_NAMES)):
            v = values[i]
            if np.all(v == 0.0):
                continue
            if np.all(v == v[0]):
                const += v[0] * basis.matrices[i]
            else:
                terms.append((basis.matrices[i], cache.term(which, i)))
    return LTPSystem(M, [(D0, None), *d_terms], [(K0, None), *k_terms], params.period)


def modal_basis(system: LTPSystem, cutoff: float, n_modes: int | None = None) -> NDArray:
    """Lowest undamped modes of (constant K, M): ``n_modes`` of them, or all below
    ``cutoff`` [rad/s] (at least MIN_MODES, degenerate partners kept together)."""
    K0 = sum((np.asarray(K) for K, c in system.K_terms if c is None), np.zeros_like(system.M))
    K0 = 0.5 * (K0 + K0.T)
    lam, V = sla.eigh(K0, 0.5 * (system.M + system.M.T))
    if n_modes is None:
        w = np.sqrt(np.abs(lam))
        n_modes = max(min(MIN_MODES, w.size), int(np.sum(w < cutoff)))
        while n_modes < w.size and abs(w[n_modes] - w[n_modes - 1]) <= 1e-6 * w[n_modes]:
            n_modes += 1
    return V[:, :n_modes]


# ---------------------------------------------------------------------------------------
# result
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class ChartAxis:
    """A chart axis: the parameter path, its values (SI) and units."""

    path: str
    values: NDArray[np.float64]
    units: str

    @property
    def name(self) -> str:
        """Dimension name (the path with '.' and brackets as '_')."""
        from rotorsfd.studies.grid import slug

        return slug(self.path)


@dataclass
class ChartResult:
    """The stability chart: ``chart.max_abs[i, j]`` at ``(x.values[i], y.values[j])``."""

    chart: StabilityChart
    x: ChartAxis
    y: ChartAxis
    speed: float | None
    natural_frequencies: NDArray[np.float64] = field(default_factory=lambda: np.zeros(0))
    title: str = ""
    config_toml: str = ""       # the resolved configuration it was run from, if any

    FILES = ("chart.nc", "chart.png")

    @property
    def stable(self) -> NDArray[np.bool_]:
        return self.chart.stable

    def to_dataset(self) -> Any:
        """xarray Dataset: max_abs_multiplier, stable, critical multiplier, axes with units,
        the base-frame natural frequencies at the chart speed (constant part)."""
        ds = self.chart.to_dataset()
        for ax in (self.x, self.y):
            ds[ax.name].attrs.update(units=ax.units, long_name=ax.path)
        ds["max_abs_multiplier"].attrs.update(units="1", long_name="max |Floquet multiplier|")
        ds["stable"].attrs.update(long_name=f"1 if max |mu| <= 1 + {self.chart.tol:g}")
        ds["natural_frequency"] = ("mode", self.natural_frequencies)
        ds["natural_frequency"].attrs.update(
            units="rad/s", long_name="damped natural frequencies of the constant part "
            "(base rates at their mean) at the chart speed")
        from rotorsfd import __version__

        ds.attrs.update(title=self.title, x=self.x.path, y=self.y.path,
                        speed_rad_s=float("nan") if self.speed is None else self.speed,
                        rotorsfd_version=__version__)
        if self.config_toml:
            ds.attrs["config_toml"] = self.config_toml
        return ds

    def plot(self, ax: Any = None) -> Any:
        """Unstable points shaded by max |mu|, stable white, the boundary max |mu| =
        1 + tol as a line (:func:`plot_chart`); returns the Axes."""
        return plot_chart(self, ax)

    def write(self, directory: str | Path) -> dict[str, Path]:
        """``chart.nc`` and ``chart.png`` written atomically into ``directory``."""
        from matplotlib.figure import Figure

        from rotorsfd.io import atomic

        out = Path(directory)
        paths = {name: out / name for name in self.FILES}
        atomic.write_netcdf(self.to_dataset(), paths["chart.nc"])
        fig = Figure(figsize=(7.4, 5.6), layout="constrained")
        self.plot(fig.add_subplot())
        atomic.save_figure(fig, paths["chart.png"], dpi=130)
        return paths

    def summary(self) -> str:
        """Points, unstable share and the largest multiplier."""
        ch = self.chart
        n_bad = int((~ch.stable).sum())
        i, j = np.unravel_index(int(np.argmax(ch.max_abs)), ch.max_abs.shape)
        return (f"stability chart {self.x.path} x {self.y.path}: {ch.max_abs.size} points, "
                f"{n_bad} unstable; max |mu| = {ch.max_abs[i, j]:.6g} at "
                f"{self.x.path} = {self.x.values[i]:.6g} {self.x.units}, "
                f"{self.y.path} = {self.y.values[j]:.6g} {self.y.units}")


# ---------------------------------------------------------------------------------------
# driver
# ---------------------------------------------------------------------------------------
def _axis_from_config(config: Config, name: str) -> ChartAxis:
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
    from rotorsfd.model.base_terms import MovingBaseRotor

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
            units = "rad/s" if t is None or t[0] < 0 else _UNITS[t[1]]
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
              else _axis_from_config(config, "x"))
        ya = (_with_units(config, y, "y") if y is not None
              else _axis_from_config(config, "y"))
        speed = sc.speed if speed is None else speed
        intervals = n_intervals or sc.intervals
        title = config.title
        # every axis value pair must make a valid configuration (ranges, law fields)
        for i in (0, -1):
            with_values(config, {a.path: float(a.values[i]) for a in (xa, ya)
                                 if a.path != "speed"})
        rotor0 = build_rotor(config)
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
        return build_rotor(with_values(config, values))

    # tasks: (index into the grid: a row, a column or a point, callable -> its chart)
    tasks: list[tuple[tuple[Any, Any], Callable[[], StabilityChart]]] = []

    def add(index: tuple[Any, Any], structural: dict[str, float], p1_t, p2_t,
            p1: NDArray, p2: NDArray) -> None:
        def run() -> StabilityChart:
            params = _Params(specs, speed, p1_t, p2_t)
            ltp = rotor_ltp_system(rotor_at(structural), params, p1, p2)
            basis = modal_basis(ltp, cutoff, n_modes)
            return stability_chart(ltp, p1, p2, n_intervals=intervals, basis=basis, tol=tol)

        tasks.append((index, run))

    if tx is not None and ty is not None:
        params = _Params(specs, speed, tx, ty)
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


def plot_chart(result: ChartResult, ax: Any = None) -> Any:
    """Figure 6 style (:func:`rotorsfd.plots.chart.chart_axes`): unstable points shaded by
    max |mu| (white: stable), the boundary max |mu| = 1 + tol in black, islands ringed, the
    axes in words with their units, the title (wrapped, never cut) saying what the grid
    shows; returns the Axes."""
    from rotorsfd.plots.chart import chart_axes

    if ax is None:
        from matplotlib.figure import Figure

        ax = Figure(figsize=(7.4, 5.6), layout="constrained").add_subplot()
    return chart_axes(ax, result.x.values, result.y.values, result.chart.max_abs,
                      x_label=f"{result.x.path} [{result.x.units}]",
                      y_label=f"{result.y.path} [{result.y.units}]", tol=result.chart.tol,
                      speed=result.speed, title=result.title or "Stability chart")


__all__ = [
    "ChartAxis",
    "ChartResult",
    "RateSpec",
    "coefficient_target",
    "modal_basis",
    "plot_chart",
    "rate_specs_from_config",
    "rate_specs_from_motion",
    "rotor_ltp_system",
    "run_stability_chart",
]
