"""Typed errors of rotorsfd.

Every error a user can cause or meet carries a one-line message that says where and why;
the command-line layer turns them into one line on stderr and an exit status.
"""

from __future__ import annotations


class RotorsfdError(Exception):
    """Base class of every error raised on purpose by rotorsfd."""


class ConfigError(RotorsfdError):
    """Bad input: names the field, the value given and what is allowed (exit status 2)."""

    def __init__(self, field: str, value: object, allowed: str) -> None:
        self.field = field
        self.value = value
        self.allowed = allowed
        super().__init__(f"{field}: got {value!r}; {allowed}")


class ElementDomainError(RotorsfdError, FloatingPointError):
    """A nonlinear element's state left the domain of its force law (a film journal at the
    housing, a non-finite state). Solvers catch it to cut their step."""


class JournalContactError(ElementDomainError):
    """The SFD journal reached the housing (eccentricity ratio eps >= 1, or above the
    configured limit): the short-bearing film force is unbounded there.

    Solvers catch it to cut their step; at the top level it is reported with the state.
    """

    def __init__(self, eps: float, y: float, z: float, vy: float, vz: float,
                 where: str = "") -> None:
        self.eps, self.y, self.z, self.vy, self.vz = eps, y, z, vy, vz
        self.where = where
        at = f" at {where}" if where else ""
        super().__init__(
            f"journal contact{at}: eccentricity ratio eps={eps:.6g} "
            f"(y={y:.6g} m, z={z:.6g} m, vy={vy:.6g} m/s, vz={vz:.6g} m/s); "
            "the squeeze-film force is unbounded at eps >= 1"
        )


class ConvergenceError(RotorsfdError):
    """A solver did not converge: the message says where (parameter value, step) and why."""
