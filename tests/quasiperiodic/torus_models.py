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
