"""``rotorsfd paper``: reproduce Zhang et al. 2025 (case studies, figures, report)."""

from __future__ import annotations

import argparse
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.output import print_summary
from rotorsfd.cli.registry import arg, command
from rotorsfd.errors import ConfigError


@command("paper", "reproduce Zhang et al. 2025: run the paper's case studies, draw every "
         "figure (DIR/fig<N>.png) and write DIR/report.md and a self-contained "
         "DIR/report.html with our numbers beside the paper's; results per case in "
         "DIR/cases/ (their figures with --case-plots)", config=False, output=True, quiet=True,
         arguments=[arg("--figure", action="append", default=[], metavar="N",
                        help="only this figure of the paper (repeatable), e.g. --figure 7"),
                    arg("--quick", action="store_true",
                        help="Figure 7 only (fixed base, Table 1) in both readings: "
                             "seconds"),
                    arg("--workers", type=options.integer(1), metavar="N",
                        help="worker processes (default: the CPUs, at most 2)"),
                    arg("--reading", choices=("both", "literal", "calibrated"),
                        default="both",
                        help="the paper's rotor as stated (literal: no structural "
                             "damping), calibrated (examples/paper_rotor_calibrated.toml: "
                             "modal damping fitted to Table 1) or both (default; the "
                             "report puts them side by side)"),
                    arg("--case-plots", action="store_true",
                        help="also draw each case's own figures under DIR/cases/ (their "
                             "data files are always written; the figures double the run)")])
def paper(args: argparse.Namespace, config: Any) -> int:
    """Run the cases, draw the figures, write the report."""
    from rotorsfd import api  # deferred: numpy, scipy, matplotlib (keeps --help fast)

    try:
        result = api.run_paper(args.output, args.figure, quick=args.quick,
                               workers=args.workers, progress=not args.quiet,
                               case_plots=args.case_plots,
                               readings=("literal", "calibrated") if args.reading == "both"
                               else (args.reading,))
    except KeyError as exc:
        bad = [f for f in args.figure if f"no figure {f} " in f"{exc.args[0]} "]
        raise ConfigError("--figure", bad[0] if bad else ", ".join(args.figure),
                          exc.args[0]) from None
    if not args.quiet:
        print_summary(result.summary(), args.verbose)
        print(f"wrote {result.paths['report.md']}, {result.paths['report.html']}")
    return 0
