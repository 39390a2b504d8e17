"""The small rotor-SFD configuration of the response and sweep tests (4 shaft elements,
one disk, an SFD with a centring spring at node 1, a linear support at node 5), importable
as ``rotors`` from any test (tests/ is on the path: its conftest.py)."""

from __future__ import annotations

from pathlib import Path

SMALL_ROTOR = """
title = "small test rotor with an SFD"

[materials.steel]
density = "7810 kg/m^3"
young_modulus = "211 GPa"
shear_modulus = "81.783 GPa"

[[rotor.shaft]]
length = "0.5 m"
n_elements = 4
inner_radius = "0 mm"
outer_radius = "25 mm"
material = "steel"

[[rotor.disks]]
node = 3
material = "steel"
outer_radius = "100 mm"
thickness = "40 mm"

[[rotor.supports]]
node = 5
stiffness = "1e7 N/m"

[elements.sfd]
kind = "sfd"
node = 1
viscosity = "0.0051 Pa*s"
clearance = "0.127 mm"
clearance_ratio = "0.5 %"
length_to_diameter = 0.325
centring_stiffness = "1e7 N/m"

[[unbalance]]
node = 3
magnitude = "{unbalance}"

[base]
{base}

[reference]
speed = "{reference}"

[analysis.response]
harmonics = 3
speed_range = {{ start_ratio = 0.6, stop_ratio = 1.4 }}
nodes = [1, 3]
step_max = 0.1
"""


def small_rotor_toml(path: Path, unbalance: str = "50 g*mm", base: str = "",
                     reference: str = "800 rad/s", extra: str = "") -> Path:
    """Write the small rotor config to ``path`` and return it."""
    path.write_text(SMALL_ROTOR.format(unbalance=unbalance, base=base,
                                       reference=reference) + extra)
    return path


#: a three-node rotor (2 shaft elements, a disk at node 2, a support at node 3) with an SFD
#: at node 1: the smallest rotor whose branches end at the film's limit
TINY_ROTOR = """\
[materials.steel]
density = "7850 kg/m^3"
young_modulus = "210 GPa"
poisson_ratio = 0.3

[[rotor.shaft]]
length = "0.4 m"
n_elements = 2
outer_radius = "25 mm"
material = "steel"

[[rotor.disks]]
node = 2
mass = "8 kg"
polar_inertia = "0.05 kg*m^2"
diametral_inertia = "0.026 kg*m^2"

[[rotor.supports]]
node = 3
stiffness = "5e7 N/m"

[elements.{element}]
kind = "sfd"
node = 1
viscosity = "0.01 Pa*s"
clearance = "0.15 mm"
radius = "40 mm"
length = "20 mm"
centring_stiffness = "4e6 N/m"

[[unbalance]]
node = 2
magnitude = "{unbalance}"

[reference]
speed = "500 rad/s"

[analysis.response]
harmonics = 3
speed_range = {{ start = "{start}", stop = "{stop}" }}

[analysis.stability]
enabled = false
"""


def tiny_rotor_text(element: str = "sfd", unbalance: str = "0.2 kg*m",
                    start: str = "100 rad/s", stop: str = "600 rad/s") -> str:
    """The TOML text of the tiny rotor with its SFD named ``element``."""
    return TINY_ROTOR.format(element=element, unbalance=unbalance, start=start, stop=stop)


def linear_rotor_toml(path: Path, unbalance: str = "0 g*mm", base: str = "",
                      extra: str = "") -> Path:
    """The small rotor with its SFD replaced by a linear support at node 1 (a linear rotor
    whose reference solutions are scipy integrations of its own M, C, G, K)."""
    text = SMALL_ROTOR.format(unbalance=unbalance, base=base, reference="800 rad/s")
    start, end = text.index("[elements.sfd]"), text.index("[[unbalance]]")
    path.write_text(text[:start] + '[[rotor.supports]]\nnode = 1\nstiffness = "1e7 N/m"\n\n'
                    + text[end:] + extra)
    return path


#: a four-element shaft with one disk on two linear supports (no nonlinear element): the
#: calibration and fit-supports tests fit the supports' stiffness to its critical speeds
TWO_SUPPORT_ROTOR = """
[materials.steel]
density = "7800 kg/m^3"
young_modulus = "210 GPa"
poisson_ratio = 0.3

[[rotor.shaft]]
length = "0.6 m"
n_elements = 4
outer_radius = "20 mm"
material = "steel"

[[rotor.disks]]
node = {disk_node}
material = "steel"
outer_radius = "100 mm"
thickness = "30 mm"

[[rotor.supports]]
node = 1
stiffness = "1e7 N/m"

[[rotor.supports]]
node = 5
stiffness = "1e7 N/m"

[reference]
speed = "500 rad/s"

[analysis.modal]
critical_speed_max = "{critical_speed_max}"
n_critical = {n_critical}
"""


def two_support_rotor_text(disk_node: int = 3, critical_speed_max: str = "2000 rad/s",
                           n_critical: int = 1) -> str:
    """The TOML text of the two-support rotor (its disk at ``disk_node``)."""
    return TWO_SUPPORT_ROTOR.format(disk_node=disk_node, critical_speed_max=critical_speed_max,
                                    n_critical=n_critical)


def chart_rotor_raw() -> dict:
    """A stiffly supported four-element rotor under harmonic pitching, as a raw config
    table: the linear time-periodic stability chart of the file tests."""
    return {"materials": {"steel": {"density": 7800.0, "young_modulus": 2e11,
                                    "poisson_ratio": 0.3}},
            "rotor": {"shaft": [{"length": 0.4, "n_elements": 4, "outer_radius": 0.01,
                                 "material": "steel"}],
                      "disks": [{"node": 2, "mass": 5.0, "polar_inertia": 0.02,
                                 "diametral_inertia": 0.01}],
                      "supports": [{"node": 1, "stiffness": 1e9},
                                   {"node": 5, "stiffness": 1e9}]},
            "base": {"pitching": {"law": "harmonic", "frequency": 300.0,
                                  "angle_amplitude": 0.1}},
            "analysis": {"stability_chart": {"speed": 250.0}}}


def uniform_sfd_rotor_raw(n_elements: int = 104, modal_ratio: float | None = None) -> dict:
    """A 1 m uniform steel shaft of ``n_elements`` elements (above DENSE_MAX_DOF at 104),
    a disk at mid-span, a support at the far end and an SFD at node 1, as a raw config
    table; ``modal_ratio``: modal damping of that ratio on the 6 lowest modes."""
    mid = n_elements // 2 + 1
    rotor = {"shaft": [{"length": 1.0, "n_elements": n_elements, "outer_radius": 0.02,
                        "material": "steel"}],
             "disks": [{"node": mid, "material": "steel", "inner_radius": 0.02,
                        "outer_radius": 0.12, "thickness": 0.03}],
             "supports": [{"node": n_elements + 1, "stiffness": 3e7, "damping": 500.0}]}
    title = "uniform rotor, SFD at node 1"
    if modal_ratio is not None:
        rotor["damping"] = {"kind": "modal", "ratio": modal_ratio, "modes": 6}
        title += ", modal damping of 6 modes"
    return {"title": title,
            "materials": {"steel": {"density": 7810.0, "young_modulus": 211e9,
                                    "shear_modulus": 81.2e9}},
            "rotor": rotor,
            "elements": {"sfd": {"kind": "sfd", "node": 1, "viscosity": 0.0051,
                                 "clearance": 1.27e-4, "clearance_ratio": 0.00485,
                                 "length_to_diameter": 0.325, "cavitation": "pi",
                                 "centring_stiffness": 1e7, "centring_damping": 0.0}},
            "unbalance": [{"node": mid, "magnitude": 5e-5}],
            "gravity": {"enabled": False}}


def forbid_dense_rotor_matrices(monkeypatch) -> None:
    """Forming the rotor's dense M, C, K, G or the dense base stack raises (the banded
    paths of a large model must not reach them)."""
    from rotorsfd.model.base_terms import BaseBasis
    from rotorsfd.model.rotor import Rotor

    def boom(self):
        raise AssertionError("a dense n x n matrix was formed")

    for name in ("M", "C", "K", "G"):
        monkeypatch.setattr(Rotor, name, property(boom))
    monkeypatch.setattr(BaseBasis, "matrices", property(boom))
