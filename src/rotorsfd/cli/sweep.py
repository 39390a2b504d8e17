"""``rotorsfd sweep``: a parameter study over a grid of config fields, in parallel and
resumable."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.output import print_summary
from rotorsfd.cli.registry import arg, command
from rotorsfd.interrupt import Interrupted


@command("sweep", "parameter study: a grid over config fields ([analysis.sweep] axes or "
         "--axis), one task per point, in parallel (local cores, or a Dask cluster): "
         "sweep.nc, summary.csv, sweep.json, points/; exit 1 if points are left pending",
         output=True, quiet=True,
         arguments=[arg("--axis", action="append", default=[], metavar="PATH=V1,V2,...",
                        help="grid axis replacing [analysis.sweep] axes (repeatable), e.g. "
                             "--axis 'elements.sfd.clearance_ratio=0.4 %%,0.5 %%'"),
                    arg("--task", metavar="NAME[:K=V,...]",
                        help="task kind: response, simulate, stability-chart, or "
                             "synthetic (tests) (default: analysis.sweep.task)"),
                    arg("--workers", type=options.integer(1), metavar="N",
                        help="local worker processes (default: the available CPUs)"),
                    arg("--scheduler", metavar="tcp://HOST:PORT",
                        help="run on this Dask distributed scheduler"),
                    arg("--resume", action="store_true",
                        help="continue the sweep in DIR: finished points are kept")])
def sweep(args: argparse.Namespace, config: Any) -> int:
    """Run the grid; exit 1 if points are left pending."""
    # deferred: the studies pull numpy, xarray and the executors
    from rotorsfd.studies import grid_from_axes, run_sweep
    from rotorsfd.studies.grid import parse_axis

    axes = grid_from_axes(config, dict(map(parse_axis, args.axis))) if args.axis else None
    try:
        result = run_sweep(config, axes, args.task, directory=args.output,
                           workers=args.workers, scheduler=args.scheduler,
                           progress=not args.quiet, resume=args.resume,
                           search_path=Path(args.config).parent)
    except KeyboardInterrupt:
        raise Interrupted(f"partial results written to {args.output} (finished points "
                          "kept; continue with --resume)") from None
    if not args.quiet:
        print_summary(result.summary(), args.verbose)
        print(f"wrote {args.output / 'sweep.nc'}, {args.output / 'summary.csv'}")
    return 0 if result.complete else 1
