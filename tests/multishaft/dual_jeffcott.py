"""Two Jeffcott-like shafts coupled at their disks by an intershaft bearing, and the closed
form of their modes, critical speeds and unbalance response (derived in the docstrings).

Each shaft: a uniform beam of length L on two end supports k_s (free to tilt there), a
rigid disk (m, Id, Ip) at mid-span, the beam nearly massless (density 1e-4 kg/m^3: its
mass is 1e-8 of the disk's; the FE frequencies differ from the closed form by 9e-9 and
that difference scales with the density, 9e-5 at 1 kg/m^3), Timoshenko with kappa = 0.9,
so the FE model tends to the discrete one (the FE element is exact for nodal loads):

- translation of the disk: the beam's mid-span compliance ``L^3 / (48 E I) + L / (4 kappa
  G A)`` (bending and shear, simply supported, load at mid-span) in series with the two
  supports (each carrying half the load: ``1 / (2 k_s)``),
  ``k = 1 / (L^3 / (48 E I) + L / (4 kappa G A) + 1 / (2 k_s))``;
- tilt of the disk: under a mid-span moment M0 the support reactions are ``+-M0 / L``
  (the mid-span does not move, by antisymmetry), the chord turns by ``2 M0 / (k_s L^2)``;
  with the shear force ``V = M0 / L`` uniform, ``EI psi' = M`` and ``w' = psi + V / (kappa
  G A)``, ``w(0) = w(L) = 0`` give the section rotation at mid-span
  ``psi = M0 L / (12 E I) + M0 / (kappa G A L)``, so
  ``k_t = 1 / (L / (12 E I) + 1 / (kappa G A L) + 2 / (k_s L^2))``.

The intershaft bearing (stiffness kc, damping cc) joins the two disks in y and z only, so
the tilts stay uncoupled: each disk's tilt mode turns with its own shaft,
``Id w^2 -+ Ip Omega_s w - k_t = 0``, i.e. ``w_fw,bw = (+-Ip Omega_s + sqrt(Ip^2
Omega_s^2 + 4 Id k_t)) / (2 Id)``, and crosses the line ``w = h Omega_LP`` (forward, shaft
at ``Omega_s = r_s Omega_LP``) at ``Omega_LP = sqrt(k_t / (h (Id h - Ip r_s)))``. The
translations of both disks (per direction, y and z alike) obey

    [m1 0; 0 m2] x'' + c_d x' + cc [1 -1; -1 1] x' + (diag(k1, k2) + kc [1 -1; -1 1]) x = f

with a grounded damper c_d at each disk: undamped (c = 0) the frequencies are
``w^2 = (a + b)/2 -+ sqrt(((a - b)/2)^2 + kc^2 / (m1 m2))``, ``a = (k1 + kc) / m1``,
``b = (k2 + kc) / m2``; they do not depend on the speed, so the LP unbalance line meets
them at ``Omega_LP = w_i``, the HP one at ``Omega_LP = w_i / r``. An unbalance U on disk
s at its speed W loads ``U W^2 (cos W t, sin W t)``: the steady response of the disks at
frequency W is ``X = Z(W)^-1 F``, ``Z = K - W^2 M + i W C`` (2 x 2, per direction; the y
and z parts are the same complex amplitude times (1, -i)).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from rotorsfd.model import Disk, LinearSupport, Material, uniform_shaft
from rotorsfd.model.multishaft import IntershaftBearing, MultiShaftRotor, Shaft

E = 2.0e11
G_SHEAR = 8.0e10
KAPPA = 0.9
MATERIAL = Material(1e-4, E, G_SHEAR)


@dataclass(frozen=True)
class Spool:
    length: float
    radius: float
    support: float
    mass: float
    diametral: float
    polar: float

    @property
    def inertia(self) -> float:
        return np.pi * self.radius**4 / 4

    @property
    def shear(self) -> float:
        """kappa G A [N]."""
        return KAPPA * G_SHEAR * np.pi * self.radius**2

    @property
    def k(self) -> float:
        return 1.0 / (self.length**3 / (48 * E * self.inertia) + self.length / (4 * self.shear)
                      + 1.0 / (2 * self.support))

    @property
    def k_tilt(self) -> float:
        return 1.0 / (self.length / (12 * E * self.inertia) + 1.0 / (self.shear * self.length)
                      + 2.0 / (self.support * self.length**2))

    def tilt(self, speed: float) -> tuple[float, float]:
        """(forward, backward) tilt frequencies at the shaft's own speed."""
        a, d = self.polar * speed, np.sqrt((self.polar * speed) ** 2
                                           + 4 * self.diametral * self.k_tilt)
        return (a + d) / (2 * self.diametral), (-a + d) / (2 * self.diametral)

    def tilt_critical(self, h: float, ratio: float) -> float:
        """Omega_LP where the forward tilt (shaft at ratio * Omega_LP) meets w = h Omega_LP
        (inf if it never does: Id h <= Ip ratio)."""
        den = h * (self.diametral * h - self.polar * ratio)
        return float(np.sqrt(self.k_tilt / den)) if den > 0 else float("inf")


LP = Spool(1.0, 0.02, 2e7, 12.0, 0.08, 0.03)
HP = Spool(0.6, 0.03, 3e7, 9.0, 0.06, 0.05)
KC, CC, CD = 4e6, 150.0, 80.0
RATIO = 1.7


def rotor(ratio: float = RATIO, damped: bool = True) -> MultiShaftRotor:
    """LP nodes 1-3 (disk 2), HP nodes 4-6 (disk 5), the bearing between nodes 2 and 5."""
    c = CD if damped else 0.0
    shafts = []
    for name, s, off, r in (("lp", LP, 0, 1.0), ("hp", HP, 3, ratio)):
        shafts.append(Shaft(name, tuple(uniform_shaft(s.length, 2, 0.0, s.radius, MATERIAL, KAPPA)),
                            r, disks=(Disk(off + 2, s.mass, s.polar, s.diametral),),
                            supports=(LinearSupport.isotropic(off + 1, s.support),
                                      LinearSupport.isotropic(off + 3, s.support),
                                      LinearSupport(off + 2, 0.0, 0.0, cyy=c, czz=c))))
    cc = CC if damped else 0.0
    return MultiShaftRotor(shafts, [IntershaftBearing(2, 5, KC, KC, cyy=cc, czz=cc)])


def translation_frequencies() -> np.ndarray:
    """The two undamped coupled frequencies [rad/s] (module docstring)."""
    a, b = (LP.k + KC) / LP.mass, (HP.k + KC) / HP.mass
    d = np.sqrt(((a - b) / 2) ** 2 + KC**2 / (LP.mass * HP.mass))
    return np.sqrt([(a + b) / 2 - d, (a + b) / 2 + d])


def translation_response(frequency: float, force: np.ndarray) -> np.ndarray:
    """Complex amplitudes (2,) of the two disks under ``force`` (2,) at ``frequency``."""
    w = frequency
    K = np.diag([LP.k, HP.k]) + KC * np.array([[1.0, -1.0], [-1.0, 1.0]])
    C = CD * np.eye(2) + CC * np.array([[1.0, -1.0], [-1.0, 1.0]])
    Z = K - w**2 * np.diag([LP.mass, HP.mass]) + 1j * w * C
    det = Z[0, 0] * Z[1, 1] - Z[0, 1] * Z[1, 0]
    return np.array([Z[1, 1] * force[0] - Z[0, 1] * force[1],
                     Z[0, 0] * force[1] - Z[1, 0] * force[0]]) / det
