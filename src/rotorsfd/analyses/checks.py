"""Plausibility warnings about a valid configuration, found before any analysis runs.

Each warning is one line in the user's terms (config fields, SI values) that says what is
suspicious and what to change; nothing here stops a run:

- a support with stiffness at the node of a damper element (one with a centring spring):
  it is in parallel with the film and holds the journal, so the damper does little;
- an element beyond its validity limit under the static load at rest (gravity or constant
  base motion; for an SFD a static deflection larger than the clearance): the journal would
  rest on the housing before the rotor turns (the film carries no static load).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rotorsfd.errors import RotorsfdError
from rotorsfd.io.schema import Config
from rotorsfd.model.build import build_system


def config_warnings(config: Config, search_path: Path | None = None) -> list[str]:
    """The warnings of ``config`` (empty if nothing is suspicious)."""
    if not config.elements:
        return []
    return [*_supports_at_dampers(config), *_static_offset_at_elements(config, search_path)]


def _supports_at_dampers(config: Config) -> list[str]:
    """A stiff support at the node of an element with a centring spring (a damper)."""
    out = []
    for name, table in config.elements.items():
        centring = getattr(table, "centring_stiffness", None)
        if centring is None:
            continue
        for i, support in enumerate(config.rotor.supports):
            c = support.coefficients()
            k = max(abs(c["kyy"]), abs(c["kzz"]))
            if support.node not in table.nodes or k == 0.0:
                continue
            label = f" ({support.name})" if support.name else ""
            out.append(f"rotor.supports[{i}]{label} is at node {support.node} of the damper "
                       f"elements.{name} with stiffness {k:.4g} N/m, in parallel with the "
                       f"squeeze film (centring spring {centring:.4g} N/m): a stiff support "
                       "holds the journal and the damper does little; give a centring "
                       f"spring as elements.{name}.centring_stiffness, or put the support "
                       "at another node")
    return out


def _static_offset_at_elements(config: Config, search_path: Path | None) -> list[str]:
    """An element beyond its validity limit under the static load at rest."""
    # deferred: analyses.static (loads numba, scipy)
    from rotorsfd.analyses.static import base_static_offset

    if config.base.is_fixed and not config.gravity.enabled:
        return []
    try:
        system = build_system(config, search_path)
        q = base_static_offset(system, 0.0)
    except RotorsfdError:  # a time-varying base or a singular stiffness: the run says so
        return []
    loads = " and ".join(n for n, on in (("gravity", config.gravity.enabled),
                                         ("the base motion", not config.base.is_fixed)) if on)
    out = []
    for e in system.elements:
        value = e.limit(q[e.dofs][None, :])
        if e.limit_label is None or not value > 1.0:
            continue
        r = float(np.linalg.norm(q[e.dofs]))
        stiff = (f"stiffen elements.{e.name}.centring_stiffness or the supports"
                 if hasattr(config.elements[e.name], "centring_stiffness")
                 else "stiffen the supports")
        out.append(f"the static deflection at elements.{e.name} (node "
                   f"{', '.join(map(str, e.nodes))}) under {loads}, at rest, is {r:.4g} m, "
                   f"{e.limit_label} = {value:.3g} > 1: the journal would rest on the "
                   f"housing (the film carries no static load); {stiff}")
    return out
