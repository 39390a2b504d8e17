"""Nonlinear elements: the local forces of the rotor (squeeze film dampers, rubs, ...).

:class:`NonlinearElement` is the interface, :class:`ElementSet` the composite the solvers
see, :data:`KINDS` the registered kinds (each module below registers its config model on
import; a new kind is its module, ``<kind>.py``, with the element class and the config
model and no numba, its compiled kernel in ``<kind>_kernel.py``, imported where the
element's ``kernel`` is first asked for, and one line here: docs/elements.md).
"""

from rotorsfd.elements import sfd  # noqa: F401  (registers "sfd")

from rotorsfd.elements import rub  # noqa: F401  # isort: skip
from rotorsfd.elements import journal_bearing  # noqa: F401  # isort: skip
from rotorsfd.elements import intershaft_sfd  # noqa: F401  # isort: skip
from rotorsfd.elements.base import NonlinearElement
from rotorsfd.elements.composite import ElementSet
from rotorsfd.elements.registry import KINDS, register

__all__ = ["KINDS", "ElementSet", "NonlinearElement", "register"]
