"""``rotorsfd modal`` (Campbell diagram, critical speeds) and ``rotorsfd fit-supports``
(support stiffnesses that meet target critical speeds)."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.output import print_summary
from rotorsfd.cli.registry import arg, command


@command("modal", "Campbell diagram and critical speeds of the linear rotor (SFD film "
         "excluded, centring spring included): critical_speeds.csv, campbell.csv, "
         "campbell.png", output=True, quiet=True)
def modal(args: argparse.Namespace, config: Any) -> int:
    """Run the modal analysis; print the critical speeds and a note if fewer were found."""
    from rotorsfd import api  # deferred: numpy, scipy (keeps --help fast)

    result = api.run_modal(config, search_path=Path(args.config).parent,
                           progress=not args.quiet)
    paths = result.write(args.output)
    if not args.quiet:
        print_summary(result.summary(), args.verbose)
        if len(result.critical_speeds) < config.analysis.modal.n_critical:
            print(f"note: {len(result.critical_speeds)} of "
                  f"{config.analysis.modal.n_critical} critical speeds found below "
                  f"{config.analysis.modal.critical_speed_max:g} rad/s")
        print("wrote " + ", ".join(str(p) for p in paths.values()))
    return 0


@command("fit-supports", "fit support stiffnesses (dotted paths) so that the lowest "
         "critical speeds meet targets; prints the values and the --set lines (the "
         "paper gives no support stiffnesses)", quiet=True,
         arguments=[arg("--field", action="append", required=True, metavar="PATH",
                        help="a stiffness field, e.g. elements.sfd.centring_stiffness "
                             "(repeatable)"),
                    arg("--target", action="append", required=True, type=options.speed,
                        metavar="SPEED", help="target critical speed, e.g. 811.3 or "
                        "'7747 rpm' (repeatable, in the order of the modes)"),
                    arg("-o", "--output", type=Path, metavar="DIR",
                        help="also write DIR/fit.json")])
def fit_supports(args: argparse.Namespace, config: Any) -> int:
    """Fit the stiffnesses; exit 1 if the targets are not met exactly."""
    from rotorsfd import api  # deferred: numpy, scipy

    result = api.run_fit_supports(config, args.field, args.target,
                                  whirl=config.analysis.modal.whirl)
    if args.output is not None:
        result.write(args.output)
    if not args.quiet:
        print_summary(result.summary(), args.verbose)
    return 0 if result.fit.exact else 1
