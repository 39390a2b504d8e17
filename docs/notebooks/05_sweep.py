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
# # Parameter sweep: a grid of analyses
#
# `rotorsfd.studies.run_sweep` runs one task (`response`, `simulate`,
# `stability-chart`) at every point of a grid over config fields given by dotted path,
# stores every finished point at once (a killed sweep continues with `resume=True`) and
# combines them into `summary.csv` and `sweep.nc` (`docs/sweeps.md`).
#
# The study: the periodic response of the paper rotor at U = 144.02 g mm under a constant
# base pitching rate w_by = 0, 2, 4, 6 rad/s (`examples/paper_pitching.toml`, the case
# of the paper's Figures 12-15), with Floquet stability; the quantity of the paper's
# Figure 19 is the summary column `unstable_width_speed_ratio`. Coarse settings: 4
# points, H = 3, Omega~ = 0.9-1.2, and `workers=1` (serial in this process, so that the
# tests that run this notebook do not start a process pool; `workers=None` uses every
# CPU, `scheduler="tcp://HOST:8786"` a Dask cluster; the files are identical either way).

# %%
# %matplotlib inline
import tempfile
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np

from rotorsfd import api
from rotorsfd.studies import run_sweep

config = api.load_config("examples/paper_pitching.toml", [
    "unbalance[0].magnitude=144.02 g*mm",
    "analysis.response.harmonics=3",
    "analysis.response.speed_range.start_ratio=0.9",
    "analysis.response.speed_range.stop_ratio=1.2",
])
out = Path(tempfile.mkdtemp(prefix="sweep-"))
sweep = run_sweep(config, {"base.pitching.value": ["0 rad/s", "2 rad/s", "4 rad/s", "6 rad/s"]},
                  "response", directory=out, workers=1, progress=False)
print(sweep.summary())
print(sorted(p.name for p in out.iterdir()))

# %% [markdown]
# One row per grid point; the columns of the `response` task are listed in
# `docs/sweeps.md`.

# %%
names, rows = sweep.table()
columns = {n: [row[i] for row in rows] for i, n in enumerate(names)}
rates = np.array(columns["base_pitching_value_rad_s"])
width = np.array(columns["unstable_width_speed_ratio"])
for rate, n_sn, w, peak in zip(rates, columns["n_saddle_node"], width,
                               columns["peak_defl_8"], strict=True):
    print(f"w_by = {rate:3.0f} rad/s: {n_sn} saddle-nodes, unstable width {w:.5f}, "
          f"max r~ at the disk {peak:.3f}")

# %% [markdown]
# The checks: at w_by = 0 the width is the distance between the fixed base's two
# saddle-nodes (1.0593 - 1.0527, notebook 02); it shrinks with the pitching rate and is
# zero at 6 rad/s, above the cusp at 4.41 rad/s that notebook 04 finds by continuing
# the folds themselves.

# %%
assert all(s == "ok" for s in columns["status"])
assert abs(width[0] - (1.0593 - 1.0527)) < 3e-4, width[0]
assert width[0] > width[1] > width[2] > 0 and width[3] == 0
assert columns["n_saddle_node"] == [2, 2, 2, 0]

# %%
fig, ax = plt.subplots(figsize=(5, 3.2))
ax.plot(rates, width, "o-")
ax.set_xlabel("pitching rate $w_{by}$ [rad/s]")
ax.set_ylabel(r"unstable width in $\tilde\Omega$")
ax.set_title("U = 144.02 g mm, H = 3")
ax.grid(alpha=0.3)

# %% [markdown]
# The same data as an xarray Dataset (what `sweep.nc` holds), with the grid values as
# coordinates:

# %%
ds = sweep.to_dataset()
print(ds["unstable_width_speed_ratio"])
