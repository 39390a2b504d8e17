"""``main``: parse, load the config, check the output folder, run the command, and turn
each kind of error into its exit status and one line.

Exit status: 0 success; 2 bad input (config, ``--set``, arguments, an output folder that
cannot be written: one line naming the field, before any work); 1 any other rotorsfd error
(numerical failure) or a file that cannot be written (one line); 130 interrupted (the
output folder keeps ``INCOMPLETE.txt``); 141 stdout closed early (``| head``), silently.
``--debug`` adds the traceback, ``--verbose`` the solver's account of a failure (see
:mod:`~rotorsfd.cli.output`). Every error line starts with ``rotorsfd: error: ``.
"""

from __future__ import annotations

import argparse
import os
import sys
import traceback
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from rotorsfd.cli.output import PREFIX, one_line, print_warning, user_text
from rotorsfd.cli.registry import Command, UsageError, build_parser, unrecognized
from rotorsfd.errors import ConfigError, RotorsfdError
from rotorsfd.interrupt import Interrupted
from rotorsfd.io import provenance

BLAS_THREAD_VARIABLES = ("OPENBLAS_NUM_THREADS", "MKL_NUM_THREADS", "BLIS_NUM_THREADS",
                         "VECLIB_MAXIMUM_THREADS")


def single_threaded_blas() -> None:
    """Default the BLAS libraries to one thread (unless the user set them): the matrices
    here are small (hundreds of DOFs), where threaded LAPACK is slower, and on a busy
    machine it can be 10-40 times slower. Effective only before numpy is first imported."""
    for name in BLAS_THREAD_VARIABLES:
        os.environ.setdefault(name, "1")


def main(argv: Sequence[str] | None = None) -> int:
    """Run the command line; return the exit status (the invocation recorded for the
    provenance of its results, :mod:`rotorsfd.io.provenance`, while it runs)."""
    try:
        return dispatch(argv)
    finally:
        provenance.clear_invocation()


def dispatch(argv: Sequence[str] | None = None) -> int:
    """Parse, load the config, run the command; return the exit status."""
    single_threaded_blas()
    parser = build_parser()
    try:
        args, extra = parser.parse_known_args(argv)
        if extra:
            raise unrecognized(args, extra)
    except UsageError as exc:
        print(f"{PREFIX}{one_line(exc)}", file=sys.stderr)
        return 2
    except SystemExit as exc:  # --help, --version
        return int(exc.code or 0)
    spec: Command = args._command
    debug = bool(getattr(args, "debug", False))
    verbose = bool(getattr(args, "verbose", False))
    try:
        argv = list(sys.argv[1:] if argv is None else argv)
        provenance.set_invocation(spec.name, argv)
        config = None
        if spec.config:
            # deferred: the config loader pulls pydantic and numpy (keeps --help fast)
            from rotorsfd import api

            config = api.load_config(args.config, args.overrides)
        status = run_command(spec, args, config)
        sys.stdout.flush()  # a closed pipe fails here, not at the interpreter's exit
        return status
    except ConfigError as exc:
        return report(exc, 2, debug, verbose=verbose)
    except RotorsfdError as exc:
        return report(exc, 1, debug, verbose=verbose)
    except Interrupted as exc:
        print(f"rotorsfd: interrupted: {exc.kept}", file=sys.stderr)
        return 130
    except KeyboardInterrupt:
        print("rotorsfd: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:  # e.g. `rotorsfd config schema | head`: the reader is gone
        silence_stdout()
        return 141
    except OSError as exc:  # e.g. an output folder that cannot be written
        return report(exc, 1, debug)
    except Exception as exc:
        return report(exc, 1, debug, f"internal error ({type(exc).__name__}), please "
                      "report it; run with --debug for the traceback: ", verbose=True)


def run_command(spec: Command, args: argparse.Namespace, config: Any) -> int:
    """Check the options and the output folder, print the config's warnings, run the
    handler (:func:`run_marked`); the loaded ``config`` is given (``rotorsfd rerun`` gives
    the saved one)."""
    if spec.check is not None:
        spec.check(args, config)
    check_output(getattr(args, "output", None))
    if spec.config and spec.output:
        print_config_warnings(config, Path(args.config).parent)
    return run_marked(spec, args, config)


def run_marked(spec: Command, args: argparse.Namespace, config: Any) -> int:
    """Run the handler with ``INCOMPLETE.txt`` in its output folder while it runs (kept,
    saying so, if the run is interrupted; left behind if it is killed) and ``run.json``
    (:func:`write_run_file`) written once the handler has written its results (also
    those of a branch stopped early, exit 1, or interrupted; not after an error before
    any result, so that a folder of an earlier run keeps its own)."""
    if not spec.output:
        return int(spec.handler(args, config) or 0)
    # deferred: io.marker (keeps `import rotorsfd.api` and --help fast)
    from rotorsfd.io.marker import MARKER, IncompleteMarker

    marker = IncompleteMarker.start(args.output, spec.name)

    def record() -> None:   # only beside results: a folder left empty is removed
        folder = Path(args.output)
        if folder.is_dir() and any(f.name != MARKER for f in folder.iterdir()):
            write_run_file(args, config)

    try:
        status = int(spec.handler(args, config) or 0)
        record()
    except Interrupted as exc:
        record()
        marker.interrupted(exc.kept)
        exc.kept += f"; {args.output / MARKER} marks the folder incomplete"
        raise
    except KeyboardInterrupt:
        marker.interrupted()
        raise Interrupted(f"{args.output / MARKER} marks the folder incomplete") from None
    except BaseException:
        marker.finished()
        raise
    marker.finished()
    return status


#: parsed arguments that are not analysis options (the parser's own, or in run.json apart)
NOT_OPTIONS = frozenset({"_command", "_parser", "config", "overrides", "debug", "verbose"})


def write_run_file(args: argparse.Namespace, config: Any) -> Path:
    """Write ``run.json`` (:func:`rotorsfd.io.provenance.run_record`) atomically in the
    output folder: the resolved config, versions, revision and the command line."""
    from rotorsfd.io.atomic import write_json  # deferred: numpy

    config_toml = None
    if config is not None:
        from rotorsfd.io.config import show_config  # deferred: pydantic

        config_toml = show_config(config)
    options = {k: v for k, v in vars(args).items() if k not in NOT_OPTIONS}
    record = provenance.run_record(config_toml, options, getattr(args, "config", None))
    return write_json(Path(args.output) / provenance.RUN_FILE, record)


def report(exc: BaseException, status: int, debug: bool, prefix: str = "", *,
           verbose: bool = True) -> int:
    """Print the error on one line (the traceback first with ``--debug``; the solver's
    account only when ``verbose``); return ``status``."""
    if debug:
        traceback.print_exc()
    print(f"{PREFIX}{prefix}{user_text(exc, verbose or debug)}", file=sys.stderr)
    return status


def silence_stdout() -> None:
    """Point stdout at /dev/null so that the interpreter's final flush does not fail
    again on a closed pipe (exit status 141, as for a process killed by SIGPIPE)."""
    devnull = os.open(os.devnull, os.O_WRONLY)
    try:
        os.dup2(devnull, sys.stdout.fileno())
    except (OSError, ValueError):  # stdout is not a real file (tests capture it)
        pass
    finally:
        os.close(devnull)


def print_config_warnings(config: Any, search_path: Path) -> None:
    """The configuration's plausibility warnings on stderr, before the work starts."""
    # deferred: the checks build the model (numpy, scipy)
    from rotorsfd.analyses.checks import config_warnings

    for line in config_warnings(config, search_path):
        print_warning(line)


def check_output(folder: Path | None) -> None:
    """ConfigError naming ``-o`` if results cannot be written in ``folder`` (checked after
    the config, before any work)."""
    # deferred: io.atomic (keeps `import rotorsfd.api` and --help fast)
    from rotorsfd.io.atomic import folder_problem

    if folder is not None and (problem := folder_problem(folder)) is not None:
        raise ConfigError("-o", str(folder), problem)
