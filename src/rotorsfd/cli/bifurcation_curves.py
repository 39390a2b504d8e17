"""``rotorsfd bifurcation-curves``: the saddle-nodes, period doublings and secondary Hopf
points of the speed response continued together in a second parameter."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.fold_curve import fold_range
from rotorsfd.cli.output import print_error, print_written
from rotorsfd.cli.registry import arg, command


def check_bifurcation_curves(args: argparse.Namespace, config: Any) -> None:
    """``--parameter``, ``--from`` and ``--to`` (see :func:`fold_range`)."""
    fold_range(config, args.parameter, args.start, args.stop)


@command("bifurcation-curves", "two-parameter continuation of every saddle-node (fold), "
         "period doubling and secondary Hopf (Neimark-Sacker) of the speed response "
         "([analysis.response] speeds and H) in a second parameter, from the speed "
         "branch at --from: curves.csv and curves.nc "
         "(a 'kind' column), summary.json, curves.png (all kinds in the (speed, "
         "parameter) plane, turning points marked); exit 1 if a curve stops early (the "
         "points so far are written)",
         output=True, quiet=True,
         arguments=[arg("--parameter", default="base.pitching.value", metavar="PATH",
                        help="second parameter: base.pitching.value (default), "
                             "base.rolling.value, base.yawing.value, "
                             "unbalance[0].magnitude, elements.<name>.clearance_ratio, ..."),
                    arg("--from", dest="start", required=True, metavar="VALUE",
                        help="start value, e.g. '5 g*mm' (SI if no unit); the speed branch "
                             "there must have a saddle-node, period doubling or secondary Hopf"),
                    arg("--to", dest="stop", required=True, metavar="VALUE",
                        help="end value, e.g. '2 g*mm'"),
                    arg("--harmonics", type=options.integer(1), metavar="H",
                        help="override H (the period-doubling curves use 4 H harmonics "
                             "of half the speed)")],
         check=check_bifurcation_curves)
def bifurcation_curves(args: argparse.Namespace, config: Any) -> int:
    """Continue the curves; exit 1 (after writing) if one stopped early."""
    from rotorsfd import api  # deferred: numpy, scipy, numba (keeps --help fast)

    start, stop = fold_range(config, args.parameter, args.start, args.stop)
    result = api.run_bifurcation_curves(config, args.parameter, start, stop,
                                        search_path=Path(args.config).parent,
                                        harmonics=args.harmonics)
    paths = result.write(args.output)
    if not result.success:
        print_error(f"bifurcation curves stopped early: {result.message}", args.verbose)
        return 1
    print_written(result, paths, args.quiet, args.verbose)
    return 0
