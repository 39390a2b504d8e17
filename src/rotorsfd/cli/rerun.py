"""``rotorsfd rerun DIR [-o NEWDIR]``: run a result's command again from its ``run.json``.

The saved, fully resolved config (``config_toml``: after ``extends`` and ``--set``) is run
with the command's analysis options parsed again from the saved ``argv``; the output folder
is replaced by ``NEWDIR`` (default: ``DIR`` itself, its files overwritten). Relative paths
among the options are taken from the saved working folder, and file names inside the config
from the original config's folder, as in the first run. The new ``run.json`` records the
analysis command (rerunnable in turn) and, as ``command_line``, the rerun typed.
"""

from __future__ import annotations

import argparse
import json
import shlex
from pathlib import Path
from typing import Any

from rotorsfd.cli.app import run_command
from rotorsfd.cli.registry import COMMANDS, arg, build_parser, command
from rotorsfd.errors import ConfigError
from rotorsfd.io import provenance


def read_run_file(folder: Path) -> dict[str, Any]:
    """The ``run.json`` of a results folder; ConfigError naming DIR when there is none or
    it does not say which command made the folder."""
    path = folder / provenance.RUN_FILE
    if not path.is_file():
        raise ConfigError("DIR", str(folder), f"has no {provenance.RUN_FILE}; give a "
                          "results folder written by a rotorsfd command")
    try:
        record = json.loads(path.read_text(encoding="utf-8"))
    except (OSError, UnicodeDecodeError, json.JSONDecodeError) as exc:
        raise ConfigError("DIR", str(folder), f"its {provenance.RUN_FILE} cannot be read "
                          f"({type(exc).__name__}: {exc})") from None
    name = record.get("command") if isinstance(record, dict) else None
    if name not in COMMANDS or not COMMANDS[name].output or not record.get("argv"):
        raise ConfigError("DIR", str(folder), f"its {provenance.RUN_FILE} names no "
                          f"command that writes a folder (command: {name!r})")
    return record


def rerun_arguments(record: dict[str, Any], output: Path) -> argparse.Namespace:
    """The saved command's arguments parsed again, writing to ``output``: the config path
    and relative paths made absolute from the saved working folder."""
    argv = [*record["argv"], "-o", str(output)]
    args, extra = build_parser().parse_known_args(argv)
    if extra:
        raise ConfigError("run.json argv", shlex.join(extra), "this rotorsfd does not take "
                          "these arguments (made by another version?)")
    cwd = Path(record.get("cwd") or ".")
    for key, value in vars(args).items():
        if isinstance(value, Path) and not value.is_absolute() and key != "output":
            setattr(args, key, cwd / value)
    if record.get("config_path"):
        args.config = record["config_path"]
    args.output = output
    return args


def saved_config(record: dict[str, Any]) -> Any:
    """The resolved config saved in ``run.json`` (validated again), or None."""
    text = record.get("config_toml")
    if not text:
        return None
    # deferred: tomllib (keeps `import rotorsfd.api` and --help fast)
    import tomllib

    from rotorsfd.io.config import config_from_dict  # deferred: pydantic, numpy

    return config_from_dict(tomllib.loads(text))


@command("rerun", "run a result's command again from its run.json (the saved resolved "
         "config and the command's options; the output folder replaced by -o, default "
         "DIR itself)", config=False,
         arguments=[arg("folder", metavar="DIR", type=Path,
                        help="results folder holding run.json"),
                    arg("-o", "--output", metavar="NEWDIR", type=Path, default=None,
                        help="output folder (default: DIR, its files overwritten)"),
                    arg("-q", "--quiet", action="store_true",
                        help="no progress or summary (also when the saved command had -q)")])
def rerun(args: argparse.Namespace, config: Any) -> int:
    """Read DIR/run.json and run its command with the saved config; its exit status."""
    record = read_run_file(args.folder)
    output = args.output if args.output is not None else args.folder
    spec = COMMANDS[record["command"]]
    again = rerun_arguments(record, output)
    if args.quiet and hasattr(again, "quiet"):
        again.quiet = True
    again.debug = bool(getattr(args, "debug", False)) or bool(getattr(again, "debug", False))
    again.verbose = bool(getattr(args, "verbose", False)) or bool(getattr(again, "verbose",
                                                                          False))
    typed = provenance.command_line()   # the rerun as typed (main recorded it)
    provenance.set_invocation(spec.name, [*record["argv"], "-o", str(output.absolute())],
                              typed, cwd=record.get("cwd"))
    return run_command(spec, again, saved_config(record))
