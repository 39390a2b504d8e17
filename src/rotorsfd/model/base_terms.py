"""Base-motion terms C_base, K_base, F_base of the rotor, as constant bases times scalars.

Derived with sympy in ``derivations/base_motion.py`` (Lagrange's equations in the base
frame, linearised in the DOFs, base rates kept exactly; ``--check`` compares with this
module). For a slice of the rotor at axial position x with mass m, diametral inertia Id,
polar inertia Ip (a rigid disk; or rho A dx, rho I dx, 2 rho I dx of a shaft slice), in
the DOFs ``(y, z)`` and ``(ty, tz)``, base rates w = (wx, wy, wz), spin Omega:

    C_b = m [[0, -2 wx], [2 wx, 0]]  (+)  (Ip - 2 Id) wx [[0, 1], [-1, 0]]

    K_b(y,z)   = m [[-(wx^2 + wz^2), wy wz - wx'], [wy wz + wx', -(wx^2 + wy^2)]]
    K_b(ty,tz) = [[Ip Omega wx + (Ip-Id)(wx^2 - wz^2),  (Ip-Id) wy wz - Id wx'],
                  [(Ip-Id) wy wz - (Ip-Id) wx',  Ip Omega wx + (Ip-Id)(wx^2 - wy^2)]]

    F_b(y)  = -m [a_y + x (wz' + wx wy)]         F_b(z)  = -m [a_z + x (wx wz - wy')]
    F_b(ty) = -Ip (Omega + wx) wz - Id (wy' - wx wz)
    F_b(tz) = +Ip (Omega + wx) wy - Id (wz' + wx wy)

with a = a0 - g the effective base acceleration (base components). The (Ip - Id) wx' entry
follows from the angle sequence of docs/INTERFACES.md (tz, then ty, then spin).

Every term is a sum of scalar coefficients times constant patterns: writing
``E11, E22, S = E12 + E21, J = E21 - E12`` on a DOF pair, and
``T_*`` = int rho A N_t^T E N_t dx (+ m E at disks, point masses) on (y, z),
``D_*`` = int rho I N_r^T E N_r dx (+ Id E at disks) and
``P_*`` = int 2 rho I N_r^T E N_r dx (+ Ip E at disks) on (ty, tz):

    K_base = -(wx^2+wz^2) T11 - (wx^2+wy^2) T22 + wy wz TS + wx' TJ
             + (Omega wx + wx^2 - wz^2) P11 + (Omega wx + wx^2 - wy^2) P22
             + (wy wz - wx'/2) PS - wx'/2 PJ
             - (wx^2 - wz^2) D11 - (wx^2 - wy^2) D22 - wy wz DS + wx' DJ
    C_base = 2 wx TJ - wx PJ + 2 wx DJ              (note Omega G = -Omega PJ)
    F_base = -a_y fy - a_z fz - (wz' + wx wy) gy - (wx wz - wy') gz
             - (Omega + wx) wz pty + (Omega + wx) wy ptz + (wx wz - wy') dty - (wz' + wx wy) dtz

with the load vectors fy = int rho A N_y^T dx, gy = int rho A x N_y^T dx, pty = int 2 rho I
N_ty^T dx, dty = int rho I N_ty^T dx (+ the disk values m, m x_d, Ip, Id), and so on.
:func:`base_basis` builds the 12 matrices and 8 vectors once per rotor,
:func:`base_coefficients` the scalars per base state (vectorised over time).

Shaft elements: the patterns follow from the element's own mass matrices, since the
Timoshenko interpolation is the same in both planes (``N_z = N_y R``, ``N_ty = -N_tz R``
with R the 90-degree rotation of the DOFs about x) and reproduces rigid-body motions
(``N_y r_t = 1``, ``N_y r_r = s``, ``N_tz r_r = 1``), so that int N^T dx = M r.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import scipy.sparse as sp

from rotorsfd.model import dofs
from rotorsfd.model.base_motion import BaseState
from rotorsfd.model.sparse import DENSE_MAX_DOF, as_csr, assemble

MATRIX_NAMES: tuple[str, ...] = (
    "T11", "T22", "TS", "TJ", "P11", "P22", "PS", "PJ", "D11", "D22", "DS", "DJ",
)
VECTOR_NAMES: tuple[str, ...] = ("fy", "fz", "gy", "gz", "pty", "ptz", "dty", "dtz")

# 8-DOF element: [y1, z1, ty1, tz1, y2, z2, ty2, tz2]
_Y_PLANE = np.array([0, 3, 4, 7])
_R8 = np.zeros((8, 8))  # (R q) in the x-y plane slots: y <- z, tz <- -ty
for _n in (0, 4):
    _R8[_n + 0, _n + 1] = 1.0
    _R8[_n + 3, _n + 2] = -1.0


def _pair_patterns(a11: np.ndarray, a12: np.ndarray, a21: np.ndarray,
                   a22: np.ndarray) -> tuple[np.ndarray, ...]:
    """(E11, E22, S, J) patterns from the four int N_i^T N_j blocks."""
    return a11, a22, a12 + a21, a21 - a12


def shaft_element_basis(element, x_left: float) -> tuple[np.ndarray, np.ndarray]:
    """Local basis of a shaft element: (12, 8, 8) matrices and (8, 8) vectors.

    Uses ``element.translational_mass_matrix()`` = rho A int N_t^T N_t and
    ``element.rotational_mass_matrix()`` = rho I int N_r^T N_r (polar 2 rho I).
    """
    mt = np.asarray(element.translational_mass_matrix(), dtype=float)
    mr = np.asarray(element.rotational_mass_matrix(), dtype=float)
    length = float(element.length)
    mask = np.zeros((8, 8))
    mask[np.ix_(_Y_PLANE, _Y_PLANE)] = 1.0
    tyy = mt * mask            # rho A int N_y^T N_y
    dzz = mr * mask            # rho I int N_tz^T N_tz
    R = _R8
    # translations: N_z = N_y R
    t_pat = _pair_patterns(tyy, tyy @ R, R.T @ tyy, R.T @ tyy @ R)
    # rotations (ty, tz): N_ty = -N_tz R
    d_pat = _pair_patterns(R.T @ dzz @ R, -R.T @ dzz, -dzz @ R, dzz)
    mats = np.array(list(t_pat) + [2.0 * p for p in d_pat] + list(d_pat))
    r_t = np.array([1.0, 0, 0, 0, 1.0, 0, 0, 0])        # y = 1
    r_r = np.array([0.0, 0, 0, 1.0, length, 0, 0, 1.0])  # y = s, tz = 1
    fy = tyy @ r_t
    gy = tyy @ (x_left * r_t + r_r)
    dtz = dzz @ r_r
    dty = -R.T @ dtz
    vecs = np.array([fy, R.T @ fy, gy, R.T @ gy, 2.0 * dty, 2.0 * dtz, dty, dtz])
    return mats, vecs


def disk_basis(mass: float, polar_inertia: float, diametral_inertia: float,
               x_d: float) -> tuple[np.ndarray, np.ndarray]:
    """Local basis of a rigid disk (or point mass with zero inertias) on [y, z, ty, tz]."""
    mats = np.zeros((12, 4, 4))
    vecs = np.zeros((8, 4))
    e11, e22 = np.diag([1.0, 0.0]), np.diag([0.0, 1.0])
    s, j = np.array([[0.0, 1.0], [1.0, 0.0]]), np.array([[0.0, -1.0], [1.0, 0.0]])
    for k, (w, sl) in enumerate(((mass, slice(0, 2)), (polar_inertia, slice(2, 4)),
                                 (diametral_inertia, slice(2, 4)))):
        for i, pat in enumerate((e11, e22, s, j)):
            mats[4 * k + i][sl, sl] = w * pat
    vecs[0, 0] = vecs[1, 1] = mass
    vecs[2, 0] = vecs[3, 1] = mass * x_d
    vecs[4, 2] = vecs[5, 3] = polar_inertia
    vecs[6, 2] = vecs[7, 3] = diametral_inertia
    return mats, vecs


# ---------------------------------------------------------------------------------------
# scalar coefficients
# ---------------------------------------------------------------------------------------
@dataclass(frozen=True)
class BaseCoefficients:
    """Scalars multiplying the basis: c_C, c_K (12, ...) and c_F (8, ...)."""

    c_C: np.ndarray
    c_K: np.ndarray
    c_F: np.ndarray


def base_coefficients(state: BaseState, speed: float) -> BaseCoefficients:
    """Coefficients of C_base, K_base, F_base (module docstring); vectorised over time."""
    wx, wy, wz = np.asarray(state.w, dtype=float)
    dwx, dwy, dwz = np.asarray(state.dw, dtype=float)
    ay, az = np.asarray(state.a_eff, dtype=float)[1:]
    om = float(speed)
    zero = np.zeros_like(wx)
    c_C = np.array([zero, zero, zero, 2.0 * wx, zero, zero, zero, -wx,
                    zero, zero, zero, 2.0 * wx])
    c_K = np.array([
        -(wx**2 + wz**2), -(wx**2 + wy**2), wy * wz, dwx,
        om * wx + wx**2 - wz**2, om * wx + wx**2 - wy**2, wy * wz - 0.5 * dwx, -0.5 * dwx,
        -(wx**2 - wz**2), -(wx**2 - wy**2), -wy * wz, dwx,
    ])
    c_F = np.array([
        -ay, -az, -(dwz + wx * wy), -(wx * wz - dwy),
        -(om + wx) * wz, (om + wx) * wy, wx * wz - dwy, -(dwz + wx * wy),
    ])
    return BaseCoefficients(c_C, c_K, c_F)


RATE_NAMES: tuple[str, ...] = ("speed", "wx", "wy", "wz", "dwx", "dwy", "dwz", "ay", "az")


def base_coefficient_derivatives(state: BaseState, speed: float) -> dict[str, BaseCoefficients]:
    """d(coefficients)/d(p) for p in RATE_NAMES (speed, rates, rate derivatives, a_eff)."""
    wx, wy, wz = (float(v) for v in np.asarray(state.w, dtype=float))
    om = float(speed)
    z12, z8 = np.zeros(12), np.zeros(8)

    def co(c=None, k=None, f=None) -> BaseCoefficients:
        return BaseCoefficients(z12.copy() if c is None else np.asarray(c, float),
                                z12.copy() if k is None else np.asarray(k, float),
                                z8.copy() if f is None else np.asarray(f, float))

    return {
        "speed": co(k=[0, 0, 0, 0, wx, wx, 0, 0, 0, 0, 0, 0],
                    f=[0, 0, 0, 0, -wz, wy, 0, 0]),
        "wx": co(c=[0, 0, 0, 2, 0, 0, 0, -1, 0, 0, 0, 2],
                 k=[-2 * wx, -2 * wx, 0, 0, om + 2 * wx, om + 2 * wx, 0, 0,
                    -2 * wx, -2 * wx, 0, 0],
                 f=[0, 0, -wy, -wz, -wz, wy, wz, -wy]),
        "wy": co(k=[0, -2 * wy, wz, 0, 0, -2 * wy, wz, 0, 0, 2 * wy, -wz, 0],
                 f=[0, 0, -wx, 0, 0, om + wx, 0, -wx]),
        "wz": co(k=[-2 * wz, 0, wy, 0, -2 * wz, 0, wy, 0, 2 * wz, 0, -wy, 0],
                 f=[0, 0, 0, -wx, -(om + wx), 0, wx, 0]),
        "dwx": co(k=[0, 0, 0, 1, 0, 0, -0.5, -0.5, 0, 0, 0, 1]),
        "dwy": co(f=[0, 0, 0, 1, 0, 0, -1, 0]),
        "dwz": co(f=[0, 0, -1, 0, 0, 0, 0, -1]),
        "ay": co(f=[-1, 0, 0, 0, 0, 0, 0, 0]),
        "az": co(f=[0, -1, 0, 0, 0, 0, 0, 0]),
    }


def base_rate_derivative(state: BaseState, speed: float, rate: str) -> BaseCoefficients:
    """d(coefficients)/d(w_i) along a constant base rate ``rate`` ("wx", "wy", "wz") with
    the rest of the base motion held (the origin velocity v0, its derivative and g): the
    partial derivative of :func:`base_coefficient_derivatives` plus the one through the
    origin acceleration a0 = v0' + w x v0, ``d a_eff / d w_i = e_i x v0`` (a base that
    translates while it rotates; through ``ay``, ``az``, the axial component carrying no
    load)."""
    d = base_coefficient_derivatives(state, speed)
    out = d[rate]
    da = state.acceleration_slope(RATE_NAMES.index(rate) - 1)
    if np.any(da[1:] != 0.0):      # without translation: the partial one (the same bits)
        out = BaseCoefficients(out.c_C, out.c_K,
                               out.c_F + da[1] * d["ay"].c_F + da[2] * d["az"].c_F)
    return out


# ---------------------------------------------------------------------------------------
# element-level terms
# ---------------------------------------------------------------------------------------
def _combine(mats: np.ndarray, vecs: np.ndarray,
             co: BaseCoefficients) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    return (np.tensordot(co.c_C, mats, axes=(0, 0)), np.tensordot(co.c_K, mats, axes=(0, 0)),
            np.tensordot(co.c_F, vecs, axes=(0, 0)))


def disk_base_terms(disk, x_d: float, state: BaseState,
                    speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(C_b, K_b, F_b) of a rigid disk at axial position x_d, local [y, z, ty, tz]."""
    mats, vecs = disk_basis(disk.mass, getattr(disk, "polar_inertia", 0.0),
                            getattr(disk, "diametral_inertia", 0.0), x_d)
    return _combine(mats, vecs, base_coefficients(state, speed))


def shaft_base_terms(element, x_left: float, state: BaseState,
                     speed: float) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """(C_b, K_b, F_b) of a Timoshenko shaft element with left end at x_left (8 local DOFs)."""
    mats, vecs = shaft_element_basis(element, x_left)
    return _combine(mats, vecs, base_coefficients(state, speed))


def sum_terms(weights: np.ndarray, arrays: Sequence[Any]) -> Any:
    """sum_i weights_i arrays_i over the nonzero weights only; None if all are zero."""
    out = None
    for c, A in zip(np.asarray(weights, dtype=float), arrays, strict=True):
        if c != 0.0:
            out = c * A if out is None else out + c * A
    return out


# ---------------------------------------------------------------------------------------
# global assembly
# ---------------------------------------------------------------------------------------
class BaseBasis:
    """Global basis of a rotor: the 12 pattern matrices (stored sparse, ``sparse_matrices``,
    CSR inside the rotor's band; ``matrices`` is their dense (12, n, n) stack, built on
    first use) and the 8 load vectors ``vectors`` (8, n)."""

    def __init__(self, matrices: Sequence[Any], vectors: np.ndarray) -> None:
        self.sparse_matrices: tuple[sp.csr_matrix, ...] = tuple(as_csr(a) for a in matrices)
        self.vectors = np.asarray(vectors, dtype=float)
        self._dense: np.ndarray | None = None

    @property
    def n_dof(self) -> int:
        return self.vectors.shape[1]

    @property
    def matrices(self) -> np.ndarray:
        """The dense (12, n, n) stack (built once, on request: 12 n^2 floats)."""
        if self._dense is None:
            self._dense = np.array([a.toarray() for a in self.sparse_matrices])
        return self._dense

    def matrix(self, name: str) -> np.ndarray:
        """Pattern ``name`` (MATRIX_NAMES), dense."""
        return self.sparse_matrices[MATRIX_NAMES.index(name)].toarray()

    def sparse_matrix(self, name: str) -> sp.csr_matrix:
        """Pattern ``name`` (MATRIX_NAMES), CSR."""
        return self.sparse_matrices[MATRIX_NAMES.index(name)]

    def vector(self, name: str) -> np.ndarray:
        return self.vectors[VECTOR_NAMES.index(name)]

    def combine_sparse(self, co: BaseCoefficients) -> tuple[sp.csr_matrix, sp.csr_matrix,
                                                            np.ndarray]:
        """(C_base, K_base, F_base) with the matrices sparse (scalar coefficients)."""
        C, K = (sum_terms(c, self.sparse_matrices) for c in (co.c_C, co.c_K))
        zero = sp.csr_matrix((self.n_dof, self.n_dof))
        F = np.tensordot(self.vectors, co.c_F, axes=(0, 0))
        return (zero if C is None else C), (zero if K is None else K), F

    def combine(self, co: BaseCoefficients) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """(C_base, K_base, F_base) = (sum c_C B, sum c_K B, sum c_F f), the matrices
        dense; F has shape (n,) or (n, nt) for time-vectorised coefficients (the matrices
        need scalar ones)."""
        C, K, F = self.combine_sparse(co)
        return C.toarray(), K.toarray(), F


def keeps_band(n_dof: int) -> bool:
    """True when a model of ``n_dof`` DOFs keeps its base terms as the CSR patterns of
    ``BaseBasis.sparse_matrices`` (inside the rotor's band) instead of the dense stack:
    above :data:`~rotorsfd.model.sparse.DENSE_MAX_DOF` (12 n^2 floats would be formed)."""
    return int(n_dof) > DENSE_MAX_DOF


def base_basis(rotor) -> BaseBasis:
    """Assemble the 12 constant matrices (sparse) and 8 vectors of a rotor (shaft, disks,
    masses)."""
    imported = getattr(rotor, "imported_base_basis", None)   # a rotor given by matrices
    if imported is not None:
        return imported()
    n = rotor.n_dof
    blocks: list[list] = [[] for _ in MATRIX_NAMES]
    vecs = np.zeros((8, n))
    ne = len(rotor.shaft_elements)
    idx = 4 * np.arange(ne)[:, None] + np.arange(8)[None, :]        # (ne, 8)
    local = [shaft_element_basis(el, float(rotor.element_x[i]))
             for i, el in enumerate(rotor.shaft_elements)]
    me = np.array([m for m, _ in local])                              # (ne, 12, 8, 8)
    ve = np.array([v for _, v in local])                              # (ne, 8, 8)
    for j, b in enumerate(blocks):
        b.append((idx, me[:, j]))
    for j in range(8):
        np.add.at(vecs[j], idx, ve[:, j])
    lumped = [(d.node, d.mass, d.polar_inertia, d.diametral_inertia) for d in rotor.disks]
    lumped += [(p.node, p.mass, 0.0, 0.0) for p in getattr(rotor, "point_masses", ())]
    for node, m, ip, idi in lumped:
        idx = dofs.node_dofs(node)
        me, ve = disk_basis(m, ip, idi, float(rotor.node_x[node - 1]))
        for b, mb in zip(blocks, me, strict=True):
            b.append((idx, mb))
        vecs[:, idx] += ve
    return BaseBasis([assemble(n, b) for b in blocks], vecs)


def assemble_base(rotor, state: BaseState, speed: float,
                  basis: BaseBasis | None = None) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Global (C_base, K_base, F_base) for one base state (scalar time)."""
    basis = base_basis(rotor) if basis is None else basis
    return basis.combine(base_coefficients(state, speed))


def base_static_deflection(rotor, state: BaseState, speed: float = 0.0,
                           force: np.ndarray | None = None,
                           basis: BaseBasis | None = None) -> np.ndarray:
    """Static offset under constant base motion: solve (K + K_base) q = F_base (+ force)."""
    basis = base_basis(rotor) if basis is None else basis
    _, K_b, F_b = basis.combine_sparse(base_coefficients(state, speed))
    rhs = F_b if force is None else F_b + np.asarray(force, dtype=float)
    # deferred: scipy.sparse.linalg is heavy (loaded only when this runs)
    from scipy.sparse.linalg import spsolve

    return spsolve(sp.csc_matrix(rotor.K_csr + K_b), rhs)


# ---------------------------------------------------------------------------------------
# time-varying terms for time stepping
# ---------------------------------------------------------------------------------------
def time_varying_terms(basis: BaseBasis, motion, speed: float, probe_times: int = 7,
                       sparse: bool | None = None):
    """Base terms of a time-varying base motion as ``(coefficient(t), array)`` pairs.

    Returns ``(damping, stiffness, force)``: lists of pairs with vectorised callables
    ``c(t) -> (nt,)`` such that C_base(t) = sum c_i(t) C_i, K_base(t) = sum k_i(t) K_i,
    F_base(t) = sum f_j(t) f_j (the shape of ``timedomain.forcing.TimeVaryingMatrices`` and
    ``Forcing.series``). Coefficients that vanish at ``probe_times`` irrational sample times
    in [0, 10] s and at the times where a law that acts only for a while (a shock pulse, a
    record) is nonzero are dropped (exact for the built-in laws). The matrices are the
    CSR patterns when ``sparse`` (default: :func:`keeps_band` of the model's size), else
    the dense stack.
    """
    sparse = keeps_band(basis.n_dof) if sparse is None else bool(sparse)
    mats = basis.sparse_matrices if sparse else basis.matrices
    cache: dict[bytes, BaseCoefficients] = {}

    def coeffs(t: np.ndarray) -> BaseCoefficients:
        t = np.asarray(t, dtype=float)
        key = t.tobytes() + bytes(str(t.shape), "ascii")
        if key not in cache:
            cache.clear()
            cache[key] = base_coefficients(motion.state(t), speed)
        return cache[key]

    probe = np.sqrt(2.0) * (1.0 + np.arange(probe_times)) * 10.0 / (probe_times * np.sqrt(2.0) + 1)
    probe = np.concatenate([probe, motion.support_times()])   # where pulses, records act
    probe_co = base_coefficients(motion.state(probe), speed)

    def make(attr: str, i: int):
        return lambda t: getattr(coeffs(t), attr)[i]

    def pairs(attr: str, arrays: Sequence[Any]) -> list:
        values = np.asarray(getattr(probe_co, attr))
        return [(make(attr, i), arrays[i]) for i in range(len(arrays))
                if np.any(values[i] != 0.0)]

    return (pairs("c_C", mats), pairs("c_K", mats),
            pairs("c_F", basis.vectors))
