"""Peak resident memory, each case in a fresh subprocess.

Measured as the kernel's peak resident set size of the process, ``VmHWM`` in
``/proc/self/status`` (all allocations: Python, numpy, numba, BLAS): after imports and
model set-up the resident size is noted (the baseline) and the peak reset
(``/proc/self/clear_refs``), so the table's peak is that of the run, with its increase
over the set-up. (``getrusage(RUSAGE_SELF).ru_maxrss`` is not used: on Linux it keeps
the parent's peak across fork + exec, so a child of a large parent reports the parent's
size.) Linux only.

- HB branch of the paper rotor, H = 8, Omega~ 0.5 .. 1.6 (U = 144.02 g mm): condensed
  (default, stores the condensed Jacobians) and the full-model path.
- 2000 periods x 200 steps of the paper rotor at Omega~ 0.8: the full time series kept
  (q and v of all 84 DOF at every step, ``record_dofs='all'``), the SFD DOFs kept at every
  step, and streamed as ``rotorsfd simulate`` does (chunks of 20 periods, the last 100
  periods of the SFD DOFs and the Poincare points kept).

Two subprocesses run at a time (each measures its own peak; ``--quick``: all five).
``--quick``: Omega~ 0.5 .. 0.6 and 20 periods.
"""

from __future__ import annotations

from concurrent.futures import ThreadPoolExecutor

from benchmarks.common import Row, run_python

PRELUDE = r"""
import json
from benchmarks.common import W1
def status(key):
    with open("/proc/self/status") as fh:
        for line in fh:
            if line.startswith(key + ":"):
                return int(line.split()[1]) / 1024.0  # kB -> MiB
def reset_peak():
    with open("/proc/self/clear_refs", "w") as fh:
        fh.write("5")  # resets VmHWM to the current RSS (Linux >= 4.0)
def rss():
    return status("VmHWM")
def setup_done():
    reset_peak()
    return status("VmRSS")
"""

HB = PRELUDE + r"""
from benchmarks.common import paper_config, paper_system, response_options
from rotorsfd.harmonic.periodic import continue_periodic
problem = paper_system().periodic_problem()
opts = response_options(paper_config())
base = setup_done()
b = continue_periodic(problem, 0.5 * W1, {stop} * W1, 8, condensed={condensed}, **opts)
print(json.dumps({{"base": base, "peak": rss(), "points": b.n_points}}))
"""

SIM = PRELUDE + r"""
from benchmarks.bench_timedomain import ours, paper_inputs
from rotorsfd.analyses.simulate import displaced_state, integrate_periods
system, inp = paper_inputs()
q0 = displaced_state(inp.M.shape[0], 1e-6)
ours(inp, 200, 1, q0, 0.0)
base = setup_done()
P = {periods}
mode = "{mode}"
if mode == "all":
    r = ours(inp, 200, P, q0, 0.0, record_dofs="all")
    kept = r.q.nbytes + r.v.nbytes
elif mode == "sfd":
    r = ours(inp, 200, P, q0, 0.0)
    kept = r.q.nbytes + r.v.nbytes
else:
    r = integrate_periods(inp, q0, 0.0, steps_per_period=200, periods=P,
                          record_dofs=[int(d) for d in inp.nl_dofs],
                          record_periods=min(P, 100), poincare_periods=min(P, 100))
    kept = r.q.nbytes + r.v.nbytes + r.poincare_q.nbytes + r.poincare_v.nbytes
print(json.dumps({{"base": base, "peak": rss(), "kept_MiB": kept / 2**20}}))
"""


def run(quick: bool = False, repeat: int = 1) -> list[Row]:
    stop = 0.6 if quick else 1.6
    P = 20 if quick else 2000
    codes = [HB.format(stop=stop, condensed=c) for c in (True, False)]
    codes += [SIM.format(periods=P, mode=m) for m in ("all", "sfd", "streamed")]
    with ThreadPoolExecutor(5 if quick else 2) as ex:  # peaks are per process
        results = list(ex.map(run_python, codes))
    rows = []
    for condensed, r in zip((True, False), results[:2], strict=True):
        rows.append(Row("memory", f"HB branch H=8, Omega~ 0.5-{stop}",
                        "condensed" if condensed else "full HB", r["peak"], unit="MiB",
                        note=(f"+{r['peak'] - r['base']:.1f} MiB over the set-up "
                              f"({r['base']:.0f} MiB); {r['points']} points"), extra=r))
    names = {"all": "all DOFs kept (q, v every step)", "sfd": "SFD DOFs kept every step",
             "streamed": "streamed (chunks; last 100 periods + Poincare)"}
    for (_mode, name), r in zip(names.items(), results[2:], strict=True):
        rows.append(Row("memory", f"simulation {P} periods x 200 steps", name, r["peak"],
                        unit="MiB",
                        note=(f"+{r['peak'] - r['base']:.1f} MiB over the set-up "
                              f"({r['base']:.0f} MiB); arrays kept {r['kept_MiB']:.1f} MiB"),
                        extra=r))
    return rows
