"""``rotorsfd attractors``: the attractor census at one speed or a stride of speeds."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.output import print_written
from rotorsfd.cli.registry import arg, command
from rotorsfd.errors import ConfigError


def _ratios(args: argparse.Namespace) -> list[float] | None:
    """``--speed-ratio`` alone, or ``--speed-ratio A --to B --stride S``."""
    if args.speed_ratio is None:
        return None
    if args.to is None:
        return [args.speed_ratio]
    n = round(abs(args.to - args.speed_ratio) / args.stride) + 1
    step = args.stride if args.to >= args.speed_ratio else -args.stride
    return [args.speed_ratio + k * step for k in range(n)]


def check_attractors(args: argparse.Namespace, config: Any) -> None:
    """The options against each other."""
    if args.speed is not None and args.speed_ratio is not None:
        raise ConfigError("--speed/--speed-ratio", (args.speed, args.speed_ratio),
                          "give --speed or --speed-ratio, not both")
    if args.to is not None and args.speed_ratio is None:
        raise ConfigError("--to", args.to, "needs --speed-ratio (the first speed ratio)")
    if args.to is not None and not args.stride:
        raise ConfigError("--stride", args.stride, "give the speed-ratio stride (> 0) "
                          "with --to")
    if args.sampling not in ("lhs", "grid"):
        raise ConfigError("--sampling", args.sampling, "lhs or grid")
    census_options(args)
    if args.branches:
        check_branch_range(args, config)


def check_branch_range(args: argparse.Namespace, config: Any) -> None:
    """``--branches``: the census speeds inside ``[analysis.response] speed_range`` where
    both are in one form (ratios, or rad/s) before the work."""
    rng = config.analysis.response.speed_range
    if args.speed_ratio is not None and rng.start_ratio is not None:
        lo, hi, first = rng.start_ratio, rng.stop_ratio, [args.speed_ratio]
    elif args.speed is not None and rng.start is not None:
        lo, hi, first = rng.start, rng.stop, [args.speed]
    else:
        return
    speeds = first + ([args.to] if args.to is not None else [])
    lo, hi = sorted((lo, hi))
    for x in speeds:
        if not lo < x < hi:
            raise ConfigError("--branches", x, f"the census speeds must lie inside "
                              f"analysis.response.speed_range ({lo:g}, {hi:g}), where "
                              f"the branches are traced")


OPTION_OF = {"n_starts": "--starts", "displacement_fraction": "--fraction",
             "velocity_fraction": "--fraction"}


def census_options(args: argparse.Namespace) -> Any:
    """The CensusOptions of the command line (checked)."""
    from rotorsfd.analyses.attractors import CensusOptions  # deferred: numpy

    try:
        return CensusOptions(n_starts=args.starts, sampling=args.sampling,
                             displacement_fraction=args.fraction,
                             velocity_fraction=args.fraction,
                             steps_per_period=args.steps_per_period,
                             max_periods=args.max_periods, seed=args.seed,
                             around=args.around, harmonics=args.harmonics).validate()
    except ConfigError as exc:
        name = str(exc.field).split(".")[-1]
        option = OPTION_OF.get(name, "--" + name.replace("_", "-"))
        raise ConfigError(option, exc.value, exc.allowed) from None


@command("attractors", "attractor census: time integrations from --starts sampled "
         "initial states of the nonlinear elements (stopped once settled), classified, "
         "grouped into attractors by their Poincare points, each periodic one corrected "
         "by HB with its Floquet stability: attractors.csv (basin fractions), starts.csv, "
         "summary.json, basins.png; with --branches each period-1 attractor's branch "
         "continued both ways in the speed (attractor_branches.csv, branch_motion<k>.csv, "
         "attractor_branches.png); over --speed-ratio A --to B --stride S one table "
         "with a speed column", output=True, quiet=True,
         arguments=[arg("--speed", type=options.positive_speed, metavar="SPEED",
                        help="rotor speed, e.g. 850 or '8000 rpm' (rad/s if no unit)"),
                    arg("--speed-ratio", type=options.positive_ratio, metavar="X",
                        help="rotor speed / [reference] speed (the first of a range "
                             "with --to)"),
                    arg("--to", type=options.positive_ratio, metavar="X",
                        help="last speed ratio of a range"),
                    arg("--stride", type=options.positive_ratio, metavar="DX",
                        help="speed-ratio stride of a range"),
                    arg("--starts", type=options.integer(1), default=64, metavar="N",
                        help="number of initial states (default 64)"),
                    arg("--sampling", default="lhs", metavar="KIND",
                        help="lhs (Latin hypercube, default) or grid"),
                    arg("--fraction", type=options.positive_ratio, default=0.5,
                        metavar="A", help="initial displacements within A clearances and "
                        "velocities within A clearances x speed (default 0.5)"),
                    arg("--around", default="orbit", metavar="WHERE",
                        help="the DOFs other than the elements' at the HB orbit's state "
                             "at a sampled phase (orbit, default) or at rest (rest); "
                             "both follow the sampled element states quasi-statically"),
                    arg("--steps-per-period", type=options.integer(8), metavar="N",
                        help="time step T/N (default: [analysis.simulate] "
                             "steps_per_period if an integer, else 400)"),
                    arg("--max-periods", type=options.integer(10), default=600,
                        metavar="N", help="periods before a start that has not settled "
                        "is classified (default 600)"),
                    arg("--harmonics", type=options.integer(1), metavar="H",
                        help="harmonics of the HB correction (default: [analysis.response] "
                             "harmonics if an integer, else 8; doubled if Newton fails)"),
                    arg("--seed", type=options.integer(0), default=0, metavar="N",
                        help="seed of the Latin hypercube"),
                    arg("--branches", action="store_true",
                        help="trace each period-1 attractor's branch both ways within "
                             "[analysis.response] speed_range, with the stability of "
                             "[analysis.stability] (the isolas among them)"),
                    arg("--workers", type=options.integer(1), metavar="N",
                        help="processes (default: the available CPUs)")],
         check=check_attractors)
def attractors(args: argparse.Namespace, config: Any) -> int:
    """Run the census, write and print it."""
    # deferred: numpy, scipy, numba (keeps --help fast)
    from rotorsfd.analyses.attractors_config import run_census
    from rotorsfd.studies.executors import make_executor

    opts = census_options(args)
    speeds = [args.speed] if args.speed is not None else None
    with make_executor(args.workers) as ex:
        result = run_census(config, speeds, speed_ratios=_ratios(args),
                            search_path=Path(args.config).parent, options=opts,
                            executor=ex)
    print_written(result, result.write(args.output), args.quiet, args.verbose)
    if args.branches:
        # deferred: analyses.attractor_branches (loads numba, scipy, threadpoolctl)
        from rotorsfd.analyses.attractor_branches import run_attractor_branches

        traced = run_attractor_branches(config, result, search_path=Path(args.config).parent)
        print_written(traced, traced.write(args.output), args.quiet, args.verbose)
    return 0
