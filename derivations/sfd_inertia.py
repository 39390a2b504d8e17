"""Fluid inertia of the short open-ended squeeze film damper, derived with sympy.

Run ``python derivations/sfd_inertia.py`` to print the derivation's results,
``python derivations/sfd_inertia.py --check`` to compare the implemented force
(``rotorsfd.model.film_inertia`` through the SFD element's inertial kernel) with an
independent double quadrature of the derived pressure field at random states, and the
centred coefficients with their closed forms; exits 1 on any mismatch.

Short film (``L << R``): only the axial flow ``u(x, y, phi, t)`` across the film
``0 <= y <= h(phi, t)``, no axial wall motion (the journal does not slide axially),
``h = C - q.n``, ``n = (cos phi, sin phi)``.

1. Averaged inertia (bulk flow; San Andres and Vance 1986, San Andres 2012). Integrate the
   axial momentum equation ``rho (u_t + (u^2)_x + (u w)_y) = -p_x + mu u_yy`` across the
   film with the axial flow ``Q = int u dy``: ``int u_t dy = Q_t``, ``int (u^2)_x dy =
   (int u^2 dy)_x`` (h does not depend on x), ``[u w] = 0`` and, with the Poiseuille
   profile ``u = 6 Q y (h - y) / h^3`` for the wall shear and ``int u^2``::

       rho (Q_t + (6/5) (Q^2/h)_x) = -h p_x - 12 mu Q / h^2

   Continuity of the short film, ``h_t + Q_x = 0`` with ``Q(0) = 0`` (symmetry), gives
   ``Q = -h_t x``, and ``p(+-L/2) = 0`` (open ends) gives the pressure printed below.
2. The formal first-order perturbation in ``Re_s`` (Reinhardt and Lund 1975; Hamzehlouia
   and Behdinan 2017): ``u = u0 + u1`` with ``mu u1_yy = p1_x + rho (u0_t + u0 u0_x + w0
   u0_y)`` and ``int u1 dy = 0``, i.e. ``p1_x = -(6 rho / h^3) int (...) y (h - y) dy``.
   Its temporal term weights the profile, which gives ``6/5`` where the averaged form has
   1: the centred added mass is 6/5 of the averaged form's (printed below). The code uses
   the averaged form (``rotorsfd.model.film_inertia`` says why).

Force ``F = -R int_film int_x p n dx dphi`` with ``h_t = -v.n``, ``h_tt = -a.n``; the
centred coefficients follow from ``int_0^(2 pi) n n^T dphi = pi I`` (half of it over the
pi film's half circle).
"""

from __future__ import annotations

import argparse
import sys

import numpy as np
import sympy as sp

x, y, L, R, C, mu, rho, t = sp.symbols("x y L R C mu rho t", positive=True)
hs, hd, hdd = sp.symbols("h h_t h_tt")   # film thickness and its time derivatives


def averaged_pressure() -> sp.Expr:
    """p(x) of the averaged-inertia short film (module doc, step 1)."""
    Q = -hd * x
    Q_t = -hdd * x                                  # d/dt at fixed x
    conv = sp.diff(sp.Rational(6, 5) * Q**2 / hs, x)
    dpdx = -(rho * (Q_t + conv) + 12 * mu * Q / hs**2) / hs
    p = sp.integrate(dpdx, x)
    p = p - p.subs(x, L / 2)                        # p(+-L/2) = 0 (p is even in x)
    return sp.factor(sp.expand(p))


def profile_weighted_temporal_factor() -> sp.Expr:
    """The perturbation's weight on the temporal term at the centred position (h fixed):
    ``int u0_t 6 y (h - y)/h^3 dy`` over ``Q_t / h``, with ``u0 = 6 Q y (h - y)/h^3``."""
    Qt = sp.Symbol("Q_t")
    u0t = 6 * Qt * y * (hs - y) / hs**3
    weighted = sp.integrate(u0t * 6 * y * (hs - y) / hs**3, (y, 0, hs))
    return sp.simplify(weighted / (Qt / hs))


def centred_coefficients(p: sp.Expr) -> dict[str, sp.Expr]:
    """Added mass and damping of the full and the pi film at the centre (h = C, small
    motion): ``F = -c v - m a``."""
    phi = sp.Symbol("phi")
    vy, ay = sp.symbols("v_y a_y")
    n = sp.Matrix([sp.cos(phi), sp.sin(phi)])
    sub = {hs: C, hd: -vy * sp.cos(phi), hdd: -ay * sp.cos(phi)}
    lin = sp.expand(p.subs(sub))
    lin = lin.subs(vy**2, 0)                        # small motion: drop (n.v)^2
    px = sp.integrate(lin, (x, -L / 2, L / 2))
    out = {}
    for film, (a, b) in {"full": (0, 2 * sp.pi), "pi": (0, sp.pi)}.items():
        Fy = sp.simplify(-R * sp.integrate(px * n[0], (phi, a, b)))
        out[f"damping_{film}"] = sp.simplify(-sp.diff(Fy, vy))
        out[f"added_mass_{film}"] = sp.simplify(-sp.diff(Fy, ay))
    return out


def check(n_states: int = 6, rtol: float = 1e-8) -> bool:
    """The element's force at random states against a double quadrature of the derived
    pressure, and the centred coefficients against their closed forms."""
    from scipy.integrate import quad

    from rotorsfd.elements.sfd import SFDConfig

    p = averaged_pressure()
    pf = sp.lambdify((x, hs, hd, hdd, L, mu, rho), p, "numpy")
    rng = np.random.default_rng(7)
    geo = dict(node=1, viscosity="0.003 Pa*s", clearance="0.15 mm", radius="40 mm",
               length="12 mm", density="860 kg/m^3", fluid_inertia=True)
    Rv, Lv, Cv, muv, rhov = 0.04, 0.012, 1.5e-4, 0.003, 860.0
    ok = True
    for cav in ("none", "pi"):
        e = SFDConfig(**geo, cavitation=cav).build("s")
        for _ in range(n_states):
            q = rng.uniform(-0.6, 0.6, 2) * Cv
            v = rng.normal(size=2) * Cv * 800.0
            a = rng.normal(size=2) * Cv * 6e5
            F = e.force_and_jacobians(q, v, a)[0]
            psi = np.arctan2(q[1], q[0])
            lo, hi = (0.0, 2 * np.pi) if cav == "none" else (psi, psi + np.pi)

            def integrand(ph: float, k: int, q=q, v=v, a=a) -> float:
                nv = np.array([np.cos(ph), np.sin(ph)])
                h, hd, hdd = Cv - q @ nv, -v @ nv, -a @ nv
                px = quad(lambda xx: pf(xx, h, hd, hdd, Lv, muv, rhov),
                          -Lv / 2, Lv / 2)[0]
                return -Rv * px * nv[k]

            ref = np.array([quad(integrand, lo, hi, args=(k,), epsabs=0, epsrel=1e-12,
                                 limit=200)[0] for k in range(2)])
            err = np.max(np.abs(F - ref)) / np.max(np.abs(ref))
            ok &= err < rtol
            print(f"{cav:5s} eps={np.hypot(*q) / Cv:.3f}: force vs quadrature {err:.2e}")
    coef = {k: float(v.subs({R: Rv, L: Lv, C: Cv, mu: muv, rho: rhov}))
            for k, v in centred_coefficients(p).items()}
    for cav, film in (("none", "full"), ("pi", "pi")):
        e = SFDConfig(**geo, cavitation=cav).build("s")
        _, _, Jv, Ja = e.force_and_jacobians(np.zeros(2), np.zeros(2), np.zeros(2))
        for name, J in (("damping", Jv), ("added_mass", Ja)):
            err = abs(-J[0, 0] - coef[f"{name}_{film}"]) / coef[f"{name}_{film}"]
            ok &= err < rtol
            print(f"{film:4s} centred {name}: {-J[0, 0]:.6e} vs {coef[f'{name}_{film}']:.6e}")
    return bool(ok)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--check", action="store_true")
    args = ap.parse_args()
    p = averaged_pressure()
    print("averaged-inertia pressure p(x) =", p)
    print("perturbation / averaged temporal weight =", profile_weighted_temporal_factor())
    for k, v in centred_coefficients(p).items():
        print(f"{k} = {v}")
    if args.check:
        good = check()
        print("check:", "ok" if good else "MISMATCH")
        return 0 if good else 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
