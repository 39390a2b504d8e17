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
# # Fold curve: where the bistability ends
#
# On a fixed base the paper rotor at U = 144.02 g mm has two saddle-nodes (notebook 02):
# between them a stable large and a stable small orbit coexist and the run-up jumps. A
# constant base pitching rate w_by narrows that range. `run_fold_curve` continues the two
# saddle-nodes themselves in the second parameter (the fold-augmented harmonic-balance
# system) until they meet in a cusp: the pitching rate above which the response is
# single-valued (the paper's Figure 19).
#
# Coarse settings: H = 3 harmonics (the paper's Table 1; the converged H = 16 moves the
# cusp from 4.410 to 4.379 rad/s, README "How our results compare with the paper") and a
# pitching range 0-6 rad/s. `examples/paper/fig19_unstable_range.toml` is the paper's
# Figure 19 case (constant pitching, H = 8, U = 252 g mm: the unbalance is set below).

# %%
# %matplotlib inline
import numpy as np

from rotorsfd import api

config = api.load_config("examples/paper/fig19_unstable_range.toml",
                         ["unbalance[0].magnitude=144.02 g*mm"])
curve = api.run_fold_curve(config, "base.pitching.value", "0 rad/s", "6 rad/s", harmonics=3)
print(curve.summary())

# %% [markdown]
# The curve starts at the fixed base's two saddle-nodes and ends where they meet:

# %%
start = sorted(w / curve.reference_speed for w in curve.start_folds)
print(f"saddle-nodes at w_by = 0: Omega~ = {start[0]:.5f}, {start[1]:.5f}")
print(f"bistability ends at w_by = {curve.bistability_end:.4f} rad/s")
assert abs(start[0] - 1.0527) < 1e-3 and abs(start[1] - 1.0593) < 1e-3
assert len(curve.cusps) == 1
assert abs(curve.bistability_end - 4.4097) < 5e-3, curve.bistability_end

# %% [markdown]
# The two fold speeds and the width of the unstable range against w_by:

# %%
curve.plot()["fold_curve.png"]

# %% [markdown]
# ## A second method at one rate
#
# At w_by = 2 rad/s the fold speeds on the curve (re-solved there by Newton on the
# fold-augmented system) must be the saddle-nodes that the ordinary speed branch locates
# from its Floquet multipliers, with the same H = 3.

# %%
on_curve = curve.speeds_at(2.0) / curve.reference_speed
pitched = api.with_values(config, {
    "base.pitching.value": 2.0, "analysis.response.harmonics": 3,
    "analysis.response.speed_range.start_ratio": 0.9,
    "analysis.response.speed_range.stop_ratio": 1.2})
branch = api.run_response(pitched, progress=False)
located = sorted(b["speed_ratio"] for b in branch.bifurcations if b["type"] == "saddle-node")
print("fold curve at 2 rad/s:  ", np.round(on_curve, 6))
print("speed branch at 2 rad/s:", np.round(located, 6))
assert len(on_curve) == 2 and len(located) == 2
assert np.allclose(on_curve, located, rtol=1e-5), (on_curve, located)
width = curve.unstable_width([0.0, 2.0, 4.0, 5.0])
print("unstable width at 0, 2, 4, 5 rad/s:", np.round(width, 5))
assert width[0] > width[1] > width[2] > 0 and width[3] == 0
