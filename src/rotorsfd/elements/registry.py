"""The registry of element kinds: kind name -> its config model.

A kind's config model is a pydantic table with a ``kind`` literal field (the discriminator
of ``[elements.<name>]`` tables), a ``nodes`` property (checked against the rotor), a
``linear_supports()`` method (its linear parts, such as an SFD's centring spring, which
become supports of the rotor) and ``build(name) -> NonlinearElement``.
"""

from __future__ import annotations

from typing import Any, Protocol

from rotorsfd.elements.base import NonlinearElement


class ElementConfig(Protocol):
    """What the model layer asks of an element's config table."""

    kind: str

    @property
    def nodes(self) -> tuple[int, ...]: ...

    def linear_supports(self) -> list[Any]: ...

    def build(self, name: str) -> NonlinearElement: ...


#: kind name -> config model class, in registration order.
KINDS: dict[str, type] = {}


def register(config_model: type) -> type:
    """Register the config model of a kind (its ``kind`` field's default is the name)."""
    name = config_model.model_fields["kind"].default
    if not isinstance(name, str) or not name:
        raise TypeError(f"{config_model.__name__}.kind needs a string default (the kind name)")
    if name in KINDS and KINDS[name] is not config_model:
        raise ValueError(f"element kind {name!r} is registered twice")
    KINDS[name] = config_model
    return config_model
