"""``rotorsfd response``: periodic response by harmonic balance and arc-length
continuation; the first Ctrl-C stops the branch after the current point and writes it."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.output import print_error, print_summary, print_warning, print_written
from rotorsfd.cli.registry import arg, command
from rotorsfd.interrupt import Interrupted, StopRequest


@command("response", "periodic response by harmonic balance and arc-length continuation "
         "([analysis.response]): branch.nc, branch.csv, response plots; a branch that "
         "ends at an element's validity limit is a result (a warning line); exit 1 if it "
         "stops early for a numerical reason (the points so far are written); under a "
         "harmonic base law the quasi-periodic response instead (a torus branch: "
         "torus.nc, torus.csv, torus_*.png)",
         output=True, quiet=True,
         arguments=[arg("--multipliers-at", type=options.ratio, default=None, metavar="X",
                        help="multipliers.png at the point nearest this speed ratio "
                             "Omega/Omega_ref (the parameter in SI for a non-speed branch); "
                             "default: the point of largest |mu|max; under a harmonic "
                             "base law: torus_spectrum.png at this speed ratio (default: "
                             "the largest deflection)"),
                    arg("--from-orbit", type=Path, metavar="DIR_OR_NC",
                        help="start the branch on the last period of a time-domain orbit "
                             "(rotorsfd simulate output), Newton-corrected at its speed, "
                             "and continue it both ways over the speed range, stopping "
                             "when it closes on itself (an isola)"),
                    arg("--switch-at", type=options.integer(1), default=None, metavar="N",
                        help="continue the period-2 branch from the branch's N-th "
                             "period-doubling point (counted from 1 along the branch, as "
                             "in the summary and bifurcations.csv) with 4H harmonics of "
                             "Omega/2: branch_period2.nc, branch_period2.csv, drawn in "
                             "the response figures; needs [analysis.stability] enabled"),
                    arg("--stability-basis", choices=("reduced", "full"), default=None,
                        help="Floquet basis ([analysis.stability].basis): full = the "
                             "unreduced monodromy of the whole model, to check "
                             "max_multiplier against max_multiplier_outside (slow on "
                             "large models)")],
         check=lambda args, config: (options.check_exists("--from-orbit", args.from_orbit),
                                     check_switch_option(args, config)))
def response(args: argparse.Namespace, config: Any) -> int:
    """Continue the branch and write it; exit 1 (after writing) if it stopped early."""
    from rotorsfd import api  # deferred: numpy, scipy, numba (keeps --help fast)

    if args.stability_basis is not None:
        from rotorsfd.io.config import with_values

        config = with_values(config, {"analysis.stability.basis": args.stability_basis})
    with StopRequest("the current point") as stop:
        result = api.run_response(config, search_path=Path(args.config).parent,
                                  progress=not args.quiet, from_orbit=args.from_orbit,
                                  callback=stop)
    paths = result.write(args.output, multipliers_at=args.multipliers_at)
    if stop.requested:
        if not args.quiet:  # the branch's own last line would say "stopped on request"
            print_summary("\n".join(line for line in result.summary().splitlines()
                                    if not line.startswith("stopped: ")), args.verbose)
            print("wrote " + ", ".join(str(p) for p in paths.values()))
        raise Interrupted(f"the {result.branch.n_points} points computed before Ctrl-C "
                          f"({branch_end(result)}) are written to {args.output}")
    if result.ended == "limit":   # a result up to the limit: exit 0, and say where and why
        print_written(result, paths, args.quiet, args.verbose)
        print_warning(result.message, args.verbose)
        return period_two(args, result)
    if not result.success:
        print_error(result.message, args.verbose)
        return 1
    print_written(result, paths, args.quiet, args.verbose)
    return period_two(args, result)


def check_switch_option(args: argparse.Namespace, config: Any) -> None:
    """``--switch-at`` before the work: the branch needs its Floquet stability (to find
    the period doublings) and a period-1 branch (not a torus)."""
    from rotorsfd.errors import ConfigError

    if args.switch_at is None:
        return
    if not config.analysis.stability.enabled:
        raise ConfigError("--switch-at", args.switch_at, "needs the branch's Floquet "
                          "stability to find its period doublings: set "
                          "analysis.stability.enabled = true (--set)")
    from rotorsfd.analyses.dual_spool_response import dual_spool
    from rotorsfd.analyses.torus_response import harmonic_base

    if harmonic_base(config) or dual_spool(config):
        raise ConfigError("--switch-at", args.switch_at, "switches from a periodic branch; "
                          "a harmonic base law or two spools give a quasi-periodic one")


def period_two(args: argparse.Namespace, result: Any) -> int:
    """``--switch-at N``: the period-2 branch written next to the main one and drawn in
    its response figures; a bad N (no such period doubling) is one line and exit 2."""
    if args.switch_at is None:
        return 0
    from rotorsfd.analyses.response_switch import check_switch, run_switch
    from rotorsfd.errors import ConfigError
    from rotorsfd.io import atomic

    try:
        check_switch(result, args.switch_at)
    except ConfigError as exc:
        print_error(str(exc), args.verbose)
        return 2
    p2 = run_switch(result, args.switch_at)
    out = Path(args.output)
    paths = p2.write(out)
    figures = result.response_figures()
    p2.draw(figures)
    paths.update(atomic.save_figures(figures, out))
    if not args.quiet:
        print_summary(p2.summary(), args.verbose)
        print("wrote " + ", ".join(str(p) for p in paths.values()))
    return 0


def branch_end(result: Any) -> str:
    """Where an interrupted response branch ends, in the parameter's terms."""
    lam = result.branch.lam
    if result.is_speed:
        return (f"Omega~ = {lam[0] / result.reference_speed:.4g} .. "
                f"{lam[-1] / result.reference_speed:.4g}")
    return f"{result.parameter} = {lam[0]:.6g} .. {lam[-1]:.6g}"
