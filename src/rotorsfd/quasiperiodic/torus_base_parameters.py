"""The torus problem continued in a parameter of the harmonic base law: the base frequency
w_b, or the amplitude of one base law.

On the torus the base state is a function of ``theta2 = w_b t``: a rate
``w = mean + A sin(theta2 + phi)`` with ``w' = A w_b cos(theta2 + phi)``, a translation
``x0 = A sin(theta2 + phi)`` with ``v0 = A w_b cos``, ``v0' = -A w_b^2 sin``. Every
coefficient of the linear terms (``model/base_terms.py``: w, w^2, products of rates, w',
``a0 = v0' + w x v0``) and of the unbalance force (``model/unbalance.py``) is therefore a
polynomial of degree <= 4 in w_b and in any one amplitude A (degree 2 in practice; with
the angle amplitude held, A = A0 w_b adds one degree per rate). The problem is built at
five values of the parameter by :func:`~rotorsfd.quasiperiodic.torus_system.torus_problem`
and its Fourier coefficients interpolated by the polynomial of degree 4 through them:
exact (to round-off) at every value, with the exact derivative.

Parameters: ``"base.frequency"`` (lam = w_b [rad/s], every harmonic law moved together;
``hold="angle"`` keeps the rotation laws' angle amplitudes A / w_b, ``"rate"`` their rate
amplitudes; translations keep their displacement amplitudes),
``"base.<component>.amplitude"`` (lam = that law's amplitude: a rate [rad/s] for rolling,
pitching, yawing, a displacement [m] for x, y, z), and the config's other forms of it,
``"base.<rotation>.angle_amplitude"`` (lam = A0 [rad], rate amplitude A0 w_b) and
``"base.<translation>.acceleration_amplitude"`` (lam = a [m/s^2], displacement a / w_b^2):
each a fixed multiple of the amplitude, so the interpolation stays exact.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model.base_motion import BaseMotion
from rotorsfd.model.sparse import DENSE_MAX_DOF
from rotorsfd.model.system import RotorSystem
from rotorsfd.quasiperiodic.torus_bands import TorusBands, dense_coefficients
from rotorsfd.quasiperiodic.torus_fourier import TorusLattice
from rotorsfd.quasiperiodic.torus_linear import TorusProblem
from rotorsfd.quasiperiodic.torus_system import base_frequency, torus_problem

COMPONENTS = ("x", "y", "z", "rolling", "pitching", "yawing")
#: the five nodes of the interpolation, relative to the parameter's value in the system
NODES = np.array([0.6, 0.8, 1.0, 1.2, 1.4])
HOLDS = ("angle", "rate")


#: the amplitude forms per component kind, and the factor amplitude / lam at frequency w
AMPLITUDE_FORMS = {"amplitude": lambda w: 1.0, "angle_amplitude": lambda w: w,
                   "acceleration_amplitude": lambda w: 1.0 / w**2}


def base_parameter_value(system: RotorSystem, parameter: str) -> float:
    """The parameter's value in ``system`` (ConfigError for an unknown one)."""
    if parameter == "base.frequency":
        return base_frequency(system)
    law, form = _law(system.base, parameter)
    return float(law.amplitude) / AMPLITUDE_FORMS[form](float(law.frequency))


def _law(base: BaseMotion, parameter: str):
    """(law, amplitude form) named by ``base.<component>.<form>``."""
    parts = parameter.split(".")
    allowed = ("must be base.frequency, base.<x|y|z|rolling|pitching|yawing>.amplitude, "
               "base.<rolling|pitching|yawing>.angle_amplitude or "
               "base.<x|y|z>.acceleration_amplitude")
    if len(parts) != 3 or parts[0] != "base" or parts[1] not in COMPONENTS \
            or parts[2] not in AMPLITUDE_FORMS:
        raise ConfigError("parameter", parameter, allowed)
    i = COMPONENTS.index(parts[1])
    if (parts[2] == "angle_amplitude" and i < 3) or \
            (parts[2] == "acceleration_amplitude" and i >= 3):
        raise ConfigError("parameter", parameter, allowed)
    law = (*base.translation, *base.rotation)[i]
    if law.kind != "harmonic":
        raise ConfigError(f"base.{parts[1]}.law", law.kind,
                          "continuing in its amplitude needs a harmonic law")
    return law, parts[2]


def with_base_value(system: RotorSystem, parameter: str, value: float,
                    hold: str = "angle") -> RotorSystem:
    """A copy of ``system`` with the base parameter set to ``value`` (module docstring)."""
    if hold not in HOLDS:
        raise ConfigError("hold", hold, "must be 'angle' or 'rate'")
    laws = list((*system.base.translation, *system.base.rotation))
    if parameter == "base.frequency":
        w0 = base_frequency(system)
        for i, law in enumerate(laws):
            if law.kind == "harmonic" and not law.is_constant:
                amp = law.amplitude
                if i >= 3 and hold == "angle":
                    amp = amp * value / w0
                laws[i] = dataclasses.replace(law, frequency=float(value), amplitude=amp)
    else:
        i = COMPONENTS.index(parameter.split(".")[1])
        law, form = _law(system.base, parameter)
        amp = float(value) * AMPLITUDE_FORMS[form](float(law.frequency))
        laws[i] = dataclasses.replace(law, amplitude=amp)
    base = BaseMotion(*laws, gravity=system.base.gravity)
    return RotorSystem(system.rotor, system.elements, system.unbalances, base)


def base_parameter_problem(system: RotorSystem, parameter: str, speed: float,
                           hold: str = "angle", banded: bool | None = None) -> TorusProblem:
    """The torus problem at the fixed ``speed`` [rad/s] continued in the base parameter
    (lam in its SI unit), by the exact degree-4 interpolation of the module docstring.
    ``banded`` (default :func:`~rotorsfd.quasiperiodic.torus_system.keeps_band`): the
    weights of the CSR terms interpolated (:class:`~rotorsfd.quasiperiodic.torus_bands.
    TorusBands`, no dense n x n array) instead of the dense stacks."""
    if not speed > 0:
        raise ConfigError("speed", speed, f"continuing in {parameter} needs a speed > 0")
    lam0 = base_parameter_value(system, parameter)
    if lam0 == 0.0:
        raise ConfigError(parameter, 0.0, "continuing needs a nonzero starting value")
    nodes = lam0 * NODES
    probs = [torus_problem(with_base_value(system, parameter, v, hold), banded=banded)
             for v in nodes]
    V = np.vander(nodes, 5, increasing=True)
    powers = np.arange(5)
    loads: dict[TorusLattice, np.ndarray] = {}

    def poly(c: np.ndarray, lam: float, d: int) -> np.ndarray:
        w = powers * lam ** np.maximum(powers - 1, 0) if d else lam ** powers
        return np.tensordot(w, c, axes=(0, 0))

    def interpolate(stacks: list[tuple[np.ndarray, np.ndarray]]
                    ) -> tuple[np.ndarray, np.ndarray]:
        """Polynomial coefficients (5, ...) of (D, K) stacks (or weights) at the nodes."""
        bw = max(D.shape[0] for D, _ in stacks)

        def pad(A: np.ndarray) -> np.ndarray:
            return np.pad(A, [(0, bw - A.shape[0])] + [(0, 0)] * (A.ndim - 1))

        shape = (bw, *stacks[0][0].shape[1:])
        Dc = np.linalg.solve(V, np.array([pad(D) for D, _ in stacks]).reshape(5, -1))
        Kc = np.linalg.solve(V, np.array([pad(K) for _, K in stacks]).reshape(5, -1))
        return Dc.reshape(5, *shape), Kc.reshape(5, *shape)

    bands = probs[0].bands
    if bands is not None:            # the same CSR terms at every node: their weights
        Wa, Wc = interpolate([p.bands.weights(speed) for p in probs])
        bands = TorusBands(bands.M, bands.terms,
                           lambda lam: (poly(Wa, lam, 0), poly(Wc, lam, 0)),
                           lambda lam: (poly(Wa, lam, 1), poly(Wc, lam, 1)))
        coefficients, dcoefficients = dense_coefficients(bands)
    else:
        Dc, Kc = interpolate([p.coefficients(speed) for p in probs])

        def coefficients(lam: float):
            return poly(Dc, lam, 0), poly(Kc, lam, 0)

        def dcoefficients(lam: float):
            return poly(Dc, lam, 1), poly(Kc, lam, 1)

    def load(lattice: TorusLattice) -> np.ndarray:
        if lattice not in loads:
            F = np.array([p.forcing(speed, lattice) for p in probs])
            loads[lattice] = np.linalg.solve(V, F.reshape(5, -1)).reshape(5, *F.shape[1:])
        return loads[lattice]

    is_frequency = parameter == "base.frequency"
    w_b = base_frequency(system)
    return TorusProblem(
        n_dof=system.n_dof, nl_dofs=system.nl_dofs,
        M=None if bands is not None and system.n_dof > DENSE_MAX_DOF else system.rotor.M,
        bands=bands,
        coefficients=coefficients, dcoefficients=dcoefficients,
        forcing=lambda lam, lattice: poly(load(lattice), lam, 0),
        dforcing=lambda lam, lattice: poly(load(lattice), lam, 1),
        frequencies=lambda lam: (float(speed), float(lam) if is_frequency else w_b),
        dfrequencies=lambda lam: (0.0, 1.0 if is_frequency else 0.0),
        elements=probs[0].elements, scaling=system.dof_scale(),
        name=f"rotor torus in {parameter}",
        info={"base_frequency": w_b, "parameter": parameter, "hold": hold})
