"""``max_multiplier_outside`` in a response's files: written with ``StabilityOptions
(outside=True)`` and equal to an independent evaluation of the averaged model's modes above
the cut-off; with ``outside=False`` not written at all (no 0.0 column standing for "not
computed").

The independent evaluation, per point of the branch: the orbit sampled at 1024 phases here
(the evaluator uses its Newmark M samples), the SFD Jacobians averaged, the averaged model
``lambda^2 M + lambda (D - P Jv_bar P^T) + K - P Jq_bar P^T`` solved as a generalized
eigenproblem ``A z = lambda B z`` of the first-order form (the code inverts M in a
companion matrix), the modes with ``|Im lambda| > omega_cut = M_b / (4 T)`` kept and
``max |exp(lambda T)|`` taken. Tolerance: the mean of the smooth periodic Jacobian
converges spectrally in the samples (100 to 4096 change the result by < 3e-7 here); the
two eigensolvers differ by a few 1e-9 of |lambda| on the modes near the cut-off, and
``|mu| = exp(Re lambda T)`` turns that into a relative error of ``|lambda| T`` (> 100
there) times it: up to 1.3e-6 observed. 1e-5 allows both and still fails for another
mode set (the next mode's |mu| differs by > 1e-3), period or damping.
"""

from __future__ import annotations

import csv

import numpy as np
import scipy.linalg as sla
import xarray as xr

from rotorsfd.analyses.response import run_response
from rotorsfd.paper.cases import CASES
from rotorsfd.paper.run import load_case_config
from rotorsfd.stability.branch_options import StabilityOptions

#: Omega~ 1.040-1.047 of the calibrated U = 144.02 g mm case: damped, a few points.
START, STOP = 1.04 * 811.3, 1.047 * 811.3


def _run(outside: bool, tmp_path):
    config = load_case_config(CASES["cal-fig7-u144"])
    options = StabilityOptions.from_section(config.analysis.stability, outside=outside)
    r = run_response(config, progress=False, stability_options=options, start=START,
                     stop=STOP)
    out = tmp_path / ("on" if outside else "off")
    r.write(out, plots=False)
    with (out / "branch.csv").open() as f:
        rows = [row for row in csv.reader(f) if row and not row[0].startswith("#")]
    with xr.open_dataset(out / "branch.nc") as ds:
        nc = ds["max_multiplier_outside"].values.copy() \
            if "max_multiplier_outside" in ds else None
    return r, options, rows, nc


def _averaged_outside(problem, lam: float, X: np.ndarray, n_basis: int) -> float:
    """max |exp(lambda T)| of the averaged model's modes above M_b / (4 T) (docstring)."""
    w = float(problem.frequency(lam))
    T = 2 * np.pi / w
    nl = np.asarray(problem.nl_dofs)
    Xnl = np.asarray(X, complex)[:, nl]
    k = np.arange(Xnl.shape[0])
    th = 2 * np.pi * np.arange(1024) / 1024
    E = np.exp(1j * np.outer(th, k))
    q, v = (E @ Xnl).real, (E @ (1j * w * k[:, None] * Xnl)).real
    Jq, Jv = problem.law(lam).jacobian(q, v)
    M, D, K = (np.array(a, float) for a in problem.matrices(lam))
    K[np.ix_(nl, nl)] -= Jq.mean(axis=0)
    D[np.ix_(nl, nl)] -= Jv.mean(axis=0)
    n = M.shape[0]
    A = np.block([[np.zeros((n, n)), np.eye(n)], [-K, -D]])
    B = np.block([[np.eye(n), np.zeros((n, n))], [np.zeros((n, n)), M]])
    ev = sla.eigvals(A, B)
    ev = ev[np.isfinite(ev) & (np.abs(ev.imag) > 0.25 * n_basis / T)]
    return float(np.max(np.abs(np.exp(ev * T)))) if ev.size else 0.0


def test_outside_on_is_written_and_matches_the_averaged_model(tmp_path):
    r, options, rows, nc = _run(True, tmp_path)
    assert r.system.periodic_problem().law(r.branch.lam[0]).force_jacobians is None
    header = rows[0]
    assert "max_multiplier_outside" in header
    col = np.array([float(x[header.index("max_multiplier_outside")]) for x in rows[1:]])
    assert col.size == r.branch.n_points >= 3
    assert nc is not None
    np.testing.assert_array_equal(nc, col)
    problem = r.system.periodic_problem()
    ref = np.array([_averaged_outside(problem, float(r.branch.lam[i]), r.branch.X[i],
                                      options.basis_intervals or options.n_intervals)
                    for i in range(r.branch.n_points)])
    assert np.all((ref > 0.5) & (ref < 1.0))         # damped: every left-out mode decays
    np.testing.assert_allclose(col, ref, rtol=1e-5)


def test_outside_off_is_not_written(tmp_path):
    r, _, rows, nc = _run(False, tmp_path)
    assert r.info["max_multiplier_outside"] is None
    assert r.info["stability"].max_multiplier_outside is None
    assert "max_multiplier_outside" not in rows[0]
    assert "max_multiplier" in rows[0]
    assert nc is None


def test_options_from_a_section_are_the_responses():
    """``StabilityOptions.from_section`` gives what ``run_response`` builds from the same
    ``[analysis.stability]`` section (the paper's cases use it to turn ``outside`` off)."""
    config = load_case_config(CASES["fig7-u144"],
                              extra=("analysis.stability.intervals=200",
                                     "analysis.stability.adaptive_intervals=false"))
    r = run_response(config, progress=False, start=0.9 * 811.3, stop=0.92 * 811.3)
    assert r.info["stability_options"] == StabilityOptions.from_section(
        config.analysis.stability)
    assert StabilityOptions.from_section(config.analysis.stability).interval_tol is None
    assert not StabilityOptions.from_section(config.analysis.stability,
                                             outside=False).outside
