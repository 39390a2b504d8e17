"""A linear rotor given by its matrices: ``[rotor.matrices]``, and ``export_matrices``.

A user's own finite-element model (M, K, C, G of ``M q'' + (C + Omega G) q' + K q = f``)
enters every analysis through ``[rotor.matrices]`` in place of ``[[rotor.shaft]]``: either one
``.npz`` file (arrays ``M``, ``K``, optional ``C``, ``G``, ``dof_node``, ``dof_direction``,
``node_x``, ``base_matrices``, ``base_vectors``) or Matrix Market files (``mass``,
``stiffness``, ``damping``, ``gyroscopic``, read with ``scipy.io.mmread``) with a DOF map.

The DOF map says what row i of the matrices is: a node (1..n_nodes) and a direction, one of
``y, z, ty, tz`` (rotorsfd's: shaft along x, ``ty ~ -dz/dx``, ``tz ~ +dy/dx``), with a
leading ``-`` if the model's DOF is the opposite of rotorsfd's (``-ty``), or ``x`` / ``tx``
(axial, torsion) for DOFs rotorsfd drops, which must not couple to the lateral ones. With
the signed selection ``S`` (``q_file = S q``) the rotor's matrices are ``S^T A S``. Every
node carries the four lateral DOFs. ``node_x`` gives the nodes' axial positions.

Supports, disks, point masses and structural damping of ``[rotor]`` and the elements'
linear parts (an SFD's centring spring) are added to the imported matrices as for a rotor
of shaft elements; unbalances, elements and base motion are placed by node. Base
*rotation* needs the base-motion terms of :mod:`rotorsfd.model.base_terms` (``base_matrices``
(12, n, n) and ``base_vectors`` (8, n), which :func:`export_matrices` writes); without them
only base translation and gravity are allowed, whose load vectors are exact from M alone
(``f_y = M r_y``: the generalised force of a unit acceleration along y).
"""

from __future__ import annotations

import csv
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import scipy.sparse as sp

from rotorsfd.errors import ConfigError
from rotorsfd.model import dofs
from rotorsfd.model.base_terms import BaseBasis, disk_basis
from rotorsfd.model.rotor import LinearRotor

if TYPE_CHECKING:
    from rotorsfd.io.schema import Config, MatricesConfig
    from rotorsfd.model import Disk, LinearSupport, ModalDamping, PointMass, RayleighDamping

FIELD = "rotor.matrices"
DIRECTIONS = ("y", "z", "ty", "tz")
DROPPED = ("x", "tx")
ARRAYS = ("M", "K", "C", "G")
N_BASE_MATRICES, N_BASE_VECTORS = 12, 8


def _path(value: str, name: str, search_path: Path | None) -> Path:
    p = Path(value)
    if not p.is_absolute() and search_path is not None:
        p = Path(search_path) / p
    if not p.is_file():
        raise ConfigError(f"{FIELD}.{name}", value, f"no such file: {p} (a path relative to "
                          "the config file's folder)")
    return p


def _read_npz(path: Path) -> dict[str, np.ndarray]:
    try:
        with np.load(path, allow_pickle=False) as data:
            return {k: np.asarray(data[k]) for k in data.files}
    except Exception as exc:  # zip, pickle or format errors of numpy
        raise ConfigError(f"{FIELD}.file", str(path), f"must be a .npz archive of arrays "
                          f"({type(exc).__name__}: {exc})") from None


def _read_mtx(path: Path, name: str) -> np.ndarray:
    # deferred: scipy.io is heavy (loaded only when this runs)
    import scipy.io

    try:
        a = scipy.io.mmread(path)
    except Exception as exc:  # scipy raises ValueError / OSError on a bad file
        raise ConfigError(f"{FIELD}.{name}", str(path), f"must be a Matrix Market file "
                          f"({type(exc).__name__}: {exc})") from None
    return np.asarray(a.toarray() if scipy.sparse.issparse(a) else a, dtype=float)


def read_dof_map(path: Path) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """(node, direction, x or None) per matrix row from a CSV with the header
    ``node,direction`` (optionally ``,x``)."""
    where = f"{FIELD}.dof_map"
    with open(path, newline="") as f:
        rows = list(csv.DictReader(f))
    if not rows or not {"node", "direction"} <= set(rows[0]):
        raise ConfigError(where, str(path), "must be a CSV file with the columns node, "
                          "direction (and optionally x), one line per matrix row")
    try:
        node = np.array([int(r["node"]) for r in rows])
        x = np.array([float(r["x"]) for r in rows]) if "x" in rows[0] else None
    except (TypeError, ValueError) as exc:
        raise ConfigError(where, str(path), f"node must be an integer and x a number ({exc})") \
            from None
    return node, np.array([r["direction"].strip() for r in rows]), x


def _selection(node: np.ndarray, direction: np.ndarray, n_nodes: int, n: int
               ) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(rows kept, their signs, their rotorsfd DOF index) of the DOF map; the dropped rows
    are the others."""
    where = f"{FIELD}.dof_map"
    if node.shape != (n,) or direction.shape != (n,):
        raise ConfigError(where, f"{node.size} rows", f"must map each of the {n} matrix rows")
    rows, signs, target, seen = [], [], [], {}
    for i, (nd, d) in enumerate(zip(node.tolist(), direction.tolist(), strict=True)):
        sign, name = (-1.0, d[1:]) if d.startswith("-") else (1.0, d)
        if name in DROPPED:
            continue
        if name not in DIRECTIONS:
            raise ConfigError(f"{where}[{i}].direction", d, "must be one of y, z, ty, tz "
                              "(a leading '-' for the opposite sense) or x, tx (dropped)")
        if not 1 <= nd <= n_nodes:
            raise ConfigError(f"{where}[{i}].node", nd, f"must be a node 1..{n_nodes} "
                              f"(rotor.matrices.n_nodes)")
        if (nd, name) in seen:
            raise ConfigError(f"{where}[{i}]", f"{nd} {name}", f"row {seen[nd, name]} is "
                              "that DOF already; each (node, direction) once")
        seen[nd, name] = i
        rows.append(i)
        signs.append(sign)
        target.append(dofs.dof_index(nd, name))
    missing = [f"{nd} {d}" for nd in range(1, n_nodes + 1) for d in DIRECTIONS
               if (nd, d) not in seen]
    if missing:
        raise ConfigError(where, f"{len(missing)} DOFs missing", f"every node 1..{n_nodes} "
                          f"needs y, z, ty, tz; missing: {', '.join(missing[:6])}"
                          + (" ..." if len(missing) > 6 else ""))
    return np.array(rows), np.array(signs), np.array(target)


def _transform(a: np.ndarray, rows: np.ndarray, signs: np.ndarray, target: np.ndarray,
               n_dof: int) -> np.ndarray:
    """``S^T a S`` (matrix) or ``S^T a`` (vector) into rotorsfd's DOF order."""
    out = np.zeros((n_dof, n_dof) if a.ndim == 2 else n_dof)
    if a.ndim == 2:
        out[np.ix_(target, target)] = signs[:, None] * a[np.ix_(rows, rows)] * signs[None, :]
    else:
        out[target] = signs * a[rows]
    return out


def _check(M: np.ndarray, K: np.ndarray, C: np.ndarray, G: np.ndarray) -> None:
    scale = {k: max(float(np.abs(a).max()), 1e-300) for k, a in zip(ARRAYS, (M, K, C, G),
                                                                     strict=True)}
    if float(np.abs(M - M.T).max()) > 1e-9 * scale["M"]:
        raise ConfigError(f"{FIELD}.M", "unsymmetric", "the mass matrix must be symmetric")
    try:
        np.linalg.cholesky(M)
    except np.linalg.LinAlgError:
        raise ConfigError(f"{FIELD}.M", "not positive definite", "every lateral DOF needs "
                          "mass or rotary inertia (condense massless DOFs first)") from None
    if float(np.abs(G + G.T).max()) > 1e-9 * scale["G"]:
        raise ConfigError(f"{FIELD}.G", "not skew-symmetric", "the gyroscopic matrix "
                          "(multiplying the speed) must satisfy G = -G^T")


class MatrixModel:
    """The imported matrices in rotorsfd's DOF order, the node positions and (if given) the
    base-motion terms."""

    def __init__(self, M: np.ndarray, K: np.ndarray, C: np.ndarray, G: np.ndarray,
                 node_x: np.ndarray, base_matrices: np.ndarray | None = None,
                 base_vectors: np.ndarray | None = None) -> None:
        self.M, self.K, self.C, self.G = M, K, C, G
        self.node_x = np.asarray(node_x, dtype=float)
        self.base_matrices, self.base_vectors = base_matrices, base_vectors

    @property
    def has_base_terms(self) -> bool:
        return self.base_matrices is not None


def read_matrices(m: MatricesConfig, search_path: Path | None = None) -> MatrixModel:
    """The :class:`MatrixModel` of ``[rotor.matrices]``; ConfigError (one line naming the
    field) for a missing file or array, a shape, a DOF map or matrix properties."""
    data: dict[str, np.ndarray] = {}
    if m.file is not None:
        data = _read_npz(_path(m.file, "file", search_path))
    else:
        for key, name in zip(ARRAYS, ("mass", "stiffness", "damping", "gyroscopic"),
                             strict=True):
            if getattr(m, name) is not None:
                data[key] = _read_mtx(_path(getattr(m, name), name, search_path), name)
    for key in ("M", "K"):
        if key not in data:
            raise ConfigError(f"{FIELD}.file", m.file, f"must hold the array {key} (and "
                              "optionally C, G, dof_node, dof_direction, node_x)")
    n = data["M"].shape[0] if data["M"].ndim == 2 else -1
    for key in ARRAYS:
        a = data.setdefault(key, np.zeros((max(n, 0), max(n, 0))))
        if a.shape != (n, n) or not np.issubdtype(a.dtype, np.number):
            raise ConfigError(f"{FIELD}.{key}", f"shape {a.shape}", f"must be a square "
                              f"numeric matrix of the size of M ({n} x {n})")
        if not np.all(np.isfinite(a)):
            raise ConfigError(f"{FIELD}.{key}", "non-finite entries", "must be finite")
    x_rows = None
    if m.dof_map is not None:
        node, direction, x_rows = read_dof_map(_path(m.dof_map, "dof_map", search_path))
    elif "dof_node" in data and "dof_direction" in data:
        node, direction = data["dof_node"].astype(int), data["dof_direction"].astype(str)
    else:
        raise ConfigError(f"{FIELD}.dof_map", None, "give dof_map (a CSV of node, direction "
                          "per matrix row) or the arrays dof_node, dof_direction in the .npz")
    rows, signs, target = _selection(node, direction, m.n_nodes, n)
    dropped = np.setdiff1d(np.arange(n), rows)
    for key in ARRAYS:
        a = data[key]
        coupling = max(float(np.abs(a[np.ix_(rows, dropped)]).max(initial=0.0)),
                       float(np.abs(a[np.ix_(dropped, rows)]).max(initial=0.0)))
        if coupling > 1e-12 * max(float(np.abs(a).max()), 1e-300):
            raise ConfigError(f"{FIELD}.{key}", f"coupling {coupling:.3g}", "the dropped "
                              "DOFs (x, tx) must not couple to the lateral ones; condense "
                              "them into the model first")
    n_dof = dofs.n_dof(m.n_nodes)
    M, K, C, G = (_transform(data[k].astype(float), rows, signs, target, n_dof)
                  for k in ARRAYS)
    _check(M, K, C, G)
    node_x = _node_x(data, x_rows, node, rows, m.n_nodes)
    bm, bv = data.get("base_matrices"), data.get("base_vectors")
    if (bm is None) != (bv is None) or (bm is not None and (
            bm.shape != (N_BASE_MATRICES, n, n) or bv.shape != (N_BASE_VECTORS, n))):
        raise ConfigError(f"{FIELD}.file", "base_matrices/base_vectors", f"give both, of "
                          f"shapes ({N_BASE_MATRICES}, {n}, {n}) and ({N_BASE_VECTORS}, {n})")
    if bm is not None:
        bm = np.stack([_transform(b, rows, signs, target, n_dof) for b in bm])
        bv = np.stack([_transform(v, rows, signs, target, n_dof) for v in bv])
    return MatrixModel(M, K, C, G, node_x, bm, bv)


def _node_x(data: dict[str, np.ndarray], x_rows: np.ndarray | None, node: np.ndarray,
            rows: np.ndarray, n_nodes: int) -> np.ndarray:
    where = f"{FIELD}.node_x"
    if x_rows is not None:
        x = np.full(n_nodes, np.nan)
        for i in rows:
            if not np.isnan(x[node[i] - 1]) and x[node[i] - 1] != x_rows[i]:
                raise ConfigError(f"{FIELD}.dof_map[{i}].x", x_rows[i], f"node {node[i]} "
                                  f"is at x = {x[node[i] - 1]:g} m in an earlier row")
            x[node[i] - 1] = x_rows[i]
    elif "node_x" in data:
        x = np.asarray(data["node_x"], dtype=float)
    else:
        raise ConfigError(where, None, "give the nodes' axial positions: the array node_x "
                          "in the .npz or the column x of dof_map")
    if x.shape != (n_nodes,) or not np.all(np.isfinite(x)) or not np.all(np.diff(x) > 0):
        raise ConfigError(where, x.tolist() if x.size < 8 else f"{x.size} values",
                          f"must be {n_nodes} increasing positions [m], one per node")
    return x


class MatrixRotor(LinearRotor):
    """A rotor whose M, K, C, G come from :class:`MatrixModel`, plus the supports, disks,
    point masses and structural damping of the configuration, added as
    :class:`~rotorsfd.model.rotor.Rotor` adds them. Same interface as ``Rotor``
    (``n_nodes``, ``n_dof``, ``node_x``, ``M, K, C, G``, ``matrices(speed)``, ...)."""

    shaft_elements: tuple = ()

    def __init__(self, model: MatrixModel, disks: tuple[Disk, ...] = (),
                 point_masses: tuple[PointMass, ...] = (),
                 supports: tuple[LinearSupport, ...] = (),
                 damping: RayleighDamping | ModalDamping | None = None) -> None:
        self.model = model
        self.disks, self.point_masses = tuple(disks), tuple(point_masses)
        self.supports, self.damping = tuple(supports), damping
        self.node_x = model.node_x
        self.element_x = self.node_x[:-1].copy()
        self.x_start = float(self.node_x[0])
        self.n_nodes = self.node_x.size
        self.n_dof = dofs.n_dof(self.n_nodes)
        for kind, items in (("disk", self.disks), ("point_mass", self.point_masses),
                            ("support", self.supports)):
            for item in items:
                if not 1 <= item.node <= self.n_nodes:
                    raise ConfigError(f"{kind}.node", item.node,
                                      f"must be a node of the rotor, 1..{self.n_nodes}")
        M, K, C, G = (a.copy() for a in (model.M, model.K, model.C, model.G))
        for d in self.disks:
            y, z, ty, tz = dofs.node_dofs(d.node)
            M[y, y] += d.mass
            M[z, z] += d.mass
            M[ty, ty] += d.diametral_inertia
            M[tz, tz] += d.diametral_inertia
            G[ty, tz] += d.polar_inertia
            G[tz, ty] -= d.polar_inertia
        for p in self.point_masses:
            y, z = dofs.node_dofs(p.node)[:2]
            M[y, y] += p.mass
            M[z, z] += p.mass
        for s in self.supports:
            yz = np.ix_(dofs.node_dofs(s.node)[:2], dofs.node_dofs(s.node)[:2])
            K[yz] += s.stiffness
            C[yz] += s.damping
        if damping is not None:
            C += damping.matrix(M, K)
        self.M, self.K, self.C, self.G = M, K, C, G
        self.M_csr, self.K_csr, self.C_csr, self.G_csr = (
            sp.csr_matrix(a) for a in (M, K, C, G))
        rows, cols = np.nonzero((M != 0) | (K != 0) | (C != 0) | (G != 0))
        #: (kl, ku): the lower and upper bandwidths of M, C, G, K together
        self.band = (int(max((rows - cols).max(initial=0), 0)),
                     int(max((cols - rows).max(initial=0), 0)))

    def with_supports(self, extra_supports: Any) -> MatrixRotor:
        """A new rotor with the same matrices, disks, masses and damping, plus
        ``extra_supports``."""
        return MatrixRotor(self.model, self.disks, self.point_masses,
                           self.supports + tuple(extra_supports), self.damping)

    def imported_base_basis(self) -> Any:
        """The :class:`~rotorsfd.model.base_terms.BaseBasis` (12 matrices, 8 vectors) of the
        imported matrices, as given or only the translation loads ``f_y = M r_y``,
        ``f_z = M r_z`` (exact; the rest zero: no base rotation, which
        :func:`check_base_motion` enforces), plus the disks' and point masses' terms."""
        m = self.model
        if m.has_base_terms:
            mats, vecs = m.base_matrices.copy(), m.base_vectors.copy()
        else:
            mats = np.zeros((N_BASE_MATRICES, self.n_dof, self.n_dof))
            vecs = np.zeros((N_BASE_VECTORS, self.n_dof))
            vecs[0] = m.M[:, 0::4].sum(axis=1)   # fy = M r_y (r_y: unit y at every node)
            vecs[1] = m.M[:, 1::4].sum(axis=1)   # fz = M r_z
        lumped = [(d.node, d.mass, d.polar_inertia, d.diametral_inertia) for d in self.disks]
        lumped += [(p.node, p.mass, 0.0, 0.0) for p in self.point_masses]
        for node, mass, ip, idi in lumped:
            idx = dofs.node_dofs(node)
            me, ve = disk_basis(mass, ip, idi, float(self.node_x[node - 1]))
            mats[:, idx[:, None], idx[None, :]] += me
            vecs[:, idx] += ve
        return BaseBasis(mats, vecs)

    @property
    def total_mass(self) -> float:
        """r_y^T M r_y [kg] (the mass moving with a rigid translation along y)."""
        return float(self.M[0::4, 0::4].sum())

    def __repr__(self) -> str:
        return (f"MatrixRotor(n_nodes={self.n_nodes}, supports={len(self.supports)}, "
                f"mass={self.total_mass:.4g} kg)")


def check_base_motion(config: Config, model: MatrixModel) -> None:
    """ConfigError if the base rotates and the imported model has no base-motion terms."""
    if model.has_base_terms:
        return
    for name in ("rolling", "pitching", "yawing"):
        law = getattr(config.base, name).law
        if law != "off":
            raise ConfigError(f"base.{name}.law", law, "a rotor given by matrices without "
                              "the base-motion terms (base_matrices, base_vectors in the "
                              ".npz, as `rotorsfd export-matrices` writes them) takes base "
                              "translation and gravity only: set it 'off' or add the terms")


def matrix_rotor(config: Config, search_path: Path | None, disks: list, point_masses: list,
                 supports: list, damping: Any) -> MatrixRotor:
    """The :class:`MatrixRotor` of a config with ``[rotor.matrices]`` (called by
    :func:`rotorsfd.model.build.build_rotor`)."""
    model = read_matrices(config.rotor.matrices, search_path)
    check_base_motion(config, model)
    return MatrixRotor(model, tuple(disks), tuple(point_masses), tuple(supports), damping)
