"""The continuation parameters: one registry of their names, config paths, units and kinds.

A continuation parameter lam is a scalar on which the harmonic-balance equations depend
with exact derivatives (:meth:`rotorsfd.model.system.RotorSystem.periodic_problem`). Its
``kind`` says how the equations depend on it, and so which derivatives apply:

- ``"speed"``: the rotor speed Omega; the damping ``C + Omega G + C_base(Omega)``, the
  base terms, the unbalance force ``~ Omega^2`` and the fundamental frequency follow it;
- ``"base_rate"``: a constant base rotation rate ``w_b[axis]`` at a fixed speed; the base
  matrices and loads are quadratic in it, the unbalance's base-rotation terms follow it;
- ``"unbalance"``: the magnitude of the first unbalance (the others scaled with it); only
  the unbalance force depends on it, linearly;
- ``"element"``: a field of one nonlinear element's table at a fixed speed,
  ``elements.<name>.<field>`` (an SFD's ``clearance_ratio`` or ``length``: the paper's
  section 4.3 varies C/R); only that element's force depends on it, through the element's
  exact ``dforce`` (:meth:`rotorsfd.elements.base.NonlinearElement.with_parameter`).

A new parameter of one of these kinds is one entry of :data:`PARAMETERS`; a new kind also
needs its derivatives in ``periodic_problem``.
"""

from __future__ import annotations

from dataclasses import dataclass

from rotorsfd.errors import ConfigError


@dataclass(frozen=True)
class Parameter:
    """One continuation parameter.

    ``paths``: the config paths that select it (``analysis.response.parameter``,
    ``fold-curve --parameter``), the first the canonical one; ``axis`` the base-rate index
    (0 rolling about x, 1 pitching about y, 2 yawing about z) of a ``"base_rate"``."""

    name: str
    kind: str
    unit: str
    description: str
    paths: tuple[str, ...]
    axis: int | None = None
    element: str | None = None
    field: str | None = None

    @property
    def path(self) -> str:
        """The canonical config path."""
        return self.paths[0]

    @property
    def rate_name(self) -> str:
        """``"wx" | "wy" | "wz"``: the base-coefficient derivative key of a base rate."""
        if self.axis is None:
            raise ValueError(f"{self.name} is not a base rate")
        return "w" + "xyz"[self.axis]


PARAMETERS: dict[str, Parameter] = {p.name: p for p in (
    Parameter("speed", "speed", "rad/s", "rotor speed Omega [rad/s]", ("speed",)),
    Parameter("base.rolling", "base_rate", "rad/s",
              "constant base rolling rate w_bx [rad/s] at fixed speed",
              ("base.rolling.value",), axis=0),
    Parameter("base.pitching", "base_rate", "rad/s",
              "constant base pitching rate w_by [rad/s] at fixed speed",
              ("base.pitching.value",), axis=1),
    Parameter("base.yawing", "base_rate", "rad/s",
              "constant base yawing rate w_bz [rad/s] at fixed speed",
              ("base.yawing.value",), axis=2),
    Parameter("unbalance.magnitude", "unbalance", "kg*m",
              "magnitude of the first unbalance [kg m], others scaled with it",
              ("unbalance[0].magnitude", "unbalance.0.magnitude")),
)}


#: element fields that a continuation may vary, and their SI units
ELEMENT_FIELDS: dict[str, str] = {
    "clearance_ratio": "1", "clearance": "m", "radius": "m", "length": "m",
    "length_to_diameter": "1", "viscosity": "Pa*s"}


def element_parameter(path: str) -> Parameter | None:
    """The ``"element"`` parameter of a path ``elements.<name>.<field>`` (None if the path
    is not of that form); whether the element has the field is checked where the system
    applies it."""
    parts = path.split(".")
    if len(parts) != 3 or parts[0] != "elements" or parts[2] not in ELEMENT_FIELDS:
        return None
    return Parameter(path, "element", ELEMENT_FIELDS[parts[2]],
                     f"{parts[2]} of element {parts[1]!r} at fixed speed", (path,),
                     element=parts[1], field=parts[2])


def find_parameter(name_or_path: str, field: str = "parameter") -> Parameter:
    """The parameter named ``name_or_path`` or selected by that config path; ConfigError
    naming ``field`` otherwise."""
    key = name_or_path.strip()
    if key in PARAMETERS:
        return PARAMETERS[key]
    for p in PARAMETERS.values():
        if key in p.paths:
            return p
    element = element_parameter(key)
    if element is not None:
        return element
    allowed = ", ".join(p.path for p in PARAMETERS.values()) + ", elements.<name>.<" \
        + "|".join(ELEMENT_FIELDS) + ">"
    raise ConfigError(field, name_or_path,
                      f"must be one of {allowed} (continuation with exact derivatives)")
