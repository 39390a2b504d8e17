"""The small test rotor (tests/rotors.py) with an [analysis.sweep] table, for the sweep
tests."""

from __future__ import annotations

from pathlib import Path

from rotors import small_rotor_toml

SWEEP_TABLES = """
[analysis.stability]
intervals = 100                 # tests: 100 Newmark intervals per period are enough here

[analysis.sweep]
task = "response"
{axes}
"""

AXES_2x3 = """
[[analysis.sweep.axes]]
parameter = "elements.sfd.clearance_ratio"
values = ["0.4 %", "0.5 %"]

[[analysis.sweep.axes]]
parameter = "unbalance[0].magnitude"
start = "40 g*mm"
stop = "60 g*mm"
n = 3
"""


def sweep_toml(path: Path, axes: str = AXES_2x3) -> Path:
    """Write the sweep test config to ``path`` and return it."""
    return small_rotor_toml(path, extra=SWEEP_TABLES.format(axes=axes))
