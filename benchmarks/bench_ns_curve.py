"""Neimark-Sacker curve: one evaluation of the NS-augmented system (residual, and the
test function's row of the Jacobian by central differences of the shifted Hill operator
in every unknown) with the shifted Hill operator built block by block in Python loops (the
previous code, kept here as the baseline) against the batched build with the receptance
blocks cached while only the orbit changes (harmonic/ns_curve.py).

Problem: examples/journal_bearing_rotor.toml at U = 1 g mm, the secondary Hopf of the
speed branch (H = 3, K = 6 pairs, as ``bifurcation-curves``). The two evaluations give
the same F and J (the largest difference is in the note).

Run: ``python -m benchmarks --only ns-curve`` (or ``python benchmarks/bench_ns_curve.py``).
"""

from __future__ import annotations

import sys
from pathlib import Path

if __package__ in (None, ""):  # run as a script: make the repository's `benchmarks` importable
    sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

import numpy as np

from benchmarks.common import ROOT, Row, interleaved

EXAMPLE = ROOT / "examples" / "journal_bearing_rotor.toml"


def loop_hill(problem, X, lam, theta, K, n_samples=64):
    """The shifted Hill operator as built before (one solve and inverse per harmonic, the
    Jacobian convolution in a double loop)."""
    from rotorsfd.harmonic.synthesis import orbit_samples

    w = float(problem.frequency(lam))
    sigma = theta * w
    nl = np.asarray(problem.nl_dofs)
    m = nl.size
    M, D, Kmat = problem.matrices(lam)
    ks = np.arange(-K, K)
    A = np.zeros((2 * K * m, 2 * K * m), dtype=complex)
    for i, k in enumerate(ks):
        W = k * w + sigma
        Z = Kmat - W**2 * M + 1j * W * D
        Hs = np.linalg.solve(Z, np.eye(Z.shape[0])[:, nl])[nl]
        A[i * m:(i + 1) * m, i * m:(i + 1) * m] = np.linalg.inv(Hs)
    N = max(n_samples, 4 * K + 2 * X.shape[0])
    q, v = orbit_samples(np.asarray(X)[:, nl], w, N)
    Jq, Jv = problem.law(lam).jacobian(q, v)
    Jq_hat = np.fft.fft(np.asarray(Jq), axis=0) / N
    Jv_hat = np.fft.fft(np.asarray(Jv), axis=0) / N
    for i, k in enumerate(ks):
        for j, kj in enumerate(ks):
            lag = (k - kj) % N
            A[i * m:(i + 1) * m, j * m:(j + 1) * m] -= (
                Jq_hat[lag] + 1j * (kj * w + sigma) * Jv_hat[lag])
    return A


def setup(H: int = 3):
    from rotorsfd.harmonic.fold_curve import TwoParameterHB
    from rotorsfd.harmonic.fourier import to_real
    from rotorsfd.harmonic.ns_curve import NeimarkSackerSystem
    from rotorsfd.harmonic.periodic import continue_periodic
    from rotorsfd.io.config import config_from_dict, read_toml
    from rotorsfd.model.build import build_system
    from rotorsfd.stability.branch_stability import branch_stability

    family = build_system(config_from_dict(read_toml(EXAMPLE))).two_parameter_problem(
        "unbalance.magnitude")
    p = family.first(1e-6)
    branch = continue_periodic(p, 950.0, 1150.0, H)
    (b,) = [b for b in branch_stability(branch, p).bifurcations
            if b.kind == "secondary-hopf"]
    pt = branch.point_at(b.s)
    xs0 = to_real(np.asarray(pt.X))[:, p.nl_dofs]
    hb = TwoParameterHB(family, H, 32, (200.0, 1e-6), xs0, (pt.lam, 1e-6))
    zb = hb.to_z(xs0, pt.lam, 1e-6)
    theta = abs(float(np.angle(b.critical))) / (2 * np.pi)
    z = np.concatenate([zb[:-1], [theta], zb[-1:]])
    return NeimarkSackerSystem(hb, z, 2 * H), z


class LoopSystem:
    """The NS system with the loop-built operator and no block cache (the baseline)."""

    def __init__(self, ns) -> None:
        self.ns = ns

    def evaluate(self, z):
        ns = self.ns

        def hill(z_):
            zb = ns.embed(z_)
            _, lam1, lam2 = ns.base.from_z(zb)
            X = ns.base.coefficients(zb)
            problem = ns.base.problem.first(lam2)
            return ns.unit * loop_hill(problem, X, lam1, ns.theta(z_), ns.K, ns.base.N)

        ns_hill, ns.hill = ns.hill, hill
        try:
            return ns.evaluate(z)
        finally:
            del ns.hill   # the method again
            assert ns.hill == ns_hill


def run(quick: bool = False, repeat: int = 3) -> list[Row]:
    ns, z = setup()
    old = LoopSystem(ns)
    F0, J0 = old.evaluate(z)
    F1, J1 = ns.evaluate(z)
    diff = float(max(np.max(np.abs(F1 - F0)), np.max(np.abs(J1 - J0))))
    res = interleaved({"loop": lambda: old.evaluate(z), "batched": lambda: ns.evaluate(z)},
                      1 if quick else repeat)
    case = f"journal-bearing rotor NS system, n = {z.size} unknowns, K = {ns.K}"
    t_old = res["loop"][0]
    return [Row("ns-curve", case, "loop-built Hill operator (previous)", t_old,
                repeat=repeat, ratio=1.0, ref="loop"),
            Row("ns-curve", case, "batched, receptance blocks cached", res["batched"][0],
                repeat=repeat, ratio=res["batched"][0] / t_old, ref="loop",
                note=f"max |F, J difference| = {diff:.1e}")]


if __name__ == "__main__":
    for r in run(quick="--quick" in sys.argv):
        print(r)
