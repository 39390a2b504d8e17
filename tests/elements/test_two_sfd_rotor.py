"""A rotor with two identical SFDs at mirror-symmetric stations (issue 15 item 4): the
rotor, its disk and unbalance are symmetric about the mid-span, so the two dampers see the
same orbit and the response is mirror-symmetric (1e-9), through the composite kernel."""

from __future__ import annotations

import numpy as np
import pytest

from rotorsfd.analyses.response import run_response
from rotorsfd.io.config import config_from_dict

SYMMETRIC = {
    "title": "symmetric rotor, two SFDs",
    "materials": {"steel": {"density": "7810 kg/m^3", "young_modulus": "211 GPa",
                            "shear_modulus": "81.783 GPa"}},
    "rotor": {"shaft": [{"length": "0.8 m", "n_elements": 8, "inner_radius": "0 mm",
                         "outer_radius": "25 mm", "material": "steel"}],
              "disks": [{"node": 5, "mass": "18 kg", "polar_inertia": "0.09 kg*m^2",
                         "diametral_inertia": "0.045 kg*m^2"}]},
    "elements": {
        name: {"kind": "sfd", "node": node, "viscosity": "0.01 Pa*s", "clearance": "0.15 mm",
               "radius": "40 mm", "length": "15 mm", "centring_stiffness": "5e6 N/m"}
        for name, node in (("front", 1), ("rear", 9))},
    "unbalance": [{"node": 5, "magnitude": "150 g*mm"}],
    "analysis": {"response": {"harmonics": 5,
                              "speed_range": {"start_ratio": 0.6, "stop_ratio": 1.4},
                              "nodes": [1, 5, 9]},
                 "stability": {"enabled": False}},
}


@pytest.fixture(scope="module")
def result():
    return run_response(config_from_dict(SYMMETRIC), progress=False)


def test_two_sfds_see_the_same_orbit(result):
    table = result.table()
    assert result.success and result.branch.n_points > 10
    assert list(result.system.elements.nl_dofs) == [0, 1, 32, 33]
    peak = float(np.max(table["eps_max_front"]))
    assert 0.2 < peak < 0.95                 # the films are well into their nonlinear range
    np.testing.assert_allclose(table["eps_max_rear"], table["eps_max_front"], rtol=0,
                               atol=1e-9 * peak)
    np.testing.assert_allclose(table["defl_9"], table["defl_1"], rtol=0, atol=1e-9 * peak)
    scale = float(np.max(table["amp_1_y_h1"]))
    for k in range(1, 6):     # the even harmonics vanish by symmetry: compared at 1e-9 of h1
        for d in ("y", "z"):
            a1, a9 = table[f"amp_1_{d}_h{k}"], table[f"amp_9_{d}_h{k}"]
            np.testing.assert_allclose(a9, a1, rtol=0, atol=1e-9 * scale)
