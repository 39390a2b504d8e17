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
# # Quasi-periodic response under harmonic base pitching
#
# When the base pitches harmonically (a ship or an aircraft pitching at w_b while the
# rotor spins at Omega) the rotor responds at every combination k1 Omega + k2 w_b: the
# motion lies on a torus and never repeats. `run_response` then computes that torus by
# two-frequency harmonic balance over the speed range instead of a periodic branch
# (`docs/quasiperiodic.md`).
#
# The case, `examples/paper_harmonic_pitching.toml`: the paper rotor pitched by 0.05 rad
# at w_b = 60 rad/s (a rate of 3 rad/s cos(60 t)), U = 144.02 g mm, Omega~ = 0.8-1.0, the
# harmonics |k1| <= 3 and |k2| <= 2. Coarse setting: the largest Lyapunov exponent (the
# torus's stability) at 2 points instead of the command's 5.

# %%
# %matplotlib inline
import numpy as np

from rotorsfd import api
from rotorsfd.analyses.torus_response import run_torus_response
from rotorsfd.plots.torus import plot_torus_components, plot_torus_spectrum

config = api.load_config("examples/paper_harmonic_pitching.toml")
torus = run_torus_response(config, progress=False, lyapunov_points=2)
print(torus.summary())

# %% [markdown]
# ## The lines of the journal's motion
#
# The amplitude of a line k1 Omega + k2 w_b at the SFD journal (node 1) is the radial
# half peak-to-peak sqrt(|X_y|^2 + |X_z|^2) / C in clearances. "1X" (k1, k2) = (1, 0) is
# the unbalance response, "1 w_b" (0, 1) the forced response to the pitching, and
# "1X - 2 w_b" (1, -2) a combination line that only the nonlinear film makes. Over the
# range the 1 w_b line stays at 0.30-0.36 C while 1X grows from 0.12 to 0.87 C towards
# the critical speed (the README's tutorial quotes these), and the combination line
# grows about 20-fold.

# %%
def line(k1, k2, node=1):
    return np.hypot(torus.amplitude(node, "y", k1, k2), torus.amplitude(node, "z", k1, k2))


x = torus.speeds / torus.reference_speed
one_x, one_wb, comb = line(1, 0), line(0, 1), line(1, -2)
for i in (0, len(x) // 2, len(x) - 1):
    print(f"Omega~ = {x[i]:.3f}: 1X {one_x[i]:.3f} C, 1 w_b {one_wb[i]:.3f} C, "
          f"1X - 2 w_b {comb[i]:.2e} C")
assert abs(x[0] - 0.8) < 1e-9 and abs(x[-1] - 1.0) < 1e-9
assert 0.29 < one_wb.min() and one_wb.max() < 0.37, (one_wb.min(), one_wb.max())
assert abs(one_x[0] - 0.12) < 0.01 and abs(one_x[-1] - 0.87) < 0.01, (one_x[0], one_x[-1])
assert comb[-1] > 10 * comb[0]          # the combination line grows as the film stiffens

# %% [markdown]
# ## Stability of the torus
#
# The largest Lyapunov exponent per rotor period at the two ends: negative (with its
# uncertainty) means a nearby motion returns to the torus.

# %%
for i, ly in sorted(torus.lyapunov.items()):
    print(f"Omega~ = {x[i]:.3f}: {ly.per_period:+.4f} +/- {ly.uncertainty:.4f} per period, "
          f"{'stable' if ly.stable else 'unstable'}")
assert len(torus.lyapunov) == 2 and all(ly.stable for ly in torus.lyapunov.values())

# %% [markdown]
# The figures `rotorsfd response` writes: the strongest lines at each output node
# against the speed, and the 2D spectrum at one speed (k1 across, k2 up).

# %%
plot_torus_components(torus)

# %%
plot_torus_spectrum(torus, torus.spectrum_index(0.9))
