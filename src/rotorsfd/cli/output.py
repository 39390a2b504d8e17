"""What the commands print: the error prefix, one-line messages, the summary and the
files written."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

#: every error line starts with this
PREFIX = "rotorsfd: error: "


def one_line(exc: BaseException | str) -> str:
    """A message on one line (newlines become spaces)."""
    return " ".join(str(exc).split("\n"))


def print_error(message: BaseException | str) -> None:
    """``rotorsfd: error: <message>`` on one line of stderr."""
    print(f"{PREFIX}{one_line(message)}", file=sys.stderr)


def print_warning(message: str) -> None:
    """``rotorsfd: warning: <message>`` on one line of stderr."""
    print(f"rotorsfd: warning: {one_line(message)}", file=sys.stderr)


def print_written(result: Any, paths: dict[str, Path] | list[Path], quiet: bool) -> None:
    """Print a result's summary and the files written (nothing when ``quiet``)."""
    if not quiet:
        print(result.summary())
        files = paths.values() if isinstance(paths, dict) else paths
        print("wrote " + ", ".join(str(p) for p in files))
