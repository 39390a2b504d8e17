"""The coded closed-form element matrices equal the integrals of the Timoshenko shape
functions, derived here independently with sympy, entry by entry."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.model import Material, ShaftElement

sp = pytest.importorskip("sympy")


def _timoshenko_shape_functions():
    """Cubic v and quadratic psi solving the homogeneous Timoshenko statics
    kGA (v'' - psi') = 0, EI psi'' + kGA (v' - psi) = 0 with end values [v1, psi1, v2, psi2]."""
    x, L, phi = sp.symbols("x L Phi", positive=True)
    a = sp.symbols("a0:4")
    b = sp.symbols("b0:3")
    v = sum(a[i] * x**i for i in range(4))
    psi = sum(b[i] * x**i for i in range(3))
    ei = 1
    kga = 12 * ei / (phi * L**2)
    eqs = list(sp.Poly(sp.expand(kga * (v.diff(x, 2) - psi.diff(x))), x).all_coeffs())
    eqs += list(sp.Poly(sp.expand(ei * psi.diff(x, 2) + kga * (v.diff(x) - psi)), x).all_coeffs())
    q = sp.symbols("q0:4")
    eqs += [v.subs(x, 0) - q[0], psi.subs(x, 0) - q[1], v.subs(x, L) - q[2], psi.subs(x, L) - q[3]]
    sol = sp.solve(eqs, list(a) + list(b), dict=True)[0]
    vs, ps = sp.expand(v.subs(sol)), sp.expand(psi.subs(sol))
    nv = [sp.diff(vs, qq) for qq in q]
    npsi = [sp.diff(ps, qq) for qq in q]
    return x, L, phi, nv, npsi


@pytest.fixture(scope="module")
def element_and_sympy():
    el = ShaftElement(0.07, 0.012, 0.031, Material(7810.0, 211e9, 81.783e9))
    x, L, phi, nv, npsi = _timoshenko_shape_functions()
    subs = {L: sp.Float(el.length, 30), phi: sp.Float(el.shear_parameter, 30)}
    nv = [sp.Poly(sp.simplify(f).subs(subs), x) for f in nv]       # numeric polynomials
    npsi = [sp.Poly(sp.simplify(f).subs(subs), x) for f in npsi]
    # 8-DOF shape rows: x-y plane [y, tz] -> (v, psi); x-z plane [z, -ty] -> (v, psi)
    zero = sp.Poly(0, x)

    def row(plane_y: bool, fun):
        r = [zero] * 8
        idx, sgn = ([0, 3, 4, 7], [1, 1, 1, 1]) if plane_y else ([1, 2, 5, 6], [1, -1, 1, -1])
        for k in range(4):
            r[idx[k]] = sgn[k] * fun[k]
        return r

    n_y, n_z = row(True, nv), row(False, nv)
    n_tz, n_ty = row(True, npsi), [-f for f in row(False, npsi)]
    g_y = [a - b for a, b in zip(row(True, [f.diff(x) for f in nv]), n_tz, strict=True)]
    # x-z plane shear strain: dz/dx - (-ty) = dz/dx + ty
    g_z = [a + b for a, b in zip(row(False, [f.diff(x) for f in nv]), n_ty, strict=True)]

    def d(r):
        return [f.diff(x) for f in r]

    def outer(a, b):
        """int_0^L a_i b_j dx as a float 8x8 array."""
        out = np.empty((8, 8))
        for i in range(8):
            for j in range(8):
                prim = (a[i] * b[j]).integrate()
                out[i, j] = float(prim.eval(el.length) - prim.eval(0))
        return out

    def integ(pairs):
        return sum(sign * outer(a, b) for sign, a, b in pairs)

    mat = el.material
    rho_a, rho_i = mat.density * el.area, mat.density * el.second_moment
    ei, kga = mat.young_modulus * el.second_moment, el.kappa * mat.shear_modulus * el.area
    ref = {
        "Mt": rho_a * integ([(1, n_y, n_y), (1, n_z, n_z)]),
        "Mr": rho_i * integ([(1, n_ty, n_ty), (1, n_tz, n_tz)]),
        "K": ei * integ([(1, d(n_ty), d(n_ty)), (1, d(n_tz), d(n_tz))])
        + kga * integ([(1, g_y, g_y), (1, g_z, g_z)]),
        "G": 2 * rho_i * integ([(1, n_ty, n_tz), (-1, n_tz, n_ty)]),
    }
    return el, ref


@pytest.mark.parametrize(
    "name, method",
    [("Mt", "translational_mass_matrix"), ("Mr", "rotational_mass_matrix"),
     ("K", "stiffness_matrix"), ("G", "gyroscopic_matrix")],
)
def test_closed_form_equals_shape_function_integral(element_and_sympy, name, method):
    el, ref = element_and_sympy
    coded = getattr(el, method)()
    scale = np.abs(ref[name]).max()
    np.testing.assert_allclose(coded, ref[name], rtol=0, atol=1e-12 * scale)


def test_gyroscopic_sign_matches_disk_convention(element_and_sympy):
    """G[ty1, tz1] > 0 like a disk's G[ty, tz] = +Ip, and the diagonal blocks sum to 2 rho I L."""
    el, _ = element_and_sympy
    g = el.gyroscopic_matrix()
    assert g[2, 3] > 0.0
    # rigid rotation of the whole element (tz1 = tz2 = 1, y = x tz, likewise ty) must give
    # the polar inertia Ip_total = 2 rho I L exactly: e_ty^T G e_tz for rigid modes
    lx = el.length
    rig_tz = np.array([0, 0, 0, 1, lx, 0, 0, 1.0])     # y = x * tz
    rig_ty = np.array([0, 0, 1, 0, 0, -lx, 1, 0.0])    # z = -x * ty
    assert rig_ty @ g @ rig_tz == pytest.approx(el.polar_inertia, rel=1e-12)
