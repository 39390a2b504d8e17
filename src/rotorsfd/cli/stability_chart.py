"""``rotorsfd stability-chart``: Floquet stability of the linear rotor under harmonic base
rotation over two parameters."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.output import print_written
from rotorsfd.cli.registry import arg, command


@command("stability-chart", "stability chart of the linear rotor (film off) under harmonic "
         "base rotation over two parameters ([analysis.stability_chart] x, y, speed): "
         "chart.nc (max |Floquet multiplier|, stable), chart.png", output=True, quiet=True,
         arguments=[arg("--workers", type=options.integer(1), default=1, metavar="N",
                        help="threads over the grid rows (default: 1)")])
def stability_chart(args: argparse.Namespace, config: Any) -> int:
    """Compute the chart over the grid and write it."""
    from rotorsfd import api  # deferred: numpy, scipy, numba (keeps --help fast)

    result = api.run_stability_chart(config, workers=args.workers,
                                     search_path=Path(args.config).parent,
                                     progress=not args.quiet)
    paths = result.write(args.output)
    print_written(result, paths, args.quiet, args.verbose)
    return 0
