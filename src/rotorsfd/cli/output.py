"""What the commands print: the error prefix, one-line messages, the summary and the
files written.

Messages are in the user's terms (where, which field or limit, what to change); a
message may end with the solver's own account in brackets, ``... [solver: corrector
failed after the point at lam=615.26 with the minimum step ds=1e-06: ...]``, which the
results files keep and the terminal shows only with ``--verbose``."""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

#: every error line starts with this
PREFIX = "rotorsfd: error: "


def one_line(exc: BaseException | str) -> str:
    """A message on one line (newlines become spaces)."""
    return " ".join(str(exc).split("\n"))


#: where the solver's account of a message starts (it runs to the matching bracket)
SOLVER_DETAIL = " [solver: "


def user_text(message: BaseException | str, verbose: bool = False) -> str:
    """The message on one line, without its ``[solver: ...]`` parts unless ``verbose``."""
    text = one_line(message).strip()
    if verbose:
        return text
    while (start := text.find(SOLVER_DETAIL)) >= 0:
        depth, end = 0, len(text)
        for i in range(start + 1, len(text)):
            depth += {"[": 1, "]": -1}.get(text[i], 0)
            if depth == 0:
                end = i + 1
                break
        text = text[:start] + text[end:]
    return text


def print_error(message: BaseException | str, verbose: bool = False) -> None:
    """``rotorsfd: error: <message>`` on one line of stderr (see :func:`user_text`)."""
    print(f"{PREFIX}{user_text(message, verbose)}", file=sys.stderr)


def print_warning(message: str, verbose: bool = False) -> None:
    """``rotorsfd: warning: <message>`` on one line of stderr (see :func:`user_text`)."""
    print(f"rotorsfd: warning: {user_text(message, verbose)}", file=sys.stderr)


def print_summary(text: str, verbose: bool = False) -> None:
    """A result's summary, each line without its solver detail unless ``verbose``."""
    print("\n".join(user_text(line, verbose) for line in text.splitlines()))


def print_written(result: Any, paths: dict[str, Path] | list[Path], quiet: bool,
                  verbose: bool = False) -> None:
    """Print a result's summary and the files written (nothing when ``quiet``)."""
    if not quiet:
        print_summary(result.summary(), verbose)
        files = paths.values() if isinstance(paths, dict) else paths
        print("wrote " + ", ".join(str(p) for p in files))
