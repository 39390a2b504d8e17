"""Rotor on a moving base: Lagrange's equations in the base frame, derived with sympy.

Run ``python derivations/base_motion.py`` to print the derived disk and unbalance terms,
``python derivations/base_motion.py --check`` to compare them, and the Timoshenko shaft
element's, with ``rotorsfd.model.base_terms`` / ``rotorsfd.model.unbalance`` (random
parameters and base states, relative tolerance 1e-10); exits 1 on any mismatch.

Kinematics (base frame Oxyz, base angular velocity w = (wx, wy, wz), velocity of O in base
components v0, gravity g in base components):

* a material point at r = (x, y, z): absolute velocity V = v0 + r' + w x r (axial motion
  neglected: x fixed); potential of gravity -m g . r;
* a rigid slice (disk, or shaft slice of length dx) tilted by tz about z, then by ty about
  the new y, then spun by Omega t about its axis (docs/INTERFACES.md): angular velocity in
  the tilted frame = R^T w + (Omega - tz' sin ty, ty', tz' cos ty), R = Rz(tz) Ry(ty);
  T_rot = 1/2 [Ip om_x^2 + Id (om_y^2 + om_z^2)];
* Lagrange's equations, linearised in the DOFs q by expanding L to second order in q
  (base rates, their derivatives and their products with Omega kept exactly):
  ``M q'' + (Omega G + C_base) q' + K_base q = F_base``.

Shaft element: with u = (y, z, ty, tz) = N(s) q (Timoshenko interpolation, shear
parameter Phi) and the slice Lagrangian L = 1/2 [u';u]^T H [u';u] + b^T [u';u] + c
(mass rho A, Id = rho I, Ip = 2 rho I per unit length), the element Lagrangian is
1/2 [q';q]^T (int N^T H N ds) [q';q] + ..., whose Lagrange equations are

    M = H_vv,  D = H_vv' + H_vq - H_vq^T,  K = H_vq' - H_qq,  F = b_q - b_v'

(each block integrated with N). The same formula applied to the disk (N = identity)
reproduces the direct sympy Lagrange derivation (checked below).
"""

from __future__ import annotations

import argparse
import sys
from functools import cache

import numpy as np
import sympy as sp

t = sp.Symbol("t", real=True)
m, Id, Ip, xd, Om = sp.symbols("m I_d I_p x_d Omega", real=True)
W = [sp.Function(n, real=True)(t) for n in ("w_x", "w_y", "w_z")]
V0 = [sp.Function(n, real=True)(t) for n in ("v_x", "v_y", "v_z")]
GR = [sp.Function(n, real=True)(t) for n in ("g_x", "g_y", "g_z")]
eps = sp.Symbol("epsilon")

# plain symbols standing for the base state at one instant (for printing and lambdify)
wx, wy, wz, dwx, dwy, dwz = sp.symbols("w_x w_y w_z dw_x dw_y dw_z", real=True)
vx, vy, vz, dvx, dvy, dvz = sp.symbols("v_x v_y v_z dv_x dv_y dv_z", real=True)
gx, gy, gz = sp.symbols("g_x g_y g_z", real=True)
STATE_SYMBOLS = (wx, wy, wz, dwx, dwy, dwz, vx, vy, vz, dvx, dvy, dvz, gx, gy, gz)


def _freeze(expr: sp.Expr) -> sp.Expr:
    """Replace the functions of t and their first derivatives by plain state symbols."""
    rep = {}
    for f, s, ds in zip(W, (wx, wy, wz), (dwx, dwy, dwz), strict=True):
        rep[f.diff(t)] = ds
        rep[f] = s
    for f, s, ds in zip(V0, (vx, vy, vz), (dvx, dvy, dvz), strict=True):
        rep[f.diff(t)] = ds
        rep[f] = s
    for f, s in zip(GR, (gx, gy, gz), strict=True):
        rep[f] = s
    return sp.expand(sp.sympify(expr).subs(rep))


def _rz(a):
    return sp.Matrix([[sp.cos(a), -sp.sin(a), 0], [sp.sin(a), sp.cos(a), 0], [0, 0, 1]])


def _ry(a):
    return sp.Matrix([[sp.cos(a), 0, sp.sin(a)], [0, 1, 0], [-sp.sin(a), 0, sp.cos(a)]])


def slice_lagrangian(u, ud, mass, i_d, i_p, x):
    """L = T - V of a rigid slice at axial x with DOFs u = (y, z, ty, tz), rates ud."""
    y, z, ty, tz = u
    w = sp.Matrix(W)
    r = sp.Matrix([x, y, z])
    vel = sp.Matrix(V0) + sp.Matrix([0, ud[0], ud[1]]) + w.cross(r)
    rot = _rz(tz) * _ry(ty)
    om = rot.T * w + sp.Matrix([Om - ud[3] * sp.sin(ty), ud[2], ud[3] * sp.cos(ty)])
    T = mass / 2 * vel.dot(vel) + (i_p * om[0] ** 2 + i_d * (om[1] ** 2 + om[2] ** 2)) / 2
    Vg = -mass * sp.Matrix(GR).dot(r)
    return T - Vg


def quadratic_part(L, variables):
    """L expanded to second order in ``variables`` (by derivatives in epsilon at 0)."""
    Le = L.subs({v: eps * v for v in variables}, simultaneous=True)
    return sum(sp.diff(Le, eps, k).subs(eps, 0) / sp.factorial(k) for k in range(3))


# ---------------------------------------------------------------------------------------
# 1. rigid disk, direct Lagrange with functions of time
# ---------------------------------------------------------------------------------------
@cache
def disk_direct():
    """(M, D, K, F) of a disk at x_d by Lagrange's equations with q(t) functions."""
    q = [sp.Function(n, real=True)(t) for n in ("y", "z", "ty", "tz")]
    qd = [qi.diff(t) for qi in q]
    L = quadratic_part(slice_lagrangian(q, qd, m, Id, Ip, xd), q)
    L = sp.expand(L.doit())
    Q = sp.symbols("Q0:4")
    Qd = sp.symbols("Qd0:4")
    Qdd = sp.symbols("Qdd0:4")
    rep = {}
    for a, b, c, d in zip(q, Q, Qd, Qdd, strict=True):
        rep[a.diff(t, 2)] = d
        rep[a.diff(t)] = c
        rep[a] = b
    eqs = [sp.expand((sp.diff(sp.diff(L, qdi), t) - sp.diff(L, qi)).subs(rep))
           for qi, qdi in zip(q, qd, strict=True)]
    zero = {s: 0 for s in Q + Qd + Qdd}
    M = sp.Matrix([[sp.diff(e, s) for s in Qdd] for e in eqs])
    D = sp.Matrix([[sp.diff(e, s) for s in Qd] for e in eqs])
    K = sp.Matrix([[sp.diff(e, s) for s in Q] for e in eqs])
    F = -sp.Matrix([e.subs(zero) for e in eqs])
    return tuple(X.applyfunc(_freeze) for X in (M, D, K, F))


# ---------------------------------------------------------------------------------------
# 2. quadratic-form Lagrange (slice blocks), used for the shaft element
# ---------------------------------------------------------------------------------------
@cache
def slice_blocks(mass=m, i_d=Id, i_p=Ip, x=xd):
    """Hessian blocks (H_vv, H_vq, H_qq) and gradients (b_v, b_q) of the slice Lagrangian."""
    u = sp.symbols("u0:4", real=True)
    ud = sp.symbols("ud0:4", real=True)
    L = sp.expand(quadratic_part(slice_lagrangian(u, ud, mass, i_d, i_p, x), list(u) + list(ud)))
    zero = {s: 0 for s in u + ud}
    Hvv = sp.Matrix(4, 4, lambda i, j: sp.diff(L, ud[i], ud[j]))
    Hvq = sp.Matrix(4, 4, lambda i, j: sp.diff(L, ud[i], u[j]))
    Hqq = sp.Matrix(4, 4, lambda i, j: sp.diff(L, u[i], u[j]))
    bv = sp.Matrix([sp.diff(L, v).subs(zero) for v in ud])
    bq = sp.Matrix([sp.diff(L, v).subs(zero) for v in u])
    return Hvv, Hvq, Hqq, bv, bq


def lagrange_from_blocks(Mvv, Mvq, Mqq, bv, bq):
    """M q'' + D q' + K q = F for L = 1/2 q'^T Mvv q' + q'^T Mvq q + 1/2 q^T Mqq q + ..."""
    d = lambda X: X.diff(t)  # noqa: E731
    M = Mvv
    D = d(Mvv) + Mvq - Mvq.T
    K = d(Mvq) - Mqq
    F = bq - d(bv)
    return tuple(X.applyfunc(_freeze) for X in (M, D, K, F))


@cache
def disk_from_blocks():
    return lagrange_from_blocks(*slice_blocks())


# ---------------------------------------------------------------------------------------
# 3. Timoshenko shaft element
# ---------------------------------------------------------------------------------------
s, Le, Phi, rhoA, rhoI, xl = sp.symbols("s L Phi rhoA rhoI x_l", real=True)


def timoshenko_shape_functions():
    """N (4 x 8): rows (y, z, ty, tz)(s), columns [y1, z1, ty1, tz1, y2, z2, ty2, tz2].

    Plane (v, psi) with psi ~ dv/dx: v = Nv [v1, psi1, v2, psi2], psi = Np [...]
    (interdependent interpolation, exact for end-loaded Timoshenko beams). x-y plane:
    v = y, psi = tz; x-z plane: v = z, psi = -ty.
    """
    xi = s / Le
    c = 1 / (1 + Phi)
    Nv = [c * (2 * xi**3 - 3 * xi**2 - Phi * xi + 1 + Phi),
          c * Le * (xi**3 - (2 + Phi / 2) * xi**2 + (1 + Phi / 2) * xi),
          c * (-2 * xi**3 + 3 * xi**2 + Phi * xi),
          c * Le * (xi**3 - (1 - Phi / 2) * xi**2 - Phi / 2 * xi)]
    Np = [6 * c / Le * (xi**2 - xi),
          c * (3 * xi**2 - (4 + Phi) * xi + 1 + Phi),
          6 * c / Le * (-xi**2 + xi),
          c * (3 * xi**2 - (2 - Phi) * xi)]
    N = sp.zeros(4, 8)
    for k, (iy, itz, iz, ity) in enumerate(((0, 3, 1, 2), (4, 7, 5, 6))):
        N[0, iy], N[0, itz] = Nv[2 * k], Nv[2 * k + 1]           # y
        N[3, iy], N[3, itz] = Np[2 * k], Np[2 * k + 1]           # tz
        N[1, iz], N[1, ity] = Nv[2 * k], -Nv[2 * k + 1]          # z
        N[2, iz], N[2, ity] = -Np[2 * k], Np[2 * k + 1]          # ty = -psi_z
    return N


@cache
def shaft_element_derived():
    """(M, D, K, F) of a shaft element (8 DOFs) with left end at x_l, consistent."""
    N = timoshenko_shape_functions()
    x = sp.Symbol("x_slice", real=True)
    Hvv, Hvq, Hqq, bv, bq = slice_blocks(rhoA, rhoI, 2 * rhoI, x)

    def integ(e):
        return sp.factor(sp.integrate(sp.expand(e), (s, 0, Le)))

    pair = {(i, j): (N[i, :].T * N[j, :]).applyfunc(integ) for i in range(4) for j in range(4)}
    ones = [N[i, :].T.applyfunc(integ) for i in range(4)]
    lin = [(N[i, :].T * (xl + s)).applyfunc(integ) for i in range(4)]

    def mat(H):
        out = sp.zeros(8, 8)
        for i in range(4):
            for j in range(4):
                if H[i, j] != 0:
                    out += H[i, j] * pair[(i, j)]
        return out

    def vec(b):
        out = sp.zeros(8, 1)
        for i in range(4):
            e = sp.expand(b[i])
            a1, a0 = e.coeff(x, 1), e.coeff(x, 0)
            out += a0 * ones[i] + a1 * lin[i]
        return out

    return lagrange_from_blocks(mat(Hvv), mat(Hvq), mat(Hqq), vec(bv), vec(bq))


# ---------------------------------------------------------------------------------------
# 4. unbalance
# ---------------------------------------------------------------------------------------
mu, e_u, eta = sp.symbols("m_u e eta", real=True)


@cache
def unbalance_derived():
    """Force on (y, z) of a mass m_u at eccentricity e, angle Omega t + eta, at q = 0.

    Lagrange's equations of the point mass at (x_d, y + e cos, z + e sin); the part
    proportional to e (terms m_u e q dropped) is minus the unbalance force.
    """
    q = [sp.Function(n, real=True)(t) for n in ("y", "z")]
    th = Om * t + eta
    r = sp.Matrix([xd, q[0] + e_u * sp.cos(th), q[1] + e_u * sp.sin(th)])
    w = sp.Matrix(W)
    vel = sp.Matrix(V0) + r.diff(t) + w.cross(r)
    T = mu / 2 * vel.dot(vel)
    F = []
    for qi in q:
        eq = sp.diff(sp.diff(T, qi.diff(t)), t) - sp.diff(T, qi)
        eq = eq.subs({qi.diff(t, 2): 0 for qi in q}).subs({qi.diff(t): 0 for qi in q})
        eq = eq.subs({qi: 0 for qi in q})
        F.append(-sp.expand(eq).coeff(e_u, 1) * e_u)
    return sp.Matrix([_freeze(f) for f in F])


# ---------------------------------------------------------------------------------------
# 5. comparison with the code
# ---------------------------------------------------------------------------------------
def _close(name, coded, derived, rtol=1e-10, failures=None):
    coded, derived = np.asarray(coded, float), np.asarray(derived, float)
    scale = max(float(np.max(np.abs(derived))), 1e-300)
    err = float(np.max(np.abs(coded - derived))) / scale if derived.size else 0.0
    ok = err <= rtol and coded.shape == derived.shape
    print(f"  {'ok  ' if ok else 'FAIL'} {name:<42s} max rel err {err:.2e}")
    if not ok and failures is not None:
        failures.append(name)
    return ok


def _random_state(rng):
    vals = dict(zip(STATE_SYMBOLS, rng.normal(size=len(STATE_SYMBOLS)) * 3.0, strict=True))
    return vals


def _state_object(vals):
    from rotorsfd.model.base_motion import BaseState
    w = np.array([vals[wx], vals[wy], vals[wz]])
    v = np.array([vals[vx], vals[vy], vals[vz]])
    dv = np.array([vals[dvx], vals[dvy], vals[dvz]])
    a0 = dv + np.cross(w, v)  # a0 = v0' + w x v0
    return BaseState(w=w, dw=np.array([vals[dwx], vals[dwy], vals[dwz]]), a0=a0, v0=v,
                     g=np.array([vals[gx], vals[gy], vals[gz]]))


def check(n_trials: int = 3, seed: int = 1) -> list[str]:
    """Compare coded terms with the derivation; return the names of failed comparisons."""
    from rotorsfd.model.base_terms import (
        assemble_base,
        base_basis,
        disk_base_terms,
        shaft_base_terms,
    )
    from rotorsfd.model.disk import Disk
    from rotorsfd.model.materials import Material
    from rotorsfd.model.rotor import Rotor
    from rotorsfd.model.shaft import ShaftElement
    from rotorsfd.model.unbalance import Unbalance, unbalance_force, unbalance_harmonics

    failures: list[str] = []
    rng = np.random.default_rng(seed)

    print("disk: direct Lagrange == quadratic-form Lagrange (symbolic)")
    for name, a, b in zip("MDKF", disk_direct(), disk_from_blocks(), strict=True):
        same = sp.simplify(a - b) == sp.zeros(*a.shape)
        print(f"  {'ok  ' if same else 'FAIL'} {name}")
        if not same:
            failures.append(f"disk blocks {name}")

    args = (m, Id, Ip, xd, Om, *STATE_SYMBOLS)
    disk_fns = [sp.lambdify(args, X, "numpy") for X in disk_direct()]
    sargs = (rhoA, rhoI, Le, Phi, xl, Om, *STATE_SYMBOLS)
    shaft_fns = [sp.lambdify(sargs, X, "numpy") for X in shaft_element_derived()]
    unb_fn = sp.lambdify((mu, e_u, eta, Om, t, *STATE_SYMBOLS), unbalance_derived(), "numpy")

    for trial in range(n_trials):
        vals = _random_state(rng)
        sv = [vals[k] for k in STATE_SYMBOLS]
        st = _state_object(vals)
        om = float(rng.uniform(-500, 500))
        print(f"trial {trial}: Omega = {om:.3f}")
        # disk
        dm, dip, did, dx = rng.uniform(0.5, 20), rng.uniform(0.01, 1), rng.uniform(0.01, 1), \
            rng.uniform(-1, 1)
        M, D, K, F = (np.asarray(f(dm, did, dip, dx, om, *sv), float) for f in disk_fns)
        disk = Disk(1, dm, dip, did)
        C_b, K_b, F_b = disk_base_terms(disk, dx, st, om)
        G = np.zeros((4, 4))
        G[2, 3], G[3, 2] = dip, -dip
        _close("disk M", np.diag([dm, dm, did, did]), M, failures=failures)
        _close("disk Omega G + C_base", om * G + C_b, D, failures=failures)
        _close("disk K_base", K_b, K, failures=failures)
        _close("disk F_base", F_b, F.ravel(), failures=failures)
        # shaft element
        young = rng.uniform(5e10, 3e11)
        mat = Material(rng.uniform(2000, 9000), young, young / (2.0 * (1.0 + rng.uniform(0.2, 0.4))))
        ro = rng.uniform(0.01, 0.08)
        el = ShaftElement(rng.uniform(0.01, 0.3), ro * rng.uniform(0, 0.9), ro, mat)
        rA = mat.density * el.area
        rI = mat.density * el.second_moment
        x_left = float(rng.uniform(-1, 1))
        M, D, K, F = (np.asarray(f(rA, rI, el.length, el.shear_parameter, x_left, om, *sv), float)
                      for f in shaft_fns)
        C_b, K_b, F_b = shaft_base_terms(el, x_left, st, om)
        _close("shaft M (vs ShaftElement.mass_matrix)", el.mass_matrix(), M, failures=failures)
        _close("shaft Omega G + C_base", om * el.gyroscopic_matrix() + C_b, D, failures=failures)
        _close("shaft K_base", K_b, K, failures=failures)
        _close("shaft F_base", F_b, F.ravel(), failures=failures)
        # global assembly of a two-element rotor with a disk at node 2
        els = [el, ShaftElement(el.length * 0.7, el.inner_radius, el.outer_radius, mat)]
        rotor = Rotor(els, disks=[disk.__class__(2, dm, dip, did)], x_start=x_left)
        C_g, K_g, F_g = assemble_base(rotor, st, om)
        Md, Cd, Kd, Fd = np.zeros((12, 12)), np.zeros((12, 12)), np.zeros((12, 12)), np.zeros(12)
        for i, e in enumerate(els):
            rA_i = mat.density * e.area
            M_i, D_i, K_i, F_i = (np.asarray(f(rA_i, rI, e.length, e.shear_parameter,
                                              float(rotor.element_x[i]), om, *sv), float)
                                for f in shaft_fns)
            ix = np.ix_(range(4 * i, 4 * i + 8), range(4 * i, 4 * i + 8))
            Md[ix] += M_i
            Cd[ix] += D_i - om * e.gyroscopic_matrix()
            Kd[ix] += K_i
            Fd[4 * i:4 * i + 8] += F_i.ravel()
        M_d, D_d, K_dd, F_dd = (np.asarray(f(dm, did, dip, rotor.node_x[1], om, *sv), float)
                              for f in disk_fns)
        ix = np.ix_(range(4, 8), range(4, 8))
        Md[ix] += M_d
        Cd[ix] += D_d - om * G
        Kd[ix] += K_dd
        Fd[4:8] += F_dd.ravel()
        _close("rotor C_base (assembled)", C_g, Cd, failures=failures)
        _close("rotor K_base (assembled)", K_g, Kd, failures=failures)
        _close("rotor F_base (assembled)", F_g, Fd, failures=failures)
        _close("rotor M (vs Rotor.M)", rotor.M, Md, failures=failures)
        _close("rotor G (vs -P_J of the basis)", rotor.G, -base_basis(rotor).matrix("PJ"),
               failures=failures)
        # unbalance
        U, ph, tt = float(rng.uniform(1e-5, 1e-3)), float(rng.uniform(0, 6.3)), \
            float(rng.uniform(0, 1))
        Fu = np.asarray(unb_fn(1.0, U, ph, om, tt, *sv), float).ravel()
        fc = unbalance_force([Unbalance(2, U, ph)], rotor, om, st, tt)
        _close("unbalance force F(t)", fc[4:6], Fu, failures=failures)
        st0 = _state_object({**vals, dwy: 0.0, dwz: 0.0})
        Fc, Fs = unbalance_harmonics([Unbalance(2, U, ph)], rotor, om, st0)
        Fu0 = np.asarray(unb_fn(1.0, U, ph, om, tt, *[vals[k] if k not in (dwy, dwz) else 0.0
                                                      for k in STATE_SYMBOLS]), float).ravel()
        harm = Fc[4:6] * np.cos(om * tt) + Fs[4:6] * np.sin(om * tt)
        _close("unbalance harmonics F_c cos + F_s sin", harm, Fu0, failures=failures)
    return failures


def show() -> None:
    """Print the derived disk terms and the unbalance force."""
    M, D, K, F = disk_direct()
    G = sp.zeros(4, 4)
    G[2, 3], G[3, 2] = Ip, -Ip
    C = sp.simplify(D - Om * G)
    print("Disk at x_d, DOFs (y, z, ty, tz); a = v0' + w x v0 - g.\n")
    print("M ="), sp.pprint(M)
    print("\nD - Omega G = C_base ="), sp.pprint(sp.factor(C))
    print("\nK_base =")
    for i in range(4):
        for j in range(4):
            if K[i, j] != 0:
                print(f"  K[{i},{j}] = {sp.factor(K[i, j])}")
    a_sub = {dvy: sp.Symbol("a_y") - (wz * vx - wx * vz) + gy,
             dvz: sp.Symbol("a_z") - (wx * vy - wy * vx) + gz}
    print("\nF_base =")
    for i in range(4):
        print(f"  F[{i}] = {sp.collect(sp.expand(F[i].subs(a_sub)), [m, Id, Ip])}")
    th = sp.Symbol("theta")
    print("\nunbalance force (y, z), theta = Omega t + eta =")
    for f in unbalance_derived():
        g = sp.expand(f.subs(t, (th - eta) / Om))
        print("  ", sp.collect(g, [sp.cos(th), sp.sin(th)], sp.factor))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--check", action="store_true", help="compare with rotorsfd")
    parser.add_argument("--trials", type=int, default=3)
    args = parser.parse_args(argv)
    if not args.check:
        show()
        return 0
    failures = check(args.trials)
    print("ALL OK" if not failures else f"MISMATCH: {failures}")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
