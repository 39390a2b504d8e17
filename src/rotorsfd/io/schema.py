"""The configuration schema: a rotor, its nonlinear elements, base motion and analyses.

Every physical field is declared with :func:`quantity`: its kind (SI unit) and allowed
range go into the field's description, so the generated documentation cannot drift.
Values are stored in SI; a TOML value may be an SI number or a string with units
(see :mod:`rotorsfd.io.units`). Unknown keys are errors. Alternatives (a disk by geometry
or by inertias, C with C/R or R, ...) are optional fields that default to ``None``; a
validator checks that exactly one form is given.

Errors raised here are pydantic errors whose context carries the offending sub-field
(``path``); :mod:`rotorsfd.io.config` turns the first one into a one-line ConfigError.
"""

import math
import operator
import re
from functools import reduce
from typing import Annotated, Any, ClassVar, Literal

from pydantic import (
    BaseModel,
    BeforeValidator,
    Field,
    StrictBool,
    field_validator,
    model_validator,
)
from pydantic_core import PydanticCustomError

from rotorsfd.elements import KINDS
from rotorsfd.errors import ConfigError
from rotorsfd.io.fields import (
    CALLABLE,
    LABEL,
    NAME,
    NAME_PATTERN,
    NODE,
    Section,
    exactly_one_form,
    fail,
    given_fields,
    integer,
    quantity,
)
from rotorsfd.io.units import UnitError, describe, to_si
from rotorsfd.model.node_names import BadNodeName, resolve_shaft_nodes

# ---- materials and rotor -----------------------------------------------------------------


class MaterialConfig(Section):
    """Isotropic material; give the shear modulus or Poisson's ratio."""

    density: quantity("density", "mass density rho", gt=0)
    young_modulus: quantity("modulus", "Young's modulus E", gt=0)
    shear_modulus: quantity("modulus", "shear modulus G (or give poisson_ratio)", gt=0,
                            optional=True) = None
    poisson_ratio: quantity("ratio", "Poisson's ratio nu (G = E / (2 (1 + nu)))",
                            gt=-1, le=0.5, optional=True) = None

    @model_validator(mode="after")
    def _one_shear_form(self):
        exactly_one_form(self, {"G": ("shear_modulus",), "nu": ("poisson_ratio",)})
        if self.shear_modulus is not None:
            nu = self.young_modulus / (2 * self.shear_modulus) - 1
            if not -1 < nu <= 0.5:
                raise fail("shear_modulus", self.shear_modulus,
                           f"E/(2G) - 1 = {nu:.4g} must lie in (-1, 0.5]")
        return self

    @property
    def resolved_shear_modulus(self) -> float:
        """G, given or from E and nu."""
        if self.shear_modulus is not None:
            return self.shear_modulus
        return self.young_modulus / (2.0 * (1.0 + self.poisson_ratio))


class ShaftSectionConfig(Section):
    """A uniform hollow shaft section, meshed into ``n_elements`` equal Timoshenko elements.
    Sections follow each other along x; element i joins nodes i and i+1."""

    length: quantity("length", "section length", gt=0)
    n_elements: integer("number of equal finite elements in the section", ge=1, le=2000)
    inner_radius: quantity("length", "bore radius (0 for a solid shaft)", ge=0) = 0.0
    outer_radius: quantity("length", "outer radius", gt=0)
    material: NAME
    shear_coefficient: quantity("ratio", "Timoshenko shear coefficient kappa (default: "
                                "hollow-circle formula of Hutchinson)", gt=0, le=1,
                                optional=True) = None

    @model_validator(mode="after")
    def _radii(self):
        if not self.inner_radius < self.outer_radius:
            raise fail("inner_radius", self.inner_radius,
                       f"must be < outer_radius = {self.outer_radius:g} m")
        return self


class DiskConfig(Section):
    """Rigid disk: by geometry (radii, thickness, material) or by mass and inertias."""

    node: NODE
    name: LABEL = ""
    material: Annotated[str | None, Field(description="material (geometry form); allowed: "
                                          "the name of a [materials.<name>] table")] = None
    inner_radius: quantity("length", "bore radius (geometry form; default 0, a solid disk)",
                           ge=0, optional=True) = None
    outer_radius: quantity("length", "outer radius (geometry form)", gt=0, optional=True) = None
    thickness: quantity("length", "axial thickness (geometry form)", gt=0, optional=True) = None
    mass: quantity("mass", "mass (inertia form)", ge=0, optional=True) = None
    polar_inertia: quantity("inertia", "polar moment of inertia Ip (inertia form)", ge=0,
                            optional=True) = None
    diametral_inertia: quantity("inertia", "diametral moment of inertia Id (inertia form)",
                                ge=0, optional=True) = None

    @model_validator(mode="after")
    def _one_form(self):
        form = exactly_one_form(
            self,
            {"geometry": ("material", "inner_radius", "outer_radius", "thickness"),
             "inertia": ("mass", "polar_inertia", "diametral_inertia")},
            {"geometry": ("material", "outer_radius", "thickness"),
             "inertia": ("mass", "polar_inertia", "diametral_inertia")},
        )
        if form == "geometry" and not (self.inner_radius or 0.0) < self.outer_radius:
            raise fail("inner_radius", self.inner_radius,
                       f"must be < outer_radius = {self.outer_radius:g} m")
        return self


class PointMassConfig(Section):
    """Lumped mass on the lateral DOFs of a node (no rotary inertia)."""

    node: NODE
    mass: quantity("mass", "mass", ge=0)


class SupportConfig(Section):
    """Linear support to ground: isotropic (stiffness, damping) or by coefficients
    (kyy, kzz, kyz, kzy; cyy, czz, cyz, czy). Cross terms may be negative."""

    node: NODE
    name: LABEL = ""
    stiffness: quantity("stiffness", "isotropic stiffness kyy = kzz", ge=0,
                        optional=True) = None
    kyy: quantity("stiffness", "direct stiffness along y", ge=0, optional=True) = None
    kzz: quantity("stiffness", "direct stiffness along z", ge=0, optional=True) = None
    kyz: quantity("stiffness", "cross stiffness (Fy from z)", optional=True) = None
    kzy: quantity("stiffness", "cross stiffness (Fz from y)", optional=True) = None
    damping: quantity("damping", "isotropic damping cyy = czz", ge=0, optional=True) = None
    cyy: quantity("damping", "direct damping along y", ge=0, optional=True) = None
    czz: quantity("damping", "direct damping along z", ge=0, optional=True) = None
    cyz: quantity("damping", "cross damping (Fy from z')", optional=True) = None
    czy: quantity("damping", "cross damping (Fz from y')", optional=True) = None

    @model_validator(mode="after")
    def _forms(self):
        exactly_one_form(self, {"isotropic": ("stiffness",),
                                 "coefficients": ("kyy", "kzz", "kyz", "kzy")},
                          {"isotropic": ("stiffness",), "coefficients": ("kyy", "kzz")})
        damping_terms = given_fields(self, ("cyy", "czz", "cyz", "czy"))
        if self.damping is not None and damping_terms:
            raise fail("damping", self.damping,
                       "give either damping or (cyy, czz, cyz, czy), not both")
        if damping_terms and (self.cyy is None or self.czz is None):
            raise fail("cyy" if self.cyy is None else "czz", None,
                       "required with damping coefficients: give both cyy and czz")
        return self

    def coefficients(self) -> dict[str, float]:
        """The eight coefficients kyy..czy in SI, from either form (zero if not given)."""
        k, c = self.stiffness, self.damping
        iso = {"kyy": k, "kzz": k, "cyy": c, "czz": c}
        names = ("kyy", "kzz", "kyz", "kzy", "cyy", "czz", "cyz", "czy")
        return {n: float(getattr(self, n) if getattr(self, n) is not None else iso.get(n) or 0.0)
                for n in names}


class DampingConfig(Section):
    """Structural damping of the shaft: none, Rayleigh (C = alpha M + beta K) or an equal
    modal damping ratio on the undamped non-rotating modes."""

    kind: Literal["none", "rayleigh", "modal"] = Field(
        "none", description="'none'; 'rayleigh' (alpha, beta); 'modal' (ratio, modes)")
    alpha: quantity("rayleigh_alpha", "Rayleigh mass coefficient alpha", ge=0,
                    optional=True) = None
    beta: quantity("rayleigh_beta", "Rayleigh stiffness coefficient beta", ge=0,
                   optional=True) = None
    ratio: quantity("ratio", "modal damping ratio zeta", ge=0, lt=1, optional=True) = None
    modes: integer("kind = 'modal': damp only the lowest this many modes (default: every "
                   "mode; a few modes keep large models banded)", ge=1,
                   optional=True) = None

    @model_validator(mode="after")
    def _fields_of_kind(self):
        needs = {"none": (), "rayleigh": ("alpha", "beta"),
                 "modal": ("ratio", "modes")}[self.kind]
        for name in ("alpha", "beta", "ratio", "modes"):
            given = getattr(self, name) is not None
            if given and name not in needs:
                raise fail(name, getattr(self, name), f"not used with kind = {self.kind!r}")
        if self.kind == "rayleigh" and not given_fields(self, ("alpha", "beta")):
            raise fail("alpha", None, "kind = 'rayleigh' needs alpha and/or beta")
        if self.kind == "modal" and self.ratio is None:
            raise fail("ratio", None, "kind = 'modal' needs the damping ratio")
        return self


class MatricesConfig(Section):
    """A linear rotor given by its matrices (a user's own FE model) in place of the shaft:
    one .npz file, or Matrix Market files and a DOF map; paths relative to the config
    file's folder (docs/interop.md)."""

    file: Annotated[str | None, Field(description=".npz archive with the arrays M, K (C, G, "
                                      "dof_node, dof_direction, node_x, base_matrices, "
                                      "base_vectors optional); allowed: a file path")] = None
    mass: Annotated[str | None, Field(description="Matrix Market file of M (instead of "
                                      "file); allowed: a file path")] = None
    stiffness: Annotated[str | None, Field(description="Matrix Market file of K; allowed: "
                                           "a file path")] = None
    damping: Annotated[str | None, Field(description="Matrix Market file of C (default "
                                         "0); allowed: a file path")] = None
    gyroscopic: Annotated[str | None, Field(description="Matrix Market file of G, the "
                                            "gyroscopic matrix per unit speed (default 0); "
                                            "allowed: a file path")] = None
    dof_map: Annotated[str | None, Field(description="CSV file with the columns node, "
                                         "direction (y, z, ty, tz, -ty, ...; x, tx dropped) "
                                         "and optionally x, one line per matrix row "
                                         "(default: the arrays of the .npz); allowed: a "
                                         "file path")] = None
    n_nodes: integer("number of nodes of the model (nodes 1..n_nodes, 4 DOFs each)", ge=2,
                     le=100000)

    @model_validator(mode="after")
    def _one_form(self):
        exactly_one_form(self, {"npz": ("file",),
                                "matrix market": ("mass", "stiffness", "damping",
                                                  "gyroscopic")},
                         {"npz": ("file",), "matrix market": ("mass", "stiffness")})
        if self.file is None and self.dof_map is None:
            raise fail("dof_map", None, "Matrix Market files need a dof_map (CSV: node, "
                       "direction per matrix row)")
        return self


class ShaftConfig(Section):
    """One shaft of a multi-shaft rotor (``[[rotor.shafts]]``): its sections, disks, point
    masses and supports, its speed ratio and axial start. Nodes are global, numbered in the
    order of the shafts (shaft 1: 1..n_1, shaft 2: n_1 + 1..n_1 + n_2, ...); this shaft's
    disks, masses and supports must be at its own nodes."""

    name: Annotated[str, Field(pattern=NAME_PATTERN, description="shaft name (in messages "
                               "and DOF names, y@<name>.<local node>); allowed: letters, "
                               "digits, '_' and '-'")]
    speed_ratio: quantity("ratio", "speed of this shaft / the continuation speed (the "
                          "first shaft's is 1)", gt=0) = 1.0
    x_start: quantity("length", "axial position of the shaft's first node") = 0.0
    sections: list[ShaftSectionConfig] = Field(min_length=1, description="shaft sections, "
                                               "left to right")
    disks: list[DiskConfig] = []
    point_masses: list[PointMassConfig] = []
    supports: list[SupportConfig] = []

    @property
    def n_nodes(self) -> int:
        return sum(s.n_elements for s in self.sections) + 1


class IntershaftConfig(SupportConfig):
    """Linear intershaft bearing between ``node`` (inner shaft) and ``outer_node`` (another
    shaft), on the relative displacement: the coefficients of a support."""

    outer_node: NODE


class RotorConfig(Section):
    """The finite-element rotor. Nodes are numbered 1..N along x from ``x_start``; a
    multi-shaft rotor (``[[rotor.shafts]]``) numbers them globally in the order of the
    shafts, each shaft from its own ``x_start``."""

    x_start: quantity("length", "axial position of node 1") = 0.0
    shaft: list[ShaftSectionConfig] = Field([], description="shaft sections, left to "
                                            "right (or give matrices, or shafts)")
    shafts: list[ShaftConfig] = Field([], description="several coaxial shafts, each at "
                                      "its own speed (instead of shaft)")
    intershaft: list[IntershaftConfig] = Field([], description="linear bearings between "
                                               "nodes of two shafts (with shafts)")
    disks: list[DiskConfig] = []
    point_masses: list[PointMassConfig] = []
    supports: list[SupportConfig] = []
    damping: DampingConfig = DampingConfig()
    matrices: MatricesConfig | None = None

    @model_validator(mode="after")
    def _shaft_or_matrices(self):
        forms = [bool(self.shaft), self.matrices is not None, bool(self.shafts)]
        if sum(forms) != 1:
            raise fail("shaft", len(self.shaft), "give the shaft ([[rotor.shaft]] sections), "
                       "its matrices ([rotor.matrices]) or several shafts "
                       "([[rotor.shafts]]), exactly one")
        if self.intershaft and not self.shafts:
            raise fail("intershaft", len(self.intershaft), "intershaft bearings need "
                       "several shafts ([[rotor.shafts]])")
        if self.shafts:
            if self.shafts[0].speed_ratio != 1.0:
                raise fail(("shafts", 0, "speed_ratio"), self.shafts[0].speed_ratio,
                           "the first shaft's ratio must be 1 (its speed is the "
                           "continuation speed)")
            names = [s.name for s in self.shafts]
            for i, name in enumerate(names):
                if name in names[:i]:
                    raise fail(("shafts", i, "name"), name, "shaft names must be distinct")
            if self.x_start != 0.0:
                raise fail("x_start", self.x_start, "with shafts, give each shaft's x_start")
        return self

    @property
    def n_nodes(self) -> int:
        """Number of nodes: total elements + 1 (or the matrices' n_nodes; with shafts, the
        sum over the shafts)."""
        if self.matrices is not None:
            return self.matrices.n_nodes
        if self.shafts:
            return sum(s.n_nodes for s in self.shafts)
        return sum(s.n_elements for s in self.shaft) + 1

    def shaft_ranges(self) -> list[tuple[int, int]]:
        """(first, last) global node of each of ``shafts``."""
        out, first = [], 1
        for s in self.shafts:
            out.append((first, first + s.n_nodes - 1))
            first += s.n_nodes
        return out

    def shaft_of(self, node: int) -> int | None:
        """0-based index in ``shafts`` of global ``node`` (None without shafts or out of
        range)."""
        for k, (lo, hi) in enumerate(self.shaft_ranges()):
            if lo <= node <= hi:
                return k
        return None

    @property
    def all_disks(self) -> list[DiskConfig]:
        """The disks of the rotor table and of every shaft."""
        return list(self.disks) + [d for s in self.shafts for d in s.disks]


# ---- squeeze film damper -----------------------------------------------------------------


#: One ``[elements.<name>]`` table: the config model of its ``kind``.
ElementTable = Annotated[reduce(operator.or_, KINDS.values()), Field(discriminator="kind")] \
    if len(KINDS) > 1 else next(iter(KINDS.values()))


# ---- loads: unbalance, base motion, gravity ---------------------------------------------------


class UnbalanceConfig(Section):
    """Unbalance U = m e at a node; force U Omega^2 rotating with the shaft, at angle
    Omega t + phase from +y towards +z (several shafts: Omega is the speed of the node's
    shaft, r Omega)."""

    node: NODE
    magnitude: quantity("unbalance", "unbalance m*e", ge=0)
    phase: quantity("angle", "angular position at t = 0") = 0.0
    start: quantity("time", "time from which it acts in the time domain (a sudden unbalance, "
                    "e.g. a blade loss, appearing at the rotor angle of that instant); "
                    "steady-state analyses see every unbalance", ge=0) = 0.0
    rise_time: quantity("time", "time over which a sudden unbalance grows to its magnitude, "
                        "(1 - cos(pi s / rise_time)) / 2 (0: a step, resolved to first order "
                        "by a fixed time step)", ge=0) = 0.0


_LAW_DOC = ("time law: 'off'; 'constant' (value); 'harmonic' (value + amplitude * "
            "sin(frequency t + phase)); 'callable' (a Python function f(t), vectorised "
            "over numpy arrays of t)")
_RECORDED_DOC = ("; 'table' (a recorded history: file or times/values of the quantity, "
                 "splined, optionally low-pass filtered); 'pulse' (a half-sine or versine "
                 "shock: shape, amplitude, duration, start)")
_TRANSLATION_LAW_DOC = _LAW_DOC + "; 'uniform_acceleration' (value + velocity t + " \
    "acceleration t^2 / 2)" + _RECORDED_DOC
_RECORD_FIELDS = ("file", "times", "values", "quantity", "filter")


class _Component(Section):
    frequency: quantity("angular_velocity", "angular frequency w of the harmonic law", ge=0,
                        optional=True) = None
    phase: quantity("angle", "phase of the harmonic law", optional=True) = None
    callable: CALLABLE = None
    derivative: CALLABLE = Field(None, description="the derivative f'(t) of the callable "
                                 "law (default: by complex step); allowed: 'module:function'")
    file: str | None = Field(None, description="the 'table' law's record: a CSV file of two "
                             "columns, time [s] and the quantity [SI] (one header line "
                             "allowed), or a netCDF file with one variable over 'time'; "
                             "relative to the config file's folder")
    times: list[float] | None = Field(None, description="the 'table' law's sample times [s] "
                                      "(instead of file)")
    values: list[float] | None = Field(None, description="the 'table' law's samples of the "
                                       "quantity [SI] (instead of file)")
    filter: quantity("angular_velocity", "cut-off of the zero-phase 4th-order Butterworth "
                     "low-pass applied to the record before it is splined (default: none, "
                     "the spline through the samples)", gt=0, optional=True) = None
    shape: Literal["half_sine", "versine"] | None = Field(
        None, description="the 'pulse' law's shape: A sin(pi s/T) or (A/2)(1 - cos(2 pi s/T)) "
                          "on 0 <= s <= T")
    duration: quantity("time", "the 'pulse' law's duration T", gt=0, optional=True) = None
    start: quantity("time", "the 'pulse' law's start time", ge=0, optional=True) = None

    _alt_amplitude: ClassVar[str] = ""  # name of the alternative amplitude field
    _law_fields: ClassVar[dict[str, tuple[str, ...]]] = {}  # fields of extra laws

    @model_validator(mode="after")
    def _fields_of_law(self):
        amps = ("amplitude", self._alt_amplitude)
        uses = {"off": (), "constant": ("value",),
                "harmonic": ("value", "frequency", "phase", *amps),
                "callable": ("callable", "derivative"), **self._law_fields}[self.law]
        names = ("value", "frequency", "phase", "callable", "derivative", *amps,
                 *{f for fields in self._law_fields.values() for f in fields})
        for name in names:
            if getattr(self, name) is not None and name not in uses:
                raise fail(name, getattr(self, name), f"not used with law = {self.law!r}")
        if self.law == "constant" and self.value is None:
            raise fail("value", None, "law = 'constant' needs a value")
        if self.law == "table":
            if (self.file is None) == (self.times is None):
                raise fail("file", self.file, "law = 'table' needs file or times/values")
            if (self.times is None) != (self.values is None):
                raise fail("values", self.values, "times and values go together")
            if self.quantity is None:
                raise fail("quantity", None, f"law = 'table' needs the recorded quantity: "
                           f"{' or '.join(repr(q) for q in self._quantities)}")
        if self.law == "pulse":
            for name in ("shape", "duration", self._pulse_amplitude):
                if getattr(self, name) is None:
                    raise fail(name, None, f"law = 'pulse' needs shape, "
                               f"{self._pulse_amplitude} and duration")
        if self.law == "callable" and self.callable is None:
            raise fail("callable", None, "law = 'callable' needs callable = 'module:function'")
        if self.law == "harmonic":
            if self.frequency is None:
                raise fail("frequency", None, "law = 'harmonic' needs a frequency")
            if (self.amplitude is None) == (getattr(self, self._alt_amplitude) is None):
                raise fail("amplitude", self.amplitude,
                           f"law = 'harmonic' needs exactly one of amplitude, "
                           f"{self._alt_amplitude}")
        return self


class RotationComponent(_Component):
    """A base rotation rate w_b(t) [rad/s] in the base frame. For the harmonic law the
    rate amplitude may be given as the angle amplitude A0 (paper section 3.3):
    w_b = A0 w sin(w t + phase)."""

    law: Literal["off", "constant", "harmonic", "callable", "table", "pulse"] = Field(
        "off", description=_LAW_DOC + _RECORDED_DOC)
    value: quantity("angular_velocity", "constant rate, or mean rate of the harmonic law",
                    optional=True) = None
    amplitude: quantity("angular_velocity", "rate amplitude", ge=0, optional=True) = None
    angle_amplitude: quantity("angle", "angle amplitude A0 (rate amplitude = A0 * frequency)",
                              ge=0, optional=True) = None
    # (the field named quantity comes last: below it the name is the field, not quantity())
    quantity: Literal["rate", "angle"] | None = Field(
        None, description="what the 'table' law's record holds: the rate [rad/s] or the "
                          "angle [rad] (differentiated through the spline)")
    _alt_amplitude: ClassVar[str] = "angle_amplitude"
    _quantities: ClassVar[tuple[str, ...]] = ("rate", "angle")
    _pulse_amplitude: ClassVar[str] = "amplitude"
    _law_fields: ClassVar[dict[str, tuple[str, ...]]] = {
        "table": _RECORD_FIELDS, "pulse": ("shape", "amplitude", "duration", "start")}

    def rate_amplitude(self) -> float:
        """Amplitude of the rate [rad/s] for the harmonic law."""
        if self.amplitude is not None:
            return self.amplitude
        return (self.angle_amplitude or 0.0) * (self.frequency or 0.0)


class TranslationComponent(_Component):
    """Base-origin displacement x0(t) [m] along a base axis (its derivatives enter the
    equations; a constant displacement has no effect). For the harmonic law the amplitude
    may be given as an acceleration amplitude a: x0 = -(a / w^2) sin(w t + phase)."""

    law: Literal["off", "constant", "uniform_acceleration", "harmonic", "callable", "table",
                 "pulse"] = Field(
        "off", description=_TRANSLATION_LAW_DOC)
    value: quantity("length", "constant displacement, or mean / initial displacement",
                    optional=True) = None
    amplitude: quantity("length", "displacement amplitude", ge=0, optional=True) = None
    acceleration_amplitude: quantity("acceleration", "acceleration amplitude a "
                                     "(displacement amplitude = a / frequency^2)", ge=0,
                                     optional=True) = None
    acceleration: quantity("acceleration", "constant acceleration (uniform_acceleration law)",
                           optional=True) = None
    velocity: quantity("velocity", "initial velocity (uniform_acceleration law)",
                       optional=True) = None
    # (last, as in RotationComponent)
    quantity: Literal["displacement", "velocity", "acceleration"] | None = Field(
        None, description="what the 'table' law's record holds: displacement [m], velocity "
                          "[m/s] or acceleration [m/s^2] (integrated from rest)")
    _alt_amplitude: ClassVar[str] = "acceleration_amplitude"
    _quantities: ClassVar[tuple[str, ...]] = ("displacement", "velocity", "acceleration")
    _pulse_amplitude: ClassVar[str] = "acceleration_amplitude"
    _law_fields: ClassVar[dict[str, tuple[str, ...]]] = {
        "uniform_acceleration": ("value", "velocity", "acceleration"),
        "table": _RECORD_FIELDS,
        "pulse": ("shape", "acceleration_amplitude", "duration", "start")}

    @model_validator(mode="after")
    def _uniform(self):
        if self.law == "uniform_acceleration" and self.acceleration is None:
            raise fail("acceleration", None, "law = 'uniform_acceleration' needs acceleration")
        if self.law == "harmonic" and self.acceleration_amplitude is not None \
                and not self.frequency > 0:
            raise fail("frequency", self.frequency,
                       "must be > 0 with acceleration_amplitude")
        return self

    def displacement_amplitude(self) -> tuple[float, float]:
        """(amplitude [m], phase [rad]) of the harmonic law, from either amplitude form."""
        phase = self.phase or 0.0
        if self.amplitude is not None:
            return self.amplitude, phase
        return (self.acceleration_amplitude or 0.0) / self.frequency**2, phase + math.pi


class BaseConfig(Section):
    """Base motion in the base frame: rotation rates (rolling about the shaft axis x,
    pitching about y, yawing about z) and translations of the origin along x, y, z."""

    rolling: RotationComponent = RotationComponent()
    pitching: RotationComponent = RotationComponent()
    yawing: RotationComponent = RotationComponent()
    x: TranslationComponent = TranslationComponent()
    y: TranslationComponent = TranslationComponent()
    z: TranslationComponent = TranslationComponent()

    @property
    def is_fixed(self) -> bool:
        """True when every component is off."""
        return all(getattr(self, c).law == "off"
                   for c in ("rolling", "pitching", "yawing", "x", "y", "z"))


class GravityConfig(Section):
    """Gravity, applied as a base translational acceleration (it tilts with the base)."""

    enabled: StrictBool = Field(False, description="include gravity (the paper neglects it)")
    magnitude: quantity("acceleration", "gravitational acceleration g", ge=0) = 9.80665
    direction: list[float] = Field([0.0, 0.0, -1.0], min_length=3, max_length=3,
                                   description="direction (x, y, z) of g in the base frame "
                                               "at t = 0, normalised on use; allowed: 3 "
                                               "finite numbers, not all zero")
    frame: Literal["inertial", "base"] = Field(
        "inertial", description="'inertial': g fixed in space (turns in the base frame as "
                                "the base rotates); 'base': g fixed to the base")

    @model_validator(mode="after")
    def _direction(self):
        if not math.hypot(*self.direction) > 0 or not all(map(math.isfinite, self.direction)):
            raise fail("direction", self.direction, "must be a finite nonzero 3-vector")
        return self


def _speed_or_keyword(value: Any) -> Any:
    if isinstance(value, str) and value.strip() == "first_critical":
        return "first_critical"
    try:
        return to_si(value, "angular_velocity")
    except UnitError:
        raise PydanticCustomError("rotorsfd", "{allowed}", {
            "allowed": f"expected 'first_critical' or {describe('angular_velocity')}"}) \
            from None


class ReferenceConfig(Section):
    """Reference speed of the dimensionless speed Omega~ = Omega / Omega_ref."""

    speed: Annotated[float | Literal["first_critical"], BeforeValidator(_speed_or_keyword),
                     Field(description="Omega_ref, or 'first_critical': the first forward "
                                       "critical speed, computed [rad/s]; allowed: > 0 "
                                       "rad/s, or 'first_critical'")
                     ] = "first_critical"

    @model_validator(mode="after")
    def _positive(self):
        if isinstance(self.speed, float) and not self.speed > 0:
            raise fail("speed", self.speed, "must be > 0 rad/s or 'first_critical'")
        return self


# ---- analyses ------------------------------------------------------------------------------


class SpeedRange(Section):
    """A range of rotor speeds, in rad/s (start, stop) or as Omega~ = Omega/Omega_ref
    (start_ratio, stop_ratio)."""

    start: quantity("angular_velocity", "first speed", ge=0, optional=True) = None
    stop: quantity("angular_velocity", "last speed", gt=0, optional=True) = None
    start_ratio: quantity("ratio", "first speed / reference speed", ge=0, optional=True) = None
    stop_ratio: quantity("ratio", "last speed / reference speed", gt=0, optional=True) = None
    n: integer("number of speeds (grids only)", ge=2, le=100000) = 101

    @model_validator(mode="after")
    def _one_form(self):
        form = exactly_one_form(self, {"rad/s": ("start", "stop"),
                                        "ratio": ("start_ratio", "stop_ratio")})
        a, b = (("start", "stop") if form == "rad/s" else ("start_ratio", "stop_ratio"))
        if getattr(self, a) == getattr(self, b):
            raise fail(b, getattr(self, b), f"must differ from {a}")
        return self

    def bounds(self, reference_speed: float) -> tuple[float, float]:
        """(start, stop) in rad/s."""
        if self.start is not None:
            return self.start, self.stop
        return self.start_ratio * reference_speed, self.stop_ratio * reference_speed


PARAMETER_DOC = ("'speed' or the dotted path of a scalar config field, e.g. "
                 "'base.pitching.value', 'unbalance[0].magnitude', "
                 "'elements.sfd.clearance_ratio'")


def _path_field(doc: str) -> Any:
    return Annotated[str, Field(pattern=r"^[A-Za-z_][\w]*(\[\d+\]|\.\w+)*$",
                                description=f"{doc}; allowed: {PARAMETER_DOC}")]


_PARAMETER_VALUE = "a number in SI units or a string with the parameter's units"


class ParameterAxis(Section):
    """A grid over one scalar config field (or 'speed'); values take that field's units."""

    parameter: _path_field("the parameter of the axis")
    start: Any = Field(None, description=f"first value; allowed: {_PARAMETER_VALUE}")
    stop: Any = Field(None, description=f"last value; allowed: {_PARAMETER_VALUE}")
    n: integer("number of grid values", ge=1, le=100000) = 11
    values: list[Any] | None = Field(None, description="explicit values instead of "
                                     f"start/stop/n; allowed: a list, each {_PARAMETER_VALUE}")

    @model_validator(mode="after")
    def _form(self):
        if self.values is not None:
            if self.start is not None or self.stop is not None:
                raise fail("values", self.values, "give values or start/stop/n, not both")
            if not self.values:
                raise fail("values", self.values, "must not be empty")
        elif self.start is None or self.stop is None:
            raise fail("start" if self.start is None else "stop", None,
                       "give start and stop (or values)")
        return self


class ModalAnalysis(Section):
    """Campbell diagram and critical speeds of the linear rotor (the nonlinear elements
    excluded; their linear parts, such as an SFD's centring spring, included)."""

    speeds: list[quantity("angular_velocity", "speed", ge=0)] | None = Field(
        None, description="explicit list of speeds [rad/s] (instead of speed_range)")
    speed_range: SpeedRange = SpeedRange(start_ratio=0.0, stop_ratio=4.0, n=81)
    n_modes: integer("number of modes per speed", ge=1, le=200) = 8
    n_critical: integer("number of critical speeds to locate", ge=1, le=50) = 2
    whirl: Literal["forward", "backward"] = Field(
        "forward", description="whirl direction of the critical speeds")
    critical_speed_max: quantity("angular_velocity", "upper end of the critical-speed search",
                                 gt=0) = 2.0e4
    spool: str | None = Field(None, description="several shafts: the [[rotor.shafts]] name "
                              "whose speed the Campbell diagram and critical speeds are "
                              "against (default: the first shaft)")


class ResponseAnalysis(Section):
    """Periodic response by harmonic balance (HB-AFT) with arc-length continuation."""

    harmonics: Annotated[Literal["auto"] | int, Field(
        description="number of harmonics H, or 'auto': H follows the branch so that the "
                    "truncation error estimate stays below harmonics_tolerance; allowed: "
                    '"auto" or an integer 1 <= value <= 64')] = "auto"
    harmonics_tolerance: quantity(
        "ratio", "largest HB truncation error estimate (the change of the solution if "
        "about 1.5 H harmonics were kept, 2-norm over the coefficients of the nonlinear "
        "elements' DOFs, in "
        "clearances); with a fixed H a warning says where it is exceeded", gt=0,
        lt=1) = 1e-3
    harmonics_min: integer("smallest H with harmonics = 'auto'", ge=1, le=64) = 1
    harmonics_max: integer("largest H with harmonics = 'auto'", ge=1, le=64) = 32
    n_samples: integer("time samples per period N_f of the AFT (default: chosen free of "
                       "aliasing)", ge=3, le=65536, optional=True) = None
    base_harmonics: integer("highest base harmonic H2 of a torus (harmonic base law): the "
                            "box |k1| <= harmonics, |k2| <= H2", ge=1, le=64) = 2
    parameter: _path_field("continuation parameter") = "speed"
    speed_range: SpeedRange = SpeedRange(start_ratio=0.5, stop_ratio=1.6)
    speed: quantity("angular_velocity", "fixed speed when the parameter is not 'speed'",
                    gt=0, optional=True) = None
    speed_ratio: quantity("ratio", "fixed speed / reference speed when the parameter is "
                          "not 'speed'", gt=0, optional=True) = None
    parameter_range: list[Any] | None = Field(
        None, min_length=2, max_length=2,
        description="[start, stop] of a non-speed parameter; allowed: a list of 2 items, "
                    f"each {_PARAMETER_VALUE}")
    step_initial: quantity("ratio", "initial arc-length step (scaled variables)", gt=0) = 0.01
    step_min: quantity("ratio", "smallest step before the branch stops", gt=0) = 1e-6
    step_max: quantity("ratio", "largest step", gt=0) = 0.1
    max_points: integer("maximum number of continuation points", ge=2, le=1000000) = 5000
    tolerance: quantity("ratio", "Newton convergence threshold (scaled residual)", gt=0,
                        lt=1) = 1e-6
    max_iterations: integer("Newton iterations per point", ge=1, le=1000) = 20
    max_tangent_angle: quantity("angle", "largest angle between successive tangents", gt=0,
                                le=math.pi / 2) = math.radians(10.0)
    max_eccentricity: quantity("ratio", "step limiter: every element's validity measure (a film's "
                                "eccentricity ratio) kept below",
                               gt=0, lt=1) = 0.95
    condensed: bool = Field(True, description="condense exactly onto the nonlinear "
                                                  "elements' DOFs")
    nodes: list[NODE] = Field([], description="output nodes (default: element and disk "
                                                      "nodes)")
    directions: list[Literal["y", "z"]] = Field(["y", "z"], min_length=1,
                                                description="output directions")

    @field_validator("harmonics", mode="before")
    @classmethod
    def _harmonics(cls, value: Any) -> Any:
        allowed = "must be 'auto' or an integer 1 <= H <= 64"
        if isinstance(value, str):
            text = value.strip().strip("'\"")
            if text == "auto":
                return "auto"
            try:
                value = int(text)
            except ValueError:
                raise fail((), value, allowed) from None
        if isinstance(value, bool) or not isinstance(value, int | float) \
                or value != int(value) or not 1 <= value <= 64:
            raise fail((), value, allowed)
        return int(value)

    def fixed_speed(self, reference_speed: float) -> float:
        """The fixed speed [rad/s] when the parameter is not 'speed'."""
        return self.speed if self.speed is not None else self.speed_ratio * reference_speed

    @property
    def adaptive_harmonics(self) -> bool:
        """True when H follows the branch (``harmonics = 'auto'``)."""
        return self.harmonics == "auto"

    @property
    def start_harmonics(self) -> int:
        """H of the first point: the given H, or 3 (within [harmonics_min, harmonics_max])
        with 'auto'."""
        if self.harmonics != "auto":
            return int(self.harmonics)
        return min(max(3, self.harmonics_min), self.harmonics_max)

    @model_validator(mode="after")
    def _parameter(self):
        if self.parameter == "speed":
            for name in ("speed", "speed_ratio", "parameter_range"):
                if getattr(self, name) is not None:
                    raise fail(name, getattr(self, name),
                               "only used when the parameter is not 'speed'")
        else:
            if (self.speed is None) == (self.speed_ratio is None):
                raise fail("speed", self.speed, f"parameter = {self.parameter!r} needs "
                           "exactly one fixed speed: speed or speed_ratio")
            if self.parameter_range is None:
                raise fail("parameter_range", None,
                           f"parameter = {self.parameter!r} needs parameter_range")
        if self.harmonics_min > self.harmonics_max:
            raise fail("harmonics_min", self.harmonics_min,
                       f"must be <= harmonics_max = {self.harmonics_max}")
        if not self.step_min <= self.step_initial <= self.step_max:
            raise fail("step_initial", self.step_initial,
                       f"must lie in [step_min, step_max] = [{self.step_min:g}, "
                       f"{self.step_max:g}]")
        return self


class StabilityAnalysis(Section):
    """Floquet stability of periodic solutions."""

    enabled: bool = Field(True, description="compute the stability of every point")
    method: Literal["newmark-cb", "newmark", "generalized-alpha", "generalized-alpha-cb",
                    "hill", "hill-koopman"] = Field(
        "newmark-cb", description="Newmark monodromy on the Craig-Bampton reduced model "
        "(newmark-cb, default), on the full model (newmark: the paper's literal method; its "
        "undamped structural modes sit at |mu| = 1), generalized-alpha, or Hill's method")
    intervals: integer("Newmark intervals per period M (paper: 400); with "
                       "adaptive_intervals the M of the first point", ge=10,
                       le=100000) = 400
    adaptive_intervals: bool = Field(
        True, description="step control of the Newmark monodromy: M doubled until the "
        "largest multipliers' error estimate (from M and M/2) is <= interval_tolerance; "
        "false: M = intervals throughout")
    interval_tolerance: quantity("ratio", "largest error estimate of the largest Floquet "
                                 "multipliers with adaptive_intervals", gt=0, lt=1) = 1e-4
    max_intervals: integer("largest M with adaptive_intervals", ge=10,
                           le=1000000) = 12800
    check_bifurcations: bool = Field(
        True, description="re-locate every bifurcation on a piece of the branch computed "
        "with about 1.5 H harmonics and twice the Floquet intervals; one that vanishes or "
        "moves by more than check_tolerance is reported as unconfirmed")
    check_tolerance: quantity("ratio", "relative shift of the parameter allowed when a "
                              "bifurcation is re-located", gt=0, lt=1) = 1e-3
    tolerance: quantity("ratio", "unstable when |mu|max > 1 + tolerance (rotorsfd."
                        "stability.STABILITY_TOL)", ge=0, lt=1) = 1e-5
    locate_tolerance: quantity("ratio", "relative parameter tolerance of located "
                               "bifurcations", gt=0, lt=1) = 1e-6
    n_modes: integer("fixed-interface modes kept with the elements' DOFs in the reduced "
                     "model "
                     "(default: those with omega h <= 1/4)", ge=1, le=10000,
                     optional=True) = None
    basis: Literal["reduced", "full"] = Field(
        "reduced", description="Floquet basis: reduced (the method's Craig-Bampton model; "
        "max_multiplier_outside gives the left-out modes) or full (the unreduced "
        "monodromy of the whole model, for a check: newmark-cb becomes newmark)")


class StabilityChartAnalysis(Section):
    """Stability chart of the linear rotor under time-periodic base motion (paper Fig. 6):
    the maximum Floquet multiplier over a grid of two parameters at a fixed speed."""

    x: ParameterAxis | None = None
    y: ParameterAxis | None = None
    speed: quantity("angular_velocity", "rotor speed", gt=0, optional=True) = None
    intervals: integer("Newmark intervals per base period", ge=10, le=100000) = 400


class SimulateAnalysis(Section):
    """Time integration of the nonlinear rotor (Newmark)."""

    speed: quantity("angular_velocity", "rotor speed (or give speed_ratio)", gt=0,
                    optional=True) = None
    speed_ratio: quantity("ratio", "rotor speed / reference speed", gt=0,
                          optional=True) = None
    scheme: Literal["newmark", "hht", "generalized-alpha"] = Field(
        "newmark", description="time integration scheme (newmark: average acceleration)")
    alpha: quantity("ratio", "HHT alpha / generalized-alpha spectral radius parameter",
                    ge=-1 / 3, le=1) = 0.0
    steps_per_period: Literal["auto"] | Annotated[int, Field(ge=8, le=1000000)] = Field(
        "auto", description="time steps per rotor period: \"auto\" halves the step from "
        "T/200 until one halving moves the journal orbit by less than step_tolerance (the "
        "transient at T/200, the recorded periods at the accepted step), or a fixed number "
        "(paper: 200), checked by one halving; allowed: \"auto\" or an integer, 8 <= "
        "value <= 1000000")
    step_tolerance: quantity("ratio", "largest change of the journal orbit from one halving "
                             "of the step, in the first element's clearance (the orbit's "
                             "max radius without elements); a fixed step above it draws a "
                             "warning",
                             gt=0, le=1) = 1e-3
    max_steps_per_period: integer("the finest step of \"auto\" (a warning if the step has "
                                  "not converged there)", ge=16, le=1000000) = 3200
    periods: integer("number of rotor periods (paper: 2000)", ge=1, le=10000000) = 2000
    poincare_periods: integer("last periods kept for Poincare sections (paper: 100)", ge=1,
                              le=10000000) = 100
    initial_displacement: quantity("length", "initial displacement of every node in y and "
                                   "z (paper: 1 um)") = 1e-6
    step_check_periods: integer(
        "periods of the step check: they are integrated again from the same state at half "
        "the step and the journal orbits compared (\"auto\": at each halving, the periods "
        "before the recorded ones; a fixed step: its last periods); 0: off (fixed step "
        "only)", ge=0, le=10000000) = 20
    nodes: list[NODE] = Field([], description="output nodes (default: element and disk "
                                                      "nodes)")
    reduction: Literal["auto", "none"] = Field(
        "auto", description="the time step's model: \"auto\" steps the Craig-Bampton model "
        "(the nonlinear elements' DOFs kept physical, their static constraint modes, the "
        "static residuals of the loads and the fixed-interface modes up to "
        "reduction_cutoff x the rotor speed; the full step if the model has no restrained "
        "interior), \"none\" the full model; allowed: "
        "\"auto\" or \"none\"")
    reduction_cutoff: quantity("ratio", "highest kept fixed-interface mode of the reduced "
                               "step, as a multiple of the rotor speed: 4 x the 10th "
                               "harmonic, the highest of interest, by default (the paper "
                               "rotor's settled orbit moves 7e-7 C from the full step's, "
                               "benchmarks/README.md)", gt=1, le=1e6) = 40.0
    speed_law: dict[str, Any] | None = Field(
        None, description="a speed law Omega(t) instead of one speed (run-up, coast-down): "
        "{ law = \"ramp\", start = \"500 rad/s\", stop = \"1200 rad/s\", duration = "
        "\"2 s\" } (or rate = \"350 rad/s^2\"; t_start holds start first), { law = "
        "\"table\", file = \"speeds.csv\" } (time [s], speed [rad/s]; or times = [...], "
        "speeds = [...]: a PCHIP interpolation) or { law = \"constant\", speed = ... }; "
        "the run lasts to the law's end (constant: periods), timeseries.nc holds the orbit "
        "against time and speed (docs: README, Run-up and coast-down); allowed: a table "
        "with law = \"constant\", \"ramp\" or \"table\" and its keys")
    overlay: str | None = Field(
        None, description="a speed-law run's steady branch to draw over its envelope: the "
        "branch.nc of `rotorsfd response` on the same rotor (relative to the working "
        "directory, as -o); allowed: a branch.nc path")

    def fixed_speed(self, reference_speed: float) -> float | None:
        """The speed [rad/s] (None if neither speed nor speed_ratio is set)."""
        if self.speed is not None:
            return self.speed
        return None if self.speed_ratio is None else self.speed_ratio * reference_speed

    @model_validator(mode="after")
    def _checks(self):
        if self.speed is not None and self.speed_ratio is not None:
            raise fail("speed", self.speed, "give speed or speed_ratio, not both")
        if self.poincare_periods > self.periods:
            raise fail("poincare_periods", self.poincare_periods,
                       f"must be <= periods = {self.periods}")
        if self.overlay is not None and self.speed_law is None:
            raise fail("overlay", self.overlay, "an overlay needs a speed_law (a run-up or "
                       "coast-down)")
        if self.speed_law is not None and "file" not in self.speed_law:
            # deferred: timedomain.speed_law_config (loads numba, scipy)
            from rotorsfd.timedomain.speed_law_config import speed_law_from_config

            try:
                speed_law_from_config(self.speed_law)
            except ConfigError as exc:
                raise fail(exc.field.removeprefix("analysis.simulate."), exc.value,
                           exc.allowed) from None
        return self


class BifurcationDiagramAnalysis(Section):
    """Brute-force bifurcation diagram: speed swept up then down, each point starting from
    the previous end state."""

    speed_range: SpeedRange = SpeedRange(start_ratio=0.9, stop_ratio=1.3, n=41)
    direction: Literal["up", "down", "up-down"] = Field(
        "up-down", description="sweep direction(s) of the speed")
    settle_periods: integer("periods discarded at each speed", ge=0, le=10000000) = 400
    record_periods: integer("periods recorded at each speed", ge=1, le=10000000) = 100


class SweepAnalysis(Section):
    """A grid over config fields; each point runs ``task``."""

    task: Literal["response", "simulate", "stability-chart"] = Field(
        "response", description="what runs at each grid point")
    axes: list[ParameterAxis] = []


class AnalysisConfig(Section):
    """Settings of every analysis; each command reads its own table."""

    modal: ModalAnalysis = ModalAnalysis()
    response: ResponseAnalysis = ResponseAnalysis()
    stability: StabilityAnalysis = StabilityAnalysis()
    stability_chart: StabilityChartAnalysis = StabilityChartAnalysis()
    simulate: SimulateAnalysis = SimulateAnalysis()
    bifurcation_diagram: BifurcationDiagramAnalysis = BifurcationDiagramAnalysis()
    sweep: SweepAnalysis = SweepAnalysis()


# ---- the whole configuration ---------------------------------------------------------------


class Config(Section):
    """A rotor with its nonlinear elements on a (possibly moving) base and the settings of
    its analyses."""

    title: str = Field("", description="a one-line title")
    description: str = Field("", description="free text")
    materials: dict[str, MaterialConfig] = Field(default_factory=dict,
                                                 description="named materials")
    rotor: RotorConfig
    elements: dict[str, ElementTable] = Field(
        default_factory=dict,
        description="the nonlinear elements, each an [elements.<name>] table with its kind")
    unbalance: list[UnbalanceConfig] = []
    base: BaseConfig = BaseConfig()
    gravity: GravityConfig = GravityConfig()
    reference: ReferenceConfig = ReferenceConfig()
    analysis: AnalysisConfig = AnalysisConfig()

    @model_validator(mode="before")
    @classmethod
    def _no_sfd_table(cls, data: Any) -> Any:
        if isinstance(data, dict) and "sfd" in data:
            raise fail(("sfd",), "[sfd]", "the squeeze film damper is an element now: "
                       "write its table as [elements.sfd] with kind = \"sfd\" (same fields)")
        return data

    @model_validator(mode="before")
    @classmethod
    def _shaft_node_names(cls, data: Any) -> Any:
        """Output nodes given as ``"hp:3"`` (:mod:`rotorsfd.model.node_names`)."""
        try:
            return resolve_shaft_nodes(data)
        except BadNodeName as exc:
            raise fail(exc.path, exc.value, exc.allowed) from None

    def output_nodes(self, section: str = "response") -> list[int]:
        """Output nodes of ``analysis.<section>``: as given, else the element and disk nodes
        (else every node)."""
        given = getattr(self.analysis, section).nodes
        if given:
            return list(given)
        nodes = {d.node for d in self.rotor.all_disks}
        for element in self.elements.values():
            nodes.update(element.nodes)
        return sorted(nodes) or list(range(1, self.rotor.n_nodes + 1))

    def _shaft_checks(self) -> None:
        """Multi-shaft rotors: each shaft's items on its own nodes, the two sides of an
        intershaft bearing or element on two shafts, unbalances on shafts at ratio 1 (the
        response at several unbalance frequencies needs the two-frequency HB)."""
        r = self.rotor
        for k, (sh, (lo, hi)) in enumerate(zip(r.shafts, r.shaft_ranges(), strict=True)):
            for kind in ("disks", "point_masses", "supports"):
                for i, item in enumerate(getattr(sh, kind)):
                    if not lo <= item.node <= hi:
                        raise fail(("rotor", "shafts", k, kind, i, "node"), item.node,
                                   f"must be a node of shaft {sh.name!r}, {lo}..{hi} "
                                   "(global numbering in the order of the shafts)")
        pairs = [(("rotor", "intershaft", i, "outer_node"), b.node, b.outer_node)
                 for i, b in enumerate(r.intershaft)]
        pairs += [(("elements", key, "outer_node"), e.node, e.outer_node)
                  for key, e in self.elements.items() if hasattr(e, "outer_node")]
        for path, a, b in pairs:
            if not r.shafts:
                raise fail(path, b, "an element between two shafts needs several shafts "
                           "([[rotor.shafts]])")
            if r.shaft_of(a) == r.shaft_of(b):
                raise fail(path, b, f"must be a node of another shaft than node {a} (both "
                           f"on shaft {r.shafts[r.shaft_of(a)].name!r})")
        if any(s.speed_ratio != 1.0 for s in r.shafts):
            for name in ("rolling", "pitching", "yawing"):
                c = getattr(self.base, name)
                if c.law != "off" and not (c.law == "constant" and not c.value):
                    raise fail(("base", name, "law"), c.law, "a rotating base with shafts "
                               "at different speeds is not supported yet (the base's spin "
                               "terms differ per shaft); base translations and gravity are")
        other: dict[float, int] = {}     # each shaft's unbalance turns at its own speed
        for i, u in enumerate(self.unbalance):
            k = r.shaft_of(u.node)
            ratio = r.shafts[k].speed_ratio if k is not None else 1.0
            if ratio != 1.0:
                other.setdefault(ratio, i)
            if len(other) > 1:
                raise fail(("unbalance", i, "node"), u.node, f"is on a shaft at speed ratio "
                           f"{ratio:g} while another unbalance turns at "
                           f"{next(iter(other)):g}: the two-frequency response takes "
                           "unbalances at two speeds (ratio 1 and one other)")

    @model_validator(mode="after")
    def _cross_checks(self):
        names = sorted(self.materials)
        for key in self.materials:
            if not re.match(NAME_PATTERN, key):
                raise fail(("materials", key), key, "a name: letters, digits, '_' and '-'")
        refs = [(("rotor", "shaft", i, "material"), s.material)
                for i, s in enumerate(self.rotor.shaft)]
        refs += [(("rotor", "disks", i, "material"), d.material)
                 for i, d in enumerate(self.rotor.disks) if d.material is not None]
        for k, sh in enumerate(self.rotor.shafts):
            refs += [(("rotor", "shafts", k, "sections", i, "material"), s.material)
                     for i, s in enumerate(sh.sections)]
            refs += [(("rotor", "shafts", k, "disks", i, "material"), d.material)
                     for i, d in enumerate(sh.disks) if d.material is not None]
        for path, name in refs:
            if name not in self.materials:
                raise fail(path, name, f"must name a material: {', '.join(names)}")
        n = self.rotor.n_nodes
        nodes = [(("rotor", kind, i, "node"), item.node)
                 for kind in ("disks", "point_masses", "supports")
                 for i, item in enumerate(getattr(self.rotor, kind))]
        nodes += [(("unbalance", i, "node"), u.node) for i, u in enumerate(self.unbalance)]
        nodes += [(("rotor", "intershaft", i, side), getattr(b, side))
                  for i, b in enumerate(self.rotor.intershaft) for side in ("node", "outer_node")]
        seen: dict[tuple[str, int], str] = {}
        for key, element in self.elements.items():
            if not re.match(NAME_PATTERN, key):
                raise fail(("elements", key), key, "a name: letters, digits, '_' and '-'")
            nodes += [(("elements", key, "node"), node) for node in element.nodes]
            for node in element.nodes:
                other = seen.setdefault((element.kind, node), key)
                if other != key:
                    raise fail(("elements", key, "node"), node,
                               f"elements.{other} is an {element.kind} at node {node} too; "
                               f"one {element.kind} element per node (elements of different "
                               "kinds may share a node)")
        for section in ("response", "simulate"):
            nodes += [(("analysis", section, "nodes", i), node)
                      for i, node in enumerate(getattr(self.analysis, section).nodes)]
        for path, node in nodes:
            if not 1 <= node <= n:
                raise fail(path, node, f"must be a node of the rotor, 1..{n} "
                           f"({n - 1} shaft elements)" if not self.rotor.shafts else
                           f"must be a node of the rotor, 1..{n} (global numbering)")
        self._shaft_checks()
        for where, path, values in _parameter_uses(self):
            try:
                kind = "angular_velocity" if path == "speed" else resolve_kind(self, path)
            except KeyError as exc:
                raise fail(where, path, exc.args[0]) from None
            for value_where, value in values:
                try:
                    to_si(value, kind)
                except UnitError as exc:
                    raise fail(value_where, value, f"{path} takes {exc}".replace(
                        "takes expected", "takes")) from None
        return self


def _axis_values(where: tuple[Any, ...], axis: ParameterAxis) -> list[tuple[tuple, Any]]:
    if axis.values is not None:
        return [((*where, "values", i), v) for i, v in enumerate(axis.values)]
    return [((*where, "start"), axis.start), ((*where, "stop"), axis.stop)]


def _parameter_uses(config: Config):
    """(where, dotted path, [(where, value), ...]) of every parameter the analyses name."""
    a = config.analysis
    r = a.response
    yield (("analysis", "response", "parameter"), r.parameter,
           [(("analysis", "response", "parameter_range", i), v)
            for i, v in enumerate(r.parameter_range or [])])
    for name in ("x", "y"):
        axis = getattr(a.stability_chart, name)
        if axis is not None:
            where = ("analysis", "stability_chart", name)
            yield (*where, "parameter"), axis.parameter, _axis_values(where, axis)
    for i, axis in enumerate(a.sweep.axes):
        where = ("analysis", "sweep", "axes", i)
        yield (*where, "parameter"), axis.parameter, _axis_values(where, axis)


_TOKEN = re.compile(r"([A-Za-z_]\w*)|\[(\d+)\]|\.(\d+)")


def split_path(path: str) -> tuple[str | int, ...]:
    """``"rotor.shaft[0].length"`` (or ``rotor.shaft.0.length``) -> ``("rotor", "shaft", 0,
    "length")``. Raise ValueError on a malformed path."""
    parts: list[str | int] = []
    pos = 0
    path = path.strip()
    while pos < len(path):
        if parts and path[pos] == "." and pos + 1 < len(path) and not path[pos + 1].isdigit():
            pos += 1
        m = _TOKEN.match(path, pos)
        if not m or (m.group(1) and parts and path[pos - 1] not in "."):
            raise ValueError(f"malformed dotted path {path!r}")
        parts.append(m.group(1) if m.group(1) else int(m.group(2) or m.group(3)))
        pos = m.end()
    if not parts or not isinstance(parts[0], str):
        raise ValueError(f"malformed dotted path {path!r}")
    return tuple(parts)


def resolve_kind(config: BaseModel, path: str) -> str:
    """Physical kind (``units.KINDS`` key) of the scalar quantity field at dotted ``path``
    of ``config``. Raise KeyError with a message if the path names no such field."""
    obj: Any = config
    parts = split_path(path)
    for i, part in enumerate(parts):
        if isinstance(obj, BaseModel):
            fields = type(obj).model_fields
            if not isinstance(part, str) or part not in fields:
                raise KeyError(f"{path!r} names no config field ({part!r} unknown)")
            if i == len(parts) - 1:
                extra = fields[part].json_schema_extra or {}
                if "kind" not in extra:
                    raise KeyError(f"{path!r} is not a scalar physical quantity")
                return extra["kind"]
            obj = getattr(obj, part)
        elif isinstance(obj, list | dict):
            try:
                obj = obj[part]
            except (IndexError, KeyError, TypeError):
                raise KeyError(f"{path!r} names no config field ({part!r} not present)") \
                    from None
        else:
            raise KeyError(f"{path!r} names no config field")
    raise KeyError(f"{path!r} is not a scalar physical quantity")


def parameter_values(config: Config, path: str, values: list[Any]) -> list[float]:
    """Values of the parameter at ``path`` converted to SI ('speed' means rad/s)."""
    kind = "angular_velocity" if path == "speed" else resolve_kind(config, path)
    return [to_si(v, kind) for v in values]


def axis_values(config: Config, axis: ParameterAxis) -> list[float]:
    """The grid values of ``axis`` in SI: ``values``, or ``n`` values from start to stop."""
    if axis.values is not None:
        return parameter_values(config, axis.parameter, axis.values)
    start, stop = parameter_values(config, axis.parameter, [axis.start, axis.stop])
    if axis.n == 1:
        return [start]
    return [start + (stop - start) * i / (axis.n - 1) for i in range(axis.n)]


__all__ = ["Config", "axis_values", "describe", "fail", "parameter_values", "resolve_kind",
           "split_path"]
