"""ROSS rotors (the ``ross-rotordynamics`` package) in and out of rotorsfd.

``from_ross(rotor) -> dict`` turns a ``ross.Rotor`` into a rotorsfd configuration (a TOML-like
dict, validated by the schema) to which nonlinear elements are then added; ``to_ross(x)``
goes the other way for the linear part (a config, a ``RotorSystem`` or a ``Rotor``).
ROSS is an optional dependency (``pip install "rotorsfd[ross]"``), imported only here and
only when called.

Coordinates. ROSS (2.x) carries 6 DOFs per node ``[x, y, z, alpha, beta, theta]`` with the
shaft along z and nodes from 0; rotorsfd 4 DOFs ``[y, z, ty, tz]`` with the shaft along x
and nodes from 1. The map (x, y, z)_ROSS -> (y, z, x)_rotorsfd is a cyclic permutation, so
both frames are right-handed and every lateral DOF maps with a + sign:

    y = x_R,  z = y_R,  ty = alpha_R (about x_R ~ -dy_R/dz_R),  tz = beta_R (~ +dx_R/dz_R),
    node = n_R + 1,

and both write ``M q'' + (C + Omega G) q' + K q = f`` with ``G[alpha, beta] = +Ip`` at a
disk (rotorsfd's ``G[ty, tz] = +Ip``). A bearing's ``[[kxx, kxy], [kyx, kyy]]`` on
``[x_R, y_R]`` is the support's ``[[kyy, kyz], [kzy, kzz]]`` on ``[y, z]`` (damping alike).
The axial and torsional DOFs of ROSS are uncoupled from the lateral ones in its linear
model and have no counterpart; they are dropped.

Elements. A cylindrical ROSS shaft element is one rotorsfd Timoshenko element with ROSS's
shear coefficient passed as ``shear_coefficient`` (both use the shear parameter
``Phi = 12 E I / (kappa G A L^2)``); equal consecutive elements become one section. A disk
keeps (m, Id, Ip); a bearing or seal with constant coefficients is a linear support. What
has no counterpart is refused in one line naming the element: conical elements, shear or
rotary inertia or gyroscopic effects switched off, element damping, axial force or torque,
bearings linked to another node (``n_link``), support masses, speed-dependent coefficient
tables (unless ``speed`` freezes them at one speed), concentric layers of a shaft element
(unless ``layers="merge"``: one section with an equivalent material that keeps E I, rho A
and kappa G A, and changes the rotary inertia rho I; see docs/interop.md).
"""

from __future__ import annotations

import itertools
import math
import re
import warnings
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.io.atomic import write_text

#: ROSS's lateral DOFs of a node in rotorsfd's order [y, z, ty, tz], per DOFs per node.
LATERAL = {6: (0, 1, 3, 4), 4: (0, 1, 2, 3)}
ROSS_EXTRA = 'pip install "rotorsfd[ross]" (ross-rotordynamics)'


def require_ross() -> Any:
    """The ``ross`` module; ConfigError with the install line if it is missing."""
    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            import ross  # the optional dependency (slow import: about 25 s)
    except ImportError as exc:
        raise ConfigError("ross", str(exc), f"the ROSS interface needs {ROSS_EXTRA}") \
            from None
    return ross


def load_ross(path: str | Path) -> Any:
    """``ross.Rotor.load(path)``; ConfigError naming the file if ROSS cannot read it."""
    p = Path(path)
    if not p.is_file():
        raise ConfigError("ROSS rotor file", str(path), "no such file")
    ross = require_ross()
    try:
        return ross.Rotor.load(p)
    except Exception as exc:  # ROSS raises whatever its TOML reader meets
        raise ConfigError("ROSS rotor file", str(path), f"ROSS cannot load it as a rotor "
                          f"({type(exc).__name__}: {exc})") from None


# ---- ROSS -> rotorsfd --------------------------------------------------------------------


def _label(element: Any) -> str:
    return f"{type(element).__name__} {element.tag!r} (ROSS node {element.n})"


def _refuse(element: Any, what: str, hint: str = "") -> ConfigError:
    return ConfigError(f"ROSS {_label(element)}", what,
                       "has no counterpart in rotorsfd" + (f"; {hint}" if hint else ""))


def _material_name(name: str, taken: dict[str, tuple[float, ...]],
                   props: tuple[float, ...]) -> str:
    """A config-safe material name for ROSS's ``name`` (suffixed if the name is taken by
    other properties)."""
    base = re.sub(r"[^A-Za-z0-9_\-]", "_", str(name)) or "material"
    if not re.match(r"[A-Za-z_]", base):
        base = f"m_{base}"
    out, k = base, 1
    while out in taken and taken[out] != props:
        k += 1
        out = f"{base}_{k}"
    taken[out] = props
    return out


def _check_shaft_element(e: Any) -> None:
    if not (math.isclose(e.idl, e.idr) and math.isclose(e.odl, e.odr)):
        raise _refuse(e, f"conical (diameters {e.idl:g}-{e.odl:g} m to {e.idr:g}-{e.odr:g} m)",
                      "rotorsfd's sections are cylindrical: split it into cylindrical "
                      "elements in ROSS")
    for flag in ("shear_effects", "rotary_inertia", "gyroscopic"):
        if not getattr(e, flag, True):
            raise _refuse(e, f"{flag} = False", "rotorsfd's element is a full Timoshenko "
                          "element with rotary inertia and gyroscopic terms")
    for name in ("axial_force", "torque", "alpha", "beta"):
        if float(getattr(e, name, 0.0) or 0.0) != 0.0:
            raise _refuse(e, f"{name} = {getattr(e, name)}")


def _section(e: Any, materials: dict[str, dict[str, float]],
             taken: dict[str, tuple[float, ...]]) -> dict[str, Any]:
    """One cylindrical element as a one-element section."""
    _check_shaft_element(e)
    mat = e.material
    props = (float(mat.rho), float(mat.E), float(mat.G_s))
    name = _material_name(mat.name, taken, props)
    materials[name] = {"density": props[0], "young_modulus": props[1],
                       "shear_modulus": props[2]}
    return {"length": float(e.L), "n_elements": 1, "inner_radius": e.idl / 2.0,
            "outer_radius": e.odl / 2.0, "material": name,
            "shear_coefficient": float(e.kappa)}


def _merged_section(layers: list[Any], materials: dict[str, dict[str, float]],
                    taken: dict[str, tuple[float, ...]]) -> dict[str, Any]:
    """Concentric layers on one node pair as one section of an equivalent material:

        E I = sum E_i I_i,   rho A = sum rho_i A_i,   kappa G A = sum kappa_i G_i A_i,
        G A = sum G_i A_i,

    on the combined annulus (innermost to outermost radius); rho I then differs from
    sum rho_i I_i (the rotary and gyroscopic terms; docs/interop.md gives the size)."""
    layers = sorted(layers, key=lambda e: e.idl)
    for e in layers:
        _check_shaft_element(e)
        if not math.isclose(e.L, layers[0].L, rel_tol=1e-9):
            raise _refuse(e, f"a layer of length {e.L:g} m over one of {layers[0].L:g} m")
    for inner, outer in itertools.pairwise(layers):
        if not math.isclose(inner.odl, outer.idl, rel_tol=1e-9, abs_tol=1e-12):
            raise _refuse(outer, f"a layer from diameter {outer.idl:g} m over one ending at "
                          f"{inner.odl:g} m (a gap)")
    ri, ro = layers[0].idl / 2.0, layers[-1].odl / 2.0
    area, second = math.pi * (ro**2 - ri**2), math.pi * (ro**4 - ri**4) / 4.0
    a = [math.pi * (e.odl**2 - e.idl**2) / 4.0 for e in layers]
    i = [math.pi * (e.odl**4 - e.idl**4) / 64.0 for e in layers]
    ei = sum(e.material.E * ii for e, ii in zip(layers, i, strict=True))
    rho_a = sum(e.material.rho * aa for e, aa in zip(layers, a, strict=True))
    ga = sum(e.material.G_s * aa for e, aa in zip(layers, a, strict=True))
    kga = sum(e.kappa * e.material.G_s * aa for e, aa in zip(layers, a, strict=True))
    props = (rho_a / area, ei / second, ga / area)
    name = _material_name("layers_" + "_".join(e.material.name for e in layers), taken, props)
    materials[name] = {"density": props[0], "young_modulus": props[1],
                       "shear_modulus": props[2]}
    return {"length": float(layers[0].L), "n_elements": 1, "inner_radius": ri,
            "outer_radius": ro, "material": name, "shear_coefficient": kga / ga}


def _shaft(rotor: Any, layers: str) -> tuple[list[dict[str, Any]], dict[str, dict]]:
    """Sections (equal consecutive elements merged) and materials of the shaft."""
    by_node: dict[int, list[Any]] = {}
    for e in rotor.shaft_elements:
        by_node.setdefault(int(e.n), []).append(e)
    nodes = sorted(by_node)
    if nodes != list(range(nodes[0], nodes[0] + len(nodes))) or nodes[0] != 0:
        raise ConfigError("ROSS shaft", nodes, "the shaft elements must join nodes 0, 1, 2, "
                          "... one after the other")
    materials: dict[str, dict[str, float]] = {}
    taken: dict[str, tuple[float, ...]] = {}
    sections: list[dict[str, Any]] = []
    for n in nodes:
        group = by_node[n]
        if len(group) == 1:
            s = _section(group[0], materials, taken)
        elif layers == "merge":
            s = _merged_section(group, materials, taken)
        else:
            raise _refuse(group[1], f"a concentric layer over {group[0].tag!r} (one node pair, "
                          f"{len(group)} elements)", "from_ross(..., layers='merge') "
                          "(import-ross --merge-layers) merges them into one equivalent "
                          "section")
        last = sections[-1] if sections else None
        if last is not None and all(
                math.isclose(last[k], s[k], rel_tol=1e-12) for k in
                ("inner_radius", "outer_radius", "shear_coefficient")) \
                and last["material"] == s["material"] \
                and math.isclose(last["length"] / last["n_elements"], s["length"],
                                 rel_tol=1e-12):
            last["n_elements"] += 1
            last["length"] = s["length"] * last["n_elements"]
        else:
            sections.append(s)
    return sections, materials


def _coefficient(b: Any, name: str, speed: float | None) -> float:
    values = np.atleast_1d(np.asarray(getattr(b, name), dtype=float))
    if values.size > 1 and not np.allclose(values, values[0], rtol=0.0, atol=0.0):
        if speed is None:
            raise _refuse(b, f"speed-dependent {name} (a table of {values.size} "
                          "frequencies)", "from_ross(..., speed=...) (import-ross --speed) "
                          "freezes every table at one speed")
        return float(getattr(b, f"{name}_interpolated")(speed))
    return float(values[0])


def _supports(rotor: Any, speed: float | None, n_nodes: int
              ) -> tuple[list[dict[str, Any]], list[dict[str, Any]]]:
    """Linear supports (and the point masses of isotropic bearing masses)."""
    supports, masses = [], []
    for b in rotor.bearing_elements:
        if getattr(b, "n_link", None) is not None:
            raise _refuse(b, f"n_link = {b.n_link} (a bearing to another node)",
                          "rotorsfd's supports act between a shaft node and ground")
        if not 0 <= int(b.n) < n_nodes:
            raise _refuse(b, f"node {b.n} off the shaft (nodes 0..{n_nodes - 1})")
        c = {name: _coefficient(b, name, speed) for name in
             ("kxx", "kyy", "kxy", "kyx", "cxx", "cyy", "cxy", "cyx", "mxx", "myy", "mxy",
              "myx")}
        if c["mxy"] or c["myx"] or c["mxx"] != c["myy"]:
            raise _refuse(b, f"an anisotropic or cross-coupled mass coefficient (mxx = "
                          f"{c['mxx']:g}, myy = {c['myy']:g}, mxy = {c['mxy']:g}, myx = "
                          f"{c['myx']:g})", "an isotropic mxx = myy becomes a point mass")
        if c["mxx"]:
            masses.append({"node": int(b.n) + 1, "mass": c["mxx"]})
        supports.append({
            "node": int(b.n) + 1, "name": str(b.tag),
            "kyy": c["kxx"], "kzz": c["kyy"], "kyz": c["kxy"], "kzy": c["kyx"],
            "cyy": c["cxx"], "czz": c["cyy"], "cyz": c["cxy"], "czy": c["cyx"]})
    return supports, masses


def from_ross(rotor: Any, *, speed: float | None = None, layers: str = "error",
              title: str | None = None) -> dict[str, Any]:
    """A rotorsfd configuration (a TOML-like dict, validated) of the ROSS rotor ``rotor``:
    materials, shaft sections, disks, supports (bearings and seals), point masses. ``speed``
    [rad/s] freezes speed-dependent coefficient tables at that speed; ``layers="merge"``
    merges concentric shaft layers. ConfigError naming the element for what has no
    counterpart. Add ``[elements.<name>]``, ``[[unbalance]]`` and analyses to it."""
    # deferred: io.config (loads scipy, pydantic)
    from rotorsfd.io.config import validate

    if layers not in ("error", "merge"):
        raise ConfigError("layers", layers, "must be 'error' or 'merge'")
    ross = require_ross()
    handled = (ross.ShaftElement, ross.DiskElement, ross.BearingElement, ross.PointMass)
    for e in rotor.elements:
        if not isinstance(e, handled):
            raise _refuse(e, f"a {type(e).__name__}")
    sections, materials = _shaft(rotor, layers)
    n_nodes = sum(s["n_elements"] for s in sections) + 1
    disks = []
    for d in rotor.disk_elements:
        if not 0 <= int(d.n) < n_nodes:
            raise _refuse(d, f"node {d.n} off the shaft (nodes 0..{n_nodes - 1})")
        disks.append({"node": int(d.n) + 1, "name": str(d.tag), "mass": float(d.m),
                      "polar_inertia": float(d.Ip), "diametral_inertia": float(d.Id)})
    supports, masses = _supports(rotor, speed, n_nodes)
    for p in rotor.point_mass_elements:
        raise _refuse(p, "a point mass on its own node (a support mass)",
                      "rotorsfd's point masses sit on shaft nodes")
    x0 = float(rotor.nodes_pos[0])
    config: dict[str, Any] = {
        "title": title or f"ROSS rotor {getattr(rotor, 'tag', '') or ''}".strip(),
        "description": ("imported from ROSS " + getattr(ross, "__version__", "?")
                        + (f"; speed-dependent coefficients frozen at {speed:g} rad/s"
                           if speed is not None else "")),
        "materials": materials,
        "rotor": {"x_start": x0, "shaft": sections, "disks": disks, "point_masses": masses,
                  "supports": supports},
    }
    validate(config)
    return config


def import_ross(path: str | Path, output: str | Path | None = None, *,
                speed: float | None = None, layers: str = "error") -> str:
    """TOML text of the rotorsfd config of the ROSS rotor file ``path`` (written atomically
    to ``output`` when given)."""
    # deferred: io.config (loads scipy, pydantic)
    from rotorsfd.io.config import to_toml

    config = from_ross(load_ross(path), speed=speed, layers=layers,
                       title=f"ROSS rotor {Path(path).name}")
    header = (f"# Imported from the ROSS rotor {Path(path).name} by rotorsfd import-ross.\n"
              "# Node n here is ROSS node n - 1; x along the shaft (ROSS's z). Add the\n"
              "# nonlinear elements ([elements.<name>]), [[unbalance]] and the analyses.\n\n")
    text = header + to_toml(config)
    if output is not None:
        write_text(Path(output), text)
    return text


# ---- rotorsfd -> ROSS --------------------------------------------------------------------


def _rotorsfd_rotor(source: Any) -> Any:
    """The rotorsfd ``Rotor`` of a Config, a RotorSystem or a Rotor."""
    # deferred: io.schema, model.build (loads scipy, pydantic)
    from rotorsfd.io.schema import Config
    from rotorsfd.model.build import build_rotor

    if isinstance(source, Config):
        return build_rotor(source)
    return getattr(source, "rotor", source)


def to_ross(source: Any, tag: str | None = None) -> Any:
    """The ``ross.Rotor`` of the linear part of a rotorsfd Config, RotorSystem or Rotor:
    shaft elements (with rotorsfd's shear parameter), disks, point masses (as disks without
    inertia), supports (an SFD's centring spring included; the film is nonlinear and left
    out). ConfigError for structural damping and for a rotor given by matrices."""
    ross = require_ross()
    rotor = _rotorsfd_rotor(source)
    if not getattr(rotor, "shaft_elements", ()):
        raise ConfigError("rotor", type(rotor).__name__, "to_ross needs a rotor of shaft "
                          "elements (a rotor given by matrices has none)")
    if rotor.damping is not None:
        raise ConfigError("rotor.damping", type(rotor.damping).__name__, "structural "
                          "damping of the whole rotor has no ROSS element counterpart; "
                          "remove it (kind = 'none') to export")
    materials: dict[tuple[float, float, float], Any] = {}
    shaft = []
    for i, el in enumerate(rotor.shaft_elements):
        m = el.material
        key = (m.density, m.young_modulus, m.shear_modulus)
        if key not in materials:
            materials[key] = ross.Material(name=f"{m.name or 'material'}_{len(materials)}",
                                           rho=m.density, E=m.young_modulus,
                                           G_s=m.shear_modulus)
        e = ross.ShaftElement(el.length, 2.0 * el.inner_radius, 2.0 * el.outer_radius,
                              material=materials[key], n=i, shear_effects=True,
                              rotary_inertia=True, gyroscopic=True)
        e.kappa, e.phi = el.kappa, el.shear_parameter   # rotorsfd's kappa, same Phi
        shaft.append(e)
    disks = [ross.DiskElement(n=d.node - 1, m=d.mass, Id=d.diametral_inertia,
                              Ip=d.polar_inertia, tag=f"Disk {k}")
             for k, d in enumerate(rotor.disks)]
    disks += [ross.DiskElement(n=p.node - 1, m=p.mass, Id=0.0, Ip=0.0, tag=f"Mass {k}")
              for k, p in enumerate(rotor.point_masses)]
    bearings = [ross.BearingElement(n=s.node - 1, kxx=s.kyy, kyy=s.kzz, kxy=s.kyz, kyx=s.kzy,
                                    cxx=s.cyy, cyy=s.czz, cxy=s.cyz, cyx=s.czy,
                                    tag=f"Support {k}")
                for k, s in enumerate(rotor.supports)]
    return ross.Rotor(shaft, disks, bearings, tag=tag)


def lateral_dofs(ross_rotor: Any, n_nodes: int | None = None) -> np.ndarray:
    """ROSS global indices of the lateral DOFs in rotorsfd's order (node by node,
    ``[y, z, ty, tz]`` = ``[x, y, alpha, beta]``) of the shaft nodes."""
    per = int(ross_rotor.number_dof)
    if per not in LATERAL:
        raise ConfigError("ROSS rotor", f"{per} DOFs per node", "expected 4 or 6")
    n = len(ross_rotor.nodes) if n_nodes is None else n_nodes
    return (per * np.arange(n)[:, None] + np.array(LATERAL[per])[None, :]).ravel()


def ross_matrices(ross_rotor: Any, speed: float = 0.0
                  ) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(M, K, C, G) of a ROSS rotor on its lateral DOFs in rotorsfd's order; bearing
    coefficients at ``speed`` [rad/s]."""
    idx = np.ix_(lateral_dofs(ross_rotor), lateral_dofs(ross_rotor))
    return (np.asarray(ross_rotor.M(speed))[idx], np.asarray(ross_rotor.K(speed))[idx],
            np.asarray(ross_rotor.C(speed))[idx], np.asarray(ross_rotor.G())[idx])


def lateral_fraction(ross_rotor: Any, vectors: np.ndarray) -> np.ndarray:
    """Share of each ROSS mode (columns of ``vectors``, DOF part first) in the lateral
    DOFs: 1 for a bending mode, 0 for an axial or torsional one."""
    nd = int(ross_rotor.ndof)
    v = np.abs(np.asarray(vectors)[:nd]) ** 2
    lat = lateral_dofs(ross_rotor)
    return v[lat].sum(axis=0) / np.maximum(v.sum(axis=0), 1e-300)


__all__: Iterable[str] = ["from_ross", "import_ross", "lateral_dofs", "lateral_fraction",
                          "load_ross", "require_ross", "ross_matrices", "to_ross"]
