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
# # Modal analysis: Campbell diagram and critical speeds
#
# The linear rotor of the reference paper (Zhang et al., Appl. Sci. 2025, 15, 1186,
# section 4, Figure 8): a 0.6 m hollow Timoshenko shaft in 20 elements, a disk at node 8,
# a squeeze film damper (SFD) with a centring spring at node 1 and a linear support at
# node 21 (`examples/paper_rotor.toml`). The modal analysis sees the linear rotor: the
# film is left out, its centring spring kept.
#
# Every tutorial runs from the repository root (the folder that holds `examples/`), as
# the tests that execute them do. This one uses the example's own settings (81 speeds
# up to 4000 rad/s, 8 modes) and takes a few seconds.

# %%
# %matplotlib inline
import tempfile

import numpy as np

from rotorsfd import api

config = api.load_config("examples/paper_rotor.toml")
result = api.run_modal(config)
print(result.summary())

# %% [markdown]
# The paper states neither the stiffness of the right support nor that of the centring
# spring. The example fits both so that the first two forward critical speeds are the
# paper's 811.3 and 2784.6 rad/s (notebook 07 does that fit). The critical speeds are
# found by root finding on the synchronous condition (a forward whirl frequency equal to
# the speed):

# %%
critical = [c.speed_rad_s for c in result.critical_speeds]
print("critical speeds [rad/s]:", [round(s, 3) for s in critical])
assert [c.whirl for c in result.critical_speeds] == ["forward", "forward"]
assert abs(critical[0] / 811.3 - 1) < 1e-6, critical
assert abs(critical[1] / 2784.6 - 1) < 1e-6, critical
assert result.reference_speed == 811.3   # [reference] speed: Omega~ = Omega / 811.3

# %% [markdown]
# ## The Campbell diagram
#
# Natural frequencies against the speed, forward and backward whirl apart, with the
# synchronous line; the critical speeds are where a forward branch crosses it.

# %%
figures = result.plot()   # the figures by file name, as `rotorsfd modal` writes them
figures["campbell.png"]  # noqa: B018 (a notebook shows its cell's last value)

# %% [markdown]
# A second, independent look at the same numbers: where each tracked forward branch of
# the Campbell diagram crosses the synchronous line, by linear interpolation between
# its 81 speeds (50 rad/s apart). It must agree with the root finding to the grid's
# interpolation error.

# %%
camp = result.campbell
speeds, freqs = camp.speeds, camp.frequencies
crossings = []
for j in range(freqs.shape[1]):
    gap = freqs[:, j] - speeds
    forward = camp.whirl[:, j] == "forward"
    for i in np.flatnonzero((gap[:-1] > 0) & (gap[1:] <= 0) & forward[:-1] & forward[1:]):
        w = gap[i] / (gap[i] - gap[i + 1])
        crossings.append(speeds[i] + w * (speeds[i + 1] - speeds[i]))
crossings = sorted(float(s) for s in crossings)[:2]
print("Campbell crossings [rad/s]:", [round(s, 2) for s in crossings])
assert np.allclose(crossings, critical, rtol=2e-3), (crossings, critical)

# %% [markdown]
# ## Changing the model
#
# Any field can be changed by its dotted path, with units, as `--set` does on the command
# line. A centring spring 20 % stiffer raises the first critical speed (the SFD journal
# moves in that mode) and hardly moves the second:

# %%
k = config.elements["sfd"].centring_stiffness
stiffer = api.with_values(config, {"elements.sfd.centring_stiffness": 1.2 * k})
critical_stiffer = [c.speed_rad_s for c in api.run_modal(stiffer).critical_speeds]
print(f"k = {k:.4g} N/m -> {critical[0]:.1f}, {critical[1]:.1f} rad/s")
print(f"k = {1.2 * k:.4g} N/m -> {critical_stiffer[0]:.1f}, {critical_stiffer[1]:.1f} rad/s")
assert critical_stiffer[0] > critical[0] + 10
assert critical_stiffer[1] > critical[1]

# %% [markdown]
# ## Files
#
# `write(directory)` writes what `rotorsfd modal CONFIG -o DIR` writes:
# `critical_speeds.csv`, `campbell.csv` and `campbell.png`.

# %%
with tempfile.TemporaryDirectory() as out:
    written = result.write(out)
    print(sorted(written))
