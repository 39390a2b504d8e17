"""``bifurcation-curves`` on the paper's C/R = 0.728 % case (examples/paper/
fig21_22_table3_clearance.toml: U = 252 g mm, w_by = 10 rad/s, H = 8), the Table 3 regions
as one chart: the period-doubling window and the secondary Hopf continued in C/R.

Independent route for the Neimark-Sacker curve (shifted Hill operator, K = 16 pairs, on the
HB equations): the secondary Hopf that Floquet (Newmark monodromy multipliers through
|mu| = 1, the config's [analysis.stability] options) locates on the one-parameter speed
branch computed at another C/R. Before the border fix (conjugated null vectors) the
curve's start went 200 rad/s away from its Hopf and was refused; the start branch did not
stop at max_eccentricity (a second Hopf at 1064.65 rad/s lay beyond the film's limit)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from rotorsfd import api
from rotorsfd.analyses.response_inputs import TwoParameterInputs, stability_settings
from rotorsfd.harmonic.periodic import continue_periodic
from rotorsfd.io.config import load_config
from rotorsfd.stability.branch_stability import branch_stability

CASE = Path(__file__).parents[2] / "examples" / "paper" / "fig21_22_table3_clearance.toml"
PARAMETER = "elements.sfd.clearance_ratio"
OTHER = 0.0065


def floquet_hopfs(cr: float) -> list[float]:
    """Secondary Hopf speeds [rad/s] of the H = 8 speed branch at C/R = ``cr`` (the
    curves' start-branch settings: the film's limit, the config's stability options)."""
    inp = TwoParameterInputs.resolve(load_config(CASE), PARAMETER, "0.728 %", "0.61 %",
                                     None, None, "test")
    problem = inp.system.two_parameter_problem(inp.param).first(cr)
    branch = continue_periodic(problem, *inp.speed_range, 8,
                               limit_max=inp.response.max_eccentricity)
    st = branch_stability(branch, problem, stability_settings(inp.stability, True))
    return [b.lam for b in st.bifurcations if b.kind == "secondary-hopf"]


@pytest.mark.slow
def test_table3_regions_neimark_sacker_curve_through_another_clearance():
    """The NS curve starts at the located Hopf (2e-4: the Hill truncation against the
    monodromy's step) and passes, at C/R = 0.65 %, through the Hopf Floquet locates on
    that C/R's own speed branch (1e-4). The PD window closes
    where its two flips meet, C/R 0.7185 % (Omega~ 1.0405). About 50 s CPU."""
    result = api.run_bifurcation_curves(load_config(CASE), PARAMETER, "0.728 %", "0.64 %")
    assert result.success, result.message
    assert len(result.start_secondary_hopfs) == 1 and len(result.ns_curves) == 1
    hopf = result.start_secondary_hopfs[0]
    start = result.speeds_at("Neimark-Sacker", 0.00728)
    on_curve = result.speeds_at("Neimark-Sacker", OTHER)
    hopfs = floquet_hopfs(OTHER)       # the one the curve reaches: the nearest
    other = min(hopfs, key=lambda w: abs(w - on_curve[0]))
    # measured 1.2e-4 (1040.016 against 1040.139: Hill's K = 16 against the step-controlled
    # monodromy; with M = 400 fixed the Hopf is at 1040.008) and 3.9e-5 (1041.754 against
    # 1041.713); the Hopf moved 1.57 rad/s between the two C/R
    assert start == pytest.approx([hopf], rel=2e-4)
    assert abs(other - hopf) > 1e-3 * hopf
    assert on_curve == pytest.approx([other], rel=1e-4)
    (turn,) = {round(t.value, 9) for t in result.turns if t.kind == "period-doubling"}
    assert turn == pytest.approx(0.0071853, rel=1e-4)
    assert np.all(result.table["max_eps"] < 0.995)
