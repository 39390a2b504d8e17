"""``rotorsfd import-ross``: a ROSS rotor file (``ross.Rotor.save``) as a rotorsfd config."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli import options
from rotorsfd.cli.registry import arg, command


@command("import-ross", "convert a ROSS rotor (the TOML file of ross.Rotor.save) into a "
         "rotorsfd config: shaft, disks, bearings and seals with constant coefficients; "
         "add the nonlinear elements to it (needs rotorsfd[ross])", config=False,
         arguments=[arg("rotor", metavar="ROTOR", type=Path, help="ROSS rotor file (TOML)"),
                    arg("-o", "--output", dest="target", metavar="FILE", type=Path,
                        required=True, help="the rotorsfd config to write"),
                    arg("--speed", type=options.speed, metavar="SPEED",
                        help="freeze speed-dependent bearing and seal coefficients at this "
                             "speed, e.g. --speed '9000 rpm' (default: refuse them)"),
                    arg("--merge-layers", action="store_true",
                        help="merge concentric shaft layers on one node pair into one "
                             "section of an equivalent material (E I, rho A, kappa G A "
                             "kept)")])
def import_ross(args: argparse.Namespace, config: Any) -> int:
    """Read the ROSS rotor, write the config, say what it holds."""
    from rotorsfd.interop.ross import import_ross as convert  # deferred: ross (~25 s)

    convert(args.rotor, args.target, speed=args.speed,
            layers="merge" if args.merge_layers else "error")
    print(f"wrote {args.target} (ROSS node n is node n + 1; check it with "
          f"`rotorsfd config check {args.target}`)")
    return 0
