"""``rotorsfd bifurcation-curves``: the saddle-nodes, period doublings and secondary Hopf
points of the speed response continued together in a second parameter."""

from __future__ import annotations

import argparse
from typing import Any

from rotorsfd.cli.fold_curve import check_fold_curve, run_two_parameter, two_parameter_arguments
from rotorsfd.cli.registry import command


@command("bifurcation-curves", "two-parameter continuation of every saddle-node (fold), "
         "period doubling and secondary Hopf (Neimark-Sacker) of the speed response "
         "([analysis.response] speeds and H) in a second parameter, from the speed "
         "branch at --from: curves.csv and curves.nc "
         "(a 'kind' column), summary.json, curves.png (all kinds in the (speed, "
         "parameter) plane, turning points marked); exit 1 if a curve stops early (the "
         "points so far are written)",
         output=True, quiet=True,
         arguments=two_parameter_arguments(
             "second parameter: base.pitching.value (default), base.rolling.value, "
             "base.yawing.value, unbalance[0].magnitude, elements.<name>.clearance_ratio, "
             "...",
             "start value, e.g. '5 g*mm' (SI if no unit); the speed branch there must "
             "have a saddle-node, period doubling or secondary Hopf",
             "end value, e.g. '2 g*mm'",
             "override H (the period-doubling curves use 4 H harmonics of half the "
             "speed)"),
         check=check_fold_curve)
def bifurcation_curves(args: argparse.Namespace, config: Any) -> int:
    """Continue the curves; exit 1 (after writing) if one stopped early."""
    from rotorsfd import api  # deferred: numpy, scipy, numba (keeps --help fast)

    return run_two_parameter(args, config, api.run_bifurcation_curves,
                             "bifurcation curves")
