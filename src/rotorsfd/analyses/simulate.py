"""Time-domain simulation of the rotor-SFD system at one speed (paper section 4.3, Fig. 23).

``run_simulation(config_or_system, speed) -> SimulationResult`` integrates

    M q'' + (C + Omega G + C_base(t)) q' + (K + K_base(t)) q = F_mu(t) + F_base(t) + F_sfd

with :func:`rotorsfd.timedomain.integrate` machinery, in chunks of rotor periods (exact
continuation of the compiled loop). A constant base gives constant matrices, the constant
load ``F_base`` (gravity through the base state) and the unbalance harmonics; a harmonic or
callable base gives ``TimeVaryingMatrices`` and series loads from
:func:`~rotorsfd.model.base_terms.time_varying_terms` and
:func:`~rotorsfd.model.unbalance.unbalance_series` (coefficients that stay constant over the
run are folded into the constant matrices). The step is ``T / steps_per_period`` with
``T = 2 pi / Omega``; Poincare points are taken once per rotor period at ``t = k T``.

Initial state: every node displaced by ``initial_displacement`` in y and z (translations
only, rotations and velocities zero; the paper's "every node displaced 1 um"), or the HB
periodic solution at that speed (``from_hb``): ``q(0) = Re sum X_k``,
``v(0) = Re sum i k Omega X_k``; with ``hb_phase = p`` the state of that orbit a fraction
p of the period later, ``X_k exp(i k 2 pi p)``, put at t = 0 (off the orbit unless it is
symmetric: a way to land on a coexisting attractor); or the final state of a previous run
(``initial_state``: its ``timeseries.nc`` or directory, :func:`load_state`).
``timeseries.nc`` stores the final state of every DOF (``final_displacement``,
``final_velocity``) with its time ``t_final_s`` and the rotor phase ``Omega t mod 2 pi``.
A run from a saved state at the same speed continues it exactly (t0 = the saved time);
at another speed it starts at the time where the new rotor phase equals the saved one
(constant base), so the unbalance force has no phase jump.
"""

from __future__ import annotations

import dataclasses
import math
import sys
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np

from rotorsfd.errors import ConfigError, ConvergenceError, JournalContactError
from rotorsfd.model import dofs
from rotorsfd.model.system import RotorSystem
from rotorsfd.timedomain import (
    Forcing,
    HarmonicLoad,
    LyapunovResult,
    MotionClass,
    TimeVaryingMatrices,
    amplitude_spectrum,
    classify_motion,
    largest_lyapunov,
)
from rotorsfd.timedomain import newmark as nm
from rotorsfd.timedomain.integrate import _MESSAGES, initial_state, prepare, run

if TYPE_CHECKING:
    import xarray as xr
    from matplotlib.figure import Figure

    from rotorsfd.io.schema import Config

FIELD = "analysis.simulate"
DIRECTIONS = ("y", "z")


# ---- inputs of the integrator ------------------------------------------------------------


@dataclass
class TimeDomainInputs:
    """Everything :func:`rotorsfd.timedomain.integrate` takes, for one rotor speed."""

    M: np.ndarray
    D: np.ndarray
    K: np.ndarray
    nl_dofs: np.ndarray
    kernel: Any
    params: np.ndarray | None
    forcing: Forcing
    time_varying: TimeVaryingMatrices | None
    speed: float

    @property
    def period(self) -> float:
        """Rotor period T = 2 pi / Omega [s]."""
        return 2.0 * math.pi / self.speed


def _fold_constant(pairs: Sequence[tuple[Any, np.ndarray]], probe: np.ndarray
                   ) -> tuple[list[tuple[Any, np.ndarray]], np.ndarray | None]:
    """Split ``(coefficient, array)`` pairs into time-varying ones and the sum of those
    whose coefficient is constant on ``probe`` (that sum, or None)."""
    varying: list[tuple[Any, np.ndarray]] = []
    const = None
    for c, X in pairs:
        values = np.broadcast_to(np.asarray(c(probe), dtype=float), probe.shape)
        if np.ptp(values) == 0.0:
            term = float(values[0]) * np.asarray(X, dtype=float)
            const = term if const is None else const + term
        else:
            varying.append((c, X))
    return varying, const


def time_domain_inputs(system: RotorSystem, speed: float, *,
                       horizon: float | None = None) -> TimeDomainInputs:
    """Integrator inputs of ``system`` at rotor speed ``speed`` [rad/s].

    Constant base (``system.base.is_constant``): ``matrices(speed)``, the constant force
    ``static_force(speed)`` and the unbalance harmonics at ``Omega``. Otherwise
    ``M, C + Omega G, K`` plus the base terms as time-varying matrices and series loads;
    ``horizon`` [s] (default 1000 rotor periods) is the interval on which a coefficient
    must be constant to be folded into the constant matrices.
    """
    if not speed > 0.0:
        raise ConfigError(f"{FIELD}.speed", speed, "the rotor speed must be > 0 rad/s")
    r = system.rotor
    nl = system.nl_dofs
    kernel = system.sfd.numba_kernel if system.sfd is not None else None
    params = system.sfd.kernel_params if system.sfd is not None else None
    if system.base.is_constant:
        M, D, K = system.matrices(speed)
        Fc, Fs = system.unbalance_harmonics(speed)
        harm = [HarmonicLoad(1.0, Fc, Fs)] if system.unbalances else []
        forcing = Forcing(omega=speed, constant=system.static_force(speed), harmonics=harm)
        return TimeDomainInputs(M, D.copy(), K.copy(), nl, kernel, params, forcing, None,
                                float(speed))
    from rotorsfd.model.base_terms import time_varying_terms
    from rotorsfd.model.unbalance import unbalance_series

    T = 2.0 * math.pi / speed
    span = horizon if horizon is not None else 1000.0 * T
    probe = np.concatenate([np.linspace(0.0, span, 257),
                            span * (np.arange(1, 64) * math.sqrt(2.0) % 1.0)])
    damping, stiffness, force = time_varying_terms(system.basis, system.base, speed)
    damping, dC = _fold_constant(damping, probe)
    stiffness, dK = _fold_constant(stiffness, probe)
    force, f0 = _fold_constant(force, probe)
    D = r.C + speed * r.G + (dC if dC is not None else 0.0)
    K = r.K + (dK if dK is not None else 0.0)
    series = list(force) + unbalance_series(system.unbalances, r, speed, system.base)
    forcing = Forcing(omega=speed, constant=f0, series=series)
    tv = TimeVaryingMatrices(damping=damping, stiffness=stiffness) \
        if damping or stiffness else None
    return TimeDomainInputs(r.M, np.asarray(D, float), np.asarray(K, float), nl, kernel,
                            params, forcing, tv, float(speed))


def scheme_options(scheme: str, alpha: float) -> dict[str, Any]:
    """``integrate`` keywords of ``[analysis.simulate] scheme, alpha``: HHT ``alpha``
    (either sign convention: |alpha| <= 1/3), generalized-alpha ``rho_inf = alpha``."""
    if scheme == "newmark":
        return {"method": "newmark"}
    if scheme == "hht":
        a = abs(float(alpha))
        if a > 1.0 / 3.0:
            raise ConfigError(f"{FIELD}.alpha", alpha, "HHT needs |alpha| <= 1/3")
        return {"method": "hht", "alpha": a}
    if scheme == "generalized-alpha":
        if not 0.0 <= alpha <= 1.0:
            raise ConfigError(f"{FIELD}.alpha", alpha, "generalized-alpha takes the "
                              "spectral radius rho_inf = alpha in [0, 1]")
        return {"method": "generalized-alpha", "rho_inf": float(alpha)}
    raise ConfigError(f"{FIELD}.scheme", scheme, "newmark, hht or generalized-alpha")


def displaced_state(n_dof: int, displacement: float) -> np.ndarray:
    """``q0`` with every node's y and z displaced by ``displacement`` (rotations zero)."""
    q0 = np.zeros(n_dof)
    q0[0::4] = q0[1::4] = displacement
    return q0


def hb_state(X: np.ndarray, speed: float) -> tuple[np.ndarray, np.ndarray]:
    """``(q(0), v(0))`` of ``q(t) = Re sum_k X_k exp(i k Omega t)``, X (H+1, n_dof)."""
    k = np.arange(X.shape[0])[:, None]
    return X.sum(axis=0).real.copy(), (1j * k * speed * X).sum(axis=0).real.copy()


def shift_phase(X: np.ndarray, phase: float) -> np.ndarray:
    """Coefficients of ``q(t + phase T)``: ``X_k exp(i k 2 pi phase)``, X (H+1, ...)."""
    k = np.arange(X.shape[0]).reshape((-1,) + (1,) * (X.ndim - 1))
    return X * np.exp(2j * math.pi * k * float(phase))


def hb_start(system: RotorSystem, speed: float, harmonics: int = 3,
             n_samples: int | None = None, phase: float = 0.0
             ) -> tuple[np.ndarray, np.ndarray]:
    """Initial state on the HB periodic solution at ``speed`` (constant base only), taken
    a fraction ``phase`` of the period later (:func:`shift_phase`).

    Newton from the linearised response; if that fails (strongly nonlinear points), the
    branch is continued from ``speed / 2`` and its first arrival at ``speed`` taken.
    """
    from rotorsfd.harmonic.periodic import continue_periodic, solve_periodic

    problem = system.periodic_problem()
    try:
        sol = solve_periodic(problem, speed, harmonics, n_samples=n_samples)
        return hb_state(shift_phase(sol.X, phase), speed)
    except ConvergenceError as first:
        branch = continue_periodic(problem, 0.5 * speed, speed, harmonics,
                                   n_samples=n_samples, limit_max=0.999)
        if not (branch.n_points and abs(branch.lam[-1] - speed) <= 1e-9 * speed):
            raise ConvergenceError(
                f"HB start at {speed:.6g} rad/s: {' '.join(str(first).split())}; "
                f"continuation from {0.5 * speed:.6g} rad/s: {branch.message}") from None
        return hb_state(shift_phase(branch.X[-1], phase), speed)


@dataclass(frozen=True)
class SavedState:
    """The final state of a run (``timeseries.nc``): every DOF's displacement ``q`` [m]
    and velocity ``v`` [m/s] at time ``t`` [s], rotor speed ``speed`` [rad/s]."""

    q: np.ndarray
    v: np.ndarray
    t: float
    speed: float
    source: str = ""

    @property
    def phase(self) -> float:
        """Rotor phase ``Omega t mod 2 pi`` at the saved time [rad]."""
        return float(math.fmod(self.speed * self.t, 2.0 * math.pi))

    def start_time(self, speed: float) -> float:
        """Start time of a run at ``speed`` from this state: the saved time at the same
        speed (exact continuation), else the time where ``speed * t`` is the saved phase."""
        if abs(speed - self.speed) <= 1e-12 * self.speed:
            return self.t
        return self.phase / speed


def timeseries_path(path: str | Path) -> Path:
    """``path`` itself, or ``path/timeseries.nc`` for a directory."""
    p = Path(path)
    return p / "timeseries.nc" if p.is_dir() else p


def load_state(path: str | Path) -> SavedState:
    """The final state stored in a ``timeseries.nc`` (or a directory holding one)."""
    import xarray as xr

    p = timeseries_path(path)
    if not p.is_file():
        raise ConfigError("initial_state", str(path), "no such file (give a simulate "
                          "output directory or its timeseries.nc)")
    with xr.open_dataset(p) as ds:
        if "final_displacement" not in ds or "t_final_s" not in ds.attrs:
            raise ConfigError("initial_state", str(path), "this timeseries.nc has no final "
                              "state (written by an older rotorsfd): run it again")
        return SavedState(np.asarray(ds["final_displacement"].values, float),
                          np.asarray(ds["final_velocity"].values, float),
                          float(ds.attrs["t_final_s"]), float(ds.attrs["speed_rad_s"]),
                          str(p))


# ---- chunked integration ---------------------------------------------------------------------


@dataclass
class Trajectory:
    """Samples of a chunked run: every step of the last ``record_periods`` and the
    Poincare points of the last ``poincare_periods`` (columns = ``dofs``)."""

    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    poincare_t: np.ndarray
    poincare_q: np.ndarray
    poincare_v: np.ndarray
    dofs: np.ndarray
    q_final: np.ndarray
    v_final: np.ndarray
    t_final: float
    max_eccentricity_run: float | None
    newton_iterations_max: int = 0
    snapshot: tuple[np.ndarray, np.ndarray, float] | None = None


def integrate_periods(inputs: TimeDomainInputs, q0: Any, v0: Any, *, steps_per_period: int,
                      periods: int, record_dofs: Sequence[int], record_periods: int,
                      poincare_periods: int, method_options: dict[str, Any] | None = None,
                      chunk_periods: int | None = None, progress: Any = None,
                      clearance: float | None = None, t0: float = 0.0,
                      snapshot_period: int | None = None) -> Trajectory:
    """Integrate ``periods`` rotor periods in chunks from ``(q0, v0)`` at ``t0``.

    ``snapshot_period`` (0 < p < periods): a chunk ends after p periods and the full state
    there is kept (``Trajectory.snapshot = (q, v, t)``, the start of the step check).

    ``progress(periods_done)`` is called after each chunk. Contact raises
    :class:`JournalContactError` (time, rotor period, eccentricity in the message); other
    failures :class:`ConvergenceError`.
    """
    spp = int(steps_per_period)
    n_steps = spp * int(periods)
    dt = inputs.period / spp
    ps = prepare(inputs.M, inputs.D, inputs.K, inputs.nl_dofs, inputs.kernel, inputs.params,
                 inputs.forcing, dt, n_steps, t0=t0, time_varying=inputs.time_varying,
                 **(method_options or {}))
    nl = ps.nl
    rd = np.asarray(record_dofs, dtype=np.int64)
    rec_all = np.concatenate([rd, nl]).astype(np.int64)
    rec_start = (periods - record_periods) * spp
    pc_start = (periods - poincare_periods + 1) * spp
    state = initial_state(ps, q0, v0)
    chunk = max(1, chunk_periods or math.ceil(periods / 100))
    parts: dict[str, list[np.ndarray]] = {k: [] for k in ("t", "q", "v", "pt", "pq", "pv")}
    eps_max = 0.0
    newton_max = 0
    done = 0
    snapshot = None
    snap = snapshot_period if snapshot_period and 0 < snapshot_period < periods else None
    while done < periods:
        k = min(chunk, periods - done)
        if snap is not None and done < snap:
            k = min(k, snap - done)
        status, smp, info = run(ps, state, k * spp, record_dofs=rec_all, record_every=1,
                                record_start=0, poincare_every=spp, poincare_start=0,
                                record_initial=(done == 0))
        newton_max = max(newton_max, int(info[nm.I_NEWTON_MAX]))
        if nl.size and clearance and smp["q"].shape[0]:
            qn = smp["q"][:, rd.size:rd.size + 2]
            eps_max = max(eps_max, float(np.max(np.hypot(qn[:, 0], qn[:, 1]))) / clearance)
        if status != nm.OK:
            step = int(info[nm.I_STEP]) + 1
            t = ps.t0 + step * dt
            where = (f"t={t:.6g} s, rotor period {step / spp:.2f} of {periods} "
                     f"(step {step})")
            if status == nm.CONTACT:
                y, z, vy, vz = (float(x) for x in smp["fail"][:4])  # q_nl (y, z), v_nl
                eps = math.hypot(y, z) / clearance if clearance else math.nan
                where += (": the step's Newton iterates reached the contact limit (state "
                          "of the last iterate)")
                err = JournalContactError(eps, y, z, vy, vz, where=where)
                err.time, err.period = t, step / spp
                raise err
            raise ConvergenceError(f"time integration: {_MESSAGES.get(status)} at {where}")
        keep = smp["t"] >= ps.t0 + (rec_start - 0.5) * dt
        parts["t"].append(smp["t"][keep])
        parts["q"].append(smp["q"][keep, :rd.size])
        parts["v"].append(smp["v"][keep, :rd.size])
        keep = smp["pt"] >= ps.t0 + (pc_start - 0.5) * dt
        parts["pt"].append(smp["pt"][keep])
        parts["pq"].append(smp["pq"][keep, :rd.size])
        parts["pv"].append(smp["pv"][keep, :rd.size])
        done += k
        if done == snap:
            snapshot = (state.X[:ps.n_dof].copy(), state.X[ps.n_dof:2 * ps.n_dof].copy(),
                        ps.t0 + state.step * dt)
        if progress is not None:
            progress(done)
    n = ps.n_dof
    cat = {k: np.concatenate(v) for k, v in parts.items()}
    return Trajectory(cat["t"], cat["q"], cat["v"], cat["pt"], cat["pq"], cat["pv"], rd,
                      state.X[:n].copy(), state.X[n:2 * n].copy(), ps.t0 + state.step * dt,
                      eps_max if nl.size and clearance else None, newton_max, snapshot)


# ---- time-step check ----------------------------------------------------------------------

STEP_CHECK_TOLERANCE = 1e-2
"""Warn when halving the step moves the checked orbit by more than this (units of C, or of
the orbit's max radius without an SFD)."""


@dataclass(frozen=True)
class StepCheck:
    """The last ``periods`` of a run integrated again from the same state at twice the
    steps per period (``steps_per_period = (base, fine)``), node ``node``.

    Periodic (settled period-n) motion: the headline ``difference`` is the larger of the
    final-period orbit difference (max over the period of the distance between the two
    orbits at equal times) and the Poincare point difference (last ``n_poincare`` points).
    Other motion (trajectories diverge): the orbit envelope, the larger change of the max
    and min radius over the ``periods``. Lengths in ``unit``: C, or the max orbit radius
    without an SFD. ``error``: the fine run failed (contact, Newton)."""

    steps_per_period: tuple[int, int]
    periods: int
    node: int
    compared: str
    difference: float | None
    orbit_difference: float | None
    poincare_difference: float | None
    envelope_difference: float | None
    n_poincare: int
    unit: str
    tolerance: float = STEP_CHECK_TOLERANCE
    error: str | None = None
    elapsed: float = 0.0

    @property
    def coarse(self) -> bool:
        """The base step looks too coarse (difference above the tolerance, or the fine run
        failed)."""
        return self.error is not None or (self.difference is not None
                                          and self.difference > self.tolerance)

    def as_dict(self) -> dict[str, Any]:
        return {"steps_per_period": list(self.steps_per_period), "periods": self.periods,
                "node": self.node, "compared": self.compared,
                "difference": self.difference, "unit": self.unit,
                "orbit_difference": self.orbit_difference,
                "poincare_difference": self.poincare_difference,
                "poincare_points": self.n_poincare,
                "envelope_difference": self.envelope_difference,
                "tolerance": self.tolerance, "too_coarse": self.coarse,
                "warning": self.warning(), "error": self.error, "elapsed_s": self.elapsed}

    def line(self) -> str:
        a, b = self.steps_per_period
        head = f"step check (T/{a} vs T/{b}, last {self.periods} periods, node {self.node})"
        if self.error is not None:
            return f"{head}: the run at T/{b} failed: {self.error}"
        return f"{head}: {self.compared} moves by {self.difference:.3g} {self.unit}"

    def warning(self) -> str | None:
        if not self.coarse:
            return None
        a, b = self.steps_per_period
        if self.error is not None:
            return (f"time step T/{a} may be too coarse here: the run at T/{b} from the same "
                    "state failed; raise analysis.simulate.steps_per_period")
        return (f"time step T/{a} may be too coarse here: halving it moves the orbit by "
                f"{self.difference:.3g} {self.unit}; raise "
                "analysis.simulate.steps_per_period")


def step_check(inputs: TimeDomainInputs, start: tuple[np.ndarray, np.ndarray, float], *,
               periods: int, steps_per_period: int, node: int, t: np.ndarray,
               q: np.ndarray, poincare_q: np.ndarray, periodic: bool,
               method_options: dict[str, Any] | None = None,
               clearance: float | None = None) -> StepCheck:
    """Integrate ``periods`` periods from ``start = (q, v, t)`` at ``2 steps_per_period``
    and compare ``node`` with the base run's samples of it: ``t, q`` (every step of the
    recorded periods, (n_t, 2) y, z, ending at the final time) and ``poincare_q`` (n, 2).
    ``periodic``: compare orbits and Poincare points, else the orbit envelope."""
    tic = time.perf_counter()
    spp = int(steps_per_period)
    fine = 2 * spp
    rd = [dofs.dof_index(node, d) for d in DIRECTIONS]
    r = np.hypot(q[:, 0], q[:, 1])
    n_env = min(periods, (q.shape[0] - 1) // spp)
    base_env = r[-(n_env * spp + 1):]
    scale, unit = (clearance, "C") if clearance else (float(np.max(base_env)) or 1.0,
                                                      "x max orbit radius")
    n_pc = min(periods, poincare_q.shape[0])
    what = (f"final-period orbit and last {n_pc} Poincare points" if periodic else
            f"orbit envelope (max and min radius over {n_env} periods; the motion is not "
            "periodic, its trajectories diverge)")
    common = {"steps_per_period": (spp, fine), "periods": periods, "node": node,
              "compared": what, "n_poincare": n_pc, "unit": unit}
    try:
        tr = integrate_periods(inputs, start[0], start[1], steps_per_period=fine,
                               periods=periods, record_dofs=rd, record_periods=n_env,
                               poincare_periods=n_pc, method_options=method_options,
                               clearance=clearance, t0=start[2])
    except (JournalContactError, ConvergenceError) as exc:
        return StepCheck(**common, difference=None, orbit_difference=None,
                         poincare_difference=None, envelope_difference=None,
                         error=" ".join(str(exc).split()),
                         elapsed=time.perf_counter() - tic)
    fq = tr.q[::2]                                   # the base run's times
    if not np.allclose(tr.t[::2][-(spp + 1):], t[-(spp + 1):], rtol=0.0,
                       atol=1e-6 * inputs.period):
        raise AssertionError("step check: the two runs' sample times differ")
    orbit = float(np.max(np.hypot(*(fq[-(spp + 1):] - q[-(spp + 1):]).T))) / scale
    pc = float(np.max(np.hypot(*(tr.poincare_q[-n_pc:] - poincare_q[-n_pc:]).T))) / scale
    fr = np.hypot(fq[:, 0], fq[:, 1])[-(n_env * spp + 1):]
    env = max(abs(float(np.max(fr) - np.max(base_env))),
              abs(float(np.min(fr) - np.min(base_env)))) / scale
    return StepCheck(**common, difference=max(orbit, pc) if periodic else env,
                     orbit_difference=orbit, poincare_difference=pc, envelope_difference=env,
                     elapsed=time.perf_counter() - tic)


# ---- the result --------------------------------------------------------------------------


def _plain(obj: Any) -> Any:
    """JSON-safe copy: numpy scalars/arrays to Python, NaN/inf to None, tuples to lists."""
    if isinstance(obj, dict):
        return {str(k): _plain(v) for k, v in obj.items()}
    if isinstance(obj, list | tuple):
        return [_plain(v) for v in obj]
    if isinstance(obj, np.ndarray):
        return _plain(obj.tolist())
    if isinstance(obj, np.bool_ | bool):
        return bool(obj)
    if isinstance(obj, np.integer | int):
        return int(obj)
    if isinstance(obj, np.floating | float):
        return float(obj) if math.isfinite(obj) else None
    return obj if obj is None or isinstance(obj, str) else str(obj)


@dataclass
class SimulationResult:
    """A simulation at one speed: recorded motion of ``nodes`` (``q, v``: (n_t, n_nodes,
    2) with directions y, z, every step of the last max(record, Poincare) periods), the
    Poincare points, the motion class and its evidence."""

    speed: float
    reference_speed: float | None
    nodes: tuple[int, ...]
    t: np.ndarray
    q: np.ndarray
    v: np.ndarray
    poincare_t: np.ndarray
    poincare_q: np.ndarray
    poincare_v: np.ndarray
    motion: MotionClass | None
    lyapunov: LyapunovResult | None
    clearance: float | None
    sfd_node: int | None
    settings: dict[str, Any]
    max_eccentricity: float | None
    max_eccentricity_run: float | None
    q_final: np.ndarray
    v_final: np.ndarray
    t_final: float
    elapsed: float
    title: str = ""
    notes: list[str] = field(default_factory=list)
    step_check: StepCheck | None = None

    FILES = ("timeseries.nc", "poincare.csv", "summary.json", "simulation.png", "orbit.png",
             "phase.png", "poincare.png", "spectrum.png")

    @property
    def period(self) -> float:
        """Rotor period T [s]."""
        return 2.0 * math.pi / self.speed

    @property
    def speed_ratio(self) -> float | None:
        return None if not self.reference_speed else self.speed / self.reference_speed

    @property
    def motion_name(self) -> str:
        return self.motion.motion if self.motion is not None else "unclassified"

    @property
    def plot_node(self) -> int:
        """The SFD journal if recorded, else the first output node."""
        return self.sfd_node if self.sfd_node in self.nodes else self.nodes[0]

    def column(self, node: int) -> int:
        return self.nodes.index(node)

    def spectrum(self, node: int | None = None, direction: str = "y"
                 ) -> tuple[np.ndarray, np.ndarray]:
        """(frequency / Omega, amplitude [m]) of the recorded ``node, direction`` over a
        whole number of periods (Blackman-Harris window, mean removed)."""
        j = self.column(self.plot_node if node is None else node)
        x = self.q[:, j, DIRECTIONS.index(direction)]
        spp = int(self.settings["steps_per_period"])
        n = (x.size - 1) // spp * spp if x.size > spp else x.size
        freq, amp = amplitude_spectrum(x[:n], self.period / spp, detrend=True)
        return freq / self.speed, amp

    # ---- files ---------------------------------------------------------------------------
    def to_dataset(self) -> xr.Dataset:
        """``timeseries.nc`` layout: ``displacement`` [m], ``velocity`` [m/s] over
        (time, node, direction) for the last ``record_periods`` (every step, both ends);
        ``period`` = t / T along time."""
        import xarray as xr

        from rotorsfd import __version__

        keep = int(self.settings["record_periods"]) * int(self.settings["steps_per_period"])
        sl = slice(max(0, self.t.size - keep - 1), None)
        t = self.t[sl]
        coords = {"time": ("time", t, {"units": "s"}),
                  "node": ("node", np.asarray(self.nodes, dtype=np.int32)),
                  "direction": ("direction", list(DIRECTIONS)),
                  "period": ("time", t / self.period, {"units": "rotor periods"})}
        attrs = {"title": self.title, "speed_rad_s": self.speed, "motion": self.motion_name,
                 "rotorsfd_version": __version__}
        if self.speed_ratio is not None:
            attrs["speed_ratio"] = self.speed_ratio
        if self.clearance is not None:
            attrs["clearance_m"] = self.clearance
            attrs["sfd_node"] = int(self.sfd_node)
        attrs["t_final_s"] = float(self.t_final)
        attrs["final_phase_rad"] = float(math.fmod(self.speed * self.t_final, 2 * math.pi))
        attrs["initial_state"] = str(self.settings.get("initial_state", ""))
        coords["dof"] = ("dof", np.arange(self.q_final.size, dtype=np.int32),
                         {"description": "global DOF index: 4 (node - 1) + (y, z, ty, tz)"})
        return xr.Dataset(
            {"displacement": (("time", "node", "direction"), self.q[sl], {"units": "m"}),
             "velocity": (("time", "node", "direction"), self.v[sl], {"units": "m/s"}),
             "final_displacement": ("dof", self.q_final, {
                 "units": "m or rad", "description": "every DOF at t_final_s (a start "
                 "state for rotorsfd simulate --initial-state)"}),
             "final_velocity": ("dof", self.v_final, {"units": "m/s or rad/s"})},
            coords=coords, attrs=attrs)

    def poincare_table(self) -> dict[str, np.ndarray]:
        """Columns of ``poincare.csv``: ``node, period, y, z, vy, vz`` (one row per node and
        rotor period; ``period`` = t / T, an integer; SI: m, m/s)."""
        n_p, n_n = self.poincare_t.size, len(self.nodes)
        per = np.rint(self.poincare_t / self.period).astype(np.int64)
        return {"node": np.repeat(np.asarray(self.nodes, dtype=np.int64)[None, :], n_p,
                                  axis=0).T.ravel(),
                "period": np.tile(per, n_n),
                "y": self.poincare_q[:, :, 0].T.ravel(),
                "z": self.poincare_q[:, :, 1].T.ravel(),
                "vy": self.poincare_v[:, :, 0].T.ravel(),
                "vz": self.poincare_v[:, :, 1].T.ravel()}

    def summary_dict(self) -> dict[str, Any]:
        """Content of ``summary.json``."""
        ev = dict(self.motion.evidence) if self.motion is not None else {}
        lines = ev.pop("spectral_lines", None)
        if lines is not None:
            ev["spectral_lines"] = [{"frequency_rad_s": f, "amplitude_m": a, "ratio": r}
                                    for f, a, r in lines]
        ly = self.lyapunov
        return _plain({
            "motion": self.motion_name,
            "speed_rad_s": self.speed, "speed_ratio": self.speed_ratio,
            "evidence": ev,
            "lyapunov": None if ly is None else {
                "exponent_per_s": ly.exponent, "per_period": ly.per_period,
                "half_spread_per_s": ly.half_spread, "d0": ly.d0,
                "renorm_every_steps": ly.renorm_every, "periods": self.settings.get(
                    "lyapunov_periods")},
            "max_eccentricity": self.max_eccentricity,
            "max_eccentricity_whole_run": self.max_eccentricity_run,
            "clearance_m": self.clearance, "sfd_node": self.sfd_node,
            "nodes": list(self.nodes), "settings": self.settings,
            "elapsed_s": self.elapsed, "t_final_s": self.t_final, "notes": self.notes,
            "step_check": None if self.step_check is None else self.step_check.as_dict(),
            "title": self.title})

    def write(self, directory: str | Path, plots: bool = True) -> dict[str, Path]:
        """Write ``timeseries.nc``, ``poincare.csv``, ``summary.json`` and the plots
        atomically (nothing is written if a value is not finite)."""
        from rotorsfd.io import atomic
        from rotorsfd.io.branch_files import check_finite, write_table

        ds = self.to_dataset()
        check_finite(ds)
        out = Path(directory)
        paths = {"timeseries.nc": atomic.write_netcdf(ds, out / "timeseries.nc"),
                 "poincare.csv": write_table(out / "poincare.csv", self.poincare_table()),
                 "summary.json": atomic.write_json(out / "summary.json", self.summary_dict())}
        if plots:
            for name, fig in self.plot().items():
                paths[name] = atomic.save_figure(fig, out / name, dpi=120)
        return paths

    # ---- plots and text ----------------------------------------------------------------------
    def plot(self, node: int | None = None) -> dict[str, Figure]:
        """Figures by file name: ``simulation.png`` (four panels like the paper's Fig. 23)
        and ``orbit.png``, ``phase.png``, ``poincare.png``, ``spectrum.png``."""
        from rotorsfd.plots.timedomain import simulation_figures

        node = self.plot_node if node is None else node
        j = self.column(node)
        ratio, amp = self.spectrum(node, "y")
        scale = self.clearance if self.clearance else 1.0
        title = (f"node {node}, Omega = {self.speed:.5g} rad/s"
                 + (f" (Omega~ = {self.speed_ratio:.4g})" if self.speed_ratio else "")
                 + f": {self.motion_name}" + (f" -- {self.title}" if self.title else ""))
        return simulation_figures(
            y=self.q[:, j, 0] / scale, z=self.q[:, j, 1] / scale,
            vy=self.v[:, j, 0] / (scale * self.speed),
            py=self.poincare_q[:, j, 0] / scale, pz=self.poincare_q[:, j, 1] / scale,
            pvy=self.poincare_v[:, j, 0] / (scale * self.speed),
            frequency_ratio=ratio, amplitude=amp / scale,
            clearance_circle=self.clearance is not None and node == self.sfd_node,
            unit="C" if self.clearance else "m", title=title)

    def summary(self) -> str:
        """A few lines: motion, evidence, eccentricity, time."""
        ev = self.motion.evidence if self.motion is not None else {}
        sr = f" (Omega~ = {self.speed_ratio:.5g})" if self.speed_ratio else ""
        lines = [f"speed {self.speed:.6g} rad/s{sr}: {self.motion_name}"
                 + (f" ({ev.get('basis')})" if ev.get("basis") else "")]
        if ev:
            ratios = ", ".join(f"{r:.4g}" for r in ev.get("frequency_ratios", [])[:8])
            lines.append(f"distinct Poincare points: {ev.get('n_distinct_poincare')} of "
                         f"{ev.get('n_poincare')}; spectral lines / Omega: {ratios}")
        if self.lyapunov is not None:
            lines.append(f"largest Lyapunov exponent: {self.lyapunov.exponent:.4g} 1/s "
                         f"({self.lyapunov.per_period:.4g} per period)")
        if self.max_eccentricity is not None:
            lines.append(f"max eccentricity ratio: {self.max_eccentricity:.4f} (recorded "
                         f"periods), {self.max_eccentricity_run:.4f} (whole run)")
        lines.append(f"{self.settings['periods']} periods x {self.settings['steps_per_period']}"
                     f" steps ({self.settings['scheme']}) in {self.elapsed:.2f} s")
        if self.step_check is not None:
            lines.append(self.step_check.line())
        if ev.get("note"):
            lines.append(f"note: {ev['note']}")
        lines += [f"note: {n}" for n in self.notes]
        warning = self.step_check.warning() if self.step_check is not None else None
        if warning:
            lines.append(f"warning: {warning}")
        return "\n".join(lines)


# ---- running ------------------------------------------------------------------------------


def system_from_config(config: Config, search_path: Path | None = None) -> RotorSystem:
    """The :class:`RotorSystem` of a configuration."""
    from rotorsfd.model.build import build_model

    m = build_model(config, search_path)
    return RotorSystem(m.rotor, m.sfd, m.sfd_node, m.unbalances, m.base_motion)


def _default_nodes(system: RotorSystem) -> tuple[int, ...]:
    nodes = {d.node for d in system.rotor.disks}
    if system.sfd_node is not None:
        nodes.add(system.sfd_node)
    return tuple(sorted(nodes)) or (1,)


def _progress_bar(enabled: bool, total: int, desc: str) -> Any:
    from tqdm import tqdm

    return tqdm(total=total, desc=desc, disable=not enabled, file=sys.stderr,
                dynamic_ncols=True, leave=False, unit="period")


def run_simulation(config_or_system: Config | RotorSystem, speed: float | None = None, *,
                   speed_ratio: float | None = None, search_path: Path | None = None,
                   reference_speed: float | None = None, scheme: str | None = None,
                   alpha: float | None = None, steps_per_period: int | None = None,
                   periods: int | None = None, poincare_periods: int | None = None,
                   record_periods: int | None = None, lyapunov_periods: int | None = None,
                   initial_displacement: float | None = None, from_hb: bool = False,
                   hb_phase: float = 0.0, initial_state: str | Path | SavedState | None = None,
                   harmonics: int | None = None, q0: Any = None, v0: Any = None,
                   nodes: Sequence[int] | None = None, chunk_periods: int | None = None,
                   progress: bool = True, title: str | None = None,
                   step_check_periods: int | None = None) -> SimulationResult:
    """Integrate the nonlinear rotor at one speed and classify the motion.

    From a Config: ``[analysis.simulate]`` and ``[reference]``, keyword arguments override
    (``speed`` [rad/s] or ``speed_ratio``). From a :class:`RotorSystem`: ``speed`` is
    required, other settings default to the paper's (200 steps per period, 2000 periods,
    100 Poincare periods, 1 um, Newmark). ``record_periods`` (default
    ``poincare_periods``): periods kept in the time series; ``lyapunov_periods`` (default
    ``min(100, periods)``, 0: none): length of the Lyapunov run from the final state.
    ``q0, v0`` override the initial state (full DOF vectors). ``from_hb`` with
    ``hb_phase`` (fraction of the period): start on the HB orbit shifted by that phase;
    ``initial_state``: the final state of a previous run (``timeseries.nc``, its
    directory, or a :class:`SavedState`), see the module docstring for its start time.
    ``step_check_periods`` (default ``[analysis.simulate] step_check_periods``, 0: off):
    the last that many periods are integrated again from the same state at half the step
    (:func:`step_check`, ``result.step_check``; a warning in the summary when the orbit
    moves by more than 1e-2 C).
    """
    from rotorsfd.io.schema import SimulateAnalysis

    h_samples = None
    if isinstance(config_or_system, RotorSystem):
        system = config_or_system
        sim = SimulateAnalysis()
        ref = reference_speed
        H = harmonics or 3
        name = title or ""
        out_nodes = tuple(nodes) if nodes else _default_nodes(system)
    else:
        config = config_or_system
        system = system_from_config(config, search_path)
        sim = config.analysis.simulate
        if reference_speed is not None:
            ref = reference_speed
        else:
            from rotorsfd.api import reference_speed as config_reference_speed

            ref = config_reference_speed(config, system)
        H = harmonics or config.analysis.response.harmonics
        h_samples = config.analysis.response.n_samples
        name = config.title if title is None else title
        out_nodes = tuple(nodes) if nodes else tuple(config.output_nodes("simulate"))
        if speed is None and speed_ratio is None:
            speed = sim.fixed_speed(ref)
    if speed is None and speed_ratio is not None:
        if not ref:
            raise ConfigError("speed_ratio", speed_ratio, "needs a reference speed")
        speed = speed_ratio * ref
    if speed is None or not speed > 0.0:
        raise ConfigError(f"{FIELD}.speed", speed, "give the rotor speed (> 0): --speed, "
                          "--speed-ratio, or speed/speed_ratio in [analysis.simulate]")
    speed = float(speed)
    spp = steps_per_period or sim.steps_per_period
    n_per = periods or sim.periods
    n_pc = poincare_periods or sim.poincare_periods
    n_rec = record_periods or n_pc
    n_ly = min(100, n_per) if lyapunov_periods is None else int(lyapunov_periods)
    n_chk = sim.step_check_periods if step_check_periods is None else int(step_check_periods)
    if n_chk < 0:
        raise ConfigError(f"{FIELD}.step_check_periods", n_chk, "must be >= 0 (0: off)")
    n_chk = min(n_chk, n_per)
    for label, value in (("poincare_periods", n_pc), ("record_periods", n_rec)):
        if not 1 <= value <= n_per:
            raise ConfigError(f"{FIELD}.{label}", value, f"must be in 1..periods = {n_per}")
    scheme = scheme or sim.scheme
    alpha = sim.alpha if alpha is None else alpha
    opts = scheme_options(scheme, alpha)
    disp = sim.initial_displacement if initial_displacement is None else initial_displacement
    for n in out_nodes:
        if not 1 <= n <= system.rotor.n_nodes:
            raise ConfigError(f"{FIELD}.nodes", n, f"must be 1..{system.rotor.n_nodes}")
    T = 2.0 * math.pi / speed
    n = system.n_dof
    t_start = 0.0
    if sum(x for x in (q0 is not None or v0 is not None, from_hb,
                       initial_state is not None)) > 1:
        raise ConfigError("initial state", "several", "give one of q0/v0, from_hb and "
                          "initial_state")
    if q0 is not None or v0 is not None:
        start = "given"
        q_init = np.zeros(n) if q0 is None else np.asarray(q0, float)
        v_init = np.zeros(n) if v0 is None else np.asarray(v0, float)
    elif initial_state is not None:
        saved = initial_state if isinstance(initial_state, SavedState) \
            else load_state(initial_state)
        if saved.q.size != n:
            raise ConfigError("initial_state", saved.source, f"has {saved.q.size} DOFs, "
                              f"this model {n}")
        q_init, v_init = saved.q.copy(), saved.v.copy()
        t_start = saved.start_time(speed) if system.base.is_constant else saved.t
        start = (f"final state of {saved.source or 'a previous run'} (t = {saved.t:.6g} s "
                 f"at {saved.speed:.6g} rad/s; this run starts at t = {t_start:.6g} s)")
    elif from_hb:
        if system.sfd is None or not system.base.is_constant:
            raise ConfigError("from_hb", True, "the HB start needs an SFD and a constant "
                              "base motion (start from the displaced state instead)")
        start = f"HB periodic solution (H={H})" + (
            f" shifted by {hb_phase:g} of the period" if hb_phase else "")
        q_init, v_init = hb_start(system, speed, H, h_samples, phase=hb_phase)
    else:
        start = f"every node displaced {disp:g} m in y and z"
        q_init, v_init = displaced_state(n, disp), np.zeros(n)
    inputs = time_domain_inputs(system, speed,
                                horizon=t_start + (n_per + n_ly + 1) * T)
    rd = [dofs.dof_index(nd, d) for nd in out_nodes for d in DIRECTIONS]
    clearance = system.sfd.clearance if system.sfd is not None else None
    settings = {"speed_rad_s": speed, "speed_ratio": speed / ref if ref else None,
                "reference_speed_rad_s": ref, "scheme": scheme, **opts,
                "steps_per_period": spp, "periods": n_per, "poincare_periods": n_pc,
                "record_periods": n_rec, "lyapunov_periods": n_ly,
                "step_check_periods": n_chk, "initial_state": start,
                "initial_displacement_m": disp, "start_time_s": t_start,
                "time_varying_matrices":
                inputs.time_varying is not None, "dt_s": T / spp}
    bar = _progress_bar(progress, n_per, "simulate")
    last = [0]

    def tick(done: int) -> None:
        bar.update(done - last[0])
        last[0] = done

    tic = time.perf_counter()
    try:
        traj = integrate_periods(inputs, q_init, v_init, steps_per_period=spp, periods=n_per,
                                 record_dofs=rd, record_periods=max(n_rec, n_pc),
                                 poincare_periods=n_pc,
                                 method_options=opts, chunk_periods=chunk_periods,
                                 progress=tick, clearance=clearance, t0=t_start,
                                 snapshot_period=n_per - n_chk if n_chk else None)
    finally:
        bar.close()
    settings["elapsed_integration_s"] = time.perf_counter() - tic
    nn = len(out_nodes)
    q = traj.q.reshape(-1, nn, 2)
    v = traj.v.reshape(-1, nn, 2)
    pq = traj.poincare_q.reshape(-1, nn, 2)
    pv = traj.poincare_v.reshape(-1, nn, 2)
    notes: list[str] = []
    lyap = None
    tic_ly = time.perf_counter()
    if n_ly > 0:
        try:
            lyap = lyapunov_estimate(largest_lyapunov(
                inputs.M, inputs.D, inputs.K, inputs.nl_dofs, inputs.kernel, inputs.params,
                inputs.forcing, steps_per_period=spp, n_periods=n_ly, q0=traj.q_final,
                v0=traj.v_final, t0=traj.t_final, time_varying=inputs.time_varying,
                method="newmark"), T)
        except (JournalContactError, ConvergenceError) as exc:
            notes.append(f"no Lyapunov exponent: {' '.join(str(exc).split())}")
    settings["elapsed_lyapunov_s"] = time.perf_counter() - tic_ly
    motion = classify(traj.poincare_q, traj.poincare_v, traj.q, traj.v, T / spp, speed,
                      lyap, first=2 * _first_column(out_nodes, system.sfd_node),
                      n_record=max(n_rec, n_pc) * spp)
    if motion is None:
        notes.append("fewer than 8 Poincare points: motion not classified")
    check = None
    if n_chk:
        tic_chk = time.perf_counter()
        jc = _first_column(out_nodes, system.sfd_node)
        periodic = (motion is not None and motion.period is not None
                    and bool(motion.evidence.get("settled", True)))
        check = step_check(inputs, traj.snapshot or (q_init, v_init, t_start),
                           periods=n_chk, steps_per_period=spp, node=out_nodes[jc],
                           t=traj.t, q=q[:, jc], poincare_q=pq[:, jc], periodic=periodic,
                           method_options=opts,
                           clearance=clearance if out_nodes[jc] == system.sfd_node
                           else None)
        settings["elapsed_step_check_s"] = time.perf_counter() - tic_chk
    elapsed = time.perf_counter() - tic
    eps_rec = None
    if clearance is not None and system.sfd_node in out_nodes:
        j = out_nodes.index(system.sfd_node)
        eps_rec = float(np.max(np.hypot(q[:, j, 0], q[:, j, 1]))) / clearance
    elif clearance is not None:
        eps_rec = traj.max_eccentricity_run
    return SimulationResult(speed, ref, tuple(out_nodes), traj.t, q, v, traj.poincare_t, pq,
                            pv, motion, lyap, clearance, system.sfd_node, settings, eps_rec,
                            traj.max_eccentricity_run, traj.q_final, traj.v_final,
                            traj.t_final, elapsed, name, notes, check)


def lyapunov_estimate(ly: LyapunovResult, period: float,
                      skip_fraction: float = 0.2) -> LyapunovResult:
    """The exponent over the renormalisations after the first ``skip_fraction``: the first
    intervals measure the alignment of the random initial perturbation (its high-mode
    content grows by orders of magnitude in the weighted norm within one period), a
    constant offset that decays only like 1/t in the running mean."""
    n = ly.history.size
    k = int(skip_fraction * n)
    if k < 1 or n - k < 2:
        return ly
    t_start = ly.times[0] - (ly.times[1] - ly.times[0])
    cum = ly.history * (ly.times - t_start)          # running sum of ln(d_j / d0)
    lam = float((cum[-1] - cum[k - 1]) / (ly.times[-1] - ly.times[k - 1]))
    mid = (k - 1 + n - 1) // 2
    first = (cum[mid] - cum[k - 1]) / (ly.times[mid] - ly.times[k - 1])
    second = (cum[-1] - cum[mid]) / (ly.times[-1] - ly.times[mid])
    return dataclasses.replace(ly, exponent=lam, per_period=lam * period,
                               half_spread=float(abs(second - first)))


def _first_column(nodes: Sequence[int], sfd_node: int | None) -> int:
    return list(nodes).index(sfd_node) if sfd_node in nodes else 0


def classify(pq: np.ndarray, pv: np.ndarray, q: np.ndarray, v: np.ndarray, dt: float,
             speed: float, lyapunov: LyapunovResult | None = None, *, first: int = 0,
             n_record: int | None = None) -> MotionClass | None:
    """:func:`~rotorsfd.timedomain.classify_motion` on recorded columns ``(.., 2 n_nodes)``:
    Poincare points ``[q, v]``, the spectrum of column ``first`` over ``n_record`` samples
    (a whole number of periods); None with fewer than 8 Poincare points."""
    if pq.shape[0] < 8:
        return None
    order = [first] + [i for i in range(q.shape[1]) if i != first]
    P = np.hstack([pq[:, order], pv[:, order]])
    m = q.shape[0] if n_record is None else min(n_record, q.shape[0])
    sig = np.hstack([q[:m, order], v[:m, order]])
    mc = classify_motion(P, sig, dt, speed, lyapunov)
    n = mc.period
    if n is not None:
        # consecutive points within tolerance but drifting along a curve: not settled
        settled = mc.evidence.get("n_distinct_poincare", n) <= n
        ev = {**mc.evidence, "settled": settled}
        if not settled:
            ev["note"] = (f"{ev['n_distinct_poincare']} distinct Poincare points for a "
                          f"period-{n} classification: the points still drift (a slow "
                          "transient); run more periods")
        mc = MotionClass(mc.motion, ev)
    return mc
