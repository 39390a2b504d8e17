"""Ctrl-C that keeps what was computed.

:class:`StopRequest` turns the first SIGINT into a request that a computation polls
(e.g. a continuation callback returning True stops the branch after the current point);
the second SIGINT raises KeyboardInterrupt as usual. :class:`Interrupted` is the
KeyboardInterrupt a command raises after it has written the partial results: its message
says what was kept and where.
"""

from __future__ import annotations

import signal
import sys
import threading
from types import FrameType
from typing import Any


class Interrupted(KeyboardInterrupt):
    """Stopped by the user after the partial results were written; ``kept`` says what."""

    def __init__(self, kept: str) -> None:
        super().__init__(kept)
        self.kept = kept


class StopRequest:
    """``with StopRequest("the current point") as stop:`` ... ``stop(...)`` is True once
    Ctrl-C was pressed (a callback for the continuation); ``stop.requested``."""

    def __init__(self, what: str = "the current step") -> None:
        self.what = what
        self.requested = False
        self._previous: Any = None

    def __enter__(self) -> StopRequest:
        if threading.current_thread() is threading.main_thread():
            self._previous = signal.signal(signal.SIGINT, self._handle)
        return self

    def __exit__(self, *exc: Any) -> None:
        if self._previous is not None:
            signal.signal(signal.SIGINT, self._previous)
            self._previous = None

    def _handle(self, signum: int, frame: FrameType | None) -> None:
        if self.requested:
            raise KeyboardInterrupt
        self.requested = True
        print(f"\nrotorsfd: interrupted: stopping after {self.what} and writing what was "
              "computed (Ctrl-C again to abort without writing)", file=sys.stderr)

    def __call__(self, *args: Any) -> bool:
        return self.requested
