"""What made a result: the rotorsfd version, the git revision of its source tree (when it is
a checkout), the dependency versions and the command line, for ``run.json`` and the netCDF
attributes (issue 23 item 3).

The command line interface records its invocation (:func:`set_invocation`) before a
command runs; every results folder then gets :func:`run_record` (written by the CLI's one
shared place, :func:`rotorsfd.cli.app.run_marked`) and every netCDF file
:func:`netcdf_attrs`. A library call (no invocation) records ``command_line = "none
(library call)"``.
"""

from __future__ import annotations

import contextvars
import functools
import os
import platform
import shlex
import subprocess
import sys
from collections.abc import Sequence
from dataclasses import dataclass
from datetime import UTC, datetime
from importlib import metadata
from pathlib import Path
from typing import Any

import rotorsfd
from rotorsfd import __version__

#: the file every results folder carries
RUN_FILE = "run.json"
#: version of the run.json layout (bumped when a key changes meaning)
RUN_FORMAT = 1
#: the dependencies whose versions are recorded (distribution names)
DEPENDENCIES: tuple[str, ...] = ("numpy", "scipy", "numba", "xarray", "pydantic", "pint",
                                 "matplotlib")
#: the command line of a result made by a library call
LIBRARY_CALL = "none (library call)"


@dataclass(frozen=True)
class Invocation:
    """A command-line invocation: the argv of the analysis command (without the program
    name; what ``rotorsfd rerun`` parses again) and the command line typed."""

    command: str
    argv: tuple[str, ...]
    command_line: str
    cwd: str


CURRENT: contextvars.ContextVar[Invocation | None] = contextvars.ContextVar(
    "rotorsfd_invocation", default=None)


def set_invocation(command: str, argv: Sequence[str], command_line: str | None = None,
                   cwd: str | None = None) -> Invocation:
    """Record the running command (``argv`` without the program name, its relative paths
    from ``cwd``, default the working folder); ``command_line`` defaults to ``rotorsfd``
    followed by ``argv``, shell-quoted."""
    inv = Invocation(command, tuple(str(a) for a in argv),
                     command_line or shlex.join(["rotorsfd", *map(str, argv)]),
                     cwd or os.getcwd())
    CURRENT.set(inv)
    return inv


def clear_invocation() -> None:
    """Forget the recorded invocation (the command has finished)."""
    CURRENT.set(None)


def invocation() -> Invocation | None:
    """The recorded invocation, or None in a library call."""
    return CURRENT.get()


def command_line() -> str:
    """The command line of the running command, or :data:`LIBRARY_CALL`."""
    inv = invocation()
    return inv.command_line if inv is not None else LIBRARY_CALL


def package_dir() -> Path:
    """The folder of the imported rotorsfd package."""
    return Path(rotorsfd.__file__).resolve().parent


def _git(folder: Path, *args: str) -> str | None:
    try:
        done = subprocess.run(["git", "-C", str(folder), *args], capture_output=True,
                              text=True, timeout=10, check=False)
    except (OSError, subprocess.SubprocessError):
        return None
    return done.stdout.strip() if done.returncode == 0 else None


@functools.lru_cache(maxsize=1)
def git_revision() -> tuple[str | None, bool | None]:
    """(commit, dirty) of the package's source tree if it is a git checkout of rotorsfd
    (its top level holds ``pyproject.toml`` and the package lies inside it, not in a
    ``site-packages``); (None, None) otherwise, without failing (no git, not a
    checkout). ``dirty``: tracked files differ from the commit."""
    where = package_dir()
    if "site-packages" in where.parts or "dist-packages" in where.parts:
        return None, None
    top = _git(where, "rev-parse", "--show-toplevel")
    if not top or not (Path(top) / "pyproject.toml").is_file():
        return None, None
    rev = _git(where, "rev-parse", "HEAD")
    if not rev:
        return None, None
    status = _git(where, "status", "--porcelain", "--untracked-files=no")
    return rev, (bool(status) if status is not None else None)


def dependency_versions() -> dict[str, str | None]:
    """Installed version of each of :data:`DEPENDENCIES` (None when not installed)."""
    out: dict[str, str | None] = {}
    for name in DEPENDENCIES:
        try:
            out[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            out[name] = None
    return out


def netcdf_attrs() -> dict[str, str]:
    """The provenance attributes of a netCDF file: ``rotorsfd_version``, ``git_revision``
    (``none`` when not a checkout; ``+dirty`` appended for local changes) and
    ``command_line`` (all strings: netCDF attributes cannot be None)."""
    rev, dirty = git_revision()
    text = "none" if rev is None else rev + ("+dirty" if dirty else "")
    return {"rotorsfd_version": __version__, "git_revision": text,
            "command_line": command_line()}


def run_record(config_toml: str | None, options: dict[str, Any],
               config_path: str | None = None) -> dict[str, Any]:
    """The content of ``run.json``: versions, revision, dependencies, the invocation
    (command, argv, command line, working folder), the analysis options as parsed, the
    original config's path (its folder is where relative file names in the config are
    found) and the fully resolved config as TOML (after ``extends`` and ``--set``)."""
    rev, dirty = git_revision()
    inv = invocation()
    return {
        "format": RUN_FORMAT,
        "created_utc": datetime.now(UTC).isoformat(timespec="seconds"),
        "rotorsfd_version": __version__,
        "git_revision": rev,
        "git_dirty": dirty,
        "python": sys.version.split()[0],
        "platform": platform.platform(),
        "dependencies": dependency_versions(),
        "command": inv.command if inv else None,
        "argv": list(inv.argv) if inv else None,
        "command_line": command_line(),
        "cwd": inv.cwd if inv else os.getcwd(),
        "config_path": (str(Path(config_path).absolute()) if config_path is not None
                        else None),
        "options": options,
        "config_toml": config_toml,
    }
