"""A small rotor-SFD configuration with an [analysis.sweep] table, for the sweep tests."""

from __future__ import annotations

from pathlib import Path

SWEEP_ROTOR = """
title = "small sweep test rotor"

[materials.steel]
density = "7810 kg/m^3"
young_modulus = "211 GPa"
shear_modulus = "81.783 GPa"

[[rotor.shaft]]
length = "0.5 m"
n_elements = 4
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

[sfd]
node = 1
viscosity = "0.0051 Pa*s"
clearance = "0.127 mm"
clearance_ratio = "0.5 %"
length_to_diameter = 0.325
centring_stiffness = "1e7 N/m"

[[unbalance]]
node = 3
magnitude = "50 g*mm"

[reference]
speed = "800 rad/s"

[analysis.response]
harmonics = 3
speed_range = {{ start_ratio = 0.6, stop_ratio = 1.4 }}
nodes = [1, 3]
step_max = 0.1

[analysis.stability]
intervals = 100                 # tests: 100 Newmark intervals per period are enough here

[analysis.sweep]
task = "response"
{axes}
"""

AXES_2x3 = """
[[analysis.sweep.axes]]
parameter = "sfd.clearance_ratio"
values = ["0.4 %", "0.5 %"]

[[analysis.sweep.axes]]
parameter = "unbalance[0].magnitude"
start = "40 g*mm"
stop = "60 g*mm"
n = 3
"""


def sweep_toml(path: Path, axes: str = AXES_2x3) -> Path:
    """Write the sweep test config to ``path`` and return it."""
    path.write_text(SWEEP_ROTOR.format(axes=axes))
    return path
