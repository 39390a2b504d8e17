"""Export a config's linear rotor as matrices, with a config that runs on them.

``export_matrices(config, "model.npz")`` writes the rotor of ``[rotor]`` (shaft, disks, point
masses, ``[[rotor.supports]]``) as M, K, C, G in rotorsfd's DOF order with its DOF map, node
positions and base-motion terms, and returns the configuration that reads them back
(``[rotor.matrices]``) with everything else of the original: the elements (whose linear
parts, an SFD's centring spring, are added again at build), unbalances, base motion,
``[rotor.damping]`` (computed again on the supported rotor) and the analyses. Both rotors
then have the same M, K, C, G to rounding, and every analysis gives the same results.
``fmt="mtx"`` writes Matrix Market files (sparse, coordinate format, from the rotor's CSR
matrices: no dense n x n array) and a DOF-map CSV instead (no base-motion terms: the model
then takes base translation and gravity, not base rotation). The npz arrays are dense:
refused above :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` DOFs (issue 17 item 2).
"""

from __future__ import annotations

import csv
import io
from pathlib import Path
from typing import Any

import numpy as np

from rotorsfd.errors import ConfigError
from rotorsfd.interop.matrices import ARRAYS, DIRECTIONS
from rotorsfd.io.atomic import write_bytes, write_text
from rotorsfd.io.schema import Config, DampingConfig
from rotorsfd.model.base_terms import base_basis
from rotorsfd.model.build import build_rotor
from rotorsfd.model.sparse import DENSE_MAX_DOF, as_csr


def element_rotor(config: Config, search_path: Path | None = None) -> Any:
    """The rotor of ``[rotor]`` alone: no structural damping, no elements' linear parts."""
    if config.rotor.matrices is not None:
        raise ConfigError("rotor.matrices", config.rotor.matrices.file or "Matrix Market",
                          "the rotor is given by matrices already; export a rotor of "
                          "[[rotor.shaft]] sections")
    bare = config.model_copy(update={
        "rotor": config.rotor.model_copy(update={"damping": DampingConfig()}),
        "elements": {}})
    return build_rotor(bare, search_path)


def sparse_matrix(rotor: Any, key: str) -> Any:
    """``rotor``'s matrix ``key`` (M, K, C or G) sparse: its CSR form (``M_csr`` ...) when
    it has one (a rotor of shaft elements), else the dense matrix as CSR."""
    csr = getattr(rotor, f"{key}_csr", None)
    return csr if csr is not None else as_csr(getattr(rotor, key))


def dof_table(n_nodes: int) -> tuple[np.ndarray, np.ndarray]:
    """(node, direction) of rotorsfd's DOF order: node 1 y, z, ty, tz, node 2 ..."""
    node = np.repeat(np.arange(1, n_nodes + 1), len(DIRECTIONS))
    return node, np.array(DIRECTIONS * n_nodes)


def _bytes_npz(**arrays: np.ndarray) -> bytes:
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return buffer.getvalue()


def matrices_config(config: Config, matrices: dict[str, Any]) -> dict[str, Any]:
    """The TOML-like dict of ``config`` with its rotor replaced by ``[rotor.matrices]``
    (keeping ``[rotor.damping]``); the fields the configuration set, in SI, and the
    output nodes it had by default (its disks' and elements')."""
    data = config.model_dump(mode="json", exclude_unset=True, exclude_none=True)
    for section in ("response", "simulate"):   # the default output nodes name the disks
        if not getattr(config.analysis, section).nodes:
            table = data.setdefault("analysis", {}).setdefault(section, {})
            table["nodes"] = config.output_nodes(section)
    data["materials"] = {}
    data["rotor"] = {"matrices": matrices, "damping": data.get("rotor", {}).get("damping", {})}
    return data


def export_matrices(config: Config, path: str | Path, fmt: str = "npz",
                    search_path: Path | None = None) -> tuple[list[Path], dict[str, Any]]:
    """Write the linear rotor of ``config`` to ``path`` (``.npz``; with ``fmt="mtx"`` the
    folder ``path`` gets M.mtx, K.mtx, C.mtx, G.mtx and dof_map.csv) and return (the files
    written, the config dict that reads them, with paths relative to the files' folder)."""
    if fmt not in ("npz", "mtx"):
        raise ConfigError("format", fmt, "allowed: 'npz' or 'mtx'")
    rotor = element_rotor(config, search_path)
    node, direction = dof_table(rotor.n_nodes)
    target = Path(path)
    if fmt == "npz":
        if rotor.n_dof > DENSE_MAX_DOF:
            raise ConfigError("format", fmt, f"npz holds dense arrays (the base terms 12 "
                              f"n x n): allowed up to {DENSE_MAX_DOF} DOFs and this rotor "
                              f"has {rotor.n_dof}; 'mtx' writes the matrices sparse")
        arrays = {k: np.asarray(getattr(rotor, k), dtype=float) for k in ARRAYS}
        basis = base_basis(rotor)
        data = _bytes_npz(**arrays, dof_node=node, dof_direction=direction,
                          node_x=np.asarray(rotor.node_x, float),
                          base_matrices=np.asarray(basis.matrices, float),
                          base_vectors=np.asarray(basis.vectors, float))
        written = [write_bytes(target, data)]
        table = {"file": target.name, "n_nodes": rotor.n_nodes}
        return written, matrices_config(config, table)
    # deferred: scipy.io is heavy (loaded only when this runs)
    import scipy.io

    target.mkdir(parents=True, exist_ok=True)
    written = []
    names = {"M": "mass", "K": "stiffness", "C": "damping", "G": "gyroscopic"}
    table: dict[str, Any] = {"n_nodes": rotor.n_nodes}
    for key in ARRAYS:   # sparse (coordinate format) from the CSR matrices: no n x n array
        buffer = io.BytesIO()
        scipy.io.mmwrite(buffer, sparse_matrix(rotor, key), precision=17)
        written.append(write_bytes(target / f"{key}.mtx", buffer.getvalue()))
        table[names[key]] = f"{target.name}/{key}.mtx"
    text = io.StringIO()
    w = csv.writer(text, lineterminator="\n")
    w.writerow(["node", "direction", "x"])
    for n, d in zip(node.tolist(), direction.tolist(), strict=True):
        w.writerow([n, d, repr(float(rotor.node_x[n - 1]))])
    written.append(write_text(target / "dof_map.csv", text.getvalue()))
    table["dof_map"] = f"{target.name}/dof_map.csv"
    return written, matrices_config(config, table)


def write_export(config: Config, path: str | Path, fmt: str = "npz",
                 search_path: Path | None = None) -> list[Path]:
    """:func:`export_matrices` plus the config that reads them, written beside them as
    ``<name>.toml`` (validated first)."""
    # deferred: io.config (loads 1 more rotorsfd module, needed only here)
    from rotorsfd.io.config import to_toml, validate

    written, data = export_matrices(config, path, fmt, search_path)
    validate(data)
    target = Path(path)
    toml_path = target.with_suffix(".toml") if fmt == "npz" else target.parent / (
        target.name + ".toml")
    header = (f"# The rotor of {config.title or 'the configuration'} as matrices "
              f"(rotorsfd export-matrices); SI units.\n\n")
    written.append(write_text(toml_path, header + to_toml(data)))
    return written
