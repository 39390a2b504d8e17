"""A marker file that says a result folder is incomplete.

A command writes ``INCOMPLETE.txt`` into its output folder before it starts and removes
it when it ends normally (success or a reported failure). If the file is still there,
the run was interrupted (Ctrl-C: the file says so and what was kept) or killed (SIGKILL,
a crash, a power cut): the other files may be partial or missing.
"""

from __future__ import annotations

import os
import time
from dataclasses import dataclass
from pathlib import Path

from rotorsfd.io.atomic import write_text

MARKER = "INCOMPLETE.txt"


def _now() -> str:
    return time.strftime("%Y-%m-%d %H:%M:%S %Z")


#: temporary files of the atomic writers: ``.<name>.<random>.tmp<suffix>``
TEMPORARY = ".*.*.tmp*"


def remove_stale_temporaries(folder: Path) -> list[Path]:
    """Delete the atomic writers' temporary files under ``folder`` (those of a killed run:
    call it only when no other run writes there); return them."""
    stale = [p for p in folder.rglob(TEMPORARY) if p.is_file()]
    for p in stale:
        p.unlink(missing_ok=True)
    return stale


@dataclass
class IncompleteMarker:
    """The marker of one run in ``folder`` (see the module docstring)."""

    folder: Path
    command: str
    created: Path | None  #: the outermost folder this run created (None: it existed)

    @property
    def path(self) -> Path:
        """The marker file."""
        return self.folder / MARKER

    @classmethod
    def start(cls, folder: str | Path, command: str) -> IncompleteMarker:
        """Create ``folder`` if needed and write the marker of a run that has started.
        If a previous run's marker is there (it was killed), its half-written temporary
        files are removed first (:func:`remove_stale_temporaries`)."""
        folder = Path(folder)
        if (folder / MARKER).is_file():
            remove_stale_temporaries(folder)
        created = None
        for candidate in (folder, *folder.parents):
            if candidate.exists():
                break
            created = candidate
        marker = cls(folder, command, created)
        write_text(marker.path, f"rotorsfd {command} started writing this folder at "
                   f"{_now()} (process {os.getpid()}) and has not finished: if this file "
                   "is still here, the run was killed and the other files may be partial "
                   "or missing. Run the command again.\n")
        return marker

    def interrupted(self, kept: str = "") -> None:
        """Rewrite the marker: the run was interrupted by the user; ``kept`` says what of
        the results was written."""
        note = f" {kept[:1].upper()}{kept[1:]}." if kept else \
            " The other files may be partial or missing."
        write_text(self.path, f"rotorsfd {self.command} was interrupted (Ctrl-C) at "
                   f"{_now()}.{note}\n")

    def finished(self) -> None:
        """Remove the marker (the run ended normally); remove the folders the run
        created too if it wrote nothing in them (e.g. an error before any result)."""
        self.path.unlink(missing_ok=True)
        if self.created is None:
            return
        for folder in (self.folder, *self.folder.parents):
            try:
                folder.rmdir()
            except OSError:  # not empty: results were written
                return
            if folder == self.created:
                return
