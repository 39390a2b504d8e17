# ---
# jupyter:
#   jupytext:
#     formats: py:percent
#   kernelspec:
#     display_name: Python 3
#     language: python
#     name: python3
# ---

# %% [markdown]
# # Time integration: the motion at one speed
#
# `run_simulation` integrates the nonlinear rotor in time (compiled Newmark, Newton on the
# SFD's degrees of freedom only) and classifies the motion from its Poincare section,
# spectrum and largest Lyapunov exponent.
#
# The case: the paper rotor at U = 144.02 g mm (Table 1) at Omega~ = 1.055, inside the
# speed range where the periodic response has two stable branches (notebook 02). Coarse
# settings: 300 periods at T/200 (the paper integrates 2000), the last 50 kept for the
# Poincare section; the run says in its summary how much halving the step moves the orbit.

# %%
# %matplotlib inline
import numpy as np

from rotorsfd import api

config = api.load_config("examples/paper_rotor.toml", [
    "unbalance[0].magnitude=144.02 g*mm",
    "analysis.response.speed_range.start_ratio=0.9",
    "analysis.response.speed_range.stop_ratio=1.2",
])
sim = api.run_simulation(config, speed_ratio=1.055, periods=300, poincare_periods=50,
                         steps_per_period=200, progress=False)
print(sim.summary())

# %% [markdown]
# From every node displaced by 1 um the rotor settles on a period-1 orbit: one Poincare
# point per revolution, one spectral line at Omega, a negative Lyapunov exponent.

# %%
evidence = sim.summary_dict()["evidence"]
print(sim.motion_name, "| Poincare points:", evidence["n_distinct_poincare"],
      "| lines / Omega:", [round(r, 6) for r in evidence["frequency_ratios"]],
      f"| Lyapunov {evidence['lyapunov_per_period']:.4f} per period")
assert sim.motion_name == "period-1"
assert evidence["n_distinct_poincare"] == 1
assert evidence["lyapunov_per_period"] < 0

# %% [markdown]
# The four panels: the journal orbit in the clearance circle, the phase diagram, the
# Poincare section and the amplitude spectrum.

# %%
figures = sim.plot()
figures["simulation.png"]

# %% [markdown]
# ## Which branch? The time domain against harmonic balance
#
# An independent check of both methods: the periodic orbit found by time integration
# must be one of the stable harmonic-balance solutions at that speed. The HB branch at
# Omega~ = 1.055 has three solutions (linear interpolation between branch points); the
# orbit's largest journal eccentricity must equal one of the two stable ones to within
# the step and truncation errors (here about 3e-3 C).

# %%
branch = api.run_response(config, progress=False)
s = branch.speeds / branch.reference_speed
r = branch.deflection(1)
stable = branch.table()["stable"]
solutions = []
for i in np.flatnonzero((s[:-1] - 1.055) * (s[1:] - 1.055) <= 0):
    w = (1.055 - s[i]) / (s[i + 1] - s[i])
    solutions.append((float(r[i] + w * (r[i + 1] - r[i])), bool(stable[i] and stable[i + 1])))
print("HB solutions at Omega~ = 1.055 (r~ at the journal, stable):", solutions)
print(f"time domain: max eccentricity {sim.max_eccentricity:.4f}")
assert len(solutions) == 3 and [st for _, st in solutions].count(True) == 2
nearest = min(solutions, key=lambda rs: abs(rs[0] - sim.max_eccentricity))
assert nearest[1] and abs(nearest[0] - sim.max_eccentricity) < 1e-2, nearest

# %% [markdown]
# It is the lower stable branch. The upper one is reached from another start: `from_hb`
# starts on an HB orbit, `initial_state` from a previous run's final state, and
# `rotorsfd attractors` samples many starts (README, "Coexisting motions").
