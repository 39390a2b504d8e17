"""H-convergence of the paper rotor's periodic response (issue 5 item 6).

The paper rotor (examples/paper_rotor.toml, U = 144.02 g mm) solved by HB-AFT at fixed
speeds with H = 1, 2, 3, 5, 8, 12; the static term X_0 and the first harmonic X_1 at the
SFD (node 1) and the disk (node 8), y and z, compared with the H = 12 solution, in units
of the clearance C.

- Fixed base: the rotor is isotropic and gravity is off, so the orbit is a centred circle
  with a constant film force in the whirling frame: H = 1 is exact and every higher
  harmonic vanishes (the AFT must not invent any).
- Constant pitching w_by = 6 rad/s (examples/paper_pitching.toml, the paper's Fig. 13):
  the gyroscopic moment offsets the orbit, the film force is no longer constant and 2X/3X
  matter (|X_2|/C ~ 2e-3..7e-3). Measured |X_1 - X_1(H=12)|/C (max over the 4 DOFs)::

      Omega~   H=1      H=2      H=3      H=5      H=8
      0.9     3.9e-4   3.2e-5   3.6e-7   3.7e-9   7.5e-12
      1.2     1.3e-3   3.2e-5   5.1e-7   9.0e-10  4.4e-14

  and for X_0: 1.7e-5 .. 7.7e-13 (0.9), 5.8e-5 .. 3.4e-15 (1.2); every step of H cut
  the error by 12x or more. Asserted: each step cuts both errors by at least 5x, and
  at H = 8 they are below 1e-10 C (X_1) and 1e-11 C (X_0), about 10x the worst measured.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd.harmonic.periodic import solve_periodic
from rotorsfd.io.config import load_config
from rotorsfd.model import dofs
from rotorsfd.model.build import build_model
from rotorsfd.model.system import RotorSystem

EXAMPLES = Path(__file__).resolve().parents[2] / "examples"
REFERENCE_SPEED = 811.3          # rad/s, the paper's first critical speed
HS = (1, 2, 3, 5, 8, 12)
DOFS = [dofs.dof_index(n, d) for n in (1, 8) for d in "yz"]    # SFD and disk, y and z
TOL = 1e-10                      # Newton tolerance (scaled residual): below the H=8 error


def _solutions(example: str, speed_ratio: float):
    """{H: X (H+1, n_dof)} at Omega = speed_ratio * 811.3 rad/s, and the clearance C."""
    config = load_config(EXAMPLES / example, ["unbalance[0].magnitude=144.02 g*mm"])
    model = build_model(config)
    problem = RotorSystem(model.rotor, model.elements, model.unbalances,
                          model.base_motion).periodic_problem()
    speed = speed_ratio * REFERENCE_SPEED
    return ({H: solve_periodic(problem, speed, H, tol=TOL).X for H in HS},
            float(model.elements[0].film.clearance))


def _errors(X: dict[int, np.ndarray], C: float) -> tuple[np.ndarray, np.ndarray]:
    """(|X_0 - X_0(12)|/C, |X_1 - X_1(12)|/C) for H in HS[:-1], max over DOFS."""
    ref = X[HS[-1]]
    e0 = [np.abs(X[H][0, DOFS].real - ref[0, DOFS].real).max() / C for H in HS[:-1]]
    e1 = [np.abs(X[H][1, DOFS] - ref[1, DOFS]).max() / C for H in HS[:-1]]
    return np.array(e0), np.array(e1)


@pytest.mark.parametrize("speed_ratio", [0.9, 1.2])
def test_fixed_base_first_harmonic_is_exact(speed_ratio):
    X, C = _solutions("paper_rotor.toml", speed_ratio)
    e0, e1 = _errors(X, C)
    assert np.abs(X[12][1, DOFS]).max() / C > 0.1          # a real orbit, not a trivial one
    assert e1.max() < 1e-12 and e0.max() < 1e-12, (e0, e1)
    for H in HS[1:]:
        assert np.abs(X[H][2:, DOFS]).max() / C < 1e-12     # no 2X, 3X, ... at all


@pytest.mark.parametrize("speed_ratio", [0.9, 1.2])
def test_pitching_converges_in_h(speed_ratio):
    X, C = _solutions("paper_pitching.toml", speed_ratio)
    e0, e1 = _errors(X, C)
    assert np.abs(X[12][2, DOFS]).max() / C > 1e-3          # 2X matters here
    assert e1[0] > 1e-4, e1                                 # so H = 1 is visibly off
    assert (e1[1:] < e1[:-1] / 5).all(), e1                 # H = 1, 2, 3, 5, 8
    assert (e0[1:] < e0[:-1] / 5).all(), e0
    i8 = HS.index(8)
    assert e1[i8] < 1e-10, e1
    assert e0[i8] < 1e-11, e0
