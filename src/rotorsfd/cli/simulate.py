"""``rotorsfd simulate``: time integration at one speed, with the motion classified."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.output import print_warning, print_written
from rotorsfd.cli.registry import arg, command
from rotorsfd.errors import ConfigError


def check_simulate(args: argparse.Namespace, config: Any) -> None:
    """The options against each other, and the initial state's file."""
    if args.speed is not None and args.speed_ratio is not None:
        raise ConfigError("--speed/--speed-ratio", (args.speed, args.speed_ratio),
                          "give --speed or --speed-ratio, not both")
    if args.hb_phase and not args.from_hb:
        raise ConfigError("--hb-phase", args.hb_phase, "needs --from-hb")
    options.check_exists("--initial-state", args.initial_state)
    if args.speed_law is not None:
        for flag, given in (("--speed", args.speed), ("--speed-ratio", args.speed_ratio),
                            ("--from-hb", args.from_hb or None),
                            ("--initial-state", args.initial_state)):
            if given is not None:
                raise ConfigError("--speed-law", args.speed_law,
                                  f"a run-up starts from the displaced state at its own "
                                  f"speeds: not with {flag}")
        # deferred: timedomain.speed_law_config (loads numba, scipy)
        from rotorsfd.timedomain.speed_law_config import (
            parse_speed_law_text,
            speed_law_from_config,
        )

        speed_law_from_config(parse_speed_law_text(args.speed_law), Path.cwd())
    if args.overlay is not None:
        if args.speed_law is None and config.analysis.simulate.speed_law is None:
            raise ConfigError("--overlay", str(args.overlay), "needs a speed law (a run-up "
                              "or coast-down: --speed-law or [analysis.simulate] speed_law)")
        if not args.overlay.is_file():
            raise ConfigError("--overlay", str(args.overlay), "an existing branch.nc of "
                              "rotorsfd response")


@command("simulate", "time integration at one speed ([analysis.simulate]): timeseries.nc, "
         "poincare.csv, summary.json (motion: period-n, quasi-periodic or chaotic, with the "
         "evidence), simulation.png and orbit/phase/poincare/spectrum.png; a journal that "
         "reaches its validity limit (contact) ends the run as a result: the periods "
         "before it written, a warning line saying where and why, exit 0 (ended = limit "
         "in summary.json); a numerical failure: one line, exit 1", output=True, quiet=True,
         arguments=[arg("--speed", type=options.positive_speed, metavar="SPEED",
                        help="rotor speed, e.g. 850 or '8000 rpm' (rad/s if no unit)"),
                    arg("--speed-ratio", type=options.positive_ratio, metavar="X",
                        help="rotor speed / [reference] speed"),
                    arg("--from-hb", action="store_true",
                        help="start on the HB periodic solution at that speed (H from "
                             "[analysis.response]) instead of the displaced state"),
                    arg("--hb-phase", type=options.ratio, default=0.0, metavar="P",
                        help="with --from-hb: start on the HB orbit a fraction P of the "
                             "period later (e.g. 0.5; off the orbit at t = 0 unless it is "
                             "symmetric: a way to find a coexisting attractor)"),
                    arg("--initial-state", type=Path, metavar="DIR_OR_NC",
                        help="start from the final state of a previous run (its output "
                             "directory or timeseries.nc); same speed: continues it"),
                    arg("--speed-law", metavar="LAW",
                        help="a run-up / coast-down instead of one speed: "
                             "'ramp,start=500 rad/s,stop=1200 rad/s,duration=2 s' (or "
                             "rate=...), 'constant,speed=...' or a CSV table (time [s], "
                             "speed [rad/s]); default [analysis.simulate] speed_law"),
                    arg("--overlay", type=Path, metavar="BRANCH_NC",
                        help="with a speed law: draw this steady branch (the branch.nc of "
                             "rotorsfd response) over the run's envelope"),
                    arg("--record-periods", type=options.integer(1), metavar="N",
                        help="last periods kept in timeseries.nc (default: poincare_periods)"),
                    arg("--lyapunov-periods", type=options.integer(0), metavar="N",
                        help="periods of the Lyapunov run (default: min(100, periods); "
                             "0: none)")],
         check=check_simulate)
def simulate(args: argparse.Namespace, config: Any) -> int:
    """Integrate, write and print the summary."""
    from rotorsfd import api  # deferred: numpy, scipy, numba (keeps --help fast)

    law = args.speed_law
    if law is not None and Path(law).is_file():      # a table: relative to the cwd
        law = str(Path(law).resolve())

    result = api.run_simulation(config, args.speed, speed_ratio=args.speed_ratio,
                                search_path=Path(args.config).parent,
                                from_hb=args.from_hb, hb_phase=args.hb_phase,
                                initial_state=args.initial_state,
                                record_periods=args.record_periods,
                                lyapunov_periods=args.lyapunov_periods,
                                progress=not args.quiet,
                                **({"speed_law": law} if law else {}),
                                **({"overlay": args.overlay} if args.overlay else {}))
    paths = result.write(args.output)
    print_written(result, paths, args.quiet, args.verbose)
    if getattr(result, "ended", "range") == "limit":   # a result up to the limit: say so
        print_warning(result.message, args.verbose)
    return 0
