"""rotorsfd: nonlinear dynamics of flexible rotors with squeeze film dampers on moving bases."""

__version__ = "0.1.0"
