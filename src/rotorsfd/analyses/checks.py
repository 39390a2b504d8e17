"""Plausibility warnings about a valid configuration, found before any analysis runs.

Each warning is one line in the user's terms (config fields, SI values) that says what is
suspicious and what to change; nothing here stops a run:

- a support with stiffness at the SFD node: it is in parallel with the film and holds the
  journal, so the damper does little;
- a static deflection at the SFD larger than its clearance (gravity or constant base
  motion at rest): the journal would rest on the housing before the rotor turns (the film
  carries no static load).
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from rotorsfd.errors import RotorsfdError
from rotorsfd.io.schema import Config


def config_warnings(config: Config, search_path: Path | None = None) -> list[str]:
    """The warnings of ``config`` (empty if nothing is suspicious)."""
    if config.sfd is None:
        return []
    return [*_supports_at_sfd(config), *_static_offset_at_sfd(config, search_path)]


def _supports_at_sfd(config: Config) -> list[str]:
    sfd = config.sfd
    assert sfd is not None
    out = []
    for i, support in enumerate(config.rotor.supports):
        c = support.coefficients()
        k = max(abs(c["kyy"]), abs(c["kzz"]))
        if support.node != sfd.node or k == 0.0:
            continue
        name = f" ({support.name})" if support.name else ""
        out.append(f"rotor.supports[{i}]{name} is at the SFD node {sfd.node} with "
                   f"stiffness {k:.4g} N/m, in parallel with the squeeze film (centring "
                   f"spring {sfd.centring_stiffness:.4g} N/m): a stiff support holds the "
                   "journal and the damper does little; give a centring spring as "
                   "sfd.centring_stiffness, or put the support at another node")
    return out


def _static_offset_at_sfd(config: Config, search_path: Path | None) -> list[str]:
    from rotorsfd.analyses.static import base_static_offset
    from rotorsfd.model.build import build_model
    from rotorsfd.model.system import RotorSystem

    sfd = config.sfd
    assert sfd is not None
    if config.base.is_fixed and not config.gravity.enabled:
        return []
    try:
        m = build_model(config, search_path)
        system = RotorSystem(m.rotor, m.sfd, m.sfd_node, m.unbalances, m.base_motion)
        q = base_static_offset(system, 0.0)
    except RotorsfdError:  # a time-varying base or a singular stiffness: the run says so
        return []
    i = 4 * (sfd.node - 1)
    r = float(np.hypot(q[i], q[i + 1]))
    c = sfd.resolved_clearance
    if not r > c:
        return []
    loads = " and ".join(n for n, on in (("gravity", config.gravity.enabled),
                                         ("the base motion", not config.base.is_fixed)) if on)
    return [f"the static deflection at the SFD (node {sfd.node}) under {loads}, at rest, "
            f"is {r:.4g} m = {r / c:.3g} C, larger than the clearance C = {c:.4g} m: the "
            "journal would rest on the housing (the film carries no static load); stiffen "
            f"sfd.centring_stiffness (now {sfd.centring_stiffness:.4g} N/m) or the supports"]
