"""Shared models of the torus tests: the small SFD rotor of tests/rotors.py under a base
moving harmonically, and its linear twin (the SFD replaced by a damped linear support)."""

from __future__ import annotations

from pathlib import Path

from rotors import SMALL_ROTOR
from rotorsfd.io.config import load_config
from rotorsfd.model.build import build_system
from rotorsfd.model.system import RotorSystem

#: the linear twin: the SFD replaced by a linear support with damping
LINEAR_SUPPORT = """
[[rotor.supports]]
node = 1
stiffness = "1e7 N/m"
damping = "{damping}"
"""


def small_system(tmp_path: Path, base: str, unbalance: str = "50 g*mm",
                 linear: bool = False, damping: str = "3000 N*s/m") -> RotorSystem:
    """The small rotor (20 DOF) under the [base] table ``base``; ``linear``: without the
    SFD, a support of ``damping`` at node 1 instead."""
    text = SMALL_ROTOR.format(unbalance=unbalance, base=base, reference="800 rad/s")
    if linear:
        head, tail = text.split("[elements.sfd]")
        tail = tail[tail.index("[[unbalance]]"):]
        text = head + LINEAR_SUPPORT.format(damping=damping) + "\n" + tail
    path = tmp_path / "rotor.toml"
    path.write_text(text)
    return build_system(load_config(path))


def heave_common_period_problem(system: RotorSystem, heave: float, w_b: float):
    """The periodic HB problem of ``system`` (SFD rotor, unbalance, harmonic heave
    ``z0 = heave sin(w_b t)``, gravity off) at a speed Omega = 2 w_b, on the common
    fundamental w0 = Omega / 2: the unbalance on harmonic 2 and the heave load
    ``F_base = heave w_b^2 sin(w_b t) fz`` (a_z = -heave w_b^2 sin, fz = int rho A N_z dx)
    on harmonic 1, ``F_1 = -i heave w_b^2 fz``; the linear part is the fixed rotor's."""
    import dataclasses

    import numpy as np

    fixed = RotorSystem(system.rotor, system.elements, system.unbalances)
    spin = fixed.periodic_problem("speed")
    fz = system.basis.vector("fz")

    def forcing(lam: float, H: int) -> np.ndarray:
        F = np.zeros((H + 1, system.n_dof), dtype=complex)
        F[1] = -1j * heave * w_b**2 * fz
        F[2] = spin.forcing(lam, 1)[1]
        return F

    def dforcing(lam: float, H: int) -> np.ndarray:
        F = np.zeros((H + 1, system.n_dof), dtype=complex)
        F[2] = spin.dforcing(lam, 1)[1]
        return F

    return dataclasses.replace(spin, forcing=forcing, dforcing=dforcing,
                               frequency=lambda lam: lam / 2, dfrequency=lambda lam: 0.5)
