"""Command-line interface: parse, call :mod:`rotorsfd.api`, print. No physics here.

``main`` (in :mod:`~rotorsfd.cli.app`) is the ``rotorsfd`` entry point; the parser is built
from the command registry (:mod:`~rotorsfd.cli.registry`); option types are in
:mod:`~rotorsfd.cli.options`, the error and summary lines in :mod:`~rotorsfd.cli.output`.
Each command (or group) is one module below, registered by importing it here.

Adding a command is one new module with its handler and one import line below::

    # src/rotorsfd/cli/import_ross.py
    @command("import-ross", "convert a ROSS rotor to a config", output=True, quiet=True,
             arguments=[arg("--harmonics", type=options.integer(1), help="override H")])
    def import_ross(args: argparse.Namespace, config: Config) -> int:
        from rotorsfd import api  # deferred: numpy, scipy (keeps --help fast)

        result = api.run_x(config, progress=not args.quiet)
        print_written(result, result.write(args.output), args.quiet, args.verbose)
        return 0

The registry adds ``CONFIG`` and ``--set`` (``config=True``, the config is loaded and
checked before the handler runs), ``-o DIR`` (``output=True``, checked writable, marked
``INCOMPLETE.txt`` while the handler runs), ``--quiet`` (``quiet=True``) and ``--debug``,
runs ``check(args, config)`` (``check=``: options that are bad together, input files
that do not exist) before the output folder, the warnings and the work, and turns errors
into exit statuses (see :mod:`~rotorsfd.cli.app`); ``--verbose`` adds the solver's account
to messages (:mod:`~rotorsfd.cli.output`). Import heavy modules inside the handler (with a
comment) so that ``rotorsfd --help`` stays fast.
"""

from __future__ import annotations

# the commands, in the order of `rotorsfd --help`: one import line each
# isort: off
from rotorsfd.cli import config  # noqa: F401
from rotorsfd.cli import modal  # noqa: F401
from rotorsfd.cli import calibrate  # noqa: F401
from rotorsfd.cli import response  # noqa: F401
from rotorsfd.cli import static  # noqa: F401
from rotorsfd.cli import sweep  # noqa: F401
from rotorsfd.cli import simulate  # noqa: F401
from rotorsfd.cli import bifurcation_diagram  # noqa: F401
from rotorsfd.cli import stability_chart  # noqa: F401
from rotorsfd.cli import fold_curve  # noqa: F401
from rotorsfd.cli import bifurcation_curves  # noqa: F401
from rotorsfd.cli import attractors  # noqa: F401
from rotorsfd.cli import paper  # noqa: F401
from rotorsfd.cli import rerun  # noqa: F401
from rotorsfd.cli import import_ross  # noqa: F401
from rotorsfd.cli import export_matrices  # noqa: F401
# isort: on
from rotorsfd.cli.app import main
from rotorsfd.cli.output import PREFIX
from rotorsfd.cli.registry import (
    COMMANDS,
    GROUPS,
    Arg,
    Command,
    UsageError,
    arg,
    build_parser,
    command,
)

__all__ = ["COMMANDS", "GROUPS", "PREFIX", "Arg", "Command", "UsageError", "arg",
           "build_parser", "command", "main"]
