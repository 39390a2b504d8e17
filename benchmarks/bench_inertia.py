"""SFD fluid inertia (issue 18 item 1): what the acceleration-dependent force costs, what
the solvers without it pay for the new path (nothing measurable is the aim), and the
figure of ``docs/sfd.md`` (force against whirl speed with and without inertia).

1. ``per sample``: the SFD element's compiled kernel over 512 states (eps uniform in
   [0, 0.9]) in a compiled loop, the plain law and the inertial one (viscous + inertia,
   Gauss-Legendre over the film arc, with dF/da), pi film.
2. ``newmark``: the paper rotor (examples/paper_rotor.toml) at Omega~ = 0.95, 40 periods
   of the compiled Newmark step at T/400 from rest, without and with the fluid inertia
   (oil 860 kg/m^3, Re_s = 1.8).
3. ``hb``: one HB solve (H = 3) of the same case, without and with inertia.

Run from the repository: ``python benchmarks/bench_inertia.py [--figure docs/sfd_inertia.png]``;
with ``PYTHONPATH`` at another tree (the baseline before this change) the parts that need
the inertia are skipped, so the plain rows compare the two trees.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

MU, C, CR, LD, RHO = 0.0051, 1.27e-4, 0.00485, 0.325, 860.0  # the paper's damper, an oil
W1 = 811.3
INERTIA = [f"elements.sfd.density={RHO} kg/m^3", "elements.sfd.fluid_inertia=true"]


def _cpu(fun, repeat: int = 5) -> float:
    best = []
    for _ in range(repeat):
        t = time.process_time()
        fun()
        best.append(time.process_time() - t)
    return float(np.median(best))


def per_sample() -> dict[str, float]:
    from numba import njit

    from rotorsfd.elements.sfd import SFDConfig

    geo = dict(node=1, viscosity=f"{MU} Pa*s", clearance=f"{C} m",
               clearance_ratio=f"{CR}", length_to_diameter=LD)
    rng = np.random.default_rng(0)
    eps = rng.uniform(0, 0.9, 512)
    psi = rng.uniform(-np.pi, np.pi, 512)
    q = np.ascontiguousarray(np.stack([eps * C * np.cos(psi), eps * C * np.sin(psi)], 1))
    v = np.ascontiguousarray(rng.normal(size=(512, 2)) * 300 * C)
    a = np.ascontiguousarray(rng.normal(size=(512, 2)) * 3e5 * C)
    out: dict[str, float] = {}
    plain = SFDConfig(**geo).build("s")

    @njit
    def loop(kernel, q, v, params, F, dq, dv):  # type: ignore[no-untyped-def]
        s = 0
        for i in range(q.shape[0]):
            s += kernel(q[i], v[i], params, F, dq, dv)
        return s

    F, dq, dv, da = np.empty(2), np.empty((2, 2)), np.empty((2, 2)), np.empty((2, 2))
    p = plain.kernel_params
    loop(plain.kernel, q, v, p, F, dq, dv)
    out["plain kernel [us/sample]"] = _cpu(lambda: [loop(plain.kernel, q, v, p, F, dq, dv)
                                                    for _ in range(200)]) / (200 * 512) * 1e6
    try:
        inert = SFDConfig(**geo, density=f"{RHO} kg/m^3", fluid_inertia=True).build("s")
    except Exception:  # the baseline tree has no fluid inertia
        return out

    @njit
    def loop_a(kernel, q, v, a, params, F, dq, dv, da):  # type: ignore[no-untyped-def]
        s = 0
        for i in range(q.shape[0]):
            s += kernel(q[i], v[i], a[i], params, F, dq, dv, da)
        return s

    pa = inert.kernel_params
    k = inert.inertial_kernel
    loop_a(k, q, v, a, pa, F, dq, dv, da)
    out["inertial kernel [us/sample]"] = _cpu(lambda: [loop_a(k, q, v, a, pa, F, dq, dv, da)
                                                       for _ in range(50)]) / (50 * 512) * 1e6
    return out


def _system(inertia: bool):
    from rotorsfd.io.config import load_config
    from rotorsfd.model.build import build_system

    root = Path(__file__).resolve().parents[1]
    return build_system(load_config(root / "examples" / "paper_rotor.toml",
                                    overrides=["unbalance[0].magnitude=144.02 g*mm",
                                               *(INERTIA if inertia else [])]))


def newmark_and_hb(inertia: bool) -> dict[str, float]:
    from rotorsfd.harmonic.periodic import solve_periodic
    from rotorsfd.timedomain.forcing import Forcing, HarmonicLoad
    from rotorsfd.timedomain.integrate import integrate

    system = _system(inertia)
    W = 0.95 * W1
    M, D, K = system.matrices(W)
    Fc, Fs = system.unbalance_harmonics(W)
    forcing = Forcing(omega=W, constant=system.static_force(W),
                      harmonics=[HarmonicLoad(1.0, Fc, Fs)])
    el = system.elements_at(W)
    extra = {"inertial_kernel": el.inertial_kernel} if inertia else {}

    def run():
        return integrate(M, D, K, system.nl_dofs, el.kernel, el.kernel_params, forcing,
                         steps_per_period=400, n_periods=40, record_every=400, **extra)

    run()
    tag = "inertia" if inertia else "plain"
    out = {f"newmark 40 T, {tag} [s]": _cpu(run, 3)}
    problem = system.periodic_problem("speed")
    solve_periodic(problem, W, 3)
    out[f"hb solve H=3, {tag} [s]"] = _cpu(lambda: solve_periodic(problem, W, 3), 3)
    sol = solve_periodic(problem, W, 3)
    out[f"hb eps_max, {tag}"] = float(system.elements.limit(
        np.real(np.exp(1j * np.outer(np.linspace(0, 2 * np.pi, 256), np.arange(4)))
                @ sol.X[:, system.nl_dofs])))
    return out


def figure(path: Path) -> None:
    """Forces of a circular centred orbit against whirl speed, with and without the
    fluid inertia (paper damper, pi and 2 pi film, eps = 0.2 and 0.6)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    from rotorsfd.elements.sfd import SFDConfig

    geo = dict(node=1, viscosity=f"{MU} Pa*s", clearance=f"{C} m",
               clearance_ratio=f"{CR}", length_to_diameter=LD, density=f"{RHO} kg/m^3")
    w = np.linspace(50.0, 3000.0, 120)
    fig, axes = plt.subplots(1, 2, figsize=(10, 4), constrained_layout=True)
    colors = {0.2: "tab:blue", 0.6: "tab:red"}
    for cav, style in (("pi", "-"), ("none", "--")):
        films = {flag: SFDConfig(**geo, cavitation=cav, fluid_inertia=flag).build("s")
                 for flag in (False, True)}
        for eps, color in colors.items():
            for flag, alpha in ((False, 0.45), (True, 1.0)):
                Fr, Ft = [], []
                for om in w:
                    q = np.array([eps * C, 0.0])
                    v = np.array([0.0, eps * C * om])
                    a = np.array([-eps * C * om**2, 0.0])
                    F = films[flag].force_and_jacobians(q, v, a)[0]
                    Fr.append(F[0])
                    Ft.append(F[1])
                label = (f"{'pi' if cav == 'pi' else '2 pi'} film, eps = {eps}, "
                         f"{'with' if flag else 'without'} inertia")
                axes[0].plot(w, Fr, style, color=color, alpha=alpha, label=label)
                axes[1].plot(w, Ft, style, color=color, alpha=alpha, label=label)
    for ax, name in zip(axes, ("radial force F_r [N]", "tangential force F_t [N]"),
                        strict=True):
        ax.set_xlabel("whirl speed omega [rad/s]")
        ax.set_ylabel(name)
        ax.axhline(0.0, color="0.6", lw=0.6)
        top = ax.secondary_xaxis("top", functions=(lambda x: RHO * x * C**2 / MU,
                                                   lambda r: r * MU / (RHO * C**2)))
        top.set_xlabel("squeeze Reynolds number rho omega C^2 / mu")
    axes[1].legend(fontsize=7, loc="lower left")
    fig.suptitle(f"circular centred orbits, C = {C * 1e3:.3g} mm, L/D = {LD}, "
                 f"mu = {MU} Pa s, rho = {RHO:g} kg/m^3")
    fig.savefig(path, dpi=120)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--figure", type=Path)
    args = ap.parse_args()
    if args.figure is not None:
        figure(args.figure)
        print("wrote", args.figure)
        return 0
    import rotorsfd

    print("tree:", Path(rotorsfd.__file__).parents[1])
    rows = per_sample()
    rows.update(newmark_and_hb(False))
    try:
        rows.update(newmark_and_hb(True))
    except Exception as exc:  # the baseline tree
        print("inertia rows skipped:", type(exc).__name__, exc)
    for k, v in rows.items():
        print(f"{k:32s} {v:.4g}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
