"""Unbalances of a multi-shaft rotor grouped by the speed they turn at (dual-spool rotors).

An unbalance ``U`` at a node of shaft ``s`` turns with that shaft, at ``Omega_s = r_s
Omega`` (``r_s`` the shaft's speed ratio, Omega the first shaft's speed): its force
(:mod:`rotorsfd.model.unbalance`, fixed base)

    F_y = U Omega_s^2 cos(Omega_s t + eta),   F_z = U Omega_s^2 sin(Omega_s t + eta),

i.e. ``F = Fc(Omega_s) cos(Omega_s t) + Fs(Omega_s) sin(Omega_s t)`` with the harmonic
vectors of :func:`~rotorsfd.model.unbalance.unbalance_harmonics` at the shaft's own speed.
With unbalances on shafts at two speeds the response is quasi-periodic (base frequencies
Omega and r Omega: :mod:`rotorsfd.quasiperiodic.dual_frequency`); a periodic harmonic
balance at Omega cannot hold the second one, so it is refused
(:func:`check_one_frequency`). A single shaft, or unbalances only on shafts at ratio 1,
keep everything as before.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.model.unbalance import Unbalance, unbalance_harmonics

__all__ = ["check_one_frequency", "other_spool_harmonics", "second_ratio", "split_unbalances"]


def _ratio_of(rotor, node: int) -> float:
    ratios = getattr(rotor, "speed_ratios", None)
    if ratios is None:
        return 1.0
    return float(rotor.node_speed_ratio(node))


def split_unbalances(rotor, unbalances: Sequence[Unbalance]
                     ) -> tuple[tuple[Unbalance, ...], dict[float, tuple[Unbalance, ...]]]:
    """(the unbalances turning at Omega (ratio 1), {ratio: the others at that ratio})."""
    own: list[Unbalance] = []
    other: dict[float, list[Unbalance]] = {}
    for u in unbalances:
        r = _ratio_of(rotor, u.node) if 1 <= u.node <= rotor.n_nodes else 1.0
        if r == 1.0:
            own.append(u)
        else:
            other.setdefault(r, []).append(u)
    return tuple(own), {r: tuple(v) for r, v in other.items()}


def second_ratio(rotor, unbalances: Sequence[Unbalance]) -> float | None:
    """The speed ratio r of the unbalances not turning at Omega (None if all do; a zero
    magnitude counts as absent). ConfigError if they turn at two or more other ratios (more
    than two base frequencies)."""
    _, other = split_unbalances(rotor, [u for u in unbalances if u.magnitude != 0.0])
    if not other:
        return None
    if len(other) > 1:
        nodes = [us[0].node for us in other.values()]
        raise ConfigError("unbalance.node", nodes, "unbalances on shafts at more than two "
                          f"speeds (ratios 1, {', '.join(f'{r:g}' for r in other)}) are not "
                          "supported: the two-frequency response has two base frequencies")
    return next(iter(other))


def other_spool_harmonics(rotor, unbalances: Sequence[Unbalance], speed: float
                          ) -> list[tuple[float, np.ndarray, np.ndarray]]:
    """``[(r, Fc, Fs)]``: the force of the unbalances on shafts at ratio r != 1,
    ``Fc cos(r Omega t) + Fs sin(r Omega t)`` at ``Omega = speed`` (fixed base rates: a
    rotating base is refused for such rotors, :func:`~rotorsfd.model.multishaft.
    check_base_motion`)."""
    _, other = split_unbalances(rotor, unbalances)
    return [(r, *unbalance_harmonics(us, rotor, r * float(speed)))
            for r, us in sorted(other.items())]


def check_one_frequency(rotor, unbalances: Sequence[Unbalance], what: str) -> None:
    """ConfigError if an unbalance turns at a speed other than Omega (``what``: the
    analysis that cannot hold a second frequency, for the message)."""
    _, other = split_unbalances(rotor, [u for u in unbalances if u.magnitude != 0.0])
    if not other:
        return
    r, us = next(iter(other.items()))
    shaft = rotor.shafts[rotor.shaft_index(us[0].node, "unbalance.node")].name
    raise ConfigError("unbalance.node", us[0].node,
                      f"this unbalance is on shaft {shaft!r} (speed ratio {r:g}): it turns "
                      f"at its own speed, so {what} is not periodic at Omega; `rotorsfd "
                      "response` runs the two-frequency (torus) response, `rotorsfd "
                      "simulate` the time integration with both unbalance frequencies")
