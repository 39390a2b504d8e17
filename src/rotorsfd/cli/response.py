"""``rotorsfd response``: periodic response by harmonic balance and arc-length
continuation; the first Ctrl-C stops the branch after the current point and writes it."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any, NamedTuple

from rotorsfd.cli import options
from rotorsfd.cli.output import print_error, print_summary, print_warning, print_written
from rotorsfd.cli.registry import arg, command
from rotorsfd.errors import ConfigError
from rotorsfd.interrupt import Interrupted, StopRequest


class SwitchPoint(NamedTuple):
    """A ``--switch-at`` value: ``kind`` ``pd`` (period doubling) or ``bp`` (branch
    point) and its ``number`` along the branch (from 1), as typed (``text``)."""

    kind: str
    number: int
    text: str


SWITCH_ALLOWED = ("pd:N (the N-th period doubling; plain N means the same) or bp:N (the "
                  "N-th branch point), N an integer >= 1")


def switch_point(text: str) -> SwitchPoint:
    """The argparse type of ``--switch-at``: ``pd:N``, ``bp:N`` or ``N`` (= ``pd:N``)."""
    kind, sep, number = text.strip().partition(":")
    if not sep:
        kind, number = "pd", kind
    if kind.lower() not in ("pd", "bp"):
        raise argparse.ArgumentTypeError(f"expected {SWITCH_ALLOWED}, got {text!r}")
    try:
        n = int(number)
    except ValueError:
        raise argparse.ArgumentTypeError(f"expected {SWITCH_ALLOWED}, got {text!r}"
                                         ) from None
    if n < 1:
        raise argparse.ArgumentTypeError(f"N must be >= 1 in {SWITCH_ALLOWED}, got "
                                         f"{text!r}")
    return SwitchPoint(kind.lower(), n, text)


switch_point.__name__ = "pd:N, bp:N or N"


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
                    arg("--switch-at", type=switch_point, default=None, metavar="pd:N|bp:N",
                        help="switch to a second branch at the branch's N-th "
                             "bifurcation of a kind (counted from 1 along the branch, as "
                             "in the summary and bifurcations.csv), drawn in the response "
                             "figures; pd:N (or plain N): the period-2 branch from the "
                             "N-th period-doubling point, with 4H harmonics of Omega/2 "
                             "(branch_period2.nc, branch_period2.csv); bp:N: the second "
                             "branch at the N-th branch point (pitchfork or "
                             "transcritical), continued both ways over the speed range "
                             "(branch_bp<N>.nc, branch_bp<N>.csv); needs "
                             "[analysis.stability] enabled"),
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
    if args.switch_at is None:
        return
    what = {"pd": "period doublings", "bp": "branch points"}[args.switch_at.kind]
    if not config.analysis.stability.enabled:
        raise ConfigError("--switch-at", args.switch_at.text, "needs the branch's Floquet "
                          f"stability to find its {what}: set "
                          "analysis.stability.enabled = true (--set)")
    # deferred: analyses.dual_spool_response, analyses.torus_response (loads numba, scipy, pydantic)
    from rotorsfd.analyses.dual_spool_response import dual_spool
    from rotorsfd.analyses.torus_response import harmonic_base

    if harmonic_base(config) or dual_spool(config):
        raise ConfigError("--switch-at", args.switch_at.text, "switches from a periodic "
                          "branch; "
                          "a harmonic base law or two spools give a quasi-periodic one")


def period_two(args: argparse.Namespace, result: Any) -> int:
    """``--switch-at pd:N`` (or ``N``): the period-2 branch, ``bp:N``: the second branch
    at a branch point, written next to the main one and drawn in its response figures;
    a bad N (no such bifurcation) is one line and exit 2."""
    if args.switch_at is None:
        return 0
    # deferred: numpy, scipy, numba (keeps --help fast)
    from rotorsfd import api
    from rotorsfd.io import atomic

    sw = args.switch_at
    check, run = api.second_branch_switch(sw.kind)
    try:
        check(result, sw.number, sw.text)
    except ConfigError as exc:
        print_error(str(exc), args.verbose)
        return 2
    second = run(result, sw.number, value=sw.text)
    out = Path(args.output)
    paths = second.write(out)
    figures = result.response_figures()
    second.draw(figures)
    paths.update(atomic.save_figures(figures, out))
    if not args.quiet:
        print_summary(second.summary(), args.verbose)
        print("wrote " + ", ".join(str(p) for p in paths.values()))
    return 0


def branch_end(result: Any) -> str:
    """Where an interrupted response branch ends, in the parameter's terms."""
    lam = result.branch.lam
    if result.is_speed:
        return (f"Omega~ = {lam[0] / result.reference_speed:.4g} .. "
                f"{lam[-1] / result.reference_speed:.4g}")
    return f"{result.parameter} = {lam[0]:.6g} .. {lam[-1]:.6g}"
