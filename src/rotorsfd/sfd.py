"""Public entry point of the squeeze film damper: ``from rotorsfd.sfd import SFD``."""

from rotorsfd.model.sfd import DEFAULT_EPS_MAX, SFD

__all__ = ["DEFAULT_EPS_MAX", "SFD"]
