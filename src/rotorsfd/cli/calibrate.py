"""``rotorsfd calibrate``: config fields fitted to computed target quantities (critical
speeds, fold speeds, bifurcation speeds, peak amplitudes) by bounded least squares."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli.output import print_error, print_written
from rotorsfd.cli.registry import arg, command


def calibration_problem(args: argparse.Namespace, config: Any) -> tuple[list, list]:
    """The parsed ``--fit`` fields and ``--target`` targets (ConfigError on bad input:
    unknown field, bad bounds or units, more fields than targets)."""
    # deferred: the schema and the unit registry pull numpy and pint
    from rotorsfd.analyses.calibrate import check_problem, parse_fit, parse_target

    fields = [parse_fit(config, text) for text in args.fit]
    targets = [parse_target(text) for text in args.target]
    check_problem(fields, targets)
    return fields, targets


def check_calibrate(args: argparse.Namespace, config: Any) -> None:
    """Every ``--fit`` and ``--target`` checked before any work starts."""
    calibration_problem(args, config)


@command("calibrate", "fit config fields to target quantities the tool computes: "
         "critical_speed[N] (exact eigen-derivatives), fold_speed[N|lower|upper], "
         "bifurcation_speed[N|TYPE], peak_amplitude[NODE] (of the [analysis.response] "
         "branch; a fold speed's derivative exact in a continuation parameter, finite "
         "differences otherwise); bounded least squares; writes calibration.json "
         "(residuals, Jacobian, covariance) and calibrated.toml (the fitted config); exit 1 "
         "if the solver did not converge", output=True, quiet=True,
         arguments=[arg("--fit", action="append", required=True, metavar="PATH[=LO:HI]",
                        help="a config field to fit, e.g. elements.sfd.centring_stiffness or "
                             "'rotor.supports[0].stiffness=1e6:1e8' (bounds with units "
                             "allowed; default [x0/100, 100 x0]; repeatable)"),
                    arg("--target", action="append", required=True,
                        metavar="KIND[SEL]=VALUE[+-TOL]",
                        help="a target, e.g. critical_speed[1]=811.3, "
                             "'fold_speed[upper]=1040 rad/s+-1', peak_amplitude[1]='0.1 mm' "
                             "(SI or units; TOL: one standard deviation; repeatable)"),
                    arg("--max-evaluations", type=int, default=100, metavar="N",
                        help="residual evaluations at most (default 100)")],
         check=check_calibrate)
def calibrate(args: argparse.Namespace, config: Any) -> int:
    """Run the fit; print the table; exit 1 if least squares stopped without converging."""
    from rotorsfd.analyses.calibrate import run_calibration  # deferred: numpy, scipy

    fields, targets = calibration_problem(args, config)
    result = run_calibration(config, fields, targets, search_path=Path(args.config).parent,
                             max_nfev=args.max_evaluations)
    paths = result.write(args.output)
    if not result.success:
        print_error(f"calibration did not converge: {result.message}", args.verbose)
        return 1
    print_written(result, paths, args.quiet, args.verbose)
    return 0
