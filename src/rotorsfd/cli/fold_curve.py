"""``rotorsfd fold-curve``: two-parameter continuation of the saddle-nodes of the speed
response in a second parameter."""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.output import print_error, print_written
from rotorsfd.cli.registry import arg, command
from rotorsfd.errors import ConfigError


def fold_range(config: Any, parameter: str, start: str, stop: str) -> tuple[float, float]:
    """``--from`` and ``--to`` in SI, checked against the kind of ``--parameter``."""
    # deferred: the parameter registry and the schema pull numpy and pydantic
    from rotorsfd.analyses.response_words import system_parameter
    from rotorsfd.io.schema import resolve_kind
    from rotorsfd.io.units import UnitError, describe, to_si

    # deferred: model.parameters (loads scipy)
    from rotorsfd.model.parameters import find_parameter

    try:
        param = system_parameter(parameter)
    except ConfigError as exc:
        raise ConfigError("--parameter", parameter, exc.allowed) from None
    if param == "speed":
        raise ConfigError("--parameter", parameter, "must differ from the speed (the "
                          "saddle-nodes are those of the speed response)")
    path = parameter.strip()
    if path == param:           # a parameter name: its config path for the units
        path = find_parameter(param).path
    try:
        kind = resolve_kind(config, path)
    except KeyError as exc:
        raise ConfigError("--parameter", parameter, exc.args[0]) from None
    values = []
    for option, text in (("--from", start), ("--to", stop)):
        try:
            values.append(to_si(text, kind))
        except UnitError as exc:
            text_exc = str(exc)
            if not text_exc.startswith("expected"):
                text_exc = f"expected {describe(kind)} for {path}; {text_exc}"
            raise ConfigError(option, text, text_exc) from None
    if values[0] == values[1]:
        raise ConfigError("--to", stop, f"must differ from --from ({start!r})")
    return values[0], values[1]


def check_fold_curve(args: argparse.Namespace, config: Any) -> None:
    """``--parameter``, ``--from`` and ``--to`` (see :func:`fold_range`)."""
    fold_range(config, args.parameter, args.start, args.stop)


def two_parameter_arguments(parameter_help: str, from_help: str, to_help: str,
                            harmonics_help: str) -> list[Any]:
    """``--parameter``, ``--from``, ``--to`` and ``--harmonics`` of a (speed, lam2)
    command, with its help texts."""
    return [arg("--parameter", default="base.pitching.value", metavar="PATH",
                help=parameter_help),
            arg("--from", dest="start", required=True, metavar="VALUE", help=from_help),
            arg("--to", dest="stop", required=True, metavar="VALUE", help=to_help),
            arg("--harmonics", type=options.integer(1), metavar="H", help=harmonics_help)]


def run_two_parameter(args: argparse.Namespace, config: Any, run: Callable[..., Any],
                      what: str) -> int:
    """Run ``run(config, parameter, start, stop, search_path=, harmonics=)``, write its
    result; exit 1 (after writing) with "<what> stopped early" if it did."""
    start, stop = fold_range(config, args.parameter, args.start, args.stop)
    result = run(config, args.parameter, start, stop, search_path=Path(args.config).parent,
                 harmonics=args.harmonics)
    paths = result.write(args.output)
    if not result.success:
        print_error(f"{what} stopped early: {result.message}", args.verbose)
        return 1
    print_written(result, paths, args.quiet, args.verbose)
    return 0


@command("fold-curve", "two-parameter continuation of the saddle-nodes of the speed "
         "response ([analysis.response] speeds and H) in a second parameter: "
         "fold_curve.csv, fold_curve.json, fold_curve.png (Omega~ of the folds and the "
         "unstable width against the parameter; the cusp where the bistability vanishes); "
         "exit 1 if the curve stops early (the points so far are written)",
         output=True, quiet=True,
         arguments=two_parameter_arguments(
             "second parameter: base.pitching.value (default), base.rolling.value, "
             "base.yawing.value, unbalance[0].magnitude",
             "start value, e.g. '0 rad/s' (SI if no unit); the speed branch there must "
             "have a saddle-node",
             "end value, e.g. '10 rad/s'", "override H"),
         check=check_fold_curve)
def fold_curve(args: argparse.Namespace, config: Any) -> int:
    """Continue the fold curve; exit 1 (after writing) if it stopped early."""
    from rotorsfd import api  # deferred: numpy, scipy, numba (keeps --help fast)

    return run_two_parameter(args, config, api.run_fold_curve, "fold curve")
