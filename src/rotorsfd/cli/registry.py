"""The command registry and the parser built from it.

A command is a function ``handler(args, config) -> exit status`` registered with
:func:`command`; the parser adds ``CONFIG`` and ``--set`` (``config=True``), ``-o DIR``
(``output=True``), ``--quiet`` (``quiet=True``) and ``--debug`` to each. A name with a
space (``"config show"``) is a subcommand of a group (``config``, described in
:data:`GROUPS`). ``args.debug`` and ``args.verbose`` are always set (given before or after
the command).
"""

from __future__ import annotations

import argparse
import difflib
from collections.abc import Callable, Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

from rotorsfd import __version__

#: help of ``--verbose`` (top level and every command)
VERBOSE_HELP = ("add the solver's account to messages (it is always in the results files)")

Handler = Callable[[argparse.Namespace, Any], "int | None"]
Check = Callable[[argparse.Namespace, Any], None]


@dataclass(frozen=True)
class Arg:
    """One extra argparse argument of a command: ``parser.add_argument(*flags, **kwargs)``."""

    flags: tuple[str, ...]
    kwargs: dict[str, Any] = field(default_factory=dict)


def arg(*flags: str, **kwargs: Any) -> Arg:
    """An extra argument of a command (same signature as ``add_argument``)."""
    return Arg(flags, kwargs)


@dataclass(frozen=True)
class Command:
    """A registered subcommand."""

    name: str
    help: str
    handler: Handler
    config: bool = True
    output: bool = False
    quiet: bool = False
    arguments: tuple[Arg, ...] = ()
    check: Check | None = None


COMMANDS: dict[str, Command] = {}
GROUPS: dict[str, str] = {"config": "inspect and check configuration files"}


def command(name: str, help: str, *, config: bool = True, output: bool = False,
            quiet: bool = False, arguments: Iterable[Arg] = (),
            check: Check | None = None) -> Callable[[Handler], Handler]:
    """Register ``handler(args, config) -> exit status`` as the subcommand ``name``;
    ``check(args, config)`` raises ConfigError for options that are bad together or
    name missing files (run after the config is loaded, before the output folder is
    made, the warnings and the work)."""

    def register(handler: Handler) -> Handler:
        if name in COMMANDS:
            raise ValueError(f"command {name!r} registered twice")
        COMMANDS[name] = Command(name, help, handler, config, output, quiet, tuple(arguments),
                                 check)
        return handler

    return register


class UsageError(Exception):
    """Bad command-line arguments (exit status 2)."""


class Parser(argparse.ArgumentParser):
    """An ArgumentParser that raises :class:`UsageError` instead of exiting."""

    def error(self, message: str) -> None:  # type: ignore[override]
        sub = self.prog.removeprefix("rotorsfd").strip()
        where = f"{sub}: " if sub else ""
        raise UsageError(f"{where}{message} (see '{self.prog} --help')")


def add_common(p: argparse.ArgumentParser, spec: Command) -> None:
    """The options every command of this kind takes, then its own."""
    if spec.config:
        p.add_argument("config", metavar="CONFIG", help="TOML configuration file")
        p.add_argument("--set", metavar="KEY=VALUE", action="append", default=[],
                       dest="overrides",
                       help="override a config field by its dotted path, e.g. "
                            "--set elements.sfd.clearance_ratio='0.61 %%' (repeatable)")
    if spec.output:
        p.add_argument("-o", "--output", metavar="DIR", required=True, type=Path,
                       help="output folder (created if missing)")
    if spec.quiet:
        p.add_argument("-q", "--quiet", action="store_true", help="no progress or summary")
    p.add_argument("--debug", action="store_true", default=argparse.SUPPRESS,
                   help="show tracebacks")
    p.add_argument("-v", "--verbose", action="store_true", default=argparse.SUPPRESS,
                   help=VERBOSE_HELP)
    for a in spec.arguments:
        p.add_argument(*a.flags, **a.kwargs)


def build_parser() -> argparse.ArgumentParser:
    """The full parser, built from the command registry."""
    parser = Parser(prog="rotorsfd", description="Nonlinear dynamics of flexible rotors with "
                    "squeeze film dampers on moving bases.")
    parser.add_argument("--version", action="version", version=f"rotorsfd {__version__}")
    parser.add_argument("--debug", action="store_true", help="show tracebacks on errors")
    parser.add_argument("-v", "--verbose", action="store_true", help=VERBOSE_HELP)
    top = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    groups: dict[str, Any] = {}
    for name, spec in COMMANDS.items():
        head, _, sub = name.partition(" ")
        if sub:
            if head not in groups:
                gp = top.add_parser(head, help=GROUPS.get(head, ""),
                                    description=GROUPS.get(head, ""))
                groups[head] = gp.add_subparsers(dest="subcommand", metavar="SUBCOMMAND",
                                                 required=True)
            p = groups[head].add_parser(sub, help=spec.help, description=spec.help)
        else:
            p = top.add_parser(name, help=spec.help, description=spec.help)
        add_common(p, spec)
        p.set_defaults(_command=spec, _parser=p)
    return parser


def unrecognized(args: argparse.Namespace, extra: Sequence[str]) -> UsageError:
    """The error for arguments the command does not take: the first one, the closest
    option (``did you mean``) or the options it takes."""
    spec: Command = args._command
    options = sorted({s for a in args._parser._actions for s in a.option_strings
                      if s.startswith("--")})
    word = extra[0].split("=", 1)[0]
    close = difflib.get_close_matches(word, options, n=1, cutoff=0.6)
    hint = (f"did you mean {close[0]}?" if close and word.startswith("-")
            else "it takes " + ", ".join(options))
    return UsageError(f"{spec.name}: got {extra[0]!r}, which it does not take; {hint} "
                      f"(see 'rotorsfd {spec.name} --help')")
