"""Fit the two support stiffnesses of the paper rotor (Zhang et al. 2025, section 4).

The paper gives the rotor but not the stiffness of the SFD centring spring (node 1) nor
of the right support (node 21); both are taken isotropic and fitted so that the first two
forward critical speeds are 811.3 and 2784.6 rad/s. The solution is unique for
stiffnesses in 1e5..1e10 N/m: along the curve where the first forward critical speed is
811.3 rad/s, the second decreases monotonically from > 4000 rad/s (k1 ~ 8e6 N/m) to about
2470 rad/s (k1 ~ 2e7 N/m), then rises towards 2775 rad/s < 2784.6 rad/s as k1 -> inf
(rigid left support); it crosses 2784.6 rad/s once. Run:

    /work/venv/bin/python scripts/fit_paper_supports.py
"""

from __future__ import annotations

import time

from rotorsfd.linear import critical_speeds
from rotorsfd.linear.fit import fit_support_stiffness
from rotorsfd.model import Disk, LinearSupport, Material, Rotor, uniform_shaft

STEEL = Material(density=7810.0, young_modulus=211e9, shear_modulus=81.783e9)
TARGETS = (811.3, 2784.6)


def paper_rotor(k_centring: float, k_right: float) -> Rotor:
    """0.5994 m hollow shaft (r 20.65/30.15 mm), 20 elements, disk at node 8,
    isotropic supports at nodes 1 (SFD centring spring) and 21; no structural damping."""
    shaft = uniform_shaft(0.5994, 20, 20.65e-3, 30.15e-3, STEEL)
    disk = Disk.from_geometry(8, STEEL.density, 30.15e-3, 101.6e-3, 50.8e-3)
    supports = [LinearSupport.isotropic(1, k_centring), LinearSupport.isotropic(21, k_right)]
    return Rotor(shaft, disks=[disk], supports=supports)


def main() -> None:
    t0 = time.perf_counter()
    fit = fit_support_stiffness(paper_rotor, TARGETS, x0=(1e7, 1e7))
    k1, k21 = fit.stiffnesses
    rotor = paper_rotor(k1, k21)
    crit = critical_speeds(rotor, n=3, speed_range=(0.0, 2e4))
    print(f"rotor: {rotor}")
    print(f"centring spring at node 1   k = {k1:.6e} N/m")
    print(f"right support at node 21    k = {k21:.6e} N/m")
    for c, t in zip(crit, (*TARGETS, float("nan")), strict=False):
        print(f"forward critical speed {c.mode}: {c.speed_rad_s:.4f} rad/s (target {t})")
    print(f"relative errors: {[f'{r:.2e}' for r in fit.relative_errors]}; exact={fit.exact}")
    print(fit.message)
    print(f"({time.perf_counter() - t0:.1f} s)")


if __name__ == "__main__":
    main()
