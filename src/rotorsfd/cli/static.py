"""``rotorsfd static``: static deflection of the linear rotor under constant base motion."""

from __future__ import annotations

import argparse
from pathlib import Path
from typing import Any

from rotorsfd.cli.output import print_written
from rotorsfd.cli.registry import command


@command("static", "static deflection of the linear rotor under constant base motion "
         "(gyroscopic moment, base acceleration, gravity) over the [analysis.modal] "
         "speeds: static_deflection.csv and .png", output=True, quiet=True)
def static(args: argparse.Namespace, config: Any) -> int:
    """The static deflection at each [analysis.modal] speed; write the table."""
    from rotorsfd import api  # deferred: numpy, scipy (keeps --help fast)

    result = api.run_static(config, search_path=Path(args.config).parent)
    print_written(result, result.write(args.output), args.quiet, args.verbose)
    return 0
