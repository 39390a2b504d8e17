"""``rotorsfd bifurcation-diagram``: brute-force bifurcation diagram, the speed swept up
then down."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli.output import print_error, print_warning, print_written
from rotorsfd.cli.registry import arg, command


@command("bifurcation-diagram", "brute-force bifurcation diagram: the speed swept up then "
         "down over [analysis.bifurcation_diagram], each speed from the previous end state "
         "(a sweep's first speed, and the speed after a failed one, from the HB orbit); "
         "diagram.csv (Poincare points), speeds.csv, diagram.json, diagram.png; a speed "
         "whose journal reaches its validity limit (contact) ends there as a result "
         "(ended = limit in speeds.csv, a warning line, exit 0); exit 1 if a speed's time "
         "stepping failed numerically (recorded, the sweep goes on)", output=True,
         quiet=True,
         arguments=[arg("--start", choices=("hb", "displaced"), default="hb",
                        help="fresh start of a sweep: 'hb' (the HB periodic solution, "
                             "default) or 'displaced' (every node displaced by "
                             "[analysis.simulate] initial_displacement)"),
                    arg("--from-hb", action="store_true",
                        help="same as --start hb (kept for older scripts)")])
def bifurcation_diagram(args: argparse.Namespace, config: Any) -> int:
    """Sweep; one warning line per speed that ended at a validity limit, one error line
    per speed that failed numerically; exit 1 if any did."""
    from rotorsfd import api  # deferred: numpy, scipy, numba (keeps --help fast)

    start = "hb" if args.from_hb else args.start
    result = api.run_bifurcation_diagram(config, search_path=Path(args.config).parent,
                                         start_state=start, progress=not args.quiet)
    paths = result.write(args.output)
    print_written(result, paths, args.quiet, args.verbose)
    for p in result.contacts:
        if p.ended == "limit":
            print_warning(f"{p.direction} sweep: speed {p.speed:.6g} rad/s ended at a "
                          f"validity limit ({p.contact}); the sweep went on", args.verbose)
        else:
            print_error(f"{p.direction} sweep: speed {p.speed:.6g} rad/s failed "
                        f"({p.contact}); the sweep went on", args.verbose)
    return 0 if result.success else 1
