"""``rotorsfd config show|check|schema|fields``: inspect and check configuration files."""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path
from typing import Any

from rotorsfd.cli.registry import arg, command


@command("config show", "print the resolved configuration (SI units, defaults filled in)",
         arguments=[arg("--format", choices=("toml", "json"), default="toml",
                        help="output format (default: toml)")])
def config_show(args: argparse.Namespace, config: Any) -> int:
    """The resolved configuration, as TOML or JSON."""
    from rotorsfd.io.config import show_config  # deferred: pydantic, numpy

    sys.stdout.write(show_config(config, args.format))
    return 0


@command("config check", "validate a configuration and build its model")
def config_check(args: argparse.Namespace, config: Any) -> int:
    """Build the model; print the derived values and the plausibility warnings."""
    # deferred: the model pulls numpy and scipy
    from rotorsfd.analyses.checks import config_warnings
    from rotorsfd.io.config import derived_values
    from rotorsfd.model.build import build_model

    build_model(config, Path(args.config).parent)
    notes = "; ".join(f"{k}: {v}" for k, v in derived_values(config).items())
    print(f"{args.config}: ok ({notes})")
    for line in config_warnings(config, Path(args.config).parent):
        print(f"warning: {line}")
    return 0


@command("config schema", "print the JSON schema of configuration files", config=False)
def config_schema(args: argparse.Namespace, config: Any) -> int:
    """The pydantic JSON schema of :class:`~rotorsfd.io.schema.Config`."""
    from rotorsfd.io.schema import Config  # deferred: pydantic

    print(json.dumps(Config.model_json_schema(), indent=2))
    return 0


@command("config fields", "print the reference of every config field: SI unit, default, "
         "allowed values or range (the README's configuration reference)", config=False,
         arguments=[arg("--format", choices=["markdown", "csv", "json"], default="markdown",
                        help="markdown (one table per section; default), csv or json")])
def config_fields(args: argparse.Namespace, config: Any) -> int:
    """The configuration reference in one of :data:`rotorsfd.io.reference.FORMATS`."""
    from rotorsfd.io.reference import FORMATS  # deferred: pydantic

    sys.stdout.write(FORMATS[args.format]())
    return 0
