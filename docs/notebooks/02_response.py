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
# # Periodic response with Floquet stability
#
# The synchronous response of the paper rotor (`examples/paper_rotor.toml`) to the
# unbalance of the paper's Table 1, U = 144.02 g mm at the disk, by harmonic balance
# (HB-AFT, condensed exactly onto the SFD's degrees of freedom) and pseudo arc-length
# continuation in the speed, with the Floquet multipliers of every point.
#
# Coarse settings, so that the notebook runs in a few seconds: the speed range is
# narrowed to Omega~ = 0.9-1.2 around the jump (the example's is 0.5-1.6), H = 3 harmonics
# as in the paper (the example's setting; `harmonics = "auto"` is the default of a new
# config) and M = 400 Newmark intervals per period for the monodromy to start with
# (doubled at a point until its largest multipliers change by less than 1e-4).
# `rotorsfd response examples/paper_rotor.toml --set "unbalance[0].magnitude=144.02 g*mm"`
# runs the same analysis over the full range.

# %%
# %matplotlib inline
import tempfile

import numpy as np

from rotorsfd import api

config = api.load_config("examples/paper_rotor.toml", [
    "unbalance[0].magnitude=144.02 g*mm",
    "analysis.response.speed_range.start_ratio=0.9",
    "analysis.response.speed_range.stop_ratio=1.2",
])
result = api.run_response(config, progress=False)
print(result.summary())

# %% [markdown]
# ## The frequency response
#
# r~ = max_t sqrt(y^2 + z^2) / C at the SFD journal (node 1) and at the disk (node 8),
# in SFD clearances C, against Omega~ = Omega / 811.3 rad/s. Solid is stable, dashed
# unstable; the circles are the located saddle-nodes. Between them three periodic
# solutions coexist: a run-up jumps down at the upper fold, a run-down jumps up at the
# lower one.

# %%
figures = result.plot()
print(sorted(figures))
figures["response_deflection.png"]

# %% [markdown]
# ## The located bifurcations
#
# Each is located where a Floquet multiplier crosses the unit circle (+1 at a
# saddle-node) and then checked on a piece of the branch recomputed at about 1.5 H
# harmonics and twice the intervals. The README's values for this case are the
# saddle-nodes at Omega~ = 1.0593 and 1.0527 (the paper's Table 1: 1.0565 and 1.0556;
# README, "How our results compare with the paper", says why they differ).

# %%
for b in result.bifurcations:
    print(f"{b['type']:12s} Omega~ = {b['speed_ratio']:.5f}  located multiplier "
          f"{b['located_multiplier_re']:+.5f}  {b['status']} (moves {b['check_shift']:.1e} "
          f"at H = {b['check_harmonics']}, M = {b['check_intervals']})")

folds = sorted(b["speed_ratio"] for b in result.bifurcations if b["type"] == "saddle-node")
assert len(result.bifurcations) == 2 and len(folds) == 2
assert abs(folds[0] - 1.0527) < 1e-3 and abs(folds[1] - 1.0593) < 1e-3, folds
for b in result.bifurcations:
    assert b["status"] == "confirmed"
    assert abs(b["located_multiplier_re"] - 1) < 1e-3       # +1 at a fold

# %% [markdown]
# Two views of the same fact must agree: the points that Floquet calls unstable (largest
# multiplier outside the unit circle) are those of the middle segment between the folds.

# %%
table = result.table()
ratio = table["speed_ratio"]
unstable = ~table["stable"]
print(f"{unstable.sum()} unstable points of {ratio.size}, at Omega~ "
      f"{ratio[unstable].min():.5f} .. {ratio[unstable].max():.5f}")
assert unstable.sum() >= 3
assert ratio[unstable].min() >= folds[0] - 1e-6 and ratio[unstable].max() <= folds[1] + 1e-6

# %% [markdown]
# ## Multipliers of one point
#
# The Floquet multipliers of the point of largest |mu| (on the middle segment) against
# the unit circle: one real multiplier outside, just above +1.

# %%
i = result.point_index()
mu = result.point_multipliers(i)
print(f"point {i} at Omega~ = {ratio[i]:.5f}: largest |mu| = {np.abs(mu).max():.5f}")
assert 1.0 < np.abs(mu).max() < 1.1
result.plot_multipliers(i)

# %% [markdown]
# ## Files
#
# `write(directory)` writes `branch.nc` (every Fourier coefficient), `branch.csv`,
# `bifurcations.csv` and the figures, as `rotorsfd response` does; `to_dataset()` gives
# the same data as an xarray Dataset.

# %%
with tempfile.TemporaryDirectory() as out:
    print(sorted(result.write(out)))
print(result.to_dataset())
